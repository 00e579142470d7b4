#include "mesh/subdivision.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace vfsd {

TriangleMesh subdivide_midpoints(const TriangleMesh& mesh, const EdgePoint& place) {
    TriangleMesh finer;
    finer.positions = mesh.positions;
    std::unordered_map<std::uint64_t, std::uint32_t> edge_vertex;
    edge_vertex.reserve(mesh.triangles.size() * 2);
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        auto [it, inserted] = edge_vertex.emplace(key, static_cast<std::uint32_t>(finer.positions.size()));
        if (inserted) {
            const Vec3& p = mesh.positions[a];
            const Vec3& q = mesh.positions[b];
            finer.positions.push_back(place ? place(p, q) : 0.5 * (p + q));
        }
        return it->second;
    };
    finer.triangles.reserve(mesh.triangles.size() * 4);
    for (const Triangle& t : mesh.triangles) {
        const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
        finer.triangles.push_back({t[0], ab, ca});
        finer.triangles.push_back({t[1], bc, ab});
        finer.triangles.push_back({t[2], ca, bc});
        finer.triangles.push_back({ab, bc, ca});
    }
    return finer;
}

}  // namespace vfsd
