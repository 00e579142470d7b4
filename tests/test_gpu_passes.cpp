// Each GPU pass alone equals its CPU counterpart (engine/deform/passes.h) on the
// same input, on meshes with valence 3 to 20, with boundaries, and a closed one.
// Inputs are rounded to float32 first, so the bounds measure the passes' own
// float arithmetic; docs/gpu.md lists the measured differences.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include "deform/fold_repair.h"
#include "deform/passes.h"
#include "deform/quality.h"
#include "deform/volume_keeper.h"
#include "field/stream_gauge.h"
#include "gpu/gl_objects.h"
#include "gpu/gpu_passes.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh_fixtures.h"
#include "test_gpu_support.h"

using namespace vfsd;

namespace {

struct PassInput {
    std::string name;
    TriangleMesh mesh;
    VertexRings rings;
    std::vector<Vec3> positions;  // float32-exact
    std::vector<double> s;        // float32-exact, 0 and 1 on large parts
    double size = 1.0;            // bounding-box diagonal
    // Bounding-box diagonal over the shortest edge: float32 loses this factor of
    // its precision when it forms y − x, so the bounds below scale with it.
    double conditioning = 1.0;
};

constexpr double kFloatEps = 1.1920929e-7;

double as_float(double x) { return static_cast<double>(static_cast<float>(x)); }

PassInput make_input(std::string name, TriangleMesh mesh) {
    PassInput in;
    in.name = std::move(name);
    in.rings = build_vertex_rings(mesh);
    const BoundingBox box = bounding_box(mesh.positions);
    in.size = glm::length(box.max - box.min);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 p = mesh.positions[v];
        // A little noise so that no ring is perfectly symmetric.
        const Vec3 q = p + 0.01 * in.size * Vec3(std::sin(7.0 * v), std::cos(5.0 * v), std::sin(3.0 * v + 1.0));
        in.positions.push_back(Vec3(as_float(q.x), as_float(q.y), as_float(q.z)));
        const double u = (q.x - box.min.x) / (box.max.x - box.min.x) + 0.3 * std::sin(4.0 * q.y);
        in.s.push_back(as_float(std::clamp(1.5 * u - 0.25, 0.0, 1.0)));
    }
    double shortest = in.size;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            shortest = std::min(shortest, glm::length(in.positions[t[k]] - in.positions[t[(k + 1) % 3]]));
    in.conditioning = in.size / shortest;
    in.mesh = std::move(mesh);
    return in;
}

std::vector<PassInput> pass_inputs() {
    std::vector<PassInput> inputs;
    inputs.push_back(make_input("valence zoo (valence 3-20, open and closed)", fixtures::valence_zoo()));
    inputs.push_back(make_input("open grid", fixtures::grid(12, 9)));
    inputs.push_back(make_input("annulus (two boundaries)", fixtures::annulus(24, 4)));
    inputs.push_back(make_input("box", make_builtin_mesh("box", 8)));
    inputs.push_back(make_input("sphere", make_builtin_mesh("sphere", 3)));
    return inputs;
}

InnerMotion test_motion() {
    BezierCurve curve({{0, 0, 0.6}, {0, 0, 1.0}, {0.3, 0, 1.4}, {0.8, 0.1, 1.6}});
    InnerMotion motion = InnerMotion::along_curve(curve, InnerMotionMode::Rotation, 0.0, 1.2);
    motion.set_twist_plane(-0.7);
    motion.set_stream_origin(Vec3(0.1, -0.2, 0.3));
    return motion;
}

// Tangent gradients of moderate size, different per vertex, 0 outside the blend
// region as the gradient pass leaves them.
std::vector<Vec3> some_gradients(const PassInput& in, const std::vector<Vec3>& normals) {
    std::vector<Vec3> g;
    for (std::size_t v = 0; v < in.positions.size(); ++v) {
        if (!(in.s[v] > 0.0 && in.s[v] < 1.0)) {
            g.push_back(Vec3(0.0));
            continue;
        }
        const Vec3 a(as_float(std::sin(1.3 * v)), as_float(std::cos(0.7 * v)), as_float(0.5 * std::sin(2.1 * v)));
        const Vec3 t = a - glm::dot(a, normals[v]) * normals[v];
        g.push_back(Vec3(as_float(t.x), as_float(t.y), as_float(t.z)) / in.size);
    }
    return g;
}

// some_gradients for `in`'s own normals, set as the GPU's gradients too.
std::vector<Vec3> upload_some_gradients(const PassInput& in, gpu::GpuPasses& gpu) {
    std::vector<Vec3> normals;
    estimate_normals(in.positions, in.rings, normals);
    const std::vector<Vec3> gradients = some_gradients(in, normals);
    gpu.set_gradients(gradients);
    return gradients;
}

void report(const char* pass, const std::string& mesh, double error, double scale) {
    std::printf("gpu-vs-cpu %-12s %-45s max error %.3g (relative %.3g)\n", pass, mesh.c_str(), error, error / scale);
}

}  // namespace

TEST_CASE("GPU normal pass equals estimate_normals", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const PassInput& in : pass_inputs()) {
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        std::vector<Vec3> cpu;
        estimate_normals(in.positions, in.rings, cpu);
        gpu.estimate_normals(gpu::At::positions);
        const double error = test::max_distance(gpu.read_normals(), cpu);
        report("normals", in.name, error, 1.0);
        CHECK(error < 4.0 * kFloatEps * in.conditioning);
    }
}

TEST_CASE("GPU gradient pass equals estimate_gradients (eq. 6)", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const PassInput& in : pass_inputs()) {
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        std::vector<Vec3> normals;
        GradientRecords records;
        estimate_normals(in.positions, in.rings, normals);
        estimate_gradients(in.positions, normals, in.s, in.rings, blend_vertices(in.s), records);
        const std::vector<Vec3> cpu = vertex_gradients(records, blend_vertices(in.s), in.positions.size());
        gpu.estimate_normals(gpu::At::positions);
        gpu.estimate_gradients(gpu::At::positions);
        const double scale = test::max_length(cpu);
        const double error = test::max_distance(gpu.read_gradients(), cpu);
        report("gradients", in.name, error, scale);
        CHECK(error < 4.0 * kFloatEps * in.conditioning * scale);
    }
}

TEST_CASE("GPU smoothing pass equals smooth_gradients, tangent or in space", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const bool tangent : {true, false})
    for (const PassInput& in : pass_inputs()) {
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        std::vector<Vec3> normals;
        SmoothingScratch scratch;
        estimate_normals(in.positions, in.rings, normals);
        const std::vector<Vec3> before = some_gradients(in, normals);
        gpu.set_gradients(before);
        gpu.estimate_normals(gpu::At::positions);
        const RegionParts parts = RegionParts::of(in.s, in.rings);
        GradientRecords records = gradient_records(before, parts.blend);
        smooth_gradients(normals, parts, 10, 0.5, tangent, records, scratch);
        const std::vector<Vec3> cpu = vertex_gradients(records, parts.blend, in.positions.size());
        gpu.smooth_gradients(10, 0.5, tangent);
        const double scale = test::max_length(cpu);
        const double error = test::max_distance(gpu.read_gradients(), cpu);
        report("smoothing", in.name, error, scale);
        CHECK(error < 1e-5 * scale);
    }
}

TEST_CASE("GPU midpoint predictor equals predict_midpoints", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    const InnerMotion motion = test_motion();
    for (const PassInput& in : pass_inputs()) {
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        std::vector<Vec3> cpu;
        const std::vector<Vec3> gradients = upload_some_gradients(in, gpu);
        const double h = 1.0 / 250.0;
        const StepMotion half = StepMotion::sample(motion, 0.3, 0.5 * h);
        const RegionParts parts = RegionParts::of(in.s, in.rings);
        predict_midpoints(half, parts, gradient_records(gradients, parts.blend), in.positions, cpu);
        gpu.predict_midpoints(half);
        const double error = test::max_distance(gpu.read_midpoints(), cpu);
        report("predictor", in.name, error, in.size);
        CHECK(error < 1e-6 * in.size);
    }
}

TEST_CASE("GPU deformation pass equals one RK4 deformation_step", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation})
    for (const auto& origin : {std::optional<Vec3>(), std::optional<Vec3>(Vec3(0.1, -0.2, 0.3))}) {
        BezierCurve curve({{0, 0, 0.6}, {0, 0, 1.0}, {0.3, 0, 1.4}, {0.8, 0.1, 1.6}});
        InnerMotion motion = InnerMotion::along_curve(curve, mode, 0.0, 1.2);
        motion.set_twist_plane(-0.7);
        motion.set_stream_origin(origin);
        for (const PassInput& in : pass_inputs()) {
            gpu::GpuPasses gpu(in.positions, in.s, in.rings);
            const std::vector<Vec3> gradients = upload_some_gradients(in, gpu);
            const StepMotion step = StepMotion::sample(motion, 0.4, 1.0 / 250.0);
            std::vector<Vec3> cpu = in.positions;
            const RegionParts parts = RegionParts::of(in.s, in.rings);
            deformation_step(step, parts, gradient_records(gradients, parts.blend), cpu, cpu);
            gpu.deformation_step(step);
            const double error = test::max_distance(gpu.read_positions(), cpu);
            report("rk4 step", in.name, error, in.size);
            CHECK(error < 1e-6 * in.size);
        }
    }
}

// Beyond the paper: the passes of the default scheme (gpu_passes.h).

TEST_CASE("GPU gauge samples are their vertices' positions and gradients, and the gauge moves as on the CPU", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    const InnerMotion motion = test_motion();
    for (const PassInput& in : pass_inputs()) {
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        const std::vector<Vec3> gradients = upload_some_gradients(in, gpu);
        const std::vector<std::uint32_t> samples = gauge_samples(in.s, blend_vertices(in.s));
        REQUIRE(samples.size() > 19);
        gpu.set_gauge_samples(samples);
        std::vector<Vec3> at, sampled_gradients;
        gpu.read_gauge_samples(gpu::At::positions, at, sampled_gradients);
        REQUIRE(at.size() == samples.size());
        std::vector<GaugeSample> fit_samples;
        for (std::size_t j = 0; j < samples.size(); ++j) {
            // Inputs are float32-exact: only the origin's subtraction rounds.
            CHECK(glm::length(at[j] - in.positions[samples[j]]) < 4 * kFloatEps * in.size);
            CHECK(glm::length(sampled_gradients[j] - gradients[samples[j]]) <=
                  kFloatEps * glm::length(gradients[samples[j]]));
            fit_samples.push_back(gauge_sample(in.positions[samples[j]], in.s[samples[j]], gradients[samples[j]]));
        }
        // An RK4 step with the fitted gauge in all three motion samples (field.glsl's gauge_gradient).
        const GaugeFit fit(fit_samples);
        StepMotion step = StepMotion::sample(motion, 0.4, 1.0 / 250.0);
        for (MotionSample* m : {&step.start, &step.middle, &step.end}) m->gauge = fit.gauge_for(*m);
        REQUIRE(step.middle.gauge.q[0][1] != 0.0);
        std::vector<Vec3> cpu = in.positions, paper = in.positions;
        const RegionParts parts = RegionParts::of(in.s, in.rings);
        const GradientRecords records = gradient_records(gradients, parts.blend);
        deformation_step(step, parts, records, cpu, cpu);
        StepMotion without = step;
        for (MotionSample* m : {&without.start, &without.middle, &without.end}) m->gauge = StreamGauge{};
        deformation_step(without, parts, records, paper, paper);
        gpu.deformation_step(step);
        const double error = test::max_distance(gpu.read_positions(), cpu);
        report("gauge step", in.name, error, in.size);
        CHECK(error < 1e-6 * in.size);
        CHECK(test::max_distance(cpu, paper) > 100 * error);  // the gauge moved the step, and the GPU with it
    }
}

TEST_CASE("GPU volume keeper pass equals VolumeKeeper::restore", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const PassInput& in : pass_inputs()) {
        const std::vector<std::uint32_t> blend = blend_vertices(in.s);
        const VolumeKeeper keeper(in.positions, in.s, in.rings, blend);
        if (!keeper.active()) continue;  // an open surface: no volume to keep
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        gpu.measure_rest_volume(bounding_box(in.positions).centre());
        // The blend region swollen along its normals: the volume drifts by about 1 %.
        std::vector<Vec3> normals, areas, moved = in.positions;
        estimate_normals(in.positions, in.rings, normals);
        for (const std::uint32_t v : blend) moved[v] += 0.01 * in.size * in.s[v] * (1.0 - in.s[v]) * normals[v];
        for (Vec3& p : moved) p = Vec3(as_float(p.x), as_float(p.y), as_float(p.z));
        gpu.set_positions(moved);
        gpu.estimate_normals(gpu::At::positions);
        gpu.keep_volume();
        std::vector<Vec3> cpu = moved;
        estimate_normals(cpu, in.rings, blend, normals, areas);
        const double drift = keeper.restore(cpu, areas);
        REQUIRE(std::abs(drift) > 1e-3 * std::abs(keeper.rest_volume()));
        const std::vector<Vec3> result = gpu.read_positions();
        const double error = test::max_distance(result, cpu);
        report("keep volume", in.name, error, in.size);
        CHECK(error < 1e-6 * in.size);
        // The GPU's step undoes the drift as the CPU's does, to first order.
        CHECK(std::abs(keeper.volume(result) - keeper.rest_volume()) < 0.01 * std::abs(drift));
    }
}

TEST_CASE("GPU fold pass counts the folds FoldRepair finds", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    for (const PassInput& in : pass_inputs()) {
        FoldRepair repair(in.positions, in.s, in.rings);
        REQUIRE(repair.active());
        std::vector<std::uint32_t> identity(in.positions.size());
        for (std::uint32_t v = 0; v < identity.size(); ++v) identity[v] = v;
        gpu::GpuPasses gpu(in.positions, in.s, in.rings);
        gpu.set_fold_checks(repair.checks(), identity);
        CHECK(gpu.count_folds() == 0);  // at rest nothing is folded
        // Blend vertices slid past a neighbour, along the surface: their fans turn over.
        std::vector<Vec3> moved = in.positions;
        std::size_t pushed = 0;
        for (const Triangle& t : in.mesh.triangles) {
            const std::uint32_t v = t[0], w = t[1];
            if (!(in.s[v] > 0.0 && in.s[v] < 1.0) || pushed++ % 7 != 0 || pushed > 40) continue;
            moved[v] = in.positions[w] + 0.5 * (in.positions[w] - in.positions[v]);
        }
        const std::vector<std::uint32_t> flipped = flipped_triangle_list(in.positions, moved, in.mesh.triangles);
        REQUIRE(!flipped.empty());
        gpu.set_positions(moved);
        // The pass counts what the repair acts on: the triangles short of its lift's
        // target, every folded one among them.
        const std::size_t counted = gpu.count_folds(), on_cpu = repair.count_folds(moved, in.rings, false);
        std::printf("gpu-vs-cpu fold count   %-45s flipped %zu cpu %zu gpu %zu\n", in.name.c_str(), flipped.size(),
                    on_cpu, counted);
        CHECK(counted == on_cpu);
        CHECK(counted >= flipped.size());
    }
}

TEST_CASE("GPU passes read nothing back", "[gpu]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    const PassInput in = make_input("box", make_builtin_mesh("box", 6));
    gpu::GpuPasses gpu(in.positions, in.s, in.rings);
    const std::uint64_t before = gpu::readback_count();
    gpu.estimate_normals(gpu::At::positions);
    gpu.estimate_gradients(gpu::At::positions);
    gpu.smooth_gradients(3, 0.5, true);
    gpu.predict_midpoints(StepMotion::sample(test_motion(), 0.0, 0.005));
    gpu.deformation_step(StepMotion::sample(test_motion(), 0.0, 0.01));
    CHECK(gpu::readback_count() == before);
    gpu.read_positions();
    CHECK(gpu::readback_count() == before + 1);
}
