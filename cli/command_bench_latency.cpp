// vfsd bench --latency [--quick] [--only TEXT] [--scene FILE] [--tolerance T | --steps N] [--reference-steps N]
//                     [--repeat N] [--threads N | --busy] [--no-reference]
//
// What a user waits for after an edit, on the 53k and 2M cylinders' bench bend
// and on the paper-figure scenes the docs measure (or on --scene FILE alone):
// the mesh is open and its rings built (an editor has both; not timed), then
// - a curve edit: the motion built, the deformation made and integrated from
//   t = 0 to 1 with error-controlled steps (deform/deformation.h);
// - the same curve edit with the rest state kept: the deformation started from
//   what an earlier run on the same mesh, region and options built at rest (the
//   editors' case for every curve edit after the first, deform/cpu_steps.h);
// - a region edit: s computed first (sec. 6), then the same;
// - the way back: from the run with the rest state kept, at t = 1, the time
//   dragged back to 0.9, 0.8, ..., 0.1, one after the other (where the fold
//   repair acted on the way, each way back across it repeats the way out from
//   rest, or from a checkpoint: deform/deformation.h); the steps in brackets,
//   and the first of them (back to 0.9) apart.
// Against a reference of N fixed steps (default 2000) on the same prepared scene:
// the largest and the 99.9th-percentile vertex distance, over the mesh's size
// (centred_diameter, the tolerance's unit), and the folds of both. Timings are
// medians over --repeat runs. --steps N runs N fixed steps instead, to compare
// schemes at equal steps. --busy runs it all beside a process spinning on one
// core, each repeat on all threads and then on one, and prints both and their
// ratio (the default thread count is to be no slower than one there).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>

#include "base/error.h"
#include "base/parallel.h"
#include "cli/busy_process.h"
#include "cli/commands.h"
#include "deform/cpu_steps.h"
#include "deform/quality.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "scene/prepared_scene.h"

namespace vfsd::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A mesh as an editor holds it: read, with its rings.
struct OpenMesh {
    Scene scene;  // the scene file's, or the default options for the bench bend
    bool bench_bend = false;
    MeshFile file;
    VertexRings rings;
};

struct LatencyCase {
    std::string name;
    std::function<OpenMesh()> open;
    // The region (s) on the open mesh: what a region edit computes.
    std::function<Region(const OpenMesh&, BezierCurve&)> region;
    bool reference = true;  // a 2M-vertex reference of 2000 steps takes minutes: skipped
};

// vfsd bench's bend of a built-in cylinder.
LatencyCase bench_case(const std::string& name, const std::string& spec, bool reference) {
    LatencyCase c;
    c.name = name;
    c.open = [spec] {
        OpenMesh m;
        m.scene.mesh = spec;
        m.bench_bend = true;
        m.file.mesh = load_mesh(spec);
        m.rings = build_vertex_rings(m.file.mesh);
        return m;
    };
    c.region = [](const OpenMesh& m, BezierCurve& curve) {
        Region region;
        bench_region_and_curve(m.file.mesh, region, curve);
        return region;
    };
    c.reference = reference;
    return c;
}

LatencyCase scene_case(const std::string& path) {
    LatencyCase c;
    c.name = std::filesystem::path(path).stem().string();
    c.open = [path] {
        OpenMesh m;
        m.scene = load_scene(path);
        m.file = load_mesh_file(m.scene.mesh);
        m.rings = build_vertex_rings(m.file.mesh);
        return m;
    };
    c.region = [](const OpenMesh& m, BezierCurve&) {
        std::vector<std::string> warnings;
        return build_region(m.scene.region, m.file.mesh.positions, m.rings, warnings);
    };
    return c;
}

// The scene ready to integrate, from the open mesh and the region: the motion
// built (the bench bend's along its curve, with the default options).
PreparedScene prepare(const OpenMesh& m, Region region, const BezierCurve& curve) {
    if (!m.bench_bend) return prepare_scene(m.scene, m.file, m.rings, std::move(region));
    PreparedScene p;
    p.file = m.file;
    p.rings = m.rings;
    p.region = std::move(region);
    p.motion = InnerMotion::along_curve(curve, InnerMotionMode::Rotation, 0.0, 0.0);
    return p;
}

std::vector<LatencyCase> cases(bool quick, const std::string& scene) {
    if (!scene.empty()) return {scene_case(scene)};
    if (quick) return {bench_case("box bend", "builtin:box:8", true)};
    std::vector<LatencyCase> list{bench_case("cylinder 53k bend", "builtin:cylinder:163", true)};
    for (const std::string& path : paper_scene_files()) list.push_back(scene_case(path));
    list.push_back(bench_case("cylinder 2M bend", "builtin:cylinder:1000", false));
    return list;
}

struct Run {
    std::vector<Vec3> positions;
    int steps = 0;
    StepErrors errors;
    std::shared_ptr<const CpuRest> rest;  // what a later curve edit may start from
};

Run finish(Deformation& d) {
    Run run;
    run.steps = d.advance(1.0);
    run.positions = d.positions();
    run.errors = d.step_errors();
    run.rest = d.cpu_rest();
    return run;
}

// The prepared scene moved into the deformation, as the editors do.
Run integrate(PreparedScene p, const DeformationOptions& options) {
    p.scene.options = options;
    Deformation d = std::move(p).start_deformation();
    return finish(d);
}

// The deformation from an earlier run's rest state, as the editors make it for a curve edit.
Deformation start_from(const std::shared_ptr<const CpuRest>& rest, PreparedScene p, const DeformationOptions& options) {
    if (!rest || !rest->fits(p.file.mesh.positions, p.rings, p.region, options))
        throw std::logic_error("the rest state does not fit its own scene");
    return Deformation(rest, std::move(p.motion), options);
}

// One case's timings (ms) over the repeats, and the way back's steps.
struct EditTimes {
    std::vector<double> region, curve_edit, rest_kept, region_edit, way_back, first_back;
    int way_back_steps = 0, first_back_steps = 0;
};

// One repeat of a case's edits, timed into `times`: the region, the curve edit
// (with `tolerance`, or `fixed_steps` when positive) and the same from the
// rest state it left; the scene as prepared into `p` (for the reference).
Run time_edits(const LatencyCase& c, const OpenMesh& open, double tolerance, int fixed_steps, EditTimes& times,
               PreparedScene& p) {
    BezierCurve curve;
    const auto start = Clock::now();
    Region region = c.region(open, curve);
    const double region_time = ms_since(start);
    const auto edit = Clock::now();
    PreparedScene prepared = prepare(open, std::move(region), curve);
    const double prepare_time = ms_since(edit);
    p = prepared;  // for the reference, not timed
    DeformationOptions options = p.scene.options;
    options.tolerance = tolerance;
    if (fixed_steps > 0) options.steps = fixed_steps;
    const auto run_start = Clock::now();
    Run run = integrate(std::move(prepared), options);
    const double curve_edit = prepare_time + ms_since(run_start);
    times.region.push_back(region_time);
    times.curve_edit.push_back(curve_edit);
    times.region_edit.push_back(region_time + curve_edit);
    // The same curve edit again, from the rest state the run left.
    Region same = p.region;  // the editor holds the region: not timed
    const auto kept = Clock::now();
    Deformation d = start_from(run.rest, prepare(open, std::move(same), curve), options);
    const Run from_rest = finish(d);
    times.rest_kept.push_back(ms_since(kept));
    if (from_rest.positions != run.positions)
        throw std::logic_error(c.name + ": the run from the kept rest state differs from the run");
    // The time dragged back from there in tenths.
    const auto back = Clock::now();
    times.way_back_steps = 0;
    for (int tenth = 9; tenth >= 1; --tenth) {
        times.way_back_steps += d.advance(tenth / 10.0);
        if (tenth == 9) times.first_back.push_back(ms_since(back)), times.first_back_steps = times.way_back_steps;
    }
    times.way_back.push_back(ms_since(back));
    return run;
}

std::size_t folds(const PreparedScene& p, const std::vector<Vec3>& positions) {
    return flipped_triangle_list(p.file.mesh.positions, positions, p.file.mesh.triangles).size();
}

}  // namespace

int run_latency_bench(const Args& args) {
    args.expect({"latency", "quick", "only", "scene", "tolerance", "steps", "reference-steps", "repeat", "threads",
                 "no-reference", "busy"},
                0, 0);
    const bool quick = args.has("quick");
    if (args.has("busy") && args.has("threads"))
        throw UsageError("--busy times all threads and one: it takes no --threads");
    const double tolerance = args.get_number("tolerance", kSceneTolerance);
    if (!(tolerance > 0.0 && tolerance <= 0.1)) throw UsageError("--tolerance expects more than 0, at most 0.1");
    const int fixed_steps = static_cast<int>(args.get_number("steps", 0));
    if (args.has("steps") && fixed_steps < 1) throw UsageError("--steps expects a positive integer");
    const int reference_steps = static_cast<int>(args.get_number("reference-steps", quick ? 200 : 2000));
    if (reference_steps < 1) throw UsageError("--reference-steps expects a positive integer");
    const int repeat = std::max(1, static_cast<int>(args.get_number("repeat", quick ? 1 : 3)));
    apply_threads_option(args);
    const std::string only = args.has("only") ? args.get("only") : "";
    const std::string scene = args.has("scene") ? args.get("scene") : "";
    if (fixed_steps > 0)
        std::printf("edit to final shape, t = 0 to 1, %d fixed steps, %u threads; reference: %d fixed steps\n",
                    fixed_steps, parallel_thread_count(), reference_steps);
    else
        std::printf(
            "edit to final shape, t = 0 to 1, tolerance %g of the mesh's size, %u threads; reference: %d "
            "fixed steps\n",
            tolerance, parallel_thread_count(), reference_steps);
    // With --busy, all threads and one take turns on each repeat, beside a busy process.
    std::optional<BusyProcess> busy;
    std::vector<unsigned> limits{0};
    if (args.has("busy")) {
        busy.emplace();
        limits.push_back(1);
        std::printf("a busy process runs beside the bench; all %u threads and one take turns\n",
                    parallel_thread_count());
    }
    std::printf("%-30s %9s %9s %10s %10s %11s %6s %8s %11s %11s %12s %17s %17s\n", "scene", "vertices", "region",
                "curve edit", "rest kept", "region edit", "steps", "rejected", "max dev", "99.9% dev", "folds / ref",
                "way back (steps)", "first (steps)");
    for (const LatencyCase& c : cases(quick, scene)) {
        if (!only.empty() && c.name.find(only) == std::string::npos) continue;
        const OpenMesh open = c.open();
        std::vector<EditTimes> times(limits.size());
        PreparedScene p;
        Run run;
        for (int r = 0; r < repeat; ++r)
            for (std::size_t k = 0; k < limits.size(); ++k) {
                if (busy) set_parallel_thread_limit(limits[k]);
                run = time_edits(c, open, fixed_steps > 0 ? 0.0 : tolerance, fixed_steps, times[k], p);
            }
        if (busy) set_parallel_thread_limit(0);
        const double size = centred_diameter(p.file.mesh.positions);
        char deviation[2][32] = {"-", "-"}, fold_text[32];
        std::snprintf(fold_text, sizeof fold_text, "%zu / -", folds(p, run.positions));
        if (c.reference && !args.has("no-reference")) {
            DeformationOptions fixed = p.scene.options;
            fixed.tolerance = 0.0;
            fixed.steps = reference_steps;
            const Run reference = integrate(p, fixed);
            std::vector<double> distance(run.positions.size());
            for (std::size_t v = 0; v < distance.size(); ++v)
                distance[v] = glm::length(run.positions[v] - reference.positions[v]) / size;
            std::sort(distance.begin(), distance.end());
            std::snprintf(deviation[0], sizeof deviation[0], "%.2e", distance.back());
            std::snprintf(deviation[1], sizeof deviation[1], "%.2e", distance[distance.size() * 999 / 1000]);
            std::snprintf(fold_text, sizeof fold_text, "%zu / %zu", folds(p, run.positions),
                          folds(p, reference.positions));
        }
        for (std::size_t k = 0; k < limits.size(); ++k) {
            const EditTimes& t = times[k];
            const std::string name =
                busy ? c.name + (limits[k] == 1 ? " [1 thread]"
                                                : " [" + std::to_string(parallel_thread_count()) + " threads]")
                     : c.name;
            std::printf(
                "%-30s %9zu %6.1f ms %7.1f ms %7.1f ms %8.1f ms %6d %8d %11s %11s %12s %8.1f ms (%4d) %8.1f ms (%4d)\n",
                name.c_str(), p.file.mesh.vertex_count(), median(t.region), median(t.curve_edit), median(t.rest_kept),
                median(t.region_edit), run.steps, run.errors.rejected, deviation[0], deviation[1], fold_text,
                median(t.way_back), t.way_back_steps, median(t.first_back), t.first_back_steps);
        }
        if (busy)
            std::printf("%-30s all threads over one: curve edit %.2f, rest kept %.2f, region edit %.2f\n",
                        c.name.c_str(), median(times[0].curve_edit) / median(times[1].curve_edit),
                        median(times[0].rest_kept) / median(times[1].rest_kept),
                        median(times[0].region_edit) / median(times[1].region_edit));
        std::fflush(stdout);
    }
    return kExitOk;
}

}  // namespace vfsd::cli
