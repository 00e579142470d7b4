// The fold count of sec. 7's evaluation (deform/quality.h): the triangles a
// deformation turned against their edge neighbours, counted whole or in the parts
// an editor keeps between frames.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "deform/quality.h"
#include "mesh/builtin_meshes.h"

using namespace vfsd;

namespace {

bool shares_edge(const Triangle& a, const Triangle& b) {
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += a[i] == b[j];
    return shared == 2;
}

}  // namespace

TEST_CASE("every triangle's neighbours are the triangles sharing one of its edges", "[quality]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 2);
    const TriangleNeighbours n = triangle_neighbours(sphere.triangles);
    REQUIRE(n.offsets.size() == sphere.triangles.size() + 1);
    for (std::uint32_t t = 0; t < sphere.triangles.size(); ++t) {
        REQUIRE(n.offsets[t + 1] - n.offsets[t] == 3);  // closed and manifold: one across each edge
        for (std::uint32_t k = n.offsets[t]; k < n.offsets[t + 1]; ++k) {
            const std::uint32_t u = n.list[k];
            CHECK(shares_edge(sphere.triangles[t], sphere.triangles[u]));
            const auto back = std::find(n.list.begin() + n.offsets[u], n.list.begin() + n.offsets[u + 1], t);
            CHECK(back != n.list.begin() + n.offsets[u + 1]);  // symmetric
        }
    }
    // An edge shared by three triangles (non-manifold) gives each the other two.
    const std::vector<Triangle> fan = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const TriangleNeighbours f = triangle_neighbours(fan);
    for (std::uint32_t t = 0; t < 3; ++t) CHECK(f.offsets[t + 1] - f.offsets[t] == 2);
}

TEST_CASE("the fold count finds the triangles a deformation turned over, and only those", "[quality]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    std::mt19937 random(7);
    std::uniform_int_distribution<std::size_t> pick(0, sphere.positions.size() - 1);
    for (int trial = 0; trial < 20; ++trial) {
        // Slide one vertex past a neighbour, along the surface: triangles of its fan turn over.
        std::vector<Vec3> after = sphere.positions;
        const std::uint32_t v = static_cast<std::uint32_t>(pick(random));
        const Triangle& fan = *std::find_if(sphere.triangles.begin(), sphere.triangles.end(),
                                            [&](const Triangle& t) { return t[0] == v || t[1] == v || t[2] == v; });
        const std::uint32_t a = fan[0] == v ? fan[1] : fan[0];
        after[v] = sphere.positions[a] + 0.7 * (sphere.positions[a] - sphere.positions[v]);
        const std::vector<std::uint32_t> folded = flipped_triangle_list(sphere.positions, after, sphere.triangles);
        REQUIRE(!folded.empty());
        for (const std::uint32_t t : folded) {
            const Triangle& tri = sphere.triangles[t];
            CHECK((tri[0] == v || tri[1] == v || tri[2] == v));
        }
        // In parts, as the editor counts: the same triangles.
        const TriangleNeighbours n = triangle_neighbours(sphere.triangles);
        CHECK(newly_facing_against(facing_against_neighbours(sphere.positions, sphere.triangles, n),
                                   facing_against_neighbours(after, sphere.triangles, n)) == folded);
        // Folded before and after is no new fold.
        CHECK(flipped_triangle_list(after, after, sphere.triangles).empty());
    }
    // A rigid motion and a uniform scale fold nothing.
    std::vector<Vec3> moved = sphere.positions;
    for (Vec3& p : moved) p = 3.0 * Vec3(-p.y, p.x, p.z) + Vec3(10.0, -4.0, 2.0);
    CHECK(flipped_triangle_list(sphere.positions, moved, sphere.triangles).empty());
}
