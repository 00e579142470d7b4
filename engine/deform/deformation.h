#pragma once
// A deformation in progress: the mesh's positions at the current time t, moved
// toward a target time by RK4 steps (sec. 5). Forward and backward both work.
// The steps are either fixed, on the grid k / steps (sec. 7.1), or, beyond the
// paper, error-controlled: each step's error is estimated and its length
// follows (StepControl below); the times reached are kept, so integrating back
// returns along them either way.
//
// Deformation is the one integrator: the time grid, the step control, the option
// checks, the advance loop, the step timing and the finite check. A StepBackend takes the
// steps: the CPU's passes (deform/cpu_steps.h, the readable reference) or their
// GPU twins (gpu/gpu_deformation.h), which mirror them pass by pass.

#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <string>
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
struct CpuRest;

// Each round at most quadruples the triangles it refines.
constexpr int kMaxFoldRefinements = 8;

struct DeformationOptions {
    int steps = 250;  // fixed RK4 steps from t = 0 to t = 1 (sec. 7.1: 200–300)
    // Error-controlled steps when > 0 (then `steps` is unused): each step's
    // estimated error (StepBackend::step) is kept at most this fraction of the
    // mesh's size at rest (centred_diameter, mesh/geometry.h: a cube's bounding
    // box diagonal, and the same however the mesh is turned), and the steps grow
    // and shrink to match.
    double tolerance = 0.0;
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

// The first grid point k / steps at or after `time`: where fixed steps that
// pass `time` end (a join aside).
double grid_time_at_or_after(double time, int steps);

// The step control's constants: the first step's length, the bounds on a step's
// length, and how much one step's length may grow or shrink the next's.
struct StepControl {
    static constexpr double kFirstStep = 1.0 / 32.0;
    static constexpr double kLongestStep = 0.25;
    static constexpr double kShortestStep = 1e-5;  // taken whatever its error
    static constexpr double kMostGrowth = 2.5, kMostShrink = 0.2, kSafety = 0.9;
    // The next step's length after a step of length h with estimated error
    // `error` (the estimate grows as h², sec. "Error-controlled steps" of docs/method.md).
    static double next_length(double h, double error, double tolerance);
    // The length to try after a step of length h rejected with estimated error
    // `error`: h · 0.9 √(tolerance / error) as well, at most h / 2, and at least
    // h / 10 rather than kMostShrink's h / 5, which after an estimate far over
    // the tolerance (the raised claw's first step of 1/32: 34 times) left the
    // retry too long, and rejected again.
    static constexpr double kMostShrinkRetry = 0.1;
    static double retry_length(double h, double error, double tolerance);
    // The next step's length after two taken steps in a row, the last of
    // length h: `length` (next_length's, which takes the estimate's coefficient
    // error / h² to stay as it was) unless the coefficient grew, from `last` to
    // `coefficient` over `apart` (the time between the steps' middles). Then it
    // is taken to grow on at that rate to the next step's middle, and the step
    // is as long as the tolerance allows there, at most `length` and at least
    // kMostShrink · h (a predictive control, as Gustafsson's). Where the estimate
    // grows along the way (the raised claw's last fifth: its coefficient doubled
    // every 0.02), the length that kept the last step within the tolerance
    // takes the next one over it, and it is tried again shorter.
    static double foreseen_length(double h, double length, double last, double coefficient, double apart,
                                  double tolerance);
};

// What the step control saw: its estimates are relative to the mesh's size (centred_diameter).
struct StepErrors {
    int rejected = 0;         // steps tried, estimated over the tolerance and tried again shorter
    // Over the error-controlled steps taken (each once: forward beyond the times
    // reached; steps back and retraced ones are not estimated).
    double largest = 0.0;     // the largest estimate
    double sum = 0.0;         // their sum: an estimate of the error at the furthest time reached
    int estimated_steps = 0;  // the steps estimated
};

// One try of the step control: the step from `time` of `length`, its estimate
// (relative to the mesh's size; −1 where none was made), and whether it was
// taken or tried again shorter.
struct StepTry {
    double time = 0.0;
    double length = 0.0;
    double error = 0.0;
    bool taken = false;
};

// The error a non-finite position raises: step `step` (counted from 1) from time
// `time` made input vertex `vertex` non-finite.
NumericalError nonfinite_position(std::size_t vertex, int step, double time);

// Positions a backend keeps on the GPU, for a renderer to draw without a read-back.
struct DeviceVertices {
    const gpu::Texture* texture = nullptr;  // xyz relative to origin, w = s (gpu/texture_layout.h)
    Vec3 origin{0.0};
};

// What one call of StepBackend::step did.
struct StepResult {
    bool taken = true;    // false: the estimate was over the bound and nothing moved
    double error = -1.0;  // the step's estimated error / the mesh's size (< 0: none)
    // prepare_step only: the device has not finished the last piece's passes,
    // and this call did nothing.
    bool waiting = false;
    // A fold repair's time the next error-controlled step ends on (−1: none;
    // deform/fold_repair.h): not taken, the step passed it and left a fold,
    // and is tried again to end there; taken, the repair acted after it, and
    // the next repair time, where it likely acts again, is landed on at once.
    double land_at = -1.0;
};

// What Deformation::prepare_step did.
enum class StepPiece {
    none,     // nothing: no piece is left before the next advance() (or at the target)
    done,     // a piece of the next step
    retried,  // a piece that ended its try (over the tolerance, or to end on a fold repair's time):
              // nothing moved, and the next piece starts the step again
    waiting,  // nothing yet: the device is still running the last piece (ask again later)
};

// One backend's steps of sec. 5. Deformation calls step() with the times of its grid.
class StepBackend {
public:
    virtual ~StepBackend() = default;
    virtual const char* name() const = 0;  // "cpu" or "gpu"
    // One RK4 step from `time` by `h` (negative: back), the `step`-th of the
    // deformation. With a finite `max_error`, a backend that estimates_error()
    // estimates the step's error once ∇r is known at the step's middle, before
    // it moves anything; when that is over `max_error` it returns {false,
    // estimate} and the step may be tried again shorter (an infinite one: no
    // estimate, error −1). Throws nonfinite_position() when it can tell at once.
    virtual StepResult step(double time, double h, int step, double max_error) = 0;
    // Whether step() estimates its error (the surface field with midpoint ∇r);
    // the step control needs it, and steps are fixed without.
    virtual bool estimates_error() const { return false; }
    // The times at which the motion's curve has a join (0 < t < 1): a step
    // ends on each rather than straddle the kink in ċ.
    virtual std::vector<double> motion_joins() const { return {}; }
    // Does now a piece of what the first step would do before it steps (the CPU:
    // the volume keeper and the fold repair built at rest; ∇r and the gauge at
    // the start), so that a caller can give each a frame of its own; true
    // when there was such work. The steps are the same either way.
    virtual bool prepare_first_step() { return false; }
    // Does now the next piece of the step() from `time` by `h` with `max_error`
    // (the `step`-th), so that a long step can be spread over frames (the CPU:
    // first ∇r and the gauge at its middle with the error estimate, then the
    // move, then where the step passes a fold repair's time the volume keeper
    // and the fold test, which may end the try to land on that time; the repair
    // is left to step(); the GPU:
    // the same passes, each piece's issued with a fence, and a piece whose fence
    // has not passed returns `waiting` and does nothing). Returns that try's result
    // so far, or nothing when no piece is left before step(). A try it finds
    // over `max_error` is over (not taken): no step() follows for it. The
    // step() from the same time by the same h then does the rest: the same step
    // as one call makes.
    virtual std::optional<StepResult> prepare_step(double /*time*/, double /*h*/, int /*step*/, double /*max_error*/) {
        return std::nullopt;
    }
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
    // What a later CPU deformation of the same mesh, region and options may start
    // from (deform/cpu_steps.h), once built: null until then, and on the GPU.
    virtual std::shared_ptr<const CpuRest> cpu_rest() const { return nullptr; }
    // Whether restart() can go back to the rest positions and the state a
    // deformation starts from, so that the steps forward from t = 0 repeat the
    // way out: on the CPU once its rest state is built, on the GPU once its
    // set-up is done; not for the sphere tool, which then steps back.
    virtual bool restarts() const { return false; }
    virtual void restart() {}
    // A copy of the state the steps go on from (its scratch left out), for a
    // way back to start from instead of rest (Deformation's checkpoints); null
    // where the backend cannot copy it (the GPU). restore() returns to it: the
    // steps forward from there are those from the state it was copied in.
    virtual std::unique_ptr<StepBackend> snapshot() const { return nullptr; }
    virtual void restore(const StepBackend& /*snapshot*/) {}
    // Bytes a snapshot() holds of its own (what it shares with this one not counted).
    virtual std::size_t snapshot_bytes() const { return 0; }
    // Frees what a run holds only on its way (the fold repair's sums, deform/fold_repair.h):
    // Deformation::advance calls it when it reaches its target.
    virtual void release_scratch() {}
};

class Deformation {
public:
    // Throws InputError when the options are out of range.
    Deformation(std::unique_ptr<StepBackend> backend, DeformationOptions options);
    // On the CPU (deform/cpu_steps.h); throws InputError when sizes disagree.
    Deformation(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                DeformationOptions options = {});
    // On the CPU, from an earlier deformation's rest state (CpuRest::fits must
    // hold for the mesh, region and options): the same steps, without building
    // what does not depend on the motion again.
    Deformation(std::shared_ptr<const CpuRest> rest, InnerMotion motion, DeformationOptions options);

    // Integrates toward `target` (clamped to [0,1]) taking at most `max_steps`
    // steps; returns the number taken. Back across a time after which the fold
    // repair moved vertices, which no step back undoes, forward across one from
    // positions that steps back gave, and back to t = 0, it starts again from
    // rest where the backend can (StepBackend::restart) and repeats the way
    // out's steps and tries: its shapes, bit for bit, and at t = 0 the rest
    // positions. A backend that waits for its steps (the
    // CPU) also stops after the first step taken that ends `budget_ms` or more
    // after the call (the tries rejected before it included): at least one step,
    // and the same steps however the calls divide them. Throws NumericalError
    // naming the step and vertex if a position becomes non-finite (on the CPU the
    // positions before that step are kept; the GPU's are checked when read).
    // With `stop_before_affine_test`, it also stops before a step (not the
    // first) that passes a time of the fold repair's affine test, the longest of
    // steps (next_step_tests_affine), so that a caller can run that one in pieces.
    int advance(double target, int max_steps = 1 << 30, double budget_ms = std::numeric_limits<double>::infinity(),
                bool stop_before_affine_test = false);
    // Whether advance(target) starts again from rest (above).
    bool rewinds_to(double target) const;
    // Whether the next step toward `target` passes a time of the fold repair's
    // affine test (FoldRepair::affine_test_due), where a step takes about two
    // to three times as long as others.
    bool next_step_tests_affine(double target) const;
    // StepBackend::prepare_first_step.
    bool prepare_first_step() { return backend_->prepare_first_step(); }
    // The next piece of the next step toward `target` (StepBackend::prepare_step;
    // a try found over the tolerance is noted as advance() notes it); the next
    // advance() toward the same target completes the step: the steps are the
    // same bit for bit. None when no piece is left before that advance(), where
    // the backend does not split its steps, or at the target. Its time counts
    // to that step's (an asynchronous backend's step: the time from its first
    // piece to its end, the GPU's work and the frames between included).
    StepPiece prepare_step(double target);

    double time() const { return time_; }
    // Whether the steps are error-controlled (options().tolerance > 0 and a backend that estimates).
    bool error_controlled() const { return controlled_; }
    const StepErrors& step_errors() const { return errors_; }
    // Every error-controlled step tried, in order (steps forward beyond the
    // times reached; steps back and retraced ones are not tried).
    const std::vector<StepTry>& step_tries() const { return tries_; }
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
    std::shared_ptr<const CpuRest> cpu_rest() const { return backend_->cpu_rest(); }

private:
    std::unique_ptr<StepBackend> backend_;
    DeformationOptions options_;
    double next_time(double target, bool& controlled) const;
    double max_error(double next, bool controlled) const;
    void note_step(double next, bool controlled, const StepResult& result);
    void rewind(double target);
    void keep_checkpoint(double from, double to, double target);
    // The next step toward `target`: where it ends, its bound, whether it is a
    // controlled step, and whether it repeats a try of the way out (rewind).
    struct NextStep {
        double end = 0.0, max_error = 0.0;
        bool controlled = false, repeated = false;
    };
    NextStep next_step(double target) const;

    double time_ = 0.0;
    int steps_taken_ = 0;
    std::vector<double> repaired_;  // the ends of the steps forward the fold repair acted after, ascending
    // After a rewind, the next of tries_ to repeat: the way out's tries, the
    // rejected ones too (each leaves its ∇r to the next), so that the steps
    // repeat its bits; none (npos) once a try does not start where it did.
    std::size_t repeat_ = std::string::npos;
    bool stepped_back_ = false;  // the positions come from steps back, not from the way out
    // Whether the positions are the way out's: from rest (or a checkpoint) by its
    // tries, or by fixed steps on the grid, none cut short and none back.
    bool on_way_out_ = true;
    // States of the way out (StepBackend::snapshot) that a way back starts from
    // instead of rest: after the first step at or past each fifth of unit time
    // short of 1 once a way back has started again, and before that, once the
    // fold repair has acted, at the last fifth short of the target alone (so a
    // run the repair leaves alone copies nothing), while the copies fit
    // kCheckpointBytes.
    struct Checkpoint {
        double time = 0.0;
        int steps_taken = 0;
        std::size_t repeat = std::string::npos;  // the next of tries_ to repeat from there
        std::unique_ptr<StepBackend> state;
    };
    static constexpr int kCheckpointsPerUnit = 5;
    static constexpr std::size_t kCheckpointBytes = std::size_t(128) << 20;
    std::vector<Checkpoint> checkpoints_;  // ascending in time
    std::size_t checkpoint_bytes_ = 0;
    bool rewound_ = false;  // a way back started again
    // The error-controlled schedule: every time reached forward, ascending (0
    // first); a step forward from grid_.back() is controlled, any other step
    // runs between the times already on it.
    bool controlled_ = false;
    std::vector<double> grid_{0.0};
    std::vector<double> joins_;
    double forced_landing_ = -1.0;  // a repair time the next controlled step ends on (StepResult::land_at)
    double next_length_ = StepControl::kFirstStep;
    bool just_rejected_ = false;
    // The last taken step's estimate / h² (−1: none) and the time of its middle.
    double last_coefficient_ = -1.0, last_middle_ = 0.0;
    StepErrors errors_;
    std::vector<StepTry> tries_;
    std::vector<double> step_ms_;
    double prepared_ms_ = 0.0;     // prepare_step()'s time, counted to the step it prepared
    std::optional<std::chrono::steady_clock::time_point> first_piece_;  // of the next step (asynchronous backends)
    mutable bool checked_ = true;  // positions() has been checked finite since the last advance
};

}  // namespace vfsd
