#include "scene/scene_run.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "deform/quality.h"
#include "mesh/subdivision.h"

namespace vfsd {
namespace {

constexpr int kChecks = 10;            // the folds are counted at every tenth of unit time
constexpr std::size_t kMaxGrowth = 2;  // a refined mesh has at most twice the input's vertices

// One run from t = 0 to the target time, its folds watched.
SceneRun run_once(const PreparedScene& p, const StartDeformation& start, const RunProgress& progress, int refinements) {
    SceneRun run;
    run.refinements = refinements;
    run.deformation.emplace(start ? start(p) : p.start_deformation());
    Deformation& d = *run.deformation;
    const int chunk = std::max(1, d.options().steps / 50);
    const double target = p.scene.target_time;
    const bool controlled = d.error_controlled();
    for (int check = 1;; ++check) {
        // The folds are counted at every tenth of unit time short of the target,
        // which are times the fold repair acts at (deform/fold_repair.h), and at
        // the target, after the step that reaches at or past each: the steps are
        // those of a run straight to the target, as in the editors. Fixed steps
        // advance to their grid's first time at or past it, in chunks (an
        // asynchronous backend waits for its steps once per chunk); error-
        // controlled ones run toward the target uncut. Cut short at every tenth,
        // error-controlled steps took more steps (the raised claw 37, not 32)
        // and gave another result than the editors' run of the same scene; and
        // counted at tenths of the way to a target short of 1 (0.06, 0.12, ...
        // for 0.6), the folds the repair leaves between its times refined a
        // scene that folds at none of them.
        const double tenth = double(check) / kChecks;
        const bool at_target = tenth >= target;
        const double time = at_target ? target : tenth;
        const double until =
            controlled || at_target ? target : std::min(target, grid_time_at_or_after(time, d.options().steps));
        while (d.time() < time && d.advance(until, controlled ? 1 : chunk) > 0)
            if (progress) progress(d, refinements);
        const std::vector<std::uint32_t> folded =
            flipped_triangle_list(p.file.mesh.positions, d.positions(), p.file.mesh.triangles);
        if (!folded.empty() && run.watch.first_step < 0) {
            run.watch.first_step = static_cast<int>(d.step_milliseconds().size());
            run.watch.first_time = d.time();
        }
        std::vector<std::uint32_t> all;
        std::set_union(run.watch.folded.begin(), run.watch.folded.end(), folded.begin(), folded.end(),
                       std::back_inserter(all));
        run.watch.folded = std::move(all);
        if (at_target) {
            run.watch.folded_at_end = folded.size();
            return run;
        }
    }
}

// The triangles that share a corner with one of `triangles` (they included): the
// folded ones and the ring around them, where the turn that folded them is as
// large.
std::vector<std::uint32_t> triangles_around(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles) {
    std::vector<char> corner(mesh.vertex_count(), 0);
    for (std::uint32_t t : triangles)
        for (int k = 0; k < 3; ++k) corner[mesh.triangles[t][k]] = 1;
    std::vector<std::uint32_t> around;
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        const Triangle& c = mesh.triangles[t];
        if (corner[c[0]] || corner[c[1]] || corner[c[2]]) around.push_back(t);
    }
    return around;
}

// Which of two runs to keep: the one that folded fewer triangles at the end (the
// shape the user gets), then fewer over its tenths (the way there).
bool folded_less(const FoldWatch& a, const FoldWatch& b) {
    return std::make_pair(a.folded_at_end, a.folded.size()) < std::make_pair(b.folded_at_end, b.folded.size());
}

RunTried tried(const PreparedScene& p, const SceneRun& run) {
    return {p.file.mesh.vertex_count(), run.watch.folded_at_end, run.watch.folded.size()};
}

}  // namespace

SceneRun run_scene(PreparedScene& prepared, const StartDeformation& start, const RunProgress& progress) {
    const std::size_t vertices_before = prepared.file.mesh.vertex_count();
    SceneRun best = run_once(prepared, start, progress, 0);
    std::vector<RunTried> runs{tried(prepared, best)};
    std::optional<PreparedScene> last;  // the mesh the next refinement starts from
    std::vector<std::uint32_t> folded = best.watch.folded;
    for (int round = 1; round <= prepared.scene.options.fold_refinements && !folded.empty(); ++round) {
        if (!last) last.emplace(prepared);
        refine_at_rest(*last, triangles_around(last->file.mesh, folded));
        if (last->file.mesh.vertex_count() > kMaxGrowth * vertices_before) break;
        std::optional<SceneRun> run;
        try {
            run.emplace(run_once(*last, start, progress, round));
        } catch (const NumericalError&) {
            break;  // keep the best run that finished
        }
        runs.push_back(tried(*last, *run));
        folded = run->watch.folded;
        if (folded_less(run->watch, best.watch)) {  // the first of equals stays
            best = std::move(*run);
            prepared = *last;
        }
    }
    best.vertices_before = vertices_before;
    best.tried = std::move(runs);
    return best;
}

void refine_at_rest(PreparedScene& prepared, const std::vector<std::uint32_t>& triangles) {
    RefinedMesh refined = refine_triangles(prepared.file.mesh, triangles);
    std::vector<double>& s = prepared.region.s;
    for (const auto& [a, b] : refined.parents) s.push_back(0.5 * (s[a] + s[b]));
    MeshFile& file = prepared.file;
    file.mesh = std::move(refined.mesh);
    file.file_to_mesh.resize(file.mesh.vertex_count());
    std::iota(file.file_to_mesh.begin(), file.file_to_mesh.end(), 0u);
    file.file_triangles = file.mesh.triangles;
    prepared.rings = build_vertex_rings(file.mesh);
}

}  // namespace vfsd
