// Each GPU pass alone equals its CPU counterpart (engine/deform/passes.h) on the
// same input, on meshes with valence 3 to 20, with boundaries, and a closed one.
// Inputs are rounded to float32 first, so the bounds measure the passes' own
// float arithmetic; docs/gpu.md lists the measured differences.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include "deform/passes.h"
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
        std::vector<Vec3> normals, cpu;
        estimate_normals(in.positions, in.rings, normals);
        estimate_gradients(in.positions, normals, in.s, in.rings, blend_vertices(in.s), cpu);
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
        std::vector<Vec3> cpu = some_gradients(in, normals);
        gpu.set_gradients(cpu);
        gpu.estimate_normals(gpu::At::positions);
        smooth_gradients(normals, RegionParts::of(in.s, in.rings), 10, 0.5, tangent, cpu, scratch);
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
        std::vector<Vec3> normals, cpu;
        estimate_normals(in.positions, in.rings, normals);
        const std::vector<Vec3> gradients = some_gradients(in, normals);
        gpu.set_gradients(gradients);
        const double h = 1.0 / 250.0;
        predict_midpoints(motion.at(0.3), h, in.s, RegionParts::of(in.s, in.rings), gradients, in.positions, cpu);
        gpu.predict_midpoints(motion.at(0.3), h);
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
            std::vector<Vec3> normals;
            estimate_normals(in.positions, in.rings, normals);
            const std::vector<Vec3> gradients = some_gradients(in, normals);
            gpu.set_gradients(gradients);
            const StepMotion step = StepMotion::sample(motion, 0.4, 1.0 / 250.0);
            std::vector<Vec3> cpu = in.positions;
            deformation_step(step, in.s, RegionParts::of(in.s, in.rings), gradients, cpu, cpu);
            gpu.deformation_step(step);
            const double error = test::max_distance(gpu.read_positions(), cpu);
            report("rk4 step", in.name, error, in.size);
            CHECK(error < 1e-6 * in.size);
        }
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
    gpu.predict_midpoints(test_motion().at(0.0), 0.01);
    gpu.deformation_step(StepMotion::sample(test_motion(), 0.0, 0.01));
    CHECK(gpu::readback_count() == before);
    gpu.read_positions();
    CHECK(gpu::readback_count() == before + 1);
}
