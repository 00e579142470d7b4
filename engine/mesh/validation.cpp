#include "mesh/validation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace vfsd {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Union-find over triangle corners (corner 3t + k is vertex triangles[t][k]).
struct DisjointSets {
    std::vector<std::uint32_t> parent;
    explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];  // path halving
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

bool is_zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    return glm::length(glm::cross(b - a, c - a)) <= 1e-12 * longest;
}

// One use of an undirected edge (lo, hi): half-edge `corner` runs from
// triangles[t][k] to triangles[t][k+1] with corner = 3t + k.
struct EdgeUse {
    std::uint32_t hi;
    std::uint32_t corner;
};

// Describes a list of indices: "3 triangles (first: 4, 9, 11)".
template <class T, class Show>
std::string describe(const std::vector<T>& items, const char* what, Show show) {
    std::string s = std::to_string(items.size()) + " " + what + " (first: ";
    for (std::size_t i = 0; i < std::min<std::size_t>(items.size(), 3); ++i) s += (i ? ", " : "") + show(items[i]);
    return s + ")";
}

std::string show_index(std::uint32_t i) { return std::to_string(i); }
std::string show_edge(const ValidationReport::Edge& e) { return std::to_string(e.from) + "-" + std::to_string(e.to); }

// Flags out-of-range indices, non-finite coordinates and degenerate triangles;
// returns which triangles can take part in the topology.
std::vector<std::uint8_t> check_arrays(const TriangleMesh& mesh, ValidationReport& r) {
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3& p = mesh.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) r.non_finite_vertices.push_back(v);
    }
    std::vector<std::uint8_t> usable(mesh.triangle_count(), 0);
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        if (tri[0] >= mesh.vertex_count() || tri[1] >= mesh.vertex_count() || tri[2] >= mesh.vertex_count()) {
            r.out_of_range_triangles.push_back(t);
        } else if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
            r.degenerate_triangles.push_back(t);
        } else {
            usable[t] = 1;
            if (is_zero_area(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]))
                r.degenerate_triangles.push_back(t);
        }
    }
    return usable;
}

void find_duplicates(const TriangleMesh& mesh, const std::vector<std::uint8_t>& usable, ValidationReport& r) {
    std::vector<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>> keys;
    keys.reserve(mesh.triangle_count());
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        if (!usable[t]) continue;
        std::array<std::uint32_t, 3> k{mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]};
        std::sort(k.begin(), k.end());
        keys.push_back({k, t});
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first) r.duplicate_triangles.push_back(keys[i].second);
    std::sort(r.duplicate_triangles.begin(), r.duplicate_triangles.end());
}

}  // namespace

std::vector<std::vector<std::uint32_t>> chain_boundary_loops(const std::vector<ValidationReport::Edge>& edges,
                                                             std::size_t vertex_count) {
    // Outgoing edges per vertex (CSR), and a cursor to the next unused one.
    std::vector<std::uint32_t> start(vertex_count + 1, 0);
    for (const auto& e : edges) ++start[e.from + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> out(edges.size());
    std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < edges.size(); ++i) out[cursor[edges[i].from]++] = i;
    std::copy(start.begin(), start.end() - 1, cursor.begin());

    std::vector<std::uint8_t> used(edges.size(), 0);
    auto take_from = [&](std::uint32_t v) -> std::uint32_t {
        while (cursor[v] < start[v + 1] && used[out[cursor[v]]]) ++cursor[v];
        return cursor[v] < start[v + 1] ? out[cursor[v]] : kNone;
    };
    std::vector<std::vector<std::uint32_t>> loops;
    for (std::uint32_t first = 0; first < edges.size(); ++first) {
        if (used[first]) continue;
        std::vector<std::uint32_t> loop;
        std::uint32_t e = first;
        while (e != kNone) {
            used[e] = 1;
            loop.push_back(edges[e].from);
            if (edges[e].to == edges[first].from) break;
            e = take_from(edges[e].to);
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

ValidationReport validate_mesh(const TriangleMesh& mesh) {
    ValidationReport r;
    r.vertex_count = mesh.vertex_count();
    r.triangle_count = mesh.triangle_count();
    const auto n = static_cast<std::uint32_t>(mesh.vertex_count());
    const std::vector<std::uint8_t> usable = check_arrays(mesh, r);
    find_duplicates(mesh, usable, r);

    // Bucket every half-edge of a usable triangle by its smaller vertex (CSR), then
    // sort each bucket by the larger one: equal runs are the uses of one edge.
    std::vector<std::uint32_t> start(n + 1, 0);
    auto tri_at = [&](std::uint32_t corner) { return mesh.triangles[corner / 3][corner % 3]; };
    auto next_corner = [](std::uint32_t corner) { return corner - corner % 3 + (corner % 3 + 1) % 3; };
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t)
        if (usable[t])
            for (int k = 0; k < 3; ++k) ++start[std::min(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]) + 1];
    for (std::uint32_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<EdgeUse> uses(start[n]);
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            if (!usable[t]) continue;
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
                uses[fill[std::min(a, b)]++] = {std::max(a, b), 3 * t + k};
            }
        }
    }

    // Classify each edge; join the fans of its ends across edges with two triangles.
    DisjointSets fans(3 * mesh.triangle_count());
    std::vector<std::uint32_t> valence(n, 0);
    std::vector<ValidationReport::Edge> crowded, flipped;  // > 2 triangles; two of one direction
    for (std::uint32_t lo = 0; lo < n; ++lo) {
        const auto first = uses.begin() + start[lo], last = uses.begin() + start[lo + 1];
        std::sort(first, last, [](const EdgeUse& a, const EdgeUse& b) { return a.hi < b.hi || (a.hi == b.hi && a.corner < b.corner); });
        for (auto run = first; run != last;) {
            auto end = run;
            while (end != last && end->hi == run->hi) ++end;
            const std::uint32_t hi = run->hi;
            ++valence[lo];
            ++valence[hi];
            const auto count = end - run;
            if (count == 1) {
                r.boundary_edges.push_back({tri_at(run->corner), tri_at(next_corner(run->corner))});
            } else if (count == 2) {
                const std::uint32_t c0 = run[0].corner, c1 = run[1].corner;
                if (tri_at(c0) == tri_at(c1)) {
                    flipped.push_back({lo, hi});
                    r.non_manifold_edges.push_back({lo, hi});
                }
                // The corner of vertex x in the triangle of half-edge c.
                auto corner_of = [&](std::uint32_t c, std::uint32_t x) { return tri_at(c) == x ? c : next_corner(c); };
                fans.unite(corner_of(c0, lo), corner_of(c1, lo));
                fans.unite(corner_of(c0, hi), corner_of(c1, hi));
            } else {
                crowded.push_back({lo, hi});
                r.non_manifold_edges.push_back({lo, hi});
            }
            run = end;
        }
    }

    // A vertex whose corners fall into more than one set has more than one fan.
    std::vector<std::uint32_t> fan_of(n, kNone);
    std::vector<std::uint8_t> pinched(n, 0), referenced(n, 0);
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][k];
            if (v < n) referenced[v] = 1;
            if (!usable[t]) continue;
            const std::uint32_t root = fans.find(3 * t + k);
            if (fan_of[v] == kNone) fan_of[v] = root;
            else if (fan_of[v] != root) pinched[v] = 1;
        }
    }
    for (std::uint32_t v = 0; v < n; ++v) {
        if (pinched[v]) r.non_manifold_vertices.push_back(v);
        if (!referenced[v]) r.isolated_vertices.push_back(v);
    }

    r.boundary_loops = chain_boundary_loops(r.boundary_edges, n);

    // Valence statistics.
    if (n > 0) {
        r.valence_min = *std::min_element(valence.begin(), valence.end());
        r.valence_max = *std::max_element(valence.begin(), valence.end());
        r.valence_histogram.assign(r.valence_max + 1, 0);
        for (std::uint32_t k : valence) ++r.valence_histogram[k];
    }

    // Verdicts and their reasons.
    const bool any_usable = std::find(usable.begin(), usable.end(), 1) != usable.end();
    r.is_closed = any_usable && r.boundary_edges.empty();
    std::size_t repeated = r.degenerate_triangles.size();
    for (std::uint32_t t : r.degenerate_triangles) repeated -= usable[t];
    if (!crowded.empty()) r.reasons.push_back(describe(crowded, "edges are shared by more than two triangles", show_edge));
    if (!flipped.empty())
        r.reasons.push_back(describe(flipped, "edges join two triangles of opposite orientation", show_edge));
    if (!r.non_manifold_vertices.empty())
        r.reasons.push_back(describe(r.non_manifold_vertices, "vertices join more than one fan of triangles", show_index));
    if (!r.duplicate_triangles.empty())
        r.reasons.push_back(describe(r.duplicate_triangles, "triangles repeat an earlier triangle", show_index));
    if (!r.out_of_range_triangles.empty())
        r.reasons.push_back(describe(r.out_of_range_triangles, "triangles have a vertex index out of range", show_index));
    if (repeated) r.reasons.push_back(std::to_string(repeated) + " triangles repeat a vertex index");
    if (!any_usable) r.reasons.push_back("no usable triangle");
    r.is_manifold = r.reasons.empty();

    if (repeated != r.degenerate_triangles.size())
        r.warnings.push_back(std::to_string(r.degenerate_triangles.size() - repeated) + " triangles have zero area");
    if (!r.isolated_vertices.empty())
        r.warnings.push_back(describe(r.isolated_vertices, "vertices are in no triangle", show_index));
    if (!r.non_finite_vertices.empty())
        r.warnings.push_back(describe(r.non_finite_vertices, "vertices have a non-finite coordinate", show_index));
    return r;
}

}  // namespace vfsd
