// vfsd battery --out DIR [--seed N] [--count K] [--mesh-dir DIR [--any-mesh]] [--coarse]
//              [--worst K] [--steps N | --tolerance T [--reference-steps N [--baseline-steps M]
//              [--reference-check]]] [--threads N] [--only INDEX]
//
// --tolerance runs error-controlled steps (deform/deformation.h); with
// --reference-steps each scene also runs that many fixed steps, and the
// report gives the largest vertex distance between the two and their folds
// (--baseline-steps: and M fixed steps' distance from the N; --reference-check:
// the N's distance from 2N fixed steps, whether the reference has converged).
//
// Generates K scenes nobody tuned (engine/scene/battery.h: built-in and given
// meshes, placed at random, regions of every kind, curves, handles, twists of
// both signs, both inner motions), deforms each on the CPU and measures what the
// method promises. Writes DIR/battery.json (every scene and its figures),
// DIR/battery.csv and, for the K worst scenes, a scene file with its placed mesh
// that `vfsd deform` reproduces and (with headless GL) a picture at t = 1.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <tuple>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "base/parallel.h"
#include "cli/commands.h"
#include "cli/runs_json.h"
#include "deform/quality.h"
#include "gpu/context.h"
#include "io/png.h"
#include "mesh/geometry.h"
#include "render/renderer.h"
#include "scene/battery.h"
#include "scene/framing.h"
#include "scene/prepared_scene.h"
#include "scene/scene_run.h"

namespace vfsd::cli {
namespace {

struct Outcome {
    BatteryScene battery;
    DeformationQuality quality;
    double first_fold_time = -1.0;       // the first tenth of t at which a triangle had folded; −1: none
    double ms_per_step = 0.0;
    FoldRepairStats repairs;
    double repair_shift_over_diagonal = 0.0;  // the fold repair's largest move of a vertex in a step, / diagonal
    std::vector<std::string> warnings;
    std::string error;  // the deformation failed (a non-finite vertex): the scene fails
    std::vector<Vec3> result;
    TriangleMesh rest;               // the mesh result belongs to: the scene's, or refined where it folded
    std::vector<double> s;           // on rest
    int refinements = 0;             // runs started again on a refined mesh (scene/scene_run.h)
    std::size_t vertices_added = 0;  // by those refinements
    std::vector<RunTried> runs;      // every run made, the input mesh's first
    int steps = 0, rejected = 0;     // the kept run's steps, and those rejected by the step control
    double estimated_error = 0.0;    // the sum of its steps' error estimates, over the mesh's size
    // With --reference-steps: the largest and the 99.9th-percentile distance to that
    // many fixed steps' result, over the mesh's size (−1: the two runs refined
    // differently), and its folds; the same distances for --baseline-steps.
    double reference_distance = -1.0, reference_distance_p999 = -1.0;
    double baseline_distance = -1.0, baseline_distance_p999 = -1.0;
    std::size_t reference_folds = 0;
    // With --reference-check: the largest distance from the reference to twice its
    // steps, over the mesh's size (−1: not run, or refined differently): how far
    // the reference itself is from converged.
    double reference_convergence = -1.0;

    bool failed() const {
        return !error.empty() || quality.flipped_triangles > 0 || quality.outer_max_displacement != 0.0 ||
               quality.inner_rigid_residual > 1e-9 || quality.nonfinite_vertices > 0;
    }
};

// A run's result and the mesh it ran on (the input's, or one refined where it folded).
struct RunResult {
    std::vector<Vec3> positions;
    TriangleMesh rest;
};

// The scene's result in `steps` fixed steps (nothing when it fails).
std::optional<RunResult> run_fixed_steps(const Outcome& o, int steps, std::size_t* folds) {
    Scene scene = o.battery.scene;
    scene.options.tolerance = 0.0;
    scene.options.steps = steps;
    PreparedScene prepared = prepare_scene(scene, o.battery.mesh);
    try {
        const SceneRun run = run_scene(prepared);
        RunResult out{run.deformation->positions(), prepared.file.mesh};
        if (folds) *folds = flipped_triangle_list(out.rest.positions, out.positions, out.rest.triangles).size();
        return out;
    } catch (const NumericalError&) {
        return std::nullopt;
    }
}

// The largest and the 99.9th-percentile distance between two results over the
// rest mesh's size; −1 when they ran on different meshes (refined differently:
// the same number of vertices is no proof of the same mesh).
std::pair<double, double> result_distance(const RunResult& a, const RunResult& b) {
    if (a.positions.empty() || a.positions.size() != b.positions.size() || a.rest.positions != b.rest.positions ||
        a.rest.triangles != b.rest.triangles)
        return {-1.0, -1.0};
    std::vector<double> distance(a.positions.size());
    for (std::size_t v = 0; v < a.positions.size(); ++v) distance[v] = glm::length(a.positions[v] - b.positions[v]);
    std::sort(distance.begin(), distance.end());
    const double size = centred_diameter(a.rest.positions);
    return {distance.back() / size, distance[distance.size() * 999 / 1000] / size};
}

// How far the outcome's result, and the scene's in `baseline_steps` fixed steps
// (0: none), are from `reference_steps` fixed steps; with `check`, how far those
// are from twice as many.
void compare_with_fixed_steps(Outcome& o, int reference_steps, int baseline_steps, bool check) {
    const auto reference = run_fixed_steps(o, reference_steps, &o.reference_folds);
    if (!reference) return;
    std::tie(o.reference_distance, o.reference_distance_p999) = result_distance({o.result, o.rest}, *reference);
    if (check)
        if (const auto finer = run_fixed_steps(o, 2 * reference_steps, nullptr))
            o.reference_convergence = result_distance(*reference, *finer).first;
    if (baseline_steps <= 0) return;
    if (const auto baseline = run_fixed_steps(o, baseline_steps, nullptr))
        std::tie(o.baseline_distance, o.baseline_distance_p999) = result_distance(*baseline, *reference);
}

Outcome run_battery_scene(BatteryScene b) {
    Outcome o;
    o.battery = std::move(b);
    PreparedScene prepared = prepare_scene(o.battery.scene, o.battery.mesh);
    o.warnings = prepared.warnings;
    try {
        const SceneRun run = run_scene(prepared);
        const Deformation& d = *run.deformation;
        o.first_fold_time = run.watch.first_time;
        o.refinements = run.refinements;
        o.vertices_added = prepared.file.mesh.vertex_count() - run.vertices_before;
        o.runs = run.tried;
        o.result = d.positions();
        o.ms_per_step = median(d.step_milliseconds());
        o.repairs = d.fold_repairs();
        o.steps = static_cast<int>(d.step_milliseconds().size());
        o.rejected = d.step_errors().rejected;
        o.estimated_error = d.step_errors().sum;
    } catch (const NumericalError& e) {
        o.error = e.what();
        o.result = prepared.file.mesh.positions;
    }
    o.rest = prepared.file.mesh;
    o.s = prepared.region.s;
    o.quality = measure_quality(o.rest.positions, o.result, o.rest.triangles, prepared.region.s);
    o.repair_shift_over_diagonal = o.repairs.max_shift / bounding_box(o.rest.positions).diagonal();
    return o;
}

nlohmann::json outcome_json(const Outcome& o) {
    const BatteryScene& b = o.battery;
    return {{"name", b.name},
            {"mesh", b.mesh_source},
            {"vertices", b.mesh.mesh.vertex_count()},
            {"region", b.region_kind},
            {"motion", b.motion_kind},
            {"inner_motion", b.scene.motion.inner_motion == InnerMotionMode::Rotation ? "rotation" : "translation"},
            {"bend_degrees", b.bend_degrees},
            {"move_over_inner", b.move_over_inner},
            {"twist_degrees", b.twist_degrees},
            {"blend_rings", b.blend_rings},
            {"scale", b.placement.scale},
            {"mirrored", b.placement.mirrors()},
            {"offset_over_diagonal", glm::length(b.placement.offset) / bounding_box(b.mesh.mesh.positions).diagonal()},
            {"flipped_triangles", o.quality.flipped_triangles},
            {"reversed_triangles", o.quality.reversed_triangles},
            {"first_fold_time", o.first_fold_time},
            {"volume_defined", o.quality.volume_defined},
            {"volume_error_percent", o.quality.volume_error_percent},
            {"volume_change_percent", o.quality.volume_change_percent},
            {"outer_max_displacement", o.quality.outer_max_displacement},
            {"inner_rigid_residual", o.quality.inner_rigid_residual},
            {"ms_per_step", o.ms_per_step},
            {"fold_repair_steps", o.repairs.steps_repaired},
            {"fold_untangle_steps", o.repairs.steps_untangled},
            {"fold_repair_vertex_moves", o.repairs.vertex_moves},
            {"fold_repair_max_shift_over_diagonal", o.repair_shift_over_diagonal},
            {"refinements", o.refinements},
            {"steps", o.steps},
            {"rejected_steps", o.rejected},
            {"estimated_error_sum", o.estimated_error},
            {"reference_distance_over_size", o.reference_distance},
            {"reference_distance_over_size_p999", o.reference_distance_p999},
            {"baseline_distance_over_size", o.baseline_distance},
            {"baseline_distance_over_size_p999", o.baseline_distance_p999},
            {"reference_flipped_triangles", o.reference_folds},
            {"reference_convergence_over_size", o.reference_convergence},
            {"vertices_added", o.vertices_added},
            {"runs", runs_json(o.runs)},
            {"warnings", o.warnings},
            {"error", o.error},
            {"passed", !o.failed()}};
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * double(v.size() - 1) + 0.5))];
}

// Scene file + placed mesh that `vfsd deform` reproduces, and a picture.
void write_worst(const std::filesystem::path& dir, int rank, const Outcome& o) {
    const std::string stem = "worst-" + std::to_string(rank) + "-" + o.battery.name;
    write_mesh_file((dir / (stem + ".ply")).string(), o.battery.mesh.mesh);
    Scene scene = o.battery.scene;
    scene.mesh = stem + ".ply";
    write_file_atomically((dir / (stem + ".json")).string(), scene_to_json(scene).dump(1) + "\n");
    try {
        const std::unique_ptr<gpu::Context> context = gpu::create_headless_context();
        const PreparedScene prepared = prepare_scene(o.battery.scene, o.battery.mesh);
        const int width = 640, height = 480;
        const Camera camera = Camera::framing(
            deformation_frame_points(prepared.file.mesh.positions, prepared.region.s, prepared.motion),
            double(width) / height);
        const render::Renderer renderer(o.rest.triangles, prepared.motion);
        render::RenderOptions options;
        options.current_time = options.target_time = prepared.scene.target_time;
        const gpu::Texture vertices = render::make_vertex_texture(o.result, o.s);
        write_png((dir / (stem + ".png")).string(), width, height,
                  render::render_image(renderer, vertices, camera, width, height, options));
    } catch (const vfsd::Error& e) {
        std::fprintf(stderr, "battery: no picture of %s: %s\n", o.battery.name.c_str(), e.what());
    }
}

void write_csv(const std::filesystem::path& path, const std::vector<Outcome>& outcomes) {
    std::ofstream out(path);
    out << "name,vertices,region,motion,inner_motion,bend_degrees,twist_degrees,scale,mirrored,flipped_triangles,"
           "reversed_triangles,first_fold_time,volume_error_percent,volume_change_percent,outer_max_displacement,"
           "inner_rigid_residual,ms_per_step,fold_repair_steps,fold_repair_max_shift_over_diagonal,refinements,"
           "vertices_added,passed\n";
    for (const Outcome& o : outcomes) {
        const nlohmann::json j = outcome_json(o);
        out << j["name"].get<std::string>() << ',' << j["vertices"] << ',' << j["region"].get<std::string>() << ','
            << j["motion"].get<std::string>() << ',' << j["inner_motion"].get<std::string>() << ',' << j["bend_degrees"]
            << ',' << j["twist_degrees"] << ',' << j["scale"] << ',' << j["mirrored"] << ',' << j["flipped_triangles"]
            << ',' << j["reversed_triangles"] << ',' << j["first_fold_time"] << ',' << j["volume_error_percent"] << ','
            << j["volume_change_percent"] << ',' << j["outer_max_displacement"] << ',' << j["inner_rigid_residual"]
            << ',' << j["ms_per_step"] << ',' << j["fold_repair_steps"] << ','
            << j["fold_repair_max_shift_over_diagonal"] << ',' << j["refinements"] << ',' << j["vertices_added"] << ','
            << j["passed"] << '\n';
    }
}

// The mesh files in `dir` that can host battery scenes; the others are named on
// stderr with the reason.
std::vector<std::string> mesh_files_in(const std::string& dir, bool any_surface) {
    std::vector<std::string> files, usable;
    if (dir.empty()) return files;
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) throw vfsd::InputError(dir + ": not a folder");
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl") files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    for (const std::string& file : files) {
        std::string why;
        try {
            why = vfsd::battery_mesh_unusable(vfsd::load_mesh_file(file), any_surface);
        } catch (const vfsd::InputError& e) {
            why = e.what();
        }
        if (why.empty()) usable.push_back(file);
        else std::fprintf(stderr, "battery: skipping %s: %s\n", file.c_str(), why.c_str());
    }
    std::fprintf(stderr, "battery: %zu of %zu mesh files in %s can host scenes\n", usable.size(), files.size(),
                 dir.c_str());
    return usable;
}

int non_negative_int(const Args& args, const char* option, int fallback) {
    const double value = args.get_number(option, fallback);
    if (!(value >= 0.0 && value <= double(std::numeric_limits<int>::max())) || value != std::floor(value))
        throw UsageError(std::string("--") + option + " expects a non-negative integer");
    return static_cast<int>(value);
}

}  // namespace

int run_battery(const Args& args) {
    args.expect({"out", "seed", "count", "mesh-dir", "any-mesh", "mesh", "coarse", "worst", "steps", "tolerance",
                 "reference-steps", "baseline-steps", "reference-check", "threads", "only", "amplitude", "scheme"},
                0, 0);
    const double tolerance = args.get_number("tolerance", 0.0);
    if (!(tolerance >= 0.0 && tolerance <= 0.1)) throw UsageError("--tolerance expects 0 to 0.1");
    if (tolerance > 0.0 && args.has("steps")) throw UsageError("--steps and --tolerance exclude each other");
    const int reference_steps = non_negative_int(args, "reference-steps", 0);
    const int baseline_steps = non_negative_int(args, "baseline-steps", 0);
    const bool reference_check = args.has("reference-check");
    if ((baseline_steps > 0 || reference_check) && reference_steps == 0)
        throw UsageError("--baseline-steps and --reference-check compare with --reference-steps N: give it");
    if (!args.has("out") || args.get("out").empty()) throw UsageError("--out DIR is required");
    const int seed = non_negative_int(args, "seed", 1), count = non_negative_int(args, "count", 30);
    if (count == 0) throw UsageError("--count expects a positive integer");
    const int worst = non_negative_int(args, "worst", 5), steps = non_negative_int(args, "steps", 0);
    const double amplitude = args.get_number("amplitude", 1.0);
    const std::string scheme = args.get("scheme", "default");
    if (scheme != "default" && scheme != "paper" && scheme != "no-repair" && scheme != "no-refinement")
        throw UsageError("--scheme must be 'default', 'paper', 'no-repair' or 'no-refinement'");
    if (!(amplitude > 0.0 && amplitude <= 1.0)) throw UsageError("--amplitude expects a number in (0, 1]");
    if (args.has("threads")) set_parallel_thread_limit(std::max(1, non_negative_int(args, "threads", 0)));
    std::vector<std::string> sources =
        args.has("mesh")
            ? std::vector<std::string>{args.get("mesh")}
            : battery_mesh_sources(mesh_files_in(args.get("mesh-dir"), args.has("any-mesh")), !args.has("coarse"));
    const std::filesystem::path dir = args.get("out");
    std::filesystem::create_directories(dir);

    std::vector<Outcome> outcomes;
    const int first = args.has("only") ? non_negative_int(args, "only", 0) : 0;
    const int last = args.has("only") ? first + 1 : count;
    for (int index = first; index < last; ++index) {
        BatteryScene b = generate_battery_scene(static_cast<std::uint64_t>(seed), index, sources, amplitude);
        if (steps > 0) b.scene.options.steps = steps;
        b.scene.options.tolerance = tolerance;
        if (scheme == "paper") {  // secs. 5 and 6 as printed, for comparison
            b.scene.options = paper_steps(b.scene.options);
            b.scene.options.tangent_smoothing = true;
            b.scene.region.profile = RegionSpec::Profile::geodesic;
        }
        if (scheme == "no-repair" || scheme == "no-refinement") b.scene.options.fold_refinements = 0;
        if (scheme == "no-repair") b.scene.options.repair_folds = false;  // the flow alone
        outcomes.push_back(run_battery_scene(std::move(b)));
        Outcome& o = outcomes.back();
        if (reference_steps > 0 && o.error.empty())
            compare_with_fixed_steps(o, reference_steps, baseline_steps, reference_check);
        char volume[32] = "   (none)";  // a surface with a border encloses no volume
        if (o.quality.volume_defined) std::snprintf(volume, sizeof volume, "%+8.4f%%", o.quality.volume_change_percent);
        std::printf(
            "%-48s %7zu v  folds %5zu (reversed %5zu)  volume %s  outer %.1e  inner %.1e  %6.2f ms/step  "
            "repaired %3zu steps (%.1e D)  refined %d (+%zu v)  %d steps (%d rejected)%s%s%s\n",
            o.battery.name.c_str(), o.battery.mesh.mesh.vertex_count(), o.quality.flipped_triangles,
            o.quality.reversed_triangles, volume, o.quality.outer_max_displacement, o.quality.inner_rigid_residual,
            o.ms_per_step, o.repairs.steps_repaired, o.repair_shift_over_diagonal, o.refinements, o.vertices_added,
            o.steps, o.rejected,
            o.reference_distance >= 0.0
                ? ("  " + std::to_string(reference_steps) + " fixed steps: " + std::to_string(o.reference_distance) +
                   " (99.9 %: " + std::to_string(o.reference_distance_p999) + ") of the size away, " +
                   std::to_string(o.reference_folds) + " folds" +
                   (o.reference_convergence >= 0.0 ? " (" + std::to_string(2 * reference_steps) + " steps: " +
                                                         std::to_string(o.reference_convergence) + " from it)"
                                                   : std::string()) +
                   (o.baseline_distance >= 0.0
                        ? "; " + std::to_string(baseline_steps) + " steps: " + std::to_string(o.baseline_distance) +
                              " (99.9 %: " + std::to_string(o.baseline_distance_p999) + ")"
                        : std::string()))
                      .c_str()
                : "",
            o.error.empty() ? "" : "  error: ", o.error.c_str());
        std::fflush(stdout);
    }

    nlohmann::json scenes = nlohmann::json::array();
    std::vector<double> volume, ms, step_counts;
    double farthest = 0.0, farthest_p999 = 0.0, baseline_farthest = 0.0, baseline_farthest_p999 = 0.0;
    std::size_t within = 0, baseline_within = 0;  // largest distance at most 1e-3 of the size
    std::size_t over_reference_folds = 0, compared = 0;
    // With --reference-check: scenes whose reference is within 1e-3 of twice its
    // steps (converged to the accuracy asked for), and of those, the result within 1e-3.
    std::size_t reference_converged = 0, within_converged = 0;
    std::size_t folded = 0, folds = 0, failed = 0, repaired = 0, reversed_scenes = 0, reversed = 0, refined = 0;
    double outer = 0.0, inner = 0.0, shift = 0.0;
    for (const Outcome& o : outcomes) {
        scenes.push_back(outcome_json(o));
        if (o.quality.volume_defined) volume.push_back(o.quality.volume_error_percent);
        ms.push_back(o.ms_per_step);
        step_counts.push_back(o.steps);
        if (o.reference_distance >= 0.0) {
            ++compared;
            farthest = std::max(farthest, o.reference_distance);
            farthest_p999 = std::max(farthest_p999, o.reference_distance_p999);
            within += o.reference_distance <= 1e-3;
            if (o.reference_convergence >= 0.0 && o.reference_convergence <= 1e-3)
                ++reference_converged, within_converged += o.reference_distance <= 1e-3;
        }
        if (o.baseline_distance >= 0.0) {
            baseline_farthest = std::max(baseline_farthest, o.baseline_distance);
            baseline_farthest_p999 = std::max(baseline_farthest_p999, o.baseline_distance_p999);
            baseline_within += o.baseline_distance <= 1e-3;
        }
        over_reference_folds += reference_steps > 0 && o.quality.flipped_triangles > o.reference_folds;
        folded += o.quality.flipped_triangles > 0;
        folds += o.quality.flipped_triangles;
        reversed_scenes += o.quality.reversed_triangles > 0;
        reversed += o.quality.reversed_triangles;
        failed += o.failed();
        outer = std::max(outer, o.quality.outer_max_displacement);
        inner = std::max(inner, o.quality.inner_rigid_residual);
        repaired += o.repairs.steps_repaired > 0;
        refined += o.refinements > 0;
        shift = std::max(shift, o.repair_shift_over_diagonal);
    }
    const nlohmann::json summary = {{"seed", seed},
                                    {"amplitude", amplitude},
                                    {"scheme", scheme},
                                    {"scenes", outcomes.size()},
                                    {"scenes_failed", failed},
                                    {"scenes_with_folds", folded},
                                    {"flipped_triangles", folds},
                                    {"scenes_with_reversed_triangles", reversed_scenes},
                                    {"reversed_triangles", reversed},
                                    {"scenes_with_volume", volume.size()},
                                    {"volume_error_percent_median", percentile(volume, 0.5)},
                                    {"volume_error_percent_p95", percentile(volume, 0.95)},
                                    {"volume_error_percent_max", percentile(volume, 1.0)},
                                    {"outer_max_displacement", outer},
                                    {"inner_rigid_residual_max", inner},
                                    {"ms_per_step_median", percentile(ms, 0.5)},
                                    {"scenes_repaired", repaired},
                                    {"fold_repair_max_shift_over_diagonal", shift},
                                    {"scenes_refined", refined},
                                    {"tolerance", tolerance},
                                    {"steps_median", percentile(step_counts, 0.5)},
                                    {"steps_max", percentile(step_counts, 1.0)},
                                    {"reference_steps", reference_steps},
                                    {"scenes_compared", compared},
                                    {"reference_distance_over_size_max", farthest},
                                    {"reference_distance_over_size_p999_max", farthest_p999},
                                    {"scenes_within_1e-3", within},
                                    {"scenes_reference_converged", reference_converged},
                                    {"scenes_within_1e-3_reference_converged", within_converged},
                                    {"baseline_steps", baseline_steps},
                                    {"baseline_distance_over_size_max", baseline_farthest},
                                    {"baseline_distance_over_size_p999_max", baseline_farthest_p999},
                                    {"baseline_scenes_within_1e-3", baseline_within},
                                    {"scenes_folding_more_than_reference", over_reference_folds}};
    write_file_atomically((dir / "battery.json").string(),
                          nlohmann::json{{"summary", summary}, {"scenes", scenes}}.dump(1) + "\n");
    write_csv(dir / "battery.csv", outcomes);

    std::vector<const Outcome*> order;
    for (const Outcome& o : outcomes) order.push_back(&o);
    std::stable_sort(order.begin(), order.end(), [](const Outcome* a, const Outcome* b) {
        if (a->quality.flipped_triangles != b->quality.flipped_triangles)
            return a->quality.flipped_triangles > b->quality.flipped_triangles;
        const auto error = [](const Outcome* o) {
            return o->quality.volume_defined ? o->quality.volume_error_percent : 0.0;
        };
        return error(a) > error(b);
    });
    for (int k = 0; k < worst && k < int(order.size()); ++k) write_worst(dir, k + 1, *order[k]);

    const std::string volume_of = volume.size() == outcomes.size()
                                      ? ""
                                      : " (of the " + std::to_string(volume.size()) + " scenes that enclose one)";
    std::printf(
        "battery seed %d, amplitude %g, scheme %s: %zu scenes, %zu failed, %zu with folds (%zu triangles), %zu with "
        "reversed triangles (%zu); volume error%s median %.4f%%, "
        "p95 %.4f%%, max %.4f%%; outer displacement max %.3g; inner rigid residual max %.3g; %.3f ms/step "
        "median; fold repair in %zu scenes (largest move %.2g D); refined in %zu\n",
        seed, amplitude, scheme.c_str(), outcomes.size(), failed, folded, folds, reversed_scenes, reversed,
        volume_of.c_str(), summary["volume_error_percent_median"].get<double>(),
        summary["volume_error_percent_p95"].get<double>(), summary["volume_error_percent_max"].get<double>(), outer,
        inner, summary["ms_per_step_median"].get<double>(), repaired, shift, refined);
    std::printf("steps: median %g, most %g%s\n", percentile(step_counts, 0.5), percentile(step_counts, 1.0),
                tolerance > 0.0 ? " (error-controlled)" : "");
    if (reference_steps > 0)
        std::printf(
            "against %d fixed steps: %zu scenes compared (the others refined differently), %zu within 1e-3 of "
            "the size; largest distance %.3g (99.9th percentile at most %.3g); %zu scenes fold more than it\n",
            reference_steps, compared, within, farthest, farthest_p999, over_reference_folds);
    if (baseline_steps > 0)
        std::printf(
            "%d fixed steps against them: %zu within 1e-3; largest distance %.3g (99.9th percentile at most "
            "%.3g)\n",
            baseline_steps, baseline_within, baseline_farthest, baseline_farthest_p999);
    if (reference_check)
        std::printf(
            "%d fixed steps against them: %zu references within 1e-3 (converged), and %zu of those scenes "
            "within 1e-3 of their reference\n",
            2 * reference_steps, reference_converged, within_converged);
    return failed == 0 ? kExitOk : kExitInput;
}

}  // namespace vfsd::cli
