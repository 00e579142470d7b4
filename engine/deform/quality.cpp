#include "deform/quality.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "base/rigid_fit.h"
#include "mesh/geometry.h"

namespace vfsd {

Vec3 unit_normal(const std::vector<Vec3>& x, const Triangle& t) {
    const Vec3 n = glm::cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
    const double len = glm::length(n);
    return len > 0.0 ? n / len : Vec3(0.0);
}

namespace {

bool is_finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

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
    return q;
}

}  // namespace vfsd
