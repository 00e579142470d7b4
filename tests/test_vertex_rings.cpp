#include <catch2/catch.hpp>

#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"

using namespace vfsd;

namespace {
// A unit cube of 8 vertices and 12 outward-facing triangles.
TriangleMesh unit_cube() {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    const unsigned q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}
}  // namespace

TEST_CASE("unit cube volume is exactly 1 and normals point outward", "[mesh]") {
    TriangleMesh cube = unit_cube();
    CHECK(signed_volume(cube.positions, cube.triangles) == 1.0);
    VertexRings rings = build_vertex_rings(cube);
    std::vector<Vec3> normals;
    vertex_normals(cube.positions, rings, normals);
    for (std::uint32_t v = 0; v < 8; ++v) {
        CHECK(rings.is_closed(v));
        CHECK(glm::dot(normals[v], cube.positions[v] - Vec3(0.5)) > 0.0);
    }
}
