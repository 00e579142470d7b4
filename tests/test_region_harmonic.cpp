// The harmonic blend profile (region/harmonic_blend.h): the default s between the
// inner and outer regions of painted and geodesic regions.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "base/error.h"
#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"
#include "region/harmonic_blend.h"
#include "region/region_field.h"
#include "region/selectors.h"
#include "scene/prepared_scene.h"
#include "test_region_meshes.h"

using namespace vfsd;
using vfsd::test::grid_mesh;
using vfsd::test::icosphere;

namespace {

bool in_blend(double s) { return s > 0.0 && s < 1.0; }

// Eq. (16) between a cap of the sphere (inner, z > 0.6) and its lower part (outer, z < -0.2).
std::vector<double> sphere_caps(const TriangleMesh& m, const VertexRings& rings) {
    std::vector<std::uint8_t> inner(m.positions.size()), outer(m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v)
        inner[v] = m.positions[v].z > 0.6, outer[v] = m.positions[v].z < -0.2;
    return painted_region_field(m.positions, rings, inner, outer).s;
}

// The gradient of the piecewise-linear s on triangle t.
Vec3 triangle_gradient(const TriangleMesh& m, const std::vector<double>& s, const Triangle& t) {
    const Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double area2 = glm::dot(n, n);
    return (s[t[0]] * glm::cross(n, c - b) + s[t[1]] * glm::cross(n, a - c) + s[t[2]] * glm::cross(n, b - a)) / area2;
}

// The largest jump of ∇s between two triangles that share an edge, both with all
// corners in the middle of the blend region (0.2 < s < 0.8) and beyond `radius`
// of `away_from` (where a small region makes any s curve strongly), relative to the mean |∇s| there: a kink (two
// slopes meeting at an angle) shows as a jump of order one.
double largest_kink(const TriangleMesh& m, const std::vector<double>& s, const Vec3& away_from, double radius) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> first;
    double jump = 0.0, mean = 0.0;
    int count = 0;
    for (const Triangle& t : m.triangles) {
        const auto middle = [&](std::uint32_t v) {
            return s[v] > 0.2 && s[v] < 0.8 && glm::length(m.positions[v] - away_from) > radius;
        };
        if (!middle(t[0]) || !middle(t[1]) || !middle(t[2])) continue;
        const Vec3 g = triangle_gradient(m, s, t);
        mean += glm::length(g), ++count;
        for (int k = 0; k < 3; ++k) {
            const auto edge = std::minmax(t[k], t[(k + 1) % 3]);
            const auto found = first.find(edge);
            if (found == first.end()) first.emplace(edge, g);
            else jump = std::max(jump, glm::length(found->second - g));
        }
    }
    return count > 0 ? jump / (mean / count) : 0.0;
}

}  // namespace

TEST_CASE("harmonic blend on a flat grid of right triangles is the linear ramp", "[region][harmonic]") {
    // Right isosceles triangles: the cotangent weights are 0 and 1, none clamped,
    // and the discrete Laplacian of a linear function vanishes exactly.
    const TriangleMesh m = grid_mesh(20, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> any(0.05, 0.95);
    std::vector<double> s(m.positions.size());
    for (std::size_t v = 0; v < s.size(); ++v) {
        const double x = m.positions[v].x;
        s[v] = x <= 0.2 + 1e-9 ? 0.0 : x >= 0.8 - 1e-9 ? 1.0 : any(random);  // a noisy start
    }
    const std::vector<double> h = harmonic_blend(m.positions, rings, s);
    for (std::size_t v = 0; v < s.size(); ++v) {
        INFO("vertex " << v << " at x = " << m.positions[v].x);
        const double ramp = std::clamp((m.positions[v].x - 0.2) / 0.6, 0.0, 1.0);
        CHECK(std::abs(h[v] - ramp) < 1e-8);
        if (!in_blend(s[v])) CHECK(h[v] == s[v]);  // the fixed values bit for bit
    }
}

TEST_CASE("harmonic blend keeps the regions, stays in (0, 1) and lies between its neighbours", "[region][harmonic]") {
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const std::vector<double> s = sphere_caps(m, rings);
    const std::vector<double> h = harmonic_blend(m.positions, rings, s);
    int blend = 0;
    for (std::uint32_t v = 0; v < s.size(); ++v) {
        if (!in_blend(s[v])) {
            CHECK(h[v] == s[v]);
            continue;
        }
        ++blend;
        REQUIRE(in_blend(h[v]));
        // A weighted mean of its neighbours with positive weights (the discrete
        // maximum principle): never above the largest or below the smallest.
        double lo = 1.0, hi = 0.0;
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
            lo = std::min(lo, h[rings.neighbours[k]]), hi = std::max(hi, h[rings.neighbours[k]]);
        CHECK(h[v] >= lo - 1e-9);
        CHECK(h[v] <= hi + 1e-9);
    }
    CHECK(blend > 100);
}

TEST_CASE("harmonic blend is the same on the mesh turned, moved far away and scaled", "[region][harmonic]") {
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const std::vector<double> s = sphere_caps(m, rings);
    const std::vector<double> h = harmonic_blend(m.positions, rings, s);
    const glm::dmat3 turn(glm::rotate(glm::dmat4(1.0), 2.1, glm::normalize(Vec3(0.3, -0.8, 0.5))));
    for (const double scale : {1e-3, 1.0, 1e4}) {
        std::vector<Vec3> placed;
        for (const Vec3& p : m.positions) placed.push_back(scale * (turn * p) + Vec3(100.0 * scale, -70.0 * scale, 3.0));
        const std::vector<double> again = harmonic_blend(placed, rings, s);
        double worst = 0.0;
        for (std::size_t v = 0; v < s.size(); ++v) worst = std::max(worst, std::abs(again[v] - h[v]));
        INFO("scale " << scale);
        CHECK(worst < 1e-8);
    }
}

TEST_CASE("harmonic blend's direct factorisation, where the iteration stops unconverged, solves the same system",
          "[region][harmonic]") {
    // The iteration stopped after one or a few of its steps leaves the rest to
    // SimplicialLDLT: the result is the converged iteration's, to its tolerance.
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const std::vector<double> s = sphere_caps(m, rings);
    const std::vector<double> iterated = harmonic_blend(m.positions, rings, s);
    for (const long stop_after : {1L, 5L}) {
        HarmonicBlend direct(m.positions, rings, s, stop_after);
        int calls = 0;
        while (!direct.iterate(0.0)) ++calls;
        CHECK(calls == stop_after - 1);  // one iteration a call, the last one factorises
        const std::vector<double>& solved = direct.s();
        double worst = 0.0, moved = 0.0;
        for (std::size_t v = 0; v < s.size(); ++v) {
            worst = std::max(worst, std::abs(solved[v] - iterated[v]));
            moved = std::max(moved, std::abs(solved[v] - s[v]));
        }
        CAPTURE(stop_after);
        CHECK(worst < 1e-9);
        CHECK(moved > 1e-3);  // the start was not already the solution
    }
}

TEST_CASE("harmonic blend's iterations do not grow with the mesh's resolution", "[region][harmonic]") {
    // The square with a disc inside (s = 0) and its border outside (s = 1), the
    // start eq. (16) gives, at 20 to 160 vertices across. Conjugate gradients
    // with Jacobi alone take about as many iterations as the blend region is
    // rings across (335 on the raised claw); the coarse correction on aggregates
    // takes out the smooth part of the error at every resolution alike.
    std::vector<long> iterations;
    for (const int n : {20, 40, 80, 160}) {
        const TriangleMesh m = grid_mesh(n, 1.0);
        const VertexRings rings = build_vertex_rings(m);
        std::vector<std::uint8_t> inner(m.positions.size()), outer(m.positions.size());
        for (std::size_t v = 0; v < m.positions.size(); ++v) {
            const Vec3& p = m.positions[v];
            inner[v] = glm::length(p - Vec3(0.4, 0.5, 0.0)) < 0.15;
            outer[v] = p.x < 0.05 || p.x > 0.95 || p.y < 0.05 || p.y > 0.95;
        }
        const std::vector<double> s = painted_region_field(m.positions, rings, inner, outer).s;
        HarmonicBlend blend(m.positions, rings, s);
        blend.iterate(std::numeric_limits<double>::infinity());
        iterations.push_back(blend.iterations());
        // Converged: each blend vertex the weighted mean of its ring (its cotangent
        // weights are those of the grid's right triangles: 1 on the legs, 0 on the diagonal).
        const std::vector<double>& h = blend.s();
        double worst = 0.0;
        for (std::uint32_t v = 0; v < h.size(); ++v) {
            if (!in_blend(s[v])) continue;
            double sum = 0.0, count = 0.0;
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                const Vec3 edge = m.positions[rings.neighbours[k]] - m.positions[v];
                if (std::abs(edge.x) > 1e-12 && std::abs(edge.y) > 1e-12) continue;  // a diagonal
                sum += h[rings.neighbours[k]], count += 1.0;
            }
            worst = std::max(worst, std::abs(h[v] - sum / count));
        }
        CAPTURE(n, iterations.back());
        CHECK(worst < 1e-9);
    }
    CAPTURE(iterations[0], iterations[1], iterations[2], iterations[3]);
    CHECK(iterations[3] < 120);
    CHECK(iterations[3] < 2 * iterations[0]);  // Jacobi alone: 73 to 510, growing as the region is rings across
}

TEST_CASE("harmonic blend has no kink where eq. (16)'s geodesic distances meet", "[region][harmonic]") {
    // A square with the inner region a disc and the outer region a U round it
    // (the right edge, the top and the bottom): the distance to the outer region
    // is the least of three and kinks where two are equal, along the lines from
    // the U's corners inwards, which cross the middle of the blend region.
    const TriangleMesh m = grid_mesh(60, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    std::vector<std::uint8_t> inner(m.positions.size()), outer(m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3& p = m.positions[v];
        inner[v] = glm::length(p - Vec3(0.3, 0.5, 0.0)) < 0.1;  // the disc
        outer[v] = p.x > 0.8 || p.y < 0.1 || p.y > 0.9;
    }
    const std::vector<double> s = painted_region_field(m.positions, rings, inner, outer).s;
    const std::vector<double> h = harmonic_blend(m.positions, rings, s);
    const Vec3 disc(0.3, 0.5, 0.0);
    const double geodesic_kink = largest_kink(m, s, disc, 0.25), harmonic_kink = largest_kink(m, h, disc, 0.25);
    INFO("largest kink: eq. (16) " << geodesic_kink << ", harmonic " << harmonic_kink);
    CHECK(harmonic_kink < 0.4 * geodesic_kink);
}

TEST_CASE("a scene's region profile: harmonic by default, eqs. (15) and (16) as printed on request",
          "[region][harmonic][scene]") {
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    RegionSpec spec;
    spec.kind = RegionSpec::Kind::geodesic;
    spec.seed = Vec3(0.0, 0.0, 1.0);
    spec.g_min = 0.4, spec.g_max = 1.6;
    std::vector<std::string> warnings;
    const std::vector<double> harmonic = build_region(spec, m.positions, rings, warnings).s;
    spec.profile = RegionSpec::Profile::geodesic;
    const std::vector<double> printed = build_region(spec, m.positions, rings, warnings).s;
    CHECK(printed == geodesic_level_field(m.positions, rings, nearest_vertex(m.positions, spec.seed), 0.4, 1.6));
    CHECK(harmonic == harmonic_blend(m.positions, rings, printed));
    CHECK(harmonic != printed);
    for (std::size_t v = 0; v < printed.size(); ++v) CHECK(in_blend(harmonic[v]) == in_blend(printed[v]));

    Scene scene;
    scene.mesh = "builtin:sphere";
    scene.region = spec;
    scene.motion.curve.bezier = {Vec3(0, 0, 1), Vec3(0, 0, 1.2), Vec3(0, 0, 1.4), Vec3(0, 0, 1.6)};
    CHECK(parse_scene(scene_to_json(scene), ".").region.profile == RegionSpec::Profile::geodesic);
    nlohmann::json j = scene_to_json(scene);
    j["region"].erase("profile");
    CHECK(parse_scene(j, ".").region.profile == RegionSpec::Profile::harmonic);
    j["region"]["profile"] = "smooth";
    CHECK_THROWS_WITH(parse_scene(j, "scene.json"), Catch::Contains("region.profile"));
}

// Generated regions: geodesic ones around a random seed with random thresholds,
// and painted ones between the far parts of the mesh along a random direction,
// with and without a band, on the sphere and the grid.
TEST_CASE("a region built in parts, one iteration a part, is the region built at once, bit for bit",
          "[region][harmonic][scene]") {
    std::mt19937 random(17);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
    const std::vector<TriangleMesh> meshes = {icosphere(3, 1.0), grid_mesh(30, 2.0)};
    for (int trial = 0; trial < 12; ++trial) {
        const TriangleMesh& m = meshes[trial % 2];
        const VertexRings rings = build_vertex_rings(m);
        const double diagonal = bounding_box(m.positions).diagonal();
        RegionSpec spec;
        const Vec3 seed = m.positions[std::size_t(fraction(random) * double(m.positions.size() - 1))];
        if (trial % 4 < 2) {
            spec.kind = RegionSpec::Kind::geodesic;
            spec.seed = seed;
            spec.g_min = (0.05 + 0.15 * fraction(random)) * diagonal;
            spec.g_max = spec.g_min + (0.1 + 0.4 * fraction(random)) * diagonal;
        } else {
            spec.kind = RegionSpec::Kind::painted;
            const Vec3 n = glm::normalize(Vec3(unit(random), unit(random), unit(random)));
            double lo = 1e300, hi = -1e300;
            for (const Vec3& p : m.positions) lo = std::min(lo, glm::dot(n, p)), hi = std::max(hi, glm::dot(n, p));
            const double inner_from = lo + (0.6 + 0.3 * fraction(random)) * (hi - lo);
            const double outer_to = lo + (0.1 + 0.3 * fraction(random)) * (hi - lo);
            spec.inner = {Selector{SelectorKind::halfspace, n, Vec3(0.0), inner_from, {}}};
            spec.outer = {Selector{SelectorKind::halfspace, -n, Vec3(0.0), -outer_to, {}}};
            spec.band = trial % 3 == 0 ? 0.1 * diagonal : 0.0;
        }
        INFO("trial " << trial);
        std::vector<std::string> at_once_warnings, in_parts_warnings;
        const std::vector<double> at_once = build_region(spec, m.positions, rings, at_once_warnings).s;

        RegionBuild build(spec, m.positions, rings);
        const std::vector<double> first = build.s();
        int parts = 1;
        while (!build.advance(0.0)) {
            ++parts;
            // Meanwhile which vertices are inner, blend and outer is final.
            for (std::size_t v = 0; v < first.size(); v += 7) {
                REQUIRE((build.s()[v] <= 0.0) == (at_once[v] <= 0.0));
                REQUIRE((build.s()[v] >= 1.0) == (at_once[v] >= 1.0));
            }
        }
        CHECK(parts > 3);
        CHECK(build.take(in_parts_warnings).s == at_once);
        CHECK(in_parts_warnings == at_once_warnings);
        for (std::size_t v = 0; v < first.size(); ++v) {
            REQUIRE((first[v] <= 0.0) == (at_once[v] <= 0.0));
            REQUIRE(in_blend(first[v]) == in_blend(at_once[v]));
        }
    }
}

TEST_CASE("a region build throws at once for what build_region rejects", "[region][harmonic][scene]") {
    const TriangleMesh m = icosphere(2, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    RegionSpec spec;
    spec.kind = RegionSpec::Kind::geodesic;
    spec.g_min = 0.5, spec.g_max = 0.2;
    CHECK_THROWS_AS(RegionBuild(spec, m.positions, rings), InputError);
    spec.kind = RegionSpec::Kind::field;
    spec.s.assign(3, 0.5);
    CHECK_THROWS_AS(RegionBuild(spec, m.positions, rings), InputError);
}
