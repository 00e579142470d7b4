// vfsd bench --gpu-schemes [--only TEXT | --scene FILE] [--steps N]
//
// What the default scheme costs on the GPU path (gpu/gpu_deformation.h), on the
// paper-figure scenes the docs measure (or on --scene FILE alone): ms per step
// over N fixed steps (default 100) after a warm-up step, for sec. 5's passes
// alone and then with the stream gauge's fit, the volume keeper and the fold
// repair added one by one (each ends with a finish(), so the GPU's work is in
// the time); then edit to final shape on the GPU path: the deformation made and
// run to t = 1 with error-controlled steps (the scene's tolerance, default
// 5e-4), median of three.

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "base/error.h"
#include "cli/commands.h"
#include "gpu/context.h"
#include "gpu/gpu_deformation.h"
#include "scene/prepared_scene.h"

namespace vfsd::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// ms per step over `steps` fixed steps, after one warm-up step.
double ms_per_step(const PreparedScene& p, DeformationOptions options, int steps, std::size_t& repaired) {
    options.steps = steps;
    options.tolerance = 0.0;
    Deformation d = gpu::make_gpu_deformation(p.file.mesh.positions, p.rings, p.region, p.motion, options);
    d.advance(1.0 / steps);
    d.finish();
    const auto start = Clock::now();
    const int taken = d.advance(1.0);
    d.finish();
    repaired = d.fold_repairs().steps_repaired;
    return ms_since(start) / taken;
}

}  // namespace

int run_gpu_schemes_bench(const Args& args) {
    args.expect({"gpu-schemes", "only", "scene", "steps"}, 0, 0);
    const int steps = static_cast<int>(args.get_number("steps", 100));
    if (steps < 2) throw UsageError("--steps expects an integer of at least 2");
    const std::string only = args.has("only") ? args.get("only") : "";
    const std::unique_ptr<gpu::Context> context = gpu::create_headless_context();  // throws GpuUnavailable
    std::printf("GPU path on %s (%s): ms per step over %d fixed steps; edit to final shape at the scene's tolerance\n",
                context->renderer().c_str(), context->kind().c_str(), steps);
    std::printf("%-34s %9s %9s %9s %9s %16s %18s %6s %8s\n", "scene", "vertices", "sec. 5", "+ gauge", "+ keeper",
                "+ repair (steps)", "edit to shape", "steps", "rejected");
    const std::vector<std::string> paths =
        args.has("scene") ? std::vector<std::string>{args.get("scene")} : paper_scene_files();
    for (const std::string& path : paths) {
        const std::string name = std::filesystem::path(path).stem().string();
        if (!only.empty() && name.find(only) == std::string::npos) continue;
        const PreparedScene p = prepare_scene(load_scene(path));
        if (p.region.sphere_tool) continue;  // the sphere tool runs on the CPU only
        double scheme_ms[4];
        std::size_t repaired = 0;
        for (int k = 0; k < 4; ++k) {  // sec. 5, then each addition of the default scheme
            DeformationOptions options = p.scene.options;
            options.fit_stream_gauge = k >= 1;
            options.keep_volume = k >= 2;
            options.repair_folds = k >= 3;
            scheme_ms[k] = ms_per_step(p, options, steps, repaired);
        }
        std::vector<double> edit_ms;
        int taken = 0, rejected = 0;
        for (int r = 0; r < 3; ++r) {
            DeformationOptions options = p.scene.options;
            if (!(options.tolerance > 0.0)) options.tolerance = kSceneTolerance;
            const auto start = Clock::now();
            Deformation d = gpu::make_gpu_deformation(p.file.mesh.positions, p.rings, p.region, p.motion, options);
            taken = d.advance(1.0);
            d.finish();
            edit_ms.push_back(ms_since(start));
            rejected = d.step_errors().rejected;
        }
        std::printf("%-34s %9zu %6.2f ms %6.2f ms %6.2f ms %8.2f ms (%zu) %15.1f ms %6d %8d\n", name.c_str(),
                    p.file.mesh.vertex_count(), scheme_ms[0], scheme_ms[1], scheme_ms[2], scheme_ms[3], repaired,
                    median(edit_ms), taken, rejected);
        std::fflush(stdout);
    }
    return kExitOk;
}

}  // namespace vfsd::cli
