#pragma once
// A whole scene's run to its target time, as `vfsd deform` and `vfsd battery`
// run it: the deformation advanced to the target in the steps of a run straight
// there (as the editors advance it), the folds counted at every tenth of unit
// time on the way, which are fold repair times, and at the target (after the
// step that reaches at or past each; deform/quality.h), and, where a triangle
// folded anyway, the mesh refined at rest around it and the run started again
// from t = 0.
//
// Beyond the paper (docs/method.md, "Refining where a triangle folds"): the
// flow's map is smooth and one-to-one, but the mesh shows it through flat
// triangles between their corners' images. Where the map turns through a large
// angle across one triangle (a coarse mesh twisted by more than its triangles
// can follow: a CAD mesh's long slivers, a box's crease), the flat triangle can
// face against its neighbours though every corner is on its path line, and the
// fold repair (deform/fold_repair.h) cannot always place the corners so that
// none does. Halving the triangle's edges halves the turn across each; its new
// vertices start where the old surface was, at rest, and follow their own path
// lines from t = 0, so the result is the same flow seen through a finer mesh.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "deform/deformation.h"
#include "scene/prepared_scene.h"

namespace vfsd {

// What the fold count saw on the way.
struct FoldWatch {
    int first_step = -1;  // the steps taken when a fold was first counted (−1: never)
    double first_time = -1.0;
    std::vector<std::uint32_t> folded;  // every triangle counted folded at some tenth or the target, ascending
    std::size_t folded_at_end = 0;      // those folded at the target time
};

// One run that run_scene made: its mesh's vertices and its folds.
struct RunTried {
    std::size_t vertices = 0;
    std::size_t folded_at_end = 0;
    std::size_t folded_over_tenths = 0;  // at some tenth of unit time on the way, or at the target
};

struct SceneRun {
    std::optional<Deformation> deformation;  // the kept run's, at the target time
    FoldWatch watch;                         // the kept run's
    int refinements = 0;                     // refinements of the mesh this run had
    std::size_t vertices_before = 0;         // the mesh's vertices before it was refined
    std::vector<RunTried> tried;             // every run made, the first (unrefined) first
};

// Starts a deformation of the prepared scene (the CPU's by default; the GPU's:
// gpu/gpu_deformation.h).
using StartDeformation = std::function<Deformation(const PreparedScene&)>;
// Called every few steps (a fiftieth of fixed steps, each error-controlled
// one): the deformation so far and the refinements behind it.
using RunProgress = std::function<void(const Deformation&, int refinements)>;

// Runs `prepared` to its scene's target time. Where triangles fold, refines them
// and the triangles around their corners (refine_at_rest) and runs again, then
// refines that mesh where its run folded, and so on, at most
// prepared.scene.options.fold_refinements times and while the mesh has at most
// twice the input's vertices; returns the run that folded fewest triangles at
// the target time, of those the one that folded fewest over its tenths (the
// first of equals), and `prepared` keeps the mesh that run
// belongs to. Throws what the first run's deformation throws (NumericalError on
// a non-finite position); a refined run that throws ends the refinement.
SceneRun run_scene(PreparedScene& prepared, const StartDeformation& start = {}, const RunProgress& progress = {});

// Splits the edges of `triangles` at rest (mesh/subdivision.h, refine_triangles):
// s is interpolated along each split edge, the rings are built again, and the
// file's layout becomes the refined welded mesh.
void refine_at_rest(PreparedScene& prepared, const std::vector<std::uint32_t>& triangles);

}  // namespace vfsd
