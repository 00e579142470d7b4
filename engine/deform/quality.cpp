#include "deform/quality.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/matrix.hpp>

#include "base/parallel.h"
#include "base/rigid_fit.h"
#include "mesh/geometry.h"

namespace vfsd {

namespace {

bool is_finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

constexpr int kNormalLanes = 64;

}  // namespace

void unit_normals(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles, std::size_t first,
                  std::size_t last, std::vector<Vec3>& normals) {
    double nx[kNormalLanes], ny[kNormalLanes], nz[kNormalLanes];
    for (std::size_t begin = first; begin < last; begin += kNormalLanes) {
        const int n = static_cast<int>(std::min<std::size_t>(kNormalLanes, last - begin));
        for (int j = 0; j < n; ++j) {  // unit_normal's cross product
            const Triangle& t = triangles[begin + j];
            const Vec3 &a = x[t[0]], &b = x[t[1]], &c = x[t[2]];
            const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, wx = c.x - a.x, wy = c.y - a.y, wz = c.z - a.z;
            nx[j] = uy * wz - wy * uz, ny[j] = uz * wx - wz * ux, nz[j] = ux * wy - wx * uy;
        }
        normalise_lanes(n, nx, ny, nz);
        for (int j = 0; j < n; ++j) normals[begin + j] = Vec3(nx[j], ny[j], nz[j]);
    }
}

bool is_closed_surface(const std::vector<Triangle>& triangles) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(3 * triangles.size());
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(t[k], t[(k + 1) % 3]));
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i != 2) return false;
        i = j;
    }
    return !triangles.empty();
}

// For each triangle, the triangles sharing one of its edges (any orientation).
TriangleNeighbours triangle_neighbours(const std::vector<Triangle>& triangles) {
    struct Edge {
        std::uint32_t a, b, triangle;
    };
    // The edges ordered by (a, b, triangle): bucketed by their lower vertex (a
    // counting sort, linear in the mesh), then each small bucket sorted.
    std::uint32_t vertices = 0;
    for (const Triangle& t : triangles) vertices = std::max({vertices, t[0] + 1, t[1] + 1, t[2] + 1});
    std::vector<std::uint32_t> start(vertices + 1, 0);
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) ++start[std::min(t[k], t[(k + 1) % 3]) + 1];
    for (std::uint32_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
    std::vector<Edge> edges(start.back());
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::uint32_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
            edges[next[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), t};
        }
    for (std::uint32_t v = 0; v < vertices; ++v)
        std::sort(edges.begin() + start[v], edges.begin() + start[v + 1], [](const Edge& x, const Edge& y) {
            return x.b != y.b ? x.b < y.b : x.triangle < y.triangle;
        });
    // Each edge shared by m triangles gives each of them m - 1 neighbours: counted, then filled.
    TriangleNeighbours n;
    n.offsets.assign(triangles.size() + 1, 0);
    const auto for_each_pair = [&](auto&& visit) {
        for (std::size_t i = 0; i < edges.size();) {
            std::size_t j = i;
            while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
            for (std::size_t p = i; p < j; ++p)
                for (std::size_t q = i; q < j; ++q)
                    if (p != q) visit(edges[p].triangle, edges[q].triangle);
            i = j;
        }
    };
    for_each_pair([&](std::uint32_t t, std::uint32_t) { ++n.offsets[t + 1]; });
    for (std::size_t t = 0; t < triangles.size(); ++t) n.offsets[t + 1] += n.offsets[t];
    n.list.resize(n.offsets.back());
    std::vector<std::uint32_t> filled(n.offsets.begin(), n.offsets.end() - 1);
    for_each_pair([&](std::uint32_t t, std::uint32_t u) { n.list[filled[t]++] = u; });
    return n;
}

std::vector<std::uint8_t> facing_against_neighbours(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles,
                                                    const TriangleNeighbours& neighbours) {
    std::vector<Vec3> normals(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) normals[t] = unit_normal(x, triangles[t]);
    std::vector<std::uint8_t> against(triangles.size(), 0);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const std::uint32_t begin = neighbours.offsets[t], end = neighbours.offsets[t + 1];
        if (begin == end) continue;
        Vec3 mean(0.0);
        for (std::uint32_t k = begin; k < end; ++k) mean += normals[neighbours.list[k]];
        against[t] = glm::dot(normals[t], mean) < 0.0;
    }
    return against;
}

std::vector<std::uint32_t> newly_facing_against(const std::vector<std::uint8_t>& before,
                                                const std::vector<std::uint8_t>& after) {
    std::vector<std::uint32_t> flipped;
    for (std::uint32_t t = 0; t < after.size(); ++t)
        if (after[t] && !before[t]) flipped.push_back(t);
    return flipped;
}

std::vector<std::uint32_t> flipped_triangle_list(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                                 const std::vector<Triangle>& triangles) {
    const TriangleNeighbours neighbours = triangle_neighbours(triangles);
    return newly_facing_against(facing_against_neighbours(before, triangles, neighbours),
                                facing_against_neighbours(after, triangles, neighbours));
}

std::size_t count_flipped_triangles(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                    const std::vector<Triangle>& triangles) {
    return flipped_triangle_list(before, after, triangles).size();
}

FoldWhere locate_folds(const std::vector<Vec3>& before, const std::vector<Triangle>& triangles,
                       const std::vector<double>& s, const std::vector<std::uint32_t>& folded) {
    FoldWhere w;
    if (folded.empty()) return w;
    w.s_min = 1.0, w.s_max = 0.0;
    for (const std::uint32_t t : folded)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = triangles[t][k];
            w.centre += before[v] / (3.0 * double(folded.size()));
            w.s_min = std::min(w.s_min, s[v]), w.s_max = std::max(w.s_max, s[v]);
        }
    return w;
}

namespace {

// Vertex v's neighbours through `triangles`, v itself included: list[offsets[v]] .. list[offsets[v + 1] - 1].
struct VertexStars {
    std::vector<std::uint32_t> offsets, list;
};

VertexStars vertex_stars(std::size_t vertices, const std::vector<Triangle>& triangles) {
    std::vector<std::vector<std::uint32_t>> star(vertices);
    for (std::uint32_t v = 0; v < vertices; ++v) star[v].push_back(v);
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) star[t[k]].push_back(t[(k + 1) % 3]), star[t[k]].push_back(t[(k + 2) % 3]);
    VertexStars out;
    out.offsets.push_back(0);
    for (auto& s : star) {
        std::sort(s.begin(), s.end());
        s.erase(std::unique(s.begin(), s.end()), s.end());
        out.list.insert(out.list.end(), s.begin(), s.end());
        out.offsets.push_back(static_cast<std::uint32_t>(out.list.size()));
    }
    return out;
}

// Whether triangle t's image faces against the one the affine fit of its corners'
// stars gives it. The fit, about the points' centres, minimises
// Σ |A pᵢ − qᵢ|² + λ |A n − R n|², n the triangle's unit normal before and R the
// points' best rotation: a star is nearly flat, so its own points leave A's action
// on n free, and a small λ (10⁻³ Σ |pᵢ|²) fills it in without biasing the rest.
bool reversed(const std::vector<Vec3>& before, const std::vector<Vec3>& after, const Triangle& t,
              const VertexStars& stars) {
    const Vec3 u = before[t[1]] - before[t[0]], w = before[t[2]] - before[t[0]];
    const Vec3 area = glm::cross(u, w);
    if (!(glm::length(area) > 0.0)) return false;
    std::vector<Vec3> from, to;
    for (int k = 0; k < 3; ++k)
        for (std::uint32_t i = stars.offsets[t[k]]; i < stars.offsets[t[k] + 1]; ++i)
            from.push_back(before[stars.list[i]]), to.push_back(after[stars.list[i]]);
    Vec3 from_centre(0.0), to_centre(0.0);
    for (std::size_t i = 0; i < from.size(); ++i) from_centre += from[i], to_centre += to[i];
    from_centre /= double(from.size()), to_centre /= double(from.size());
    glm::dmat3 qp(0.0), pp(0.0);
    double size = 0.0;
    for (std::size_t i = 0; i < from.size(); ++i) {
        const Vec3 p = from[i] - from_centre, q = to[i] - to_centre;
        qp += glm::outerProduct(q, p), pp += glm::outerProduct(p, p), size += glm::dot(p, p);
    }
    const Vec3 n = glm::normalize(area);
    const double lambda = 1e-3 * size;
    const Vec3 turned = fit_rigid(from, to).rotation * n;
    const glm::dmat3 a =
        (qp + lambda * glm::outerProduct(turned, n)) * glm::inverse(pp + lambda * glm::outerProduct(n, n));
    const Vec3 predicted = glm::cross(a * u, a * w);
    const Vec3 image = glm::cross(after[t[1]] - after[t[0]], after[t[2]] - after[t[0]]);
    return glm::dot(predicted, image) <= 0.0;
}

}  // namespace

std::vector<std::uint32_t> reversed_triangle_list(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                                  const std::vector<Triangle>& triangles) {
    const VertexStars stars = vertex_stars(before.size(), triangles);
    std::vector<std::uint8_t> flags(triangles.size(), 0);
    parallel_for(triangles.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t t = first; t < last; ++t) {
            const Triangle& tri = triangles[t];
            const bool moved =
                after[tri[0]] != before[tri[0]] || after[tri[1]] != before[tri[1]] || after[tri[2]] != before[tri[2]];
            flags[t] = moved && reversed(before, after, tri, stars);
        }
    });
    std::vector<std::uint32_t> out;
    for (std::uint32_t t = 0; t < triangles.size(); ++t)
        if (flags[t]) out.push_back(t);
    return out;
}

DeformationQuality measure_quality(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                   const std::vector<Triangle>& triangles, const std::vector<double>& s) {
    DeformationQuality q;
    q.volume_defined = is_closed_surface(triangles);
    // About the centre of the mesh before, so that a mesh far from (0,0,0) keeps its digits.
    const Vec3 centre = bounding_box(before).centre();
    q.volume_before = signed_volume(before, triangles, centre);
    q.volume_after = signed_volume(after, triangles, centre);
    q.volume_change_percent =
        q.volume_before != 0.0 ? 100.0 * (q.volume_after - q.volume_before) / std::abs(q.volume_before) : 0.0;
    q.volume_error_percent = std::abs(q.volume_change_percent);
    std::vector<Vec3> inner_before, inner_after;
    for (std::size_t v = 0; v < before.size(); ++v) {
        if (!is_finite(after[v])) ++q.nonfinite_vertices;
        if (s[v] >= 1.0) {
            ++q.outer_vertices;
            q.outer_max_displacement = std::max(q.outer_max_displacement, glm::length(after[v] - before[v]));
        } else if (s[v] <= 0.0) {
            inner_before.push_back(before[v]);
            inner_after.push_back(after[v]);
        }
    }
    q.inner_vertices = inner_before.size();
    const double diagonal = bounding_box(before).diagonal();
    if (!inner_before.empty() && diagonal > 0.0)
        q.inner_rigid_residual = fit_rigid(inner_before, inner_after).rms_residual / diagonal;
    q.flipped_triangles = count_flipped_triangles(before, after, triangles);
    q.reversed_triangles = reversed_triangle_list(before, after, triangles).size();
    return q;
}

}  // namespace vfsd
