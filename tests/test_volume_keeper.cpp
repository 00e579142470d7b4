// The volume keeper (deform/volume_keeper.h): it measures the closed mesh's
// volume as signed_volume does, undoes a small drift of the blend region to
// second order in it, moves nothing outside the blend region, does nothing on an
// open surface, and refuses area vectors that do not match its blend region. Its
// rate is the volume's derivative along the vertices' velocities, and its
// velocity cancels that rate. Its sum of the volume in SIMD lanes has the bits
// of parallel_sum over single tetrahedra.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "base/parallel.h"
#include "deform/passes.h"
#include "deform/volume_keeper.h"
#include "field/vector_field.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh_fixtures.h"

using namespace vfsd;

namespace {

// s rising with height from 0 (inner) below z0 to 1 (outer) above z1.
std::vector<double> s_by_height(const std::vector<Vec3>& positions, double z0, double z1) {
    std::vector<double> s;
    for (const Vec3& p : positions) s.push_back(std::clamp((p.z - z0) / (z1 - z0), 0.0, 1.0));
    return s;
}

// Every blend vertex moved by up to `size` in a random direction.
std::vector<Vec3> jiggled(std::vector<Vec3> positions, const std::vector<std::uint32_t>& blend, double size,
                          std::mt19937& random) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (const std::uint32_t v : blend) positions[v] += size * Vec3(unit(random), unit(random), unit(random));
    return positions;
}

// A unit vector in a random direction.
Vec3 random_direction(std::mt19937& random) {
    std::normal_distribution<double> normal;
    return glm::normalize(Vec3(normal(random), normal(random), normal(random)));
}

}  // namespace

TEST_CASE("the keeper's rate is dV/dt, the inner region moving rigidly, and its velocity cancels it",
          "[volume_keeper]") {
    std::mt19937 random(23);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 24; ++trial) {
        // A closed mesh of each kind (two spheres touching at a vertex among
        // them), turned, scaled and moved off the origin, its surface roughened.
        TriangleMesh mesh = trial % 4 == 3 ? fixtures::pinched_spheres(random)
                                           : make_builtin_mesh(trial % 4 == 0   ? "sphere"
                                                               : trial % 4 == 1 ? "box"
                                                                                : "cylinder",
                                                               3);
        const double scale = std::pow(10.0, unit(random) * 2.0);
        const Vec3 offset = 100.0 * scale * Vec3(unit(random), unit(random), unit(random));
        const Vec3 axis = random_direction(random);
        const double along_lo = unit(random) * 0.3, along_hi = along_lo + 0.3 + 0.3 * (unit(random) + 1.0);
        std::vector<double> s;
        for (Vec3& p : mesh.positions) {
            p += 0.01 * Vec3(unit(random), unit(random), unit(random));
            s.push_back(std::clamp((glm::dot(p, axis) - along_lo) / (along_hi - along_lo), 0.0, 1.0));
        }
        for (Vec3& p : mesh.positions) p = scale * p + offset;
        const VertexRings rings = build_vertex_rings(mesh);
        const RegionParts parts = RegionParts::of(s, rings);
        const VolumeKeeper keeper(mesh.positions, s, rings, parts.blend);
        REQUIRE(keeper.active());
        REQUIRE(!parts.blend.empty());
        REQUIRE(!parts.inner.empty());

        // A rigid motion on the inner region, random velocities on the blend region.
        MotionSample sample;
        sample.position = offset + scale * Vec3(unit(random), unit(random), unit(random));
        sample.velocity = scale * Vec3(unit(random), unit(random), unit(random));
        sample.angular_velocity = Vec3(unit(random), unit(random), unit(random));
        sample.twist = 0.5 * Vec3(unit(random), unit(random), unit(random));
        std::vector<Vec3> u(mesh.positions.size(), Vec3(0.0));
        for (const std::uint32_t v : parts.inner) u[v] = inner_velocity(sample, mesh.positions[v]);
        for (const std::uint32_t v : parts.blend) u[v] = scale * Vec3(unit(random), unit(random), unit(random));
        std::vector<Vec3> area_vectors;
        ring_area_vectors(mesh.positions, rings, parts.blend, area_vectors);
        double blend_flux = 0.0;
        for (std::size_t i = 0; i < parts.blend.size(); ++i) blend_flux += glm::dot(u[parts.blend[i]], area_vectors[i]);

        const double rate = keeper.rate(mesh.positions, blend_flux, sample);
        // V is cubic along x + e u: the central difference errs by e² times its third derivative / 6.
        const double epsilon = 1e-4;
        const auto volume_at = [&](double e) {
            std::vector<Vec3> x = mesh.positions;
            for (std::size_t v = 0; v < x.size(); ++v) x[v] += e * u[v];
            return keeper.volume(x);
        };
        const double difference = (volume_at(epsilon) - volume_at(-epsilon)) / (2.0 * epsilon);
        const double scale_of_terms = std::pow(scale, 3.0) * static_cast<double>(mesh.positions.size());
        INFO("trial " << trial << ": rate " << rate << ", central difference " << difference);
        CHECK(std::abs(rate - difference) <= 1e-7 * scale_of_terms);
        CHECK(std::abs(rate) > 1e-4 * scale_of_terms / std::sqrt(double(mesh.positions.size())));

        // The keeper's velocity, λ w ∂V/∂x on the blend region, adds −rate.
        const double lambda = keeper.lambda(rate, area_vectors);
        double added = 0.0;
        for (std::size_t i = 0; i < parts.blend.size(); ++i) {
            const double s_i = s[parts.blend[i]];
            const double w = (1.0 - bernstein_blend(s_i)) * bernstein_blend_derivative(s_i);
            added += glm::dot(lambda * w * area_vectors[i] / 6.0, area_vectors[i] / 6.0);
        }
        CHECK(added == Approx(-rate).epsilon(1e-9));
    }
}

TEST_CASE("the volume keeper undoes a blend region's drift to second order and moves nothing else", "[volume_keeper]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(mesh);
    const std::vector<double> s = s_by_height(mesh.positions, -0.3, 0.4);
    const RegionParts parts = RegionParts::of(s, rings);
    REQUIRE(!parts.blend.empty());
    const VolumeKeeper keeper(mesh.positions, s, rings, parts.blend);
    REQUIRE(keeper.active());
    const double rest = signed_volume(mesh.positions, mesh.triangles);
    CHECK(keeper.rest_volume() == Approx(rest).epsilon(1e-12));

    std::mt19937 random(14);
    for (int trial = 0; trial < 20; ++trial) {
        const double size = 1e-3 * (1 + trial % 4);
        const std::vector<Vec3> before = jiggled(mesh.positions, parts.blend, size, random);
        std::vector<Vec3> after = before;
        std::vector<Vec3> area_vectors;
        ring_area_vectors(before, rings, parts.blend, area_vectors);
        const double drift = keeper.restore(after, area_vectors);
        CHECK(drift == Approx(signed_volume(before, mesh.triangles) - rest).epsilon(1e-9));
        // One Newton step: what is left is second order in the move.
        const double left = signed_volume(after, mesh.triangles) - rest;
        CHECK(std::abs(left) <= 1e-2 * std::abs(drift) + 1e-14);
        for (std::size_t v = 0; v < s.size(); ++v)
            if (s[v] == 0.0 || s[v] == 1.0) REQUIRE(after[v] == before[v]);  // bit for bit
    }
}

TEST_CASE("the volume keeper's steps after a repair stop where the drift is settled, wherever the mesh is",
          "[volume_keeper]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(mesh);
    std::mt19937 random(27);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    // A repair moves a few vertices by up to an edge (large drifts) or many by
    // little: both, on the sphere moved and scaled at random.
    int settled_trials = 0;
    for (int trial = 0; trial < 12; ++trial) {
        const double scale = std::pow(10.0, 3.0 * unit(random));
        const Vec3 offset = Vec3(unit(random), unit(random), unit(random)) * (100.0 * scale);
        std::vector<Vec3> placed;
        for (const Vec3& p : mesh.positions) placed.push_back(p * scale + offset);
        const std::vector<double> s = s_by_height(mesh.positions, -0.3, 0.4);
        const RegionParts parts = RegionParts::of(s, rings);
        const VolumeKeeper keeper(placed, s, rings, parts.blend);
        REQUIRE(keeper.active());
        const double size = scale * (trial % 2 == 0 ? 1e-4 : 3e-2);
        const std::vector<Vec3> before = jiggled(placed, parts.blend, size, random);
        std::vector<Vec3> after = before;
        std::vector<Vec3> area_vectors;
        double area_norm = 0.0;
        const int steps = keeper.restore_after_repair(after, rings, area_vectors, area_norm);
        CAPTURE(trial, scale, size, steps);
        CHECK(steps >= 1);
        CHECK(steps <= VolumeKeeper::kStepsAfterRepair);
        // Quadratic convergence: a small move's drift settles in one or two steps, not three.
        if (size < 1e-3 * scale) CHECK(steps < VolumeKeeper::kStepsAfterRepair);
        const double left = std::abs(keeper.volume(after) - keeper.rest_volume());
        CHECK(left <= 10 * VolumeKeeper::kSettledDrift * std::abs(keeper.rest_volume()));
        for (std::size_t v = 0; v < s.size(); ++v)
            if (s[v] == 0.0 || s[v] == 1.0) REQUIRE(after[v] == before[v]);  // bit for bit
        // Settled: a second call takes no step, and leaves the area vectors and the positions.
        const std::vector<Vec3> settled = after, vectors = area_vectors;
        const double norm = area_norm;
        if (left <= VolumeKeeper::kSettledDrift * std::abs(keeper.rest_volume())) {
            ++settled_trials;
            CHECK(keeper.restore_after_repair(after, rings, area_vectors, area_norm) == 0);
            CHECK(after == settled);
            CHECK(area_vectors == vectors);
            CHECK(area_norm == norm);
        }
    }
    CHECK(settled_trials >= 6);  // every small move's, at least
}

TEST_CASE("the volume keeper does nothing on an open surface", "[volume_keeper]") {
    const TriangleMesh mesh = fixtures::grid(6, 6);
    const VertexRings rings = build_vertex_rings(mesh);
    std::vector<double> s;
    for (const Vec3& p : mesh.positions) s.push_back(std::clamp((p.x - 1.0) / 4.0, 0.0, 1.0));
    const RegionParts parts = RegionParts::of(s, rings);
    const VolumeKeeper keeper(mesh.positions, s, rings, parts.blend);
    CHECK_FALSE(keeper.active());
    std::vector<Vec3> positions = mesh.positions;
    for (const std::uint32_t v : parts.blend) positions[v].z += 0.1;
    const std::vector<Vec3> before = positions;
    std::vector<Vec3> area_vectors;
    ring_area_vectors(positions, rings, parts.blend, area_vectors);
    CHECK(keeper.restore(positions, area_vectors) == 0.0);
    CHECK(positions == before);
}

TEST_CASE("the volume keeper refuses area vectors that are not one per blend vertex", "[volume_keeper]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 2);
    const VertexRings rings = build_vertex_rings(mesh);
    const std::vector<double> s = s_by_height(mesh.positions, -0.3, 0.4);
    const RegionParts parts = RegionParts::of(s, rings);
    const VolumeKeeper keeper(mesh.positions, s, rings, parts.blend);
    REQUIRE(keeper.active());
    std::vector<Vec3> positions = mesh.positions;
    std::vector<Vec3> area_vectors;
    ring_area_vectors(positions, rings, parts.blend, area_vectors);
    area_vectors.pop_back();
    CHECK_THROWS_AS(keeper.restore(positions, area_vectors), std::invalid_argument);
    CHECK(positions == mesh.positions);
}

TEST_CASE("the volume's sum in SIMD lanes has the bits of parallel_sum over single tetrahedra", "[volume_keeper]") {
    std::mt19937 random(31);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<std::uint32_t> corner(0, 199);
    for (int trial = 0; trial < 8; ++trial) {
        // Points far from the centre and from the origin, at any scale.
        const double scale = std::pow(10.0, 3.0 * unit(random));
        const Vec3 offset = 50.0 * scale * Vec3(unit(random), unit(random), unit(random));
        std::vector<Vec3> p;
        for (int i = 0; i < 200; ++i) p.push_back(offset + scale * Vec3(unit(random), unit(random), unit(random)));
        const Vec3 centre = offset + scale * Vec3(unit(random), unit(random), unit(random));
        std::vector<Triangle> triangles;
        for (int i = 0; i < 3000; ++i) triangles.push_back(Triangle(corner(random), corner(random), corner(random)));

        for (const Triangle& t : triangles) {
            const double det = glm::dot(p[t.x] - centre, glm::cross(p[t.y] - centre, p[t.z] - centre));
            REQUIRE(six_volume(p.data(), t, centre) == Approx(det).scale(scale * scale * scale));
        }
        // Every length of a block, its last triangles past a multiple of four included.
        for (std::size_t count = 0; count <= 40; ++count) {
            double sum[4] = {0.0, 0.0, 0.0, 0.0};
            std::size_t i = 0;
            for (; i + 4 <= count; i += 4)
                for (int j = 0; j < 4; ++j) sum[j] += six_volume(p.data(), triangles[i + j], centre);
            for (; i < count; ++i) sum[0] += six_volume(p.data(), triangles[i], centre);
            INFO("trial " << trial << ", " << count << " triangles");
            REQUIRE(six_volume_block(p.data(), triangles.data(), count, centre) ==
                    (sum[0] + sum[1]) + (sum[2] + sum[3]));
        }
        // Over several blocks, as the keeper sums the moving triangles.
        const double lanes = parallel_block_sum(triangles.size(), [&](std::size_t begin, std::size_t end) {
            return six_volume_block(p.data(), triangles.data() + begin, end - begin, centre);
        });
        const double single =
            parallel_sum(triangles.size(), [&](std::size_t i) { return six_volume(p.data(), triangles[i], centre); });
        CHECK(lanes == single);
    }
}
