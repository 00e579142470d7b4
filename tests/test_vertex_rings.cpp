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

TEST_CASE("two closed fans meeting at one vertex keep only real wedges", "[mesh]") {
    // Two tetrahedra sharing vertex 0: two closed cycles around it.
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
    const VertexRings rings = build_vertex_rings(m);
    CHECK_FALSE(rings.is_closed(0));
    std::size_t wedges = 0;
    for (std::uint32_t i = rings.begin(0); i < rings.end(0); ++i) {
        if (!rings.wedge[i]) continue;
        ++wedges;
        // Every claimed wedge (0, a, b) is a triangle of the mesh, in its orientation.
        const std::uint32_t a = rings.neighbours[i], b = rings.neighbours[rings.next(0, i)];
        bool found = false;
        for (const Triangle& t : m.triangles)
            for (int k = 0; k < 3; ++k) found = found || (t[k] == 0 && t[(k + 1) % 3] == a && t[(k + 2) % 3] == b);
        CHECK(found);
    }
    CHECK(wedges == 6);
}
