// Ordered 1-rings (mesh/vertex_rings.h) checked against the triangles themselves.

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <random>
#include <set>

#include "mesh/validation.h"
#include "mesh/vertex_rings.h"
#include "mesh_fixtures.h"

using namespace vfsd;

namespace {

// A triangle up to rotation (orientation kept): rotated to start at its smallest index.
std::array<std::uint32_t, 3> canonical(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (b < a && b < c) return {b, c, a};
    if (c < a && c < b) return {c, a, b};
    return {a, b, c};
}

// Checks every ring of `mesh` against its triangles: ring sizes are the valences,
// each wedge is a triangle of the mesh with the right orientation, every triangle
// appears once in the ring of each of its corners, and exactly the boundary
// vertices have a (single, trailing) gap.
void check_rings(const TriangleMesh& mesh) {
    const VertexRings rings = build_vertex_rings(mesh);
    REQUIRE(rings.vertex_count() == mesh.vertex_count());
    std::set<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::set<std::uint32_t>> neighbours(mesh.vertex_count());
    std::vector<std::size_t> incident(mesh.vertex_count(), 0);
    for (const Triangle& t : mesh.triangles) {
        triangles.insert(canonical(t[0], t[1], t[2]));
        for (int k = 0; k < 3; ++k) {
            neighbours[t[k]].insert({t[(k + 1) % 3], t[(k + 2) % 3]});
            ++incident[t[k]];
        }
    }
    std::vector<std::uint8_t> on_boundary(mesh.vertex_count(), 0);
    for (const auto& e : validate_mesh(mesh).boundary_edges) on_boundary[e.from] = on_boundary[e.to] = 1;

    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        INFO("vertex " << v);
        REQUIRE(rings.valence(v) == neighbours[v].size());
        std::set<std::uint32_t> ring(rings.neighbours.begin() + rings.begin(v), rings.neighbours.begin() + rings.end(v));
        CHECK(ring == neighbours[v]);
        std::size_t wedges = 0, gaps = 0;
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
            if (!rings.wedge[i]) {
                ++gaps;
                CHECK(i + 1 == rings.end(v));  // an open ring ends at its gap
                continue;
            }
            ++wedges;
            CHECK(triangles.count(canonical(v, rings.neighbours[i], rings.neighbours[rings.next(v, i)])) == 1);
        }
        CHECK(wedges == incident[v]);
        CHECK(gaps == (on_boundary[v] ? 1u : 0u));
        CHECK(rings.is_closed(v) == !on_boundary[v]);
    }
}

}  // namespace

TEST_CASE("ordered rings of valence 3 to 20, open and closed", "[mesh][rings]") {
    TriangleMesh zoo = fixtures::valence_zoo();
    const VertexRings rings = build_vertex_rings(zoo);
    std::set<std::uint32_t> valences;
    for (std::uint32_t v = 0; v < zoo.vertex_count(); ++v) valences.insert(rings.valence(v));
    for (std::uint32_t k = 3; k <= 20; ++k) CHECK(valences.count(k) == 1);
    CHECK(rings.max_valence() == 20);
    check_rings(zoo);

    // The order of the triangles in the input must not matter.
    std::mt19937 random(7);
    std::shuffle(zoo.triangles.begin(), zoo.triangles.end(), random);
    check_rings(zoo);
}

TEST_CASE("ordered rings on a grid, an annulus and a cube", "[mesh][rings]") {
    check_rings(fixtures::grid(4, 3));
    check_rings(fixtures::annulus(9, 2));
    check_rings(fixtures::cube());
    check_rings(make_builtin_mesh("cylinder", 12));
}
