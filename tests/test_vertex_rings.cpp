#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <random>

#include <glm/geometric.hpp>

#include "deform/quality.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_order.h"
#include "mesh/vertex_rings.h"
#include "mesh_fixtures.h"

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

TEST_CASE("the ring sums and the triangle normals in scalars are glm's cross products, to the bit", "[mesh]") {
    // The normal pass, the volume keeper and the fold test compute them in
    // scalars (mesh/geometry.cpp, deform/quality.h); these are the Vec3 forms
    // they replaced, on irregular rings far from the origin and randomly moved;
    // the ring sums unrolled for valences 5 to 7 and looped over the others, open
    // wedges skipped as the loop here skips them.
    const auto same_bits = [](const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    std::mt19937 random(11);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    for (TriangleMesh mesh : {fixtures::valence_zoo(), make_builtin_mesh("sphere", 3)}) {
        for (Vec3& p : mesh.positions)
            p = 1e4 * Vec3(1.0, -2.0, 3.0) + p + Vec3(jitter(random), jitter(random), jitter(random));
        const VertexRings rings = build_vertex_rings(mesh);
        const std::vector<Vec3>& x = mesh.positions;
        std::vector<std::uint32_t> all(x.size());
        for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
        std::vector<Vec3> normals, area_vectors;
        vertex_normals(x, rings, all, normals, area_vectors);
        for (std::uint32_t v = 0; v < x.size(); ++v) {
            Vec3 sum(0.0);
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
                if (rings.wedge[k])
                    sum += glm::cross(x[rings.neighbours[k]] - x[v], x[rings.neighbours[rings.next(v, k)]] - x[v]);
            const double length = glm::length(sum);
            CHECK(same_bits(ring_area_vector(x, rings, v), sum));
            CHECK(same_bits(area_vectors[v], sum));
            CHECK(same_bits(normals[v], length > 0.0 ? sum / length : Vec3(0.0)));
            CHECK(same_bits(vertex_normal(x, rings, v), normals[v]));
        }
        for (const Triangle& t : mesh.triangles) {
            const Vec3 n = glm::cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
            const double length = glm::length(n);
            CHECK(unit_normal(x, t) == (length > 0.0 ? n / length : Vec3(0.0)));
        }
    }
}
