// vfsd deform SCENE.json --out OUT [--report REPORT.json] [--steps N | --tolerance T] [--backend cpu|gpu]
//             [--field-out FILE] [--force]
//
// Runs the scene's deformation from t = 0 to its target time and writes the
// deformed mesh in the input's vertex order and layout, and a measured report.
// Where triangles fold, the run is repeated on a mesh refined there
// (scene/scene_run.h); the mesh written is then the refined one, the welded
// input's vertices first.
// --backend gpu runs the same steps as fragment passes (docs/gpu.md) in a headless
// GL context (OSMesa, or EGL in a build with VFSD_HEADLESS_GL=egl); when none can
// be made it exits 1 saying why (no silent fall-back to the CPU). The report names
// the context and renderer.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "cli/commands.h"
#include "cli/runs_json.h"
#include "deform/quality.h"
#include "gpu/context.h"
#include "gpu/gpu_deformation.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "scene/prepared_scene.h"
#include "scene/scene_run.h"

namespace vfsd::cli {
namespace {

void refuse_overwrite(const std::string& out, const std::vector<std::string>& inputs, bool force) {
    std::error_code ec;
    if (!std::filesystem::exists(out, ec)) return;
    for (const std::string& in : inputs)
        if (std::filesystem::exists(in, ec) && std::filesystem::equivalent(in, out, ec))
            throw vfsd::InputError(out + ": is an input of this run; write to another file");
    if (!force) throw vfsd::InputError(out + ": already exists (pass --force to replace it)");
}

// Shows on a terminal how far the run is, and which run after a refinement.
RunProgress terminal_progress() {
    if (!isatty(fileno(stderr))) return {};
    return [](const Deformation& d, int refinements) {
        if (refinements == 0)
            std::fprintf(stderr, "\rdeforming: t = %.3f", d.time());
        else
            std::fprintf(stderr, "\rdeforming the refined mesh (%d): t = %.3f", refinements, d.time());
    };
}

// The report's "folds" and a warning on stderr when triangles folded.
nlohmann::json describe_folds(const PreparedScene& p, const std::vector<Vec3>& after, const FoldWatch& watch) {
    const std::vector<std::uint32_t> folded = flipped_triangle_list(p.file.mesh.positions, after, p.file.mesh.triangles);
    if (folded.empty()) return nlohmann::json::object();
    const FoldWhere where = locate_folds(p.file.mesh.positions, p.file.mesh.triangles, p.region.s, folded);
    std::fprintf(stderr,
                 "warning: %zu triangles folded (first seen after step %d, t = %.3g), around (%.6g, %.6g, %.6g) "
                 "before the deformation, where s is %.3g to %.3g; the report's \"folds\" lists them\n",
                 folded.size(), watch.first_step, watch.first_time, where.centre.x, where.centre.y, where.centre.z,
                 where.s_min, where.s_max);
    constexpr std::size_t kListed = 1000;
    return {{"count", folded.size()},
            {"first_seen_after_step", watch.first_step},
            {"first_seen_at_time", watch.first_time},
            {"centre", {where.centre.x, where.centre.y, where.centre.z}},
            {"s_min", where.s_min},
            {"s_max", where.s_max},
            {"triangles", std::vector<std::uint32_t>(folded.begin(), folded.begin() + std::min(folded.size(), kListed))}};
}

// The report's "refinement" and a note on stderr when the mesh was refined, or
// refined runs were made and none folded fewer than the input's.
nlohmann::json describe_refinement(const PreparedScene& p, const SceneRun& run) {
    if (run.tried.size() <= 1) return nlohmann::json::object();
    if (run.refinements > 0)
        std::fprintf(
            stderr,
            "note: triangles folded, so the mesh was refined where they did and run again from t = 0 (%d "
            "times): the result has %zu vertices, the input's %zu (welded, in their order) and then the new ones\n",
            run.refinements, p.file.mesh.vertex_count(), run.vertices_before);
    else
        std::fprintf(stderr,
                     "note: triangles folded, so the mesh was refined where they did and run again from t = 0 (%zu "
                     "times), but no refined run folded fewer: the result is the input mesh's run\n",
                     run.tried.size() - 1);
    return {{"rounds", run.refinements},
            {"vertices_before", run.vertices_before},
            {"vertices_added", p.file.mesh.vertex_count() - run.vertices_before},
            {"runs", runs_json(run.tried)}};
}

// Each try of the step control as [t, h, estimate, taken].
nlohmann::json step_tries_json(const std::vector<StepTry>& tries) {
    nlohmann::json out = nlohmann::json::array();
    for (const StepTry& t : tries) out.push_back({t.time, t.length, t.error, t.taken});
    return out;
}

nlohmann::json report_json(const PreparedScene& p, const Deformation& d, const DeformationQuality& q,
                           double total_ms) {
    const FoldRepairStats repairs = d.fold_repairs();
    return {{"vertices", p.file.mesh.vertex_count()},
            {"triangles", p.file.mesh.triangle_count()},
            {"steps", d.step_milliseconds().size()},
            {"steps_per_unit_time", d.options().steps},
            // deform/deformation.h: the step control's tolerance and what its estimates saw
            {"step_control",
             {{"error_controlled", d.error_controlled()},
              {"tolerance", d.options().tolerance},
              {"rejected_steps", d.step_errors().rejected},
              {"estimated_step_error_largest", d.step_errors().largest},
              {"estimated_error_sum", d.step_errors().sum},
              {"tries", step_tries_json(d.step_tries())}}},
            {"target_time", d.time()},
            {"backend", d.backend_name()},
            {"ms_per_step", d.ms_per_step()},
            {"total_ms", total_ms},
            {"volume_before", q.volume_before},
            {"volume_after", q.volume_after},
            {"volume_error_percent", q.volume_error_percent},
            {"volume_change_percent", q.volume_change_percent},
            {"volume_defined", q.volume_defined},  // false for an open or non-manifold surface
            {"outer_max_displacement", q.outer_max_displacement},
            {"inner_rigid_residual", q.inner_rigid_residual},
            {"inner_vertices", q.inner_vertices},
            {"outer_vertices", q.outer_vertices},
            {"flipped_triangles", q.flipped_triangles},
            {"reversed_triangles", q.reversed_triangles},  // deform/quality.h: exact for affine maps
            {"nonfinite_vertices", q.nonfinite_vertices},
            // deform/fold_repair.h: steps after which it placed vertices again, and its largest move
            {"fold_repair_steps", repairs.steps_repaired},
            {"fold_untangle_steps", repairs.steps_untangled},
            {"fold_repair_max_shift_over_diagonal", repairs.max_shift / bounding_box(p.file.mesh.positions).diagonal()},
            {"warnings", p.warnings}};
}

// s in the input file's vertex order, one value per line.
void write_field(const std::string& path, const MeshFile& file, const std::vector<double>& s) {
    std::ostringstream out;
    out.precision(17);
    for (std::uint32_t v : file.file_to_mesh) out << s[v] << '\n';
    write_file_atomically(path, out.str());
}

// Integrates to the scene's target time (refining where triangles fold), writes
// the mesh and the report.
int deform_and_write(const Args& args, PreparedScene& prepared, const StartDeformation& start,
                     const nlohmann::json& backend_fields) {
    const auto begin = std::chrono::steady_clock::now();
    const SceneRun run = run_scene(prepared, start, terminal_progress());
    if (isatty(fileno(stderr))) std::fprintf(stderr, "\n");
    const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    const Deformation& deformation = *run.deformation;

    TriangleMesh result = prepared.file.mesh;
    result.positions = deformation.positions();
    result.scalar = prepared.region.s;
    write_mesh_file(args.get("out"), to_file_layout(prepared.file, result));
    if (args.has("field-out")) write_field(args.get("field-out"), prepared.file, prepared.region.s);
    const DeformationQuality quality =
        measure_quality(prepared.file.mesh.positions, result.positions, result.triangles, prepared.region.s);
    nlohmann::json report = report_json(prepared, deformation, quality, total_ms);
    report.update(backend_fields);
    const nlohmann::json refinement = describe_refinement(prepared, run);
    if (!refinement.empty()) report["refinement"] = refinement;
    const nlohmann::json folds = describe_folds(prepared, result.positions, run.watch);
    if (!folds.empty()) report["folds"] = folds;
    if (args.has("report")) write_file_atomically(args.get("report"), report.dump(2) + "\n");
    char volume[64] = "volume undefined (open or non-manifold surface)";
    if (quality.volume_defined) std::snprintf(volume, sizeof volume, "volume error %.4f%%", quality.volume_error_percent);
    std::printf("%s: %zu vertices, %d steps%s, %.3f ms/step, %s, %zu flipped triangles\n", args.get("out").c_str(),
                result.vertex_count(), static_cast<int>(deformation.step_milliseconds().size()),
                deformation.error_controlled() ? " (error-controlled)" : "", report["ms_per_step"].get<double>(),
                volume, quality.flipped_triangles);
    return kExitOk;
}

}  // namespace

int run_deform(const Args& args) {
    args.expect({"out", "report", "steps", "tolerance", "backend", "field-out", "force", "threads"}, 1, 1);
    const std::string scene_path = args.positional(0, "scene file");
    if (!args.has("out") || args.get("out").empty()) throw UsageError("--out OUT is required");
    const std::string backend = args.get("backend", "cpu");
    if (backend != "cpu" && backend != "gpu") throw UsageError("--backend must be 'cpu' or 'gpu'");
    apply_threads_option(args);
    Scene scene = load_scene(scene_path);
    if (args.has("steps")) {
        const double steps = args.get_number("steps", 0);
        if (steps < 1 || steps != static_cast<int>(steps)) throw UsageError("--steps expects a positive integer");
        scene.options.steps = static_cast<int>(steps);
        scene.options.tolerance = 0.0;
    }
    if (args.has("tolerance")) {
        if (args.has("steps"))
            throw UsageError("--steps (fixed steps) and --tolerance (error-controlled) exclude each other");
        const double tolerance = args.get_number("tolerance", 0);
        if (!(tolerance >= 0.0 && tolerance <= 0.1)) throw UsageError("--tolerance expects 0 to 0.1 (of the diagonal)");
        scene.options.tolerance = tolerance;
    }
    const std::vector<std::string> inputs = {scene_path, scene.mesh};
    for (const char* option : {"out", "report", "field-out"})
        if (args.has(option)) refuse_overwrite(args.get(option), inputs, args.has("force"));

    PreparedScene prepared = prepare_scene(scene);
    for (const std::string& w : prepared.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

    if (backend == "cpu") return deform_and_write(args, prepared, {}, nlohmann::json::object());
    const std::unique_ptr<gpu::Context> context = gpu::create_headless_context();  // GpuUnavailable: exit 1
    const StartDeformation on_gpu = [](const PreparedScene& p) {
        return gpu::make_gpu_deformation(p.file.mesh.positions, p.rings, p.region, p.motion, p.scene.options);
    };
    return deform_and_write(args, prepared, on_gpu,
                            {{"gl_context", context->kind()}, {"gl_renderer", context->renderer()}});
}

}  // namespace vfsd::cli
