// Drawn boundaries (figs. 2a, 9-11): two loops around a capped cylinder give three bands.
#include <catch2/catch.hpp>

#include <algorithm>

#include "base/error.h"
#include "mesh/vertex_rings.h"
#include "region/boundary_cut.h"
#include "region/region_field.h"
#include "test_region_meshes.h"

using namespace vfsd;

namespace {

constexpr int kAround = 32, kRings = 40;
constexpr double kHeight = 4.0, kDz = kHeight / kRings;

// A loop around the cylinder half-way up band j (between rings j and j + 1): two points
// per quad column, one in each of its triangles, at z = (j + 0.5) * dz. `reverse`
// walks the other way round.
SurfaceLoop band_loop(int j, bool reverse) {
    SurfaceLoop loop;
    for (int k = 0; k < kAround; ++k) {
        const auto f = static_cast<std::uint32_t>(2 * (j * kAround + k));
        loop.push_back({f, Vec3(0.3, 0.2, 0.5)});      // (k,j) (k+1,j) (k+1,j+1)
        loop.push_back({f + 1, Vec3(0.5, 0.3, 0.2)});  // (k,j) (k+1,j+1) (k,j+1)
    }
    if (reverse) std::reverse(loop.begin(), loop.end());
    return loop;
}

struct Cylinder {
    TriangleMesh mesh = vfsd::test::cylinder_mesh(kAround, kRings, 1.0, kHeight, true);
    VertexRings rings = build_vertex_rings(mesh);
    std::uint32_t bottom = static_cast<std::uint32_t>((kRings + 1) * kAround);  // cap centres
    std::uint32_t top = bottom + 1;
};

}  // namespace

TEST_CASE("two drawn loops on a cylinder give exactly the three expected bands", "[region][boundary]") {
    Cylinder c;
    const double z_inner = 10.5 * kDz, z_outer = 25.5 * kDz;
    for (bool reverse : {false, true}) {
        const SurfacePoint seed = surface_point_at_vertex(c.mesh.triangles, c.mesh.positions.size(), c.bottom);
        const LoopRegions r = regions_from_loops(c.mesh.positions, c.mesh.triangles, c.rings, band_loop(10, reverse),
                                                 band_loop(25, !reverse), seed);
        for (std::size_t v = 0; v < c.mesh.positions.size(); ++v) {
            const double z = c.mesh.positions[v].z;
            CHECK(static_cast<bool>(r.inner[v]) == (z < z_inner));
            CHECK(static_cast<bool>(r.outer[v]) == (z > z_outer));
        }
        // The masks feed eq. (16): s grows monotonically up the intermediate band.
        const RegionField f = painted_region_field(c.mesh.positions, c.rings, r.inner, r.outer);
        CHECK(f.warnings.empty());
        for (int j = 11; j < 25; ++j) CHECK(f.s[static_cast<std::size_t>(j * kAround)] < f.s[static_cast<std::size_t>((j + 1) * kAround)]);
    }
    // Seeded from the top, with the loops swapped, the bands swap.
    const SurfacePoint top = surface_point_at_vertex(c.mesh.triangles, c.mesh.positions.size(), c.top);
    const LoopRegions r = regions_from_loops(c.mesh.positions, c.mesh.triangles, c.rings, band_loop(25, false),
                                             band_loop(10, false), top);
    for (std::size_t v = 0; v < c.mesh.positions.size(); ++v) {
        CHECK(static_cast<bool>(r.inner[v]) == (c.mesh.positions[v].z > z_outer));
        CHECK(static_cast<bool>(r.outer[v]) == (c.mesh.positions[v].z < z_inner));
    }
}

TEST_CASE("a seed inside a triangle picks its side; a seed on the loop is refused", "[region][boundary]") {
    Cylinder c;
    const SurfacePoint below{static_cast<std::uint32_t>(2 * (3 * kAround + 5)), Vec3(0.2, 0.3, 0.5)};
    const auto side = seed_side_of_loops(c.mesh.positions, c.mesh.triangles, c.rings, {band_loop(10, false)}, below);
    CHECK(side[c.bottom] == 1);
    CHECK(side[c.top] == 0);
    const SurfacePoint on_loop{static_cast<std::uint32_t>(2 * (10 * kAround + 5)), Vec3(0.2, 0.3, 0.5)};
    CHECK_THROWS_AS(seed_side_of_loops(c.mesh.positions, c.mesh.triangles, c.rings, {band_loop(10, false)}, on_loop),
                    InputError);
}

TEST_CASE("loops that are too short, cut nothing, cannot be traced or cross are refused", "[region][boundary]") {
    Cylinder c;
    const SurfacePoint seed = surface_point_at_vertex(c.mesh.triangles, c.mesh.positions.size(), c.bottom);
    auto side = [&](const SurfaceLoop& loop) {
        return seed_side_of_loops(c.mesh.positions, c.mesh.triangles, c.rings, {loop}, seed);
    };
    SurfaceLoop two = {{100, Vec3(1.0 / 3.0)}, {101, Vec3(1.0 / 3.0)}};
    CHECK_THROWS_WITH(side(two), Catch::Contains("at least 3 points"));
    // Three points in one triangle cross no edge: the seed's side is the whole mesh.
    SurfaceLoop tiny = {{100, Vec3(0.5, 0.25, 0.25)}, {100, Vec3(0.25, 0.5, 0.25)}, {100, Vec3(0.25, 0.25, 0.5)}};
    CHECK_THROWS_WITH(side(tiny), Catch::Contains("do not separate"));
    // A loop around the tube that stops half-way and jumps back cuts nothing.
    SurfaceLoop half = band_loop(10, false);
    half.resize(half.size() / 2);
    CHECK_THROWS_AS(side(half), InputError);
    // A point on another component cannot be reached.
    TriangleMesh two_parts = c.mesh;
    const auto base = static_cast<std::uint32_t>(two_parts.positions.size());
    for (const Vec3& p : c.mesh.positions) two_parts.positions.push_back(p + Vec3(10.0, 0.0, 0.0));
    for (const Triangle& t : c.mesh.triangles) two_parts.triangles.push_back(t + Triangle(base));
    const VertexRings rings2 = build_vertex_rings(two_parts);
    SurfaceLoop split = band_loop(10, false);
    split[7].triangle += static_cast<std::uint32_t>(c.mesh.triangles.size());
    CHECK_THROWS_WITH(seed_side_of_loops(two_parts.positions, two_parts.triangles, rings2, {split}, seed),
                      Catch::Contains("cannot trace"));
    // Swapped loops: the outer loop lies between the seed and the inner loop.
    CHECK_THROWS_WITH(regions_from_loops(c.mesh.positions, c.mesh.triangles, c.rings, band_loop(25, false),
                                         band_loop(10, false), seed),
                      Catch::Contains("swapped"));
}
