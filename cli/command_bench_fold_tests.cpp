// vfsd bench --fold-tests [--mesh SPEC] [--time T] [--repeat N]
//
// What the fold repair's tests cost (deform/fold_repair.h): an error-controlled
// run of a mesh that folds nothing spends about a quarter of its time in them
// (docs/benchmarks.md, "Where the time goes"). vfsd bench's bend of the mesh
// (default the 53k cylinder) is run to time T (default 0.5), and on that shape
// the neighbour test alone and with the affine test are timed, each N times
// (default 40) on all threads and then on one; medians are printed with the
// triangles each test found short of the lift's target. The same follows on
// that shape with its blend vertices jittered, which folds triangles all over
// (what a repair's tests meet). The command fails when a test finds other
// triangles on one thread than on all.

#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "base/error.h"
#include "base/parallel.h"
#include "cli/commands.h"
#include "deform/deformation.h"
#include "deform/fold_repair.h"
#include "io/mesh_file.h"

namespace vfsd::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct TestTimes {
    double neighbour_ms = 0.0, both_ms = 0.0;
    std::size_t neighbour_short = 0, both_short = 0;
};

TestTimes time_tests(FoldRepair& repair, const std::vector<Vec3>& x, const VertexRings& rings, int repeat) {
    TestTimes t;
    std::vector<double> neighbour, both;
    for (int i = 0; i < repeat; ++i) {
        auto start = Clock::now();
        t.neighbour_short = repair.count_folds(x, rings, false);
        neighbour.push_back(ms_since(start));
        start = Clock::now();
        t.both_short = repair.count_folds(x, rings, true);
        both.push_back(ms_since(start));
    }
    t.neighbour_ms = median(neighbour);
    t.both_ms = median(both);
    return t;
}

// x with every blend vertex moved by up to 0.4 of its ring's mean edge in a
// random direction (seeded): a shape with triangles short of the lift's target
// everywhere, as a repair meets them.
std::vector<Vec3> jitter(std::vector<Vec3> x, const std::vector<double>& s, const VertexRings& rings) {
    std::mt19937 random(1);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const std::vector<Vec3> at = x;
    for (std::uint32_t v = 0; v < x.size(); ++v) {
        if (!(s[v] > 0.0 && s[v] < 1.0) || rings.begin(v) == rings.end(v)) continue;
        double edge = 0.0;
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
            edge += glm::length(at[rings.neighbours[k]] - at[v]);
        edge /= double(rings.end(v) - rings.begin(v));
        x[v] += 0.4 * edge * Vec3(unit(random), unit(random), unit(random));
    }
    return x;
}

}  // namespace

int run_fold_tests_bench(const Args& args) {
    args.expect({"fold-tests", "mesh", "time", "repeat"}, 0, 0);
    const std::string spec = args.get("mesh", "builtin:cylinder:163");
    const double time = args.get_number("time", 0.5);
    const int repeat = static_cast<int>(args.get_number("repeat", 40));
    if (!(time >= 0.0 && time <= 1.0)) throw UsageError("--time must be in [0, 1]");
    if (repeat < 1) throw UsageError("--repeat must be positive");

    const TriangleMesh mesh = load_mesh(spec);
    const VertexRings rings = build_vertex_rings(mesh);
    Region region;
    BezierCurve curve;
    bench_region_and_curve(mesh, region, curve);
    DeformationOptions options;
    options.tolerance = 5e-4;
    Deformation d(mesh.positions, rings, region, InnerMotion::along_curve(curve, InnerMotionMode::Rotation, 0.0, 0.0),
                  options);
    d.advance(time);
    const std::vector<Vec3> x = d.positions();

    const auto build = Clock::now();
    FoldRepair repair(mesh.positions, region.s, rings);
    const double build_ms = ms_since(build);
    std::printf("fold tests on %s (%zu vertices) at t = %g: %zu checked triangles, built in %.2f ms\n", spec.c_str(),
                mesh.vertex_count(), time, repair.checks().check.size(), build_ms);
    std::printf("%-10s %-8s %16s %22s %12s\n", "shape", "threads", "neighbour test", "with the affine test", "short");
    const unsigned all = parallel_thread_count();
    bool agree = true;
    for (const bool jittered : {false, true}) {
        const std::vector<Vec3> shape = jittered ? jitter(x, region.s, rings) : x;
        std::vector<TestTimes> times;
        for (const unsigned threads : {all, 1u}) {
            set_parallel_thread_limit(threads);
            const TestTimes& t = times.emplace_back(time_tests(repair, shape, rings, repeat));
            std::printf("%-10s %-8u %13.3f ms %19.3f ms %5zu / %zu\n", jittered ? "jittered" : "smooth", threads,
                        t.neighbour_ms, t.both_ms, t.neighbour_short, t.both_short);
        }
        set_parallel_thread_limit(0);
        // What the tests find may not depend on the threads, and the affine test only adds.
        for (const TestTimes& t : times)
            agree = agree && t.neighbour_short == times[0].neighbour_short && t.both_short == times[0].both_short &&
                    t.both_short >= t.neighbour_short;
    }
    if (!agree) {
        std::fprintf(stderr, "vfsd bench: the fold tests found different triangles on different threads\n");
        return 1;
    }
    return 0;
}

}  // namespace vfsd::cli
