// vfsd bench [--quick] [--only TEXT] [--markdown FILE] [--data FILE] [--steps N] [--repeat N] [--busy]
// (vfsd bench --picking: command_bench_picking.cpp; --latency: command_bench_latency.cpp;
// --gpu-schemes: command_bench_gpu.cpp; --fold-tests: command_bench_fold_tests.cpp)
//
// Reproduces the paper's timing table (sec. 7.1) with our models: per mesh,
// a bending deformation of 250 RK4 steps with 10 smoothing steps, timed per
// step on one thread and on all, plus the GPU backend when a context can be
// made; volume error, flipped triangles and memory per vertex beside it.
// --busy runs a competing program the whole time: a child process spinning on
// one core, as a desktop user's other work would.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "base/error.h"
#include "base/parallel.h"
#include "cli/busy_process.h"
#include "cli/commands.h"
#include "deform/cpu_steps.h"
#include "deform/quality.h"
#include "gpu/context.h"
#include "gpu/gpu_deformation.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"

namespace vfsd::cli {
namespace {

struct Model {
    std::string name;  // shown in the table
    std::string spec;  // mesh file or builtin:NAME:RES
    int paper_vertices = 0;
    double paper_ms = 0.0;  // GeForce 7800 GTX, sec. 7.1 (0: not in the paper)
};

struct Result {
    Model model;
    std::size_t vertices = 0, blend_vertices = 0;
    double cpu1_ms = 0, cpu1_spread = 0, cpu_ms = 0, cpu_spread = 0, total_ms = 0, gpu_ms = -1;
    double cpu1_mean_ms = 0, cpu_mean_ms = 0;  // the mean step, beside the median ones above
    double volume_error = 0, bytes_per_vertex = 0;
    std::size_t flipped = 0;
};

std::vector<Model> models(bool quick) {
    if (quick) return {{"box", "builtin:box:8", 0, 0}, {"bar", "builtin:bar:6", 0, 0}};
    std::vector<Model> list = {{"box (fig. 4)", "builtin:box", 2462, 4}, {"bar (fig. 13)", "builtin:bar", 9730, 9},
                               {"cylinder (fig. 14)", "builtin:cylinder", 21302, 20}};
    const std::string cgal = std::string(VFSD_SOURCE_DIR) + "/assets/cgal/";
    for (const auto& [name, file] : {std::pair{"camel (~ squirrel)", "camel.off"}, {"armadillo (~ horse)", "armadillo.off"},
                                     {"bunny", "bunny00.off"}})
        if (std::filesystem::exists(cgal + file)) list.push_back({name, cgal + file, 0, 0});
    list.push_back({"sphere 40k", "builtin:sphere:6", 0, 0});
    list.push_back({"cylinder 53k (~ hand)", "builtin:cylinder:163", 53054, 55});
    list.push_back({"cylinder 200k", "builtin:cylinder:316", 0, 0});
    list.push_back({"cylinder 1M", "builtin:cylinder:707", 0, 0});
    list.push_back({"cylinder 2M", "builtin:cylinder:1000", 0, 0});
    return list;
}

// Half the spread between the 10th and 90th percentile, relative to the median.
double spread(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    if (v.size() < 3) return 0.0;
    const double m = v[v.size() / 2];
    return m > 0 ? 0.5 * (v[v.size() * 9 / 10] - v[v.size() / 10]) / m : 0.0;
}

// The median step's milliseconds (ms), their spread and, returned, the mean
// step's (a step that also runs the fold repair's affine test costs more).
double time_cpu(const TriangleMesh& mesh, const VertexRings& rings, const Region& region, const InnerMotion& motion,
                const DeformationOptions& options, int repeat, unsigned threads, double& ms, double& rel_spread,
                std::vector<Vec3>* final_positions) {
    set_parallel_thread_limit(threads);
    std::vector<double> all;
    for (int r = 0; r < repeat; ++r) {
        Deformation d(mesh.positions, rings, region, motion, options);
        d.advance(1.0);
        all.insert(all.end(), d.step_milliseconds().begin(), d.step_milliseconds().end());
        if (final_positions) *final_positions = d.positions();
    }
    set_parallel_thread_limit(0);
    ms = median(all);
    rel_spread = spread(all);
    double sum = 0.0;
    for (const double m : all) sum += m;
    return all.empty() ? 0.0 : sum / double(all.size());
}

double time_gpu(const TriangleMesh& mesh, const VertexRings& rings, const Region& region, const InnerMotion& motion,
                DeformationOptions options, int steps) {
    options.steps = steps;
    Deformation d = gpu::make_gpu_deformation(mesh.positions, rings, region, motion, options);
    d.advance(1.0 / steps);  // warm up: shader compilation, first upload
    const auto start = std::chrono::steady_clock::now();
    const int taken = d.advance(1.0);  // ends with a finish()
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / taken;
}

Result run_model(const Model& model, int steps, int repeat, bool with_gpu) {
    Result r;
    r.model = model;
    const TriangleMesh mesh = load_mesh(model.spec);
    const VertexRings rings = build_vertex_rings(mesh);
    Region region;
    BezierCurve curve;
    bench_region_and_curve(mesh, region, curve);
    const InnerMotion motion = InnerMotion::along_curve(curve, InnerMotionMode::Rotation, 0.0, 0.0);
    DeformationOptions options;
    options.steps = steps;
    r.vertices = mesh.vertex_count();
    r.blend_vertices = blend_vertices(region.s).size();
    {
        CpuSteps state(mesh.positions, rings, region, motion, options);
        state.prepare_first_step();  // the volume keeper and the fold repair, built before the first step
        r.bytes_per_vertex = double(state.state_bytes()) / double(r.vertices);
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<Vec3> final_positions;
    r.cpu_mean_ms = time_cpu(mesh, rings, region, motion, options, repeat, 0, r.cpu_ms, r.cpu_spread, &final_positions);
    r.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / repeat;
    r.cpu1_mean_ms = time_cpu(mesh, rings, region, motion, options, 1, 1, r.cpu1_ms, r.cpu1_spread, nullptr);
    const DeformationQuality q = measure_quality(mesh.positions, final_positions, mesh.triangles, region.s);
    r.volume_error = q.volume_error_percent;
    r.flipped = q.flipped_triangles;
    if (with_gpu) r.gpu_ms = time_gpu(mesh, rings, region, motion, options, std::min(steps, 25));
    return r;
}

std::string ratio(double paper_ms, double ours) {
    if (paper_ms <= 0.0 || ours <= 0.0) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f×", paper_ms / ours);
    return buf;
}

std::string markdown_table(const std::vector<Result>& results, unsigned threads) {
    std::ostringstream out;
    out << "| model | vertices | blend vertices | ms/step, 1 thread | ms/step, " << threads
        << " threads | total 250 steps | paper ms/step | paper / ours | GPU ms/step | volume error | flipped | bytes/vertex |\n"
        << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    char row[512];
    for (const Result& r : results) {
        std::snprintf(row, sizeof row, "| %s | %zu | %zu | %.2f ±%.0f%% | %.2f ±%.0f%% | %.0f ms | %s | %s | %s | %.3f %% | %zu | %.0f |\n",
                      r.model.name.c_str(), r.vertices, r.blend_vertices, r.cpu1_ms, 100 * r.cpu1_spread, r.cpu_ms,
                      100 * r.cpu_spread, r.total_ms, r.model.paper_ms > 0 ? std::to_string(int(r.model.paper_ms)).c_str() : "",
                      ratio(r.model.paper_ms, r.cpu_ms).c_str(), r.gpu_ms >= 0 ? (std::to_string(r.gpu_ms).substr(0, 6)).c_str() : "",
                      r.volume_error, r.flipped, r.bytes_per_vertex);
        out << row;
    }
    return out.str();
}

std::string data_lines(const std::vector<Result>& results) {
    std::ostringstream out;
    out << "# vertices cpu1_ms cpuN_ms gpu_ms (gpu -1: not run)\n";
    for (const Result& r : results) out << r.vertices << ' ' << r.cpu1_ms << ' ' << r.cpu_ms << ' ' << r.gpu_ms << '\n';
    return out.str();
}

}  // namespace

// A bend of the top of the mesh's longest axis by about 45°: s = 0 on the top
// 15 %, 1 on the bottom 40 %, linear between; the curve leaves the top along the
// axis and turns toward the next axis.
void bench_region_and_curve(const TriangleMesh& mesh, Region& region, BezierCurve& curve) {
    const BoundingBox box = bounding_box(mesh.positions);
    const Vec3 e = box.extent();
    const int a = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const int p = (a + 1) % 3;
    const double lo = box.min[a], length = e[a];
    region.s.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        region.s[v] = std::clamp((box.max[a] - 0.15 * length - mesh.positions[v][a]) / (0.45 * length), 0.0, 1.0);
    Vec3 axis(0.0), side(0.0);
    axis[a] = 1.0;
    side[p] = 1.0;
    Vec3 c0 = box.centre();
    c0[a] = lo + length;
    const double r = 0.5 * length;
    curve = BezierCurve(
        {c0, c0 + 0.3 * r * axis, c0 + 0.55 * r * axis + 0.15 * r * side, c0 + 0.7 * r * axis + 0.35 * r * side});
}

void apply_threads_option(const Args& args) {
    if (!args.has("threads")) return;
    const double threads = args.get_number("threads", 0);
    if (threads < 1 || threads != static_cast<int>(threads)) throw UsageError("--threads expects a positive integer");
    set_parallel_thread_limit(static_cast<unsigned>(threads));
}

std::vector<std::string> paper_scene_files() {
    std::vector<std::string> paths;
    const std::string dir = std::string(VFSD_SOURCE_DIR) + "/assets/scenes/";
    for (const char* file : {"fig11-armadillo-arm-painted.json", "armadillo-claw-raised.json",
                             "fig14-cylinder-knot.json", "fig13-bar-handle-bend.json"}) {
        const Scene scene = load_scene(dir + file);
        std::error_code ec;
        if (scene.mesh.rfind("builtin:", 0) == 0 || std::filesystem::exists(scene.mesh, ec))
            paths.push_back(dir + file);
        else
            std::printf("(%s skipped: its mesh is not here; scripts/get-cgal-meshes)\n", file);
    }
    return paths;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

int run_bench(const Args& args) {
    if (args.has("picking")) return run_picking_bench(args);
    if (args.has("latency")) return run_latency_bench(args);
    if (args.has("gpu-schemes")) return run_gpu_schemes_bench(args);
    if (args.has("fold-tests")) return run_fold_tests_bench(args);
    args.expect({"quick", "only", "markdown", "data", "steps", "repeat", "no-gpu", "busy"}, 0, 0);
    const bool quick = args.has("quick");
    const int steps = static_cast<int>(args.get_number("steps", quick ? 10 : 250));
    const int repeat = static_cast<int>(args.get_number("repeat", quick ? 1 : 3));
    if (steps < 1 || repeat < 1) throw UsageError("--steps and --repeat must be positive");
    bool with_gpu = !args.has("no-gpu");
    std::unique_ptr<gpu::Context> context;
    try {
        if (with_gpu) context = gpu::create_headless_context();
    } catch (const Error& e) {
        std::fprintf(stderr, "bench: no GPU backend (%s)\n", e.what());
        with_gpu = false;
    }
    if (context) std::printf("GPU backend: %s (%s)\n", context->renderer().c_str(), context->kind().c_str());
    std::optional<BusyProcess> busy;
    if (args.has("busy")) {
        busy.emplace();
        std::printf("a busy process runs beside the bench (on %u hardware threads)\n",
                    std::thread::hardware_concurrency());
    }
    std::vector<Result> results;
    const std::string only = args.has("only") ? args.get("only") : "";
    for (const Model& m : models(quick)) {
        if (m.name.find(only) == std::string::npos) continue;
        results.push_back(run_model(m, steps, repeat, with_gpu));
        const Result& r = results.back();
        std::printf(
            "%-22s %9zu vertices  %8.3f ms/step (1 thread; mean %.3f)  %8.3f ms/step (%u threads; mean %.3f)  "
            "gpu %8.3f  vol %.3f%%  flips %zu  %.0f B/vertex\n",
            m.name.c_str(), r.vertices, r.cpu1_ms, r.cpu1_mean_ms, r.cpu_ms, parallel_thread_count(), r.cpu_mean_ms,
            r.gpu_ms, r.volume_error, r.flipped, r.bytes_per_vertex);
        std::fflush(stdout);
    }
    if (args.has("markdown")) write_file_atomically(args.get("markdown"), markdown_table(results, parallel_thread_count()));
    if (args.has("data")) write_file_atomically(args.get("data"), data_lines(results));
    return kExitOk;
}

}  // namespace vfsd::cli
