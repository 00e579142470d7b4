#include "mesh/subdivision.h"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace vfsd {
namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

// Marks the edges of `triangles`, then the third edge of every triangle with two
// marked, until none has two.
std::unordered_set<std::uint64_t> edges_to_split(const TriangleMesh& mesh,
                                                 const std::vector<std::uint32_t>& triangles) {
    std::unordered_set<std::uint64_t> split;
    for (std::uint32_t t : triangles)
        for (int k = 0; k < 3; ++k) split.insert(edge_key(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]));
    for (bool changed = true; changed;) {
        changed = false;
        for (const Triangle& t : mesh.triangles) {
            int marked = 0;
            for (int k = 0; k < 3; ++k) marked += split.count(edge_key(t[k], t[(k + 1) % 3])) > 0;
            if (marked != 2) continue;
            for (int k = 0; k < 3; ++k) split.insert(edge_key(t[k], t[(k + 1) % 3]));
            changed = true;
        }
    }
    return split;
}

// Splits the edges `order` lists, numbering their new vertices in that order.
RefinedMesh split_edges(const TriangleMesh& mesh, const std::vector<std::uint64_t>& order, const EdgePoint& place) {
    RefinedMesh refined;
    TriangleMesh& finer = refined.mesh;
    finer.positions = mesh.positions;
    const bool scalar = mesh.has_scalar();
    if (scalar) finer.scalar = mesh.scalar;
    std::unordered_map<std::uint64_t, std::uint32_t> edge_vertex;
    edge_vertex.reserve(order.size());
    for (std::uint64_t key : order) {
        const std::uint32_t a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key);
        edge_vertex.emplace(key, static_cast<std::uint32_t>(finer.positions.size()));
        const Vec3& p = mesh.positions[a];
        const Vec3& q = mesh.positions[b];
        finer.positions.push_back(place ? place(p, q) : 0.5 * (p + q));
        if (scalar) finer.scalar.push_back(0.5 * (mesh.scalar[a] + mesh.scalar[b]));
        refined.parents.push_back({a, b});
    }
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
        const auto it = edge_vertex.find(edge_key(a, b));
        return it == edge_vertex.end() ? ~0u : it->second;
    };
    finer.triangles.reserve(mesh.triangles.size() + 3 * order.size());
    for (const Triangle& t : mesh.triangles) {
        const std::uint32_t m[3] = {midpoint(t[0], t[1]), midpoint(t[1], t[2]), midpoint(t[2], t[0])};
        const int marked = (m[0] != ~0u) + (m[1] != ~0u) + (m[2] != ~0u);
        if (marked == 0) {
            finer.triangles.push_back(t);
        } else if (marked == 1) {  // cut from the midpoint of edge (a, b) to c
            const int k = m[0] != ~0u ? 0 : m[1] != ~0u ? 1 : 2;
            const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
            finer.triangles.push_back({a, m[k], c});
            finer.triangles.push_back({m[k], b, c});
        } else {
            finer.triangles.push_back({t[0], m[0], m[2]});
            finer.triangles.push_back({t[1], m[1], m[0]});
            finer.triangles.push_back({t[2], m[2], m[1]});
            finer.triangles.push_back({m[0], m[1], m[2]});
        }
    }
    return refined;
}

}  // namespace

TriangleMesh subdivide_midpoints(const TriangleMesh& mesh, const EdgePoint& place) {
    // Numbered as the triangles meet their edges (the built-in spheres' numbering).
    std::vector<std::uint64_t> order;
    std::unordered_set<std::uint64_t> seen;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            if (seen.insert(edge_key(t[k], t[(k + 1) % 3])).second) order.push_back(edge_key(t[k], t[(k + 1) % 3]));
    return split_edges(mesh, order, place).mesh;
}

RefinedMesh refine_triangles(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                             const EdgePoint& place) {
    // Numbered by the edge's vertex indices, not by the winding that meets them.
    const std::unordered_set<std::uint64_t> split = edges_to_split(mesh, triangles);
    std::vector<std::uint64_t> order(split.begin(), split.end());
    std::sort(order.begin(), order.end());
    return split_edges(mesh, order, place);
}

}  // namespace vfsd
