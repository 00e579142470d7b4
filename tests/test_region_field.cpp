// The region field s (sec. 3) from eq. (15) (geodesic levels) and eq. (16) (painted
// inner and outer regions).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "base/error.h"
#include "mesh/vertex_rings.h"
#include "region/region_field.h"
#include "test_region_meshes.h"

using namespace vfsd;
using vfsd::test::grid_mesh;
using vfsd::test::icosphere;

namespace {

std::vector<std::uint8_t> mask_where(const TriangleMesh& m, bool (*pred)(const Vec3&)) {
    std::vector<std::uint8_t> mask(m.positions.size(), 0);
    for (std::size_t v = 0; v < mask.size(); ++v) mask[v] = pred(m.positions[v]) ? 1 : 0;
    return mask;
}

// Appends a copy of `other` moved by `offset` as a separate component.
void append(TriangleMesh& m, const TriangleMesh& other, Vec3 offset) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const Vec3& p : other.positions) m.positions.push_back(p + offset);
    for (const Triangle& t : other.triangles) m.triangles.push_back(t + Triangle(base));
}

}  // namespace

TEST_CASE("geodesic level field: s = 0 at the seed, 1 beyond g_max, linear between", "[region][field]") {
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    GeodesicOptions o;
    o.method = GeodesicMethod::fast_marching;
    const double g_min = 0.3, g_max = 1.2;
    const auto s = geodesic_level_field(m.positions, rings, 5, g_min, g_max, o);
    const auto g = geodesic_distance(m.positions, rings, {5}, o);
    CHECK(s[5] == 0.0);  // the clicked vertex moves fully (sec. 3, fig. 7)
    for (std::size_t v = 0; v < s.size(); ++v) {
        REQUIRE(s[v] >= 0.0);
        REQUIRE(s[v] <= 1.0);
        if (g[v] <= g_min) CHECK(s[v] == 0.0);
        if (g[v] >= g_max) CHECK(s[v] == 1.0);
        if (g[v] > g_min && g[v] < g_max) CHECK(s[v] == Approx((g[v] - g_min) / (g_max - g_min)));
    }
    CHECK(std::count(s.begin(), s.end(), 0.0) > 1);
    CHECK(std::count(s.begin(), s.end(), 1.0) > 1);
}

TEST_CASE("geodesic level field: stopping the march past g_max leaves every s bit for bit", "[region][field]") {
    // geodesic_level_field marches only a few edges past g_max; s must be what a
    // march over the whole mesh gives, on irregular meshes with and without a
    // boundary, for any thresholds, smoothing passes and method.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    TriangleMesh grid = grid_mesh(24, 2.0), sphere = icosphere(3, 1.0);
    for (TriangleMesh* m : {&grid, &sphere})
        for (Vec3& p : m->positions) p += 0.01 * Vec3(unit(random), unit(random), unit(random));
    for (const TriangleMesh* m : {&grid, &sphere}) {
        const VertexRings rings = build_vertex_rings(*m);
        for (int trial = 0; trial < 12; ++trial) {
            GeodesicOptions o;
            o.method = trial % 3 == 0 ? GeodesicMethod::dijkstra : GeodesicMethod::fast_marching;
            o.smoothing_iterations = trial % 4;
            const auto seed = static_cast<std::uint32_t>(unit(random) * double(m->positions.size() - 1));
            const double g_min = 0.3 * unit(random), g_max = g_min + 0.05 + 0.8 * unit(random);
            const std::vector<double> whole =
                level_field_from_distance(geodesic_distance(m->positions, rings, {seed}, o), g_min, g_max);
            const std::vector<double> s = geodesic_level_field(m->positions, rings, seed, g_min, g_max, o);
            REQUIRE(s == whole);
            CHECK(std::count(s.begin(), s.end(), 1.0) > 0);  // the thresholds leave some vertices outer
        }
    }
}

TEST_CASE("geodesic level field rejects invalid thresholds and seeds", "[region][field]") {
    const TriangleMesh m = grid_mesh(4, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 0, 0.5, 0.5), InputError);
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 0, 0.6, 0.5), InputError);
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 0, -0.1, 0.5), InputError);
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 0, nan, 0.5), InputError);
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 0, 0.0, std::numeric_limits<double>::infinity()), InputError);
    CHECK_THROWS_AS(geodesic_level_field(m.positions, rings, 25, 0.1, 0.5), InputError);
    CHECK_THROWS_WITH(geodesic_level_field(m.positions, rings, 0, 0.6, 0.5), Catch::Contains("g_min < g_max"));
}

TEST_CASE("painted regions: s is 0 on inner, 1 on outer, and changes slowly across edges", "[region][field]") {
    const TriangleMesh m = icosphere(4, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const auto inner = mask_where(m, [](const Vec3& p) { return p.z > 0.6; });
    const auto outer = mask_where(m, [](const Vec3& p) { return p.z < -0.3; });
    for (GeodesicMethod method : {GeodesicMethod::dijkstra, GeodesicMethod::fast_marching}) {
        GeodesicOptions o;
        o.method = method;
        const RegionField f = painted_region_field(m.positions, rings, inner, outer, o);
        CHECK(f.warnings.empty());
        // D: the approximate distance between the regions. With |grad g| ~ 1, eq. (16)
        // gives |grad s| <= 1 / (g_i + g_o) <= 1 / D, so an edge changes s by at most
        // about its length / D; allow 25% for the distance approximation.
        const auto gi = geodesic_distance_to_region(m.positions, rings, inner, o);
        double d_between = std::numeric_limits<double>::infinity();
        for (std::size_t v = 0; v < gi.size(); ++v)
            if (outer[v]) d_between = std::min(d_between, gi[v]);
        for (std::uint32_t v = 0; v < f.s.size(); ++v) {
            if (inner[v]) REQUIRE(f.s[v] == 0.0);
            if (outer[v]) REQUIRE(f.s[v] == 1.0);
            if (!inner[v] && !outer[v]) REQUIRE((f.s[v] > 0.0 && f.s[v] < 1.0));
            for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
                const std::uint32_t w = rings.neighbours[i];
                REQUIRE(std::abs(f.s[v] - f.s[w]) <= 1.25 * glm::length(m.positions[v] - m.positions[w]) / d_between);
            }
        }
    }
}

TEST_CASE("painted regions: components without both regions get defined values and warnings", "[region][field]") {
    TriangleMesh m = icosphere(2, 1.0);
    const auto n = m.positions.size();
    append(m, icosphere(2, 1.0), Vec3(5.0, 0.0, 0.0));   // neither region
    append(m, icosphere(2, 1.0), Vec3(10.0, 0.0, 0.0));  // inner only
    const VertexRings rings = build_vertex_rings(m);
    std::vector<std::uint8_t> inner(m.positions.size(), 0), outer(m.positions.size(), 0);
    for (std::size_t v = 0; v < n; ++v) {
        inner[v] = m.positions[v].z > 0.5;
        outer[v] = m.positions[v].z < -0.5;
    }
    for (std::size_t v = 2 * n; v < 3 * n; ++v) inner[v] = m.positions[v].z > 0.5;
    const RegionField f = painted_region_field(m.positions, rings, inner, outer);
    CHECK(f.warnings.size() == 2);
    for (std::size_t v = n; v < 2 * n; ++v) CHECK(f.s[v] == 1.0);
    for (std::size_t v = 2 * n; v < 3 * n; ++v) CHECK(f.s[v] == 0.0);
}

TEST_CASE("painted regions: empty inner warns, overlap and size mismatch throw", "[region][field]") {
    const TriangleMesh m = grid_mesh(6, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const std::vector<std::uint8_t> none(m.positions.size(), 0);
    std::vector<std::uint8_t> some(m.positions.size(), 0);
    some[3] = 1;
    const RegionField f = painted_region_field(m.positions, rings, none, some);
    CHECK(f.warnings.size() == 1);
    CHECK(std::all_of(f.s.begin(), f.s.end(), [](double x) { return x == 1.0; }));
    CHECK_THROWS_AS(painted_region_field(m.positions, rings, some, some), InputError);
    CHECK_THROWS_WITH(painted_region_field(m.positions, rings, some, some), Catch::Contains("both the inner and the outer"));
    CHECK_THROWS_AS(painted_region_field(m.positions, rings, std::vector<std::uint8_t>(3, 0), some), InputError);
}

TEST_CASE("recomputing with deformed positions follows the new shape", "[region][field]") {
    TriangleMesh m = grid_mesh(20, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const auto inner = mask_where(m, [](const Vec3& p) { return p.x < 0.2; });
    const auto outer = mask_where(m, [](const Vec3& p) { return p.x > 0.8; });
    const RegionField before = painted_region_field(m.positions, rings, inner, outer);
    // Stretch the left half of the sheet: the intermediate vertices there now lie
    // relatively farther from the inner region, so s grows in the stretched part.
    for (Vec3& p : m.positions) p.x = p.x < 0.5 ? 3.0 * p.x : p.x + 1.0;
    const RegionField after = painted_region_field(m.positions, rings, inner, outer);
    const std::uint32_t probe = 10 * 21 + 8;  // (0.4, 0.5) before stretching
    CHECK(after.s[probe] > before.s[probe] + 0.1);
}

TEST_CASE("painted regions that touch: a warning says where, a band opens the transition", "[region][field]") {
    // A 40 x 40 sheet on [0, 1]²: inner x < 0.5, outer x ≥ 0.5, so they touch.
    const TriangleMesh m = grid_mesh(40, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const auto inner = mask_where(m, [](const Vec3& p) { return p.x < 0.5 - 1e-9; });
    const auto outer = mask_where(m, [](const Vec3& p) { return p.x >= 0.5 - 1e-9; });
    const RegionField touching = painted_region_field(m.positions, rings, inner, outer);
    CHECK(blend_ring_width(touching.s, rings) < kThinBlendRings);
    REQUIRE(touching.warnings.size() == 1);
    CHECK_THAT(touching.warnings[0], Catch::Contains("ring wide near (0.5,") && Catch::Contains("region.band"));

    const double band = 0.2;  // 8 edges of 0.025
    const RegionField banded = painted_region_field(m.positions, rings, inner, outer, {}, band);
    CHECK(banded.warnings.empty());
    CHECK(blend_ring_width(banded.s, rings) >= kThinBlendRings);
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const double x = m.positions[v].x;
        INFO("x = " << x);
        if (inner[v]) CHECK(banded.s[v] == 0.0);
        else if (x >= 0.5 + band + 0.03) CHECK(banded.s[v] == 1.0);  // beyond the band (geodesic ≈ Euclidean here)
        else if (x <= 0.5 + band - 0.03) CHECK((banded.s[v] > 0.0 && banded.s[v] < 1.0));
    }
    // s rises across the band along a row.
    const std::size_t row = 20 * 41;
    for (std::size_t i = 20; i < 28; ++i) CHECK(banded.s[row + i + 1] > banded.s[row + i]);
    CHECK_THROWS_WITH(painted_region_field(m.positions, rings, inner, outer, {}, -1.0), Catch::Contains("band"));
}

TEST_CASE("an inner region painted alone blends over the band; without one its whole piece moves", "[region][field]") {
    const TriangleMesh m = grid_mesh(40, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    for (const double corner : {0.2, 0.35}) {  // inner: the square [0, corner)²
        std::vector<std::uint8_t> inner(m.positions.size(), 0);
        for (std::size_t v = 0; v < inner.size(); ++v)
            inner[v] = m.positions[v].x < corner - 1e-9 && m.positions[v].y < corner - 1e-9;
        const std::vector<std::uint8_t> none(m.positions.size(), 0);
        const RegionField hard = painted_region_field(m.positions, rings, inner, none);
        for (std::size_t v = 0; v < m.positions.size(); ++v) CHECK(hard.s[v] == 0.0);  // no outer: all inner
        for (const double band : {0.1, 0.25}) {
            INFO("corner " << corner << ", band " << band);
            const RegionField alone = painted_region_field(m.positions, rings, inner, none, {}, band);
            CHECK(blend_ring_width(alone.s, rings) >= kThinBlendRings);
            CHECK(alone.warnings.empty());
            for (std::size_t v = 0; v < m.positions.size(); ++v) {
                // Distance to the inner square (geodesic ≈ Euclidean on the flat sheet).
                const Vec3& p = m.positions[v];
                const double d = std::hypot(std::max(0.0, p.x - corner), std::max(0.0, p.y - corner));
                if (inner[v]) CHECK(alone.s[v] == 0.0);
                else if (d >= band) CHECK(alone.s[v] == 1.0);  // geodesic ≥ Euclidean
                else if (d <= 0.65 * band) CHECK((alone.s[v] > 0.0 && alone.s[v] < 1.0));  // the grid's geodesic runs up to √2 long
            }
        }
    }
}
