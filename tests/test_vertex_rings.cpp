#include <catch2/catch.hpp>

#include <cstdint>

#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_order.h"
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

TEST_CASE("the breadth-first order is a permutation and reorder_rings renumbers the rings", "[mesh]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(mesh);
    const std::vector<std::uint32_t> order = breadth_first_order(rings);
    REQUIRE(order.size() == mesh.vertex_count());
    std::vector<std::uint32_t> rank(order.size(), UINT32_MAX);
    for (std::size_t i = 0; i < order.size(); ++i) {
        REQUIRE(rank[order[i]] == UINT32_MAX);  // each vertex once
        rank[order[i]] = static_cast<std::uint32_t>(i);
    }
    const VertexRings reordered = reorder_rings(rings, order);
    std::size_t reached_from_earlier = 0;
    for (std::uint32_t i = 0; i < order.size(); ++i) {
        const std::uint32_t v = order[i];
        REQUIRE(reordered.valence(i) == rings.valence(v));
        bool earlier_neighbour = false;
        for (std::uint32_t k = 0; k < rings.valence(v); ++k) {
            CHECK(order[reordered.neighbours[reordered.begin(i) + k]] == rings.neighbours[rings.begin(v) + k]);
            CHECK(reordered.wedge[reordered.begin(i) + k] == rings.wedge[rings.begin(v) + k]);
            earlier_neighbour |= reordered.neighbours[reordered.begin(i) + k] < i;
        }
        reached_from_earlier += earlier_neighbour;
    }
    // Breadth-first on a connected mesh: every vertex but the first is found
    // from one listed before it.
    CHECK(reached_from_earlier == order.size() - 1);
}
