// Geodesic distance (sec. 6.1): accuracy against exact distances, monotonicity along
// shortest paths, exact zeros on the sources.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "base/error.h"
#include "mesh/vertex_rings.h"
#include "region/geodesic.h"
#include "test_region_meshes.h"

using namespace vfsd;
using vfsd::test::cylinder_mesh;
using vfsd::test::grid_mesh;
using vfsd::test::icosphere;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct ErrorStats {
    double max_relative = 0.0;   // max |g - d| / d over vertices with d >= min_distance
    double mean_relative = 0.0;
};

ErrorStats compare(const std::vector<double>& g, const std::vector<double>& exact, double min_distance) {
    ErrorStats e;
    std::size_t count = 0;
    for (std::size_t v = 0; v < g.size(); ++v) {
        if (exact[v] < min_distance) continue;
        const double rel = std::abs(g[v] - exact[v]) / exact[v];
        e.max_relative = std::max(e.max_relative, rel);
        e.mean_relative += rel;
        ++count;
    }
    if (count > 0) e.mean_relative /= static_cast<double>(count);
    return e;
}

GeodesicOptions with(GeodesicMethod method, int smoothing = 2) {
    GeodesicOptions o;
    o.method = method;
    o.smoothing_iterations = smoothing;
    return o;
}

const GeodesicMethod kMethods[] = {GeodesicMethod::dijkstra, GeodesicMethod::dijkstra_flip_links,
                                   GeodesicMethod::fast_marching};
const char* method_name(GeodesicMethod m) {
    return m == GeodesicMethod::dijkstra ? "dijkstra" : m == GeodesicMethod::fast_marching ? "fast_marching" : "flip_links";
}

// Every vertex with a positive finite distance has a neighbour with a smaller one.
bool descends_to_sources(const VertexRings& rings, const std::vector<double>& g) {
    for (std::uint32_t v = 0; v < g.size(); ++v) {
        if (g[v] == 0.0 || !std::isfinite(g[v])) continue;
        bool lower = false;
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) lower = lower || g[rings.neighbours[i]] < g[v];
        if (!lower) return false;
    }
    return true;
}

std::vector<double> plane_exact(const TriangleMesh& m, std::uint32_t source) {
    std::vector<double> d;
    for (const Vec3& p : m.positions) d.push_back(glm::length(p - m.positions[source]));
    return d;
}

std::vector<double> sphere_exact(const TriangleMesh& m, std::uint32_t source, double radius) {
    std::vector<double> d;
    const Vec3 s = glm::normalize(m.positions[source]);
    for (const Vec3& p : m.positions) d.push_back(radius * std::acos(std::clamp(glm::dot(glm::normalize(p), s), -1.0, 1.0)));
    return d;
}

// Distance on the smooth tube unrolled: sqrt((r * dtheta)^2 + dz^2), dtheta <= pi.
std::vector<double> tube_exact(const TriangleMesh& m, std::uint32_t source, double radius) {
    std::vector<double> d;
    const Vec3 s = m.positions[source];
    for (const Vec3& p : m.positions) {
        double dt = std::abs(std::atan2(p.y, p.x) - std::atan2(s.y, s.x));
        dt = std::min(dt, 2.0 * kPi - dt);
        d.push_back(std::hypot(radius * dt, p.z - s.z));
    }
    return d;
}

}  // namespace

// Stated bounds (max relative error beyond 8 edge lengths from the source, smoothing 2).
// Plane, one diagonal per quad: Dijkstra's worst direction is the missing diagonal,
// where it walks |dx| + |dy| (sqrt(2) - 1 = 41.4% too long); the flip links add that
// diagonal (10%); fast marching is exact for a point source on a flat mesh up to the
// smoothing (2%). Icosphere: 20%, 5%, 2%.
TEST_CASE("geodesic distance on a flat grid is close to the Euclidean distance", "[region][geodesic]") {
    const int n = 40;
    const TriangleMesh m = grid_mesh(n, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    const std::uint32_t source = (n / 3) * (n + 1) + n / 4;  // off-centre, off the diagonals
    const std::vector<double> exact = plane_exact(m, source);
    const double bound[] = {std::sqrt(2.0) - 1.0 + 1e-3, 0.10, 0.02};
    for (int k = 0; k < 3; ++k) {
        CAPTURE(method_name(kMethods[k]));
        const auto g = geodesic_distance(m.positions, rings, {source}, with(kMethods[k]));
        CHECK(compare(g, exact, 8.0 / n).max_relative < bound[k]);
        CHECK(g[source] == 0.0);
        CHECK(descends_to_sources(rings, g));
    }
}

TEST_CASE("geodesic distance on a sphere is close to the great-circle distance", "[region][geodesic]") {
    const double radius = 2.0;
    const TriangleMesh m = icosphere(4, radius);
    const VertexRings rings = build_vertex_rings(m);
    const double h = radius * 0.0757;  // about the edge length at level 4 (1.2 / 16 on the unit sphere)
    const std::vector<double> exact = sphere_exact(m, 17, radius);
    const double bound[] = {0.20, 0.05, 0.03};
    for (int k = 0; k < 3; ++k) {
        CAPTURE(method_name(kMethods[k]));
        const auto g = geodesic_distance(m.positions, rings, {17}, with(kMethods[k]));
        CHECK(compare(g, exact, 8.0 * h).max_relative < bound[k]);
        CHECK(descends_to_sources(rings, g));
    }
}

TEST_CASE("distance to a region is exactly zero on it and descends towards it", "[region][geodesic]") {
    const TriangleMesh m = icosphere(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    std::vector<std::uint8_t> region(m.positions.size(), 0);
    for (std::size_t v = 0; v < region.size(); ++v) region[v] = m.positions[v].z > 0.5;
    for (GeodesicMethod method : kMethods) {
        CAPTURE(method_name(method));
        const auto g = geodesic_distance_to_region(m.positions, rings, region, with(method, 3));
        for (std::size_t v = 0; v < g.size(); ++v) {
            if (region[v]) CHECK(g[v] == 0.0);
            else CHECK(g[v] > 0.0);
        }
        CHECK(descends_to_sources(rings, g));
        // The distance to the cap z > 0.5 is the arc from the cap's edge (angle pi/3 from
        // the pole), measured from its border vertices: allow one edge length (0.15) plus
        // the method's relative error.
        const double rel = method == GeodesicMethod::dijkstra ? 0.20 : 0.05;
        for (std::size_t v = 0; v < g.size(); ++v) {
            const double exact = std::acos(m.positions[v].z) - kPi / 3.0;
            if (!region[v]) CHECK(std::abs(g[v] - exact) <= 0.15 + rel * exact);
        }
    }
}

TEST_CASE("geodesic distance leaves other components unreached", "[region][geodesic]") {
    TriangleMesh m = grid_mesh(4, 1.0);
    const TriangleMesh other = grid_mesh(3, 1.0);
    const auto offset = static_cast<std::uint32_t>(m.positions.size());
    for (const Vec3& p : other.positions) m.positions.push_back(p + Vec3(5.0, 0.0, 0.0));
    for (const Triangle& t : other.triangles) m.triangles.push_back(t + Triangle(offset));
    const VertexRings rings = build_vertex_rings(m);
    for (GeodesicMethod method : kMethods) {
        const auto g = geodesic_distance(m.positions, rings, {0}, with(method));
        for (std::size_t v = 0; v < g.size(); ++v) CHECK(std::isfinite(g[v]) == (v < offset));
    }
}

TEST_CASE("distance from a surface point seeds the corners with their exact distance", "[region][geodesic]") {
    const TriangleMesh m = grid_mesh(10, 1.0);  // edge length h = 0.1
    const VertexRings rings = build_vertex_rings(m);
    const SurfacePoint p{57, Vec3(0.2, 0.3, 0.5)};
    const Vec3 x = surface_position(m.positions, m.triangles, p);
    // Fast marching reconstructs the off-vertex point source to within 0.2 h; the
    // smoothing kernel rounds the cone at the source by less than half an edge more.
    for (int smoothing : {0, 2}) {
        const auto g = geodesic_distance_from_point(m.positions, m.triangles, rings, p,
                                                    with(GeodesicMethod::fast_marching, smoothing));
        for (int k = 0; k < 3; ++k) CHECK(g[m.triangles[57][k]] == glm::length(m.positions[m.triangles[57][k]] - x));
        double worst = 0.0;
        for (std::size_t v = 0; v < g.size(); ++v) worst = std::max(worst, std::abs(g[v] - glm::length(m.positions[v] - x)));
        CHECK(worst <= (smoothing == 0 ? 0.02 : 0.05));
    }
}

TEST_CASE("max_distance stops the propagation", "[region][geodesic]") {
    const TriangleMesh m = grid_mesh(20, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    GeodesicOptions o = with(GeodesicMethod::dijkstra, 0);
    o.max_distance = 0.3;
    const auto g = geodesic_distance(m.positions, rings, {0}, o);
    const auto full = geodesic_distance(m.positions, rings, {0}, with(GeodesicMethod::dijkstra, 0));
    for (std::size_t v = 0; v < g.size(); ++v) CHECK(g[v] == (full[v] <= 0.3 ? full[v] : std::numeric_limits<double>::infinity()));
}

TEST_CASE("geodesic distance rejects bad input", "[region][geodesic]") {
    const TriangleMesh m = grid_mesh(3, 1.0);
    const VertexRings rings = build_vertex_rings(m);
    CHECK_THROWS_AS(geodesic_distance(m.positions, rings, {99}), InputError);
    CHECK_THROWS_AS(geodesic_distance_to_region(m.positions, rings, {1, 0}), InputError);
    CHECK_THROWS_AS(geodesic_distance_from_point(m.positions, m.triangles, rings, {99, Vec3(1, 0, 0)}), InputError);
    CHECK_THROWS_AS(geodesic_distance_from_point(m.positions, m.triangles, rings, {0, Vec3(0.5, 0.6, 0.0)}), InputError);
    GeodesicOptions o;
    o.smoothing_iterations = -1;
    CHECK_THROWS_AS(geodesic_distance(m.positions, rings, {0}, o), InputError);
}

// Prints the accuracy and cost figures quoted in docs/regions.md. Hidden: run with
// `vfsd_tests "[region-bench]"` on a Release build.
TEST_CASE("geodesic accuracy and cost figures", "[.][region-bench]") {
    struct Case { const char* name; TriangleMesh mesh; std::uint32_t source; int kind; };
    std::vector<Case> cases;
    cases.push_back({"plane 141x141", grid_mesh(140, 1.0), 70 * 141 + 35, 0});
    cases.push_back({"sphere r=1 (40,962 v)", icosphere(6, 1.0), 17, 1});
    cases.push_back({"tube r=1 h=4 (128x161)", cylinder_mesh(128, 160, 1.0, 4.0, false), 80 * 128, 2});
    for (const Case& c : cases) {
        const VertexRings rings = build_vertex_rings(c.mesh);
        const auto exact = c.kind == 0 ? plane_exact(c.mesh, c.source)
                         : c.kind == 1 ? sphere_exact(c.mesh, c.source, 1.0) : tube_exact(c.mesh, c.source, 1.0);
        for (GeodesicMethod method : kMethods)
            for (int smoothing : {0, 2, 5}) {
                std::vector<double> g;
                double ms = std::numeric_limits<double>::infinity();  // the best of 5 runs
                for (int run = 0; run < 5; ++run) {
                    const auto t0 = std::chrono::steady_clock::now();
                    g = geodesic_distance(c.mesh.positions, rings, {c.source}, with(method, smoothing));
                    ms = std::min(ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                }
                const ErrorStats e = compare(g, exact, 0.25);
                std::printf("%-24s %-14s smooth %d  %6zu v  mean %.4f  max %.4f  %7.2f ms\n", c.name,
                            method_name(method), smoothing, g.size(), e.mean_relative, e.max_relative, ms);
            }
    }
}
