#pragma once
// A deformation in progress: the mesh's positions at the current time t, moved
// toward a target time by fixed RK4 steps (sec. 5). Forward and backward both
// work; the time grid is k / steps, so integrating back returns along it.
//
// Deformation is the one integrator: the time grid, the option checks, the
// advance loop, the step timing and the finite check. A StepBackend takes the
// steps: the CPU's passes (deform/cpu_steps.h, the readable reference) or their
// GPU twins (gpu/gpu_deformation.h), which mirror them pass by pass.

#include <memory>
#include <optional>
#include <vector>

#include "base/error.h"
#include "curve/inner_motion.h"
#include "deform/fold_repair.h"
#include "deform/passes.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

namespace gpu {
class Texture;
}

// Each round at most quadruples the triangles it refines.
constexpr int kMaxFoldRefinements = 8;

struct DeformationOptions {
    int steps = 250;                // RK4 steps from t = 0 to t = 1 (sec. 7.1: 200–300)
    int smoothing_steps = 10;       // Laplacian steps on ∇r per integration step
    double smoothing_weight = 0.5;  // how far each step moves ∇r toward its ring mean
    // Estimate normals and ∇r at the predicted middle of each step (second order)
    // rather than at its start as sec. 5 does (first order in time).
    bool gradients_at_midpoint = true;
    // Beyond the paper, to keep its promise on any scene (docs/method.md,
    // "Keeping the promise"); all four false is sec. 5 as printed. The fold
    // repair acts only after a step that folded a triangle; it moves those
    // vertices off their path lines, by the shifts its stats report.
    bool fit_stream_gauge = true;    // fit the stream's gauge to the blend region every step (field/stream_gauge.h)
    bool tangent_smoothing = false;  // keep ∇r tangent while smoothing it (sec. 5) instead of smoothing it in space
    bool keep_volume = true;         // undo the scheme's volume drift after every step (deform/volume_keeper.h)
    bool repair_folds = true;        // place a folded triangle's blend vertices again (deform/fold_repair.h)
    // A whole scene's run (scene/scene_run.h), not a Deformation, reads this: how
    // many times to refine the mesh at rest where triangles folded anyway and run
    // again from t = 0; 0: never.
    int fold_refinements = 6;
};

// Throws InputError when an option is out of range.
void check_options(const DeformationOptions& options);

// The options with the steps beyond sec. 5 turned off (the stream gauge fit, the
// volume keeper, the fold repair and the refinement): with tangent smoothing
// and the geodesic profile, the scheme as printed.
DeformationOptions paper_steps(DeformationOptions options);

// Which part of the shape moves: s per vertex (0 full, 1 none), or the sphere tool.
struct Region {
    std::vector<double> s;
    std::optional<SphereTool> sphere_tool;
};

// The next time after `time` on the way to `target`: the neighbouring grid point
// k / steps, or `target` itself when that comes first.
double next_time_on_grid(double time, double target, int steps);

// The error a non-finite position raises: step `step` (counted from 1) from time
// `time` made input vertex `vertex` non-finite.
NumericalError nonfinite_position(std::size_t vertex, int step, double time);

// Positions a backend keeps on the GPU, for a renderer to draw without a read-back.
struct DeviceVertices {
    const gpu::Texture* texture = nullptr;  // xyz relative to origin, w = s (gpu/texture_layout.h)
    Vec3 origin{0.0};
};

// One backend's steps of sec. 5. Deformation calls step() with the times of its grid.
class StepBackend {
public:
    virtual ~StepBackend() = default;
    virtual const char* name() const = 0;  // "cpu" or "gpu"
    // One RK4 step from `time` by `h` (negative: back), the `step`-th of the
    // deformation. Throws nonfinite_position() when it can tell at once.
    virtual void step(double time, double h, int step) = 0;
    // Does now a piece of what the first step would do before it steps (the CPU:
    // the volume keeper and the fold repair built at rest; ∇r and the gauge at
    // the start), so that a caller can give each a frame of its own; true
    // when there was such work. The steps are the same either way.
    virtual bool prepare_first_step() { return false; }
    // The positions at the last step's end, in the input's vertex order.
    virtual const std::vector<Vec3>& positions() const = 0;
    // Whether step() returns before its work is done (the GPU's command queue):
    // then steps are timed over finish(), and positions are checked when read.
    virtual bool asynchronous() const { return false; }
    // Waits until every step issued has been executed.
    virtual void finish() const {}
    virtual std::optional<DeviceVertices> device_vertices() const { return std::nullopt; }
    // What the fold repair (deform/fold_repair.h) did so far; zero where it is off.
    virtual FoldRepairStats fold_repairs() const { return {}; }
};

class Deformation {
public:
    // Throws InputError when the options are out of range.
    Deformation(std::unique_ptr<StepBackend> backend, DeformationOptions options);
    // On the CPU (deform/cpu_steps.h); throws InputError when sizes disagree.
    Deformation(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                DeformationOptions options = {});

    // Integrates toward `target` (clamped to [0,1]) taking at most `max_steps`
    // steps; returns the number taken. Throws NumericalError naming the step and
    // vertex if a position becomes non-finite (on the CPU the positions before
    // that step are kept; the GPU's are checked when read).
    int advance(double target, int max_steps = 1 << 30);
    // StepBackend::prepare_first_step.
    bool prepare_first_step() { return backend_->prepare_first_step(); }

    double time() const { return time_; }
    // In the input's vertex order (the GPU reads them back once per advance).
    const std::vector<Vec3>& positions() const;
    const DeformationOptions& options() const { return options_; }
    // Wall time of every step taken so far, in milliseconds (an asynchronous
    // backend's advance() is timed whole, finish() included, and spread evenly).
    const std::vector<double>& step_milliseconds() const { return step_ms_; }
    // The median of step_milliseconds(): robust to a slow first step.
    double ms_per_step() const;
    const char* backend_name() const { return backend_->name(); }
    void finish() const { backend_->finish(); }
    std::optional<DeviceVertices> device_vertices() const { return backend_->device_vertices(); }
    FoldRepairStats fold_repairs() const { return backend_->fold_repairs(); }

private:
    std::unique_ptr<StepBackend> backend_;
    DeformationOptions options_;
    double time_ = 0.0;
    int steps_taken_ = 0;
    std::vector<double> step_ms_;
    mutable bool checked_ = true;  // positions() has been checked finite since the last advance
};

}  // namespace vfsd
