#pragma once
// The CPU's steps of a deformation (sec. 5), the readable reference the GPU's
// passes mirror: every step runs the four passes of deform/passes.h in order.
// The region is either a surface field s (sec. 3, r = s) or the implicit sphere
// tool of [23]. Deformation (deform/deformation.h) walks the time grid over it.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "deform/deformation.h"
#include "deform/fold_repair.h"
#include "deform/local_frame.h"
#include "deform/passes.h"
#include "deform/volume_keeper.h"
#include "field/stream_gauge.h"

namespace vfsd {

// What a CPU deformation computes before its first step and its motion does not
// change: the work order, the local frame and the region's parts, the volume
// keeper and the fold repair at rest, and ∇r, the normals and the gauge's fit at
// rest. An editor keeps it across curve edits (every event of a curve drag
// restarts the run from t = 0) and starts the next deformation of the same mesh,
// region and options from it: the steps are the same, bit for bit.
struct CpuRest {
    // The input it was built from, to tell whether another deformation fits it.
    std::vector<Vec3> input_positions;  // in the input's order
    std::uint64_t rings_hash = 0;       // of the input's rings (FNV-1a over their lists)
    DeformationOptions options;
    // In the work order: vertex i is input vertex order[i] (mesh/vertex_order.h),
    // positions in frame's local coordinates (deform/local_frame.h).
    LocalFrame frame;
    std::vector<std::uint32_t> order;
    VertexRings rings;
    std::vector<double> s;
    std::vector<Vec3> positions;
    RegionParts parts;
    std::vector<std::uint32_t> gauge_samples;  // the blend vertices the stream's gauge is fitted to
    std::vector<std::uint32_t> gauge_in_blend;  // their positions in parts.blend (their ∇r records)
    double size = 0.0;                         // centred_diameter at rest, in frame's units
    // Built before the first step (CpuSteps::prepare_first_step, a part a call), then kept.
    bool keepers_begun = false, keepers_built = false;
    VolumeKeeper volume;
    FoldRepair fold_repair;
    bool estimated = false;                              // the estimates at rest (with midpoint gradients only)
    std::vector<Vec3> normals, area_vectors;             // per blend vertex (parts.blend)
    GradientRecords gradients;
    std::optional<GaugeFit> gauge_fit;

    // Whether a deformation of these positions, rings, region and options may start from it.
    bool fits(const std::vector<Vec3>& positions, const VertexRings& input_rings, const Region& region,
              const DeformationOptions& other) const;
    std::size_t bytes() const;
};

class CpuSteps final : public StepBackend {
public:
    // Throws InputError when sizes disagree.
    CpuSteps(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
             DeformationOptions options);
    // From what an earlier deformation built at rest, as its cpu_rest() handed it
    // out (CpuRest::fits must hold for it: the same mesh, region and options);
    // std::invalid_argument for a rest state not yet built.
    CpuSteps(std::shared_ptr<const CpuRest> rest, InnerMotion motion, DeformationOptions options);

    const char* name() const override { return "cpu"; }
    StepResult step(double time, double h, int step, double max_error) override;
    bool estimates_error() const override { return !region_.sphere_tool && options_.gradients_at_midpoint; }
    std::vector<double> motion_joins() const override { return motion_.joins(); }
    bool prepare_first_step() override;
    std::optional<StepResult> prepare_step(double time, double h, int step, double max_error) override;
    const std::vector<Vec3>& positions() const override;
    FoldRepairStats fold_repairs() const override;
    std::shared_ptr<const CpuRest> cpu_rest() const override;
    bool restarts() const override;
    void restart() override;
    void release_scratch() override { fold_repair_.release_scratch(); }
    std::unique_ptr<StepBackend> snapshot() const override;
    void restore(const StepBackend& snapshot) override;
    std::size_t snapshot_bytes() const override;

    // Bytes held by the deformation state: positions, work arrays, s, rings, region parts, the rest state.
    std::size_t state_bytes() const;

private:
    void check_finite(const std::vector<Vec3>& candidate, int step, double time) const;
    void estimate_surface_gradients(const std::vector<Vec3>& at);
    void estimate_at_start(double time);
    StepResult estimate_try(double time, double h, double max_error);
    void move(double time, double h, int step);
    // What settle_move found: whether the step is taken and the fold repair acts.
    struct FoldTest {
        enum Verdict { clean, land, repair } verdict = clean;
        double land_at = -1.0;  // land: the repair's time the step is tried again to end on
        bool measured = false;  // repair: the test's measures kept for the repair (FoldRepair::count_folds)
    };
    FoldTest settle_move(double time, double h, double max_error, bool test_all);
    void repair_folds(double time, double h, double max_error, bool measured, StepResult& result);
    bool prepared_for(double time, double h, double max_error) const;
    void start_from_rest();
    double estimate_error(const MotionSample& middle, double h, double span) const;
    double motion_error(const StepMotion& full, const StepMotion& first_half, double time, double h) const;
    bool build_keeper_part();
    void build_keepers() {
        while (build_keeper_part()) continue;
    }
    GaugeFit fit_stream_gauge(const std::vector<Vec3>& at) const;
    MotionSample sample_at(double time) const;
    void estimate_keeper_velocity(const std::vector<Vec3>& at, const MotionSample& sample);
    KeeperVelocity keeper_velocity() const;
    Vec3 gradient_at_sample(std::size_t j) const;

    // rest_ holds what does not change over the steps (null for the sphere tool);
    // building_ is the same object where this deformation built it (null where
    // it came built): build_keepers and the first estimate at rest write to it,
    // before cpu_rest() hands it out, and nothing after. positions_ are in the work order
    // and the local frame (the identity for the sphere tool); input_order_ holds
    // the input's positions, of which positions() overwrites the moving ones, so
    // the outer region is handed back bit for bit.
    std::shared_ptr<const CpuRest> rest_;
    std::shared_ptr<CpuRest> building_;
    LocalFrame frame_;
    std::vector<Vec3> positions_;
    mutable std::vector<Vec3> input_order_;  // positions() for a work order
    mutable bool input_order_current_ = false;
    Region region_;  // the sphere tool's; s is in rest_
    InnerMotion motion_;
    DeformationOptions options_;
    // Per-step work arrays, sized once. The outer region never moves, so
    // positions_, next_ and midpoints_ hold the same outer positions throughout.
    std::vector<Vec3> normals_, next_, midpoints_;
    GradientRecords gradients_;       // ∇r on the blend region
    std::vector<Vec3> area_vectors_;  // per blend vertex, where normals_ were taken: the volume keeper's ∂V/∂x
    double keeper_lambda_ = 0.0;      // λ of the keeper's velocity where normals_ were taken
    double area_norm_ = 0.0;          // the keeper's area_norm(area_vectors_), taken wherever they are
    SmoothingScratch smoothing_;
    bool have_gradients_ = false;               // gradients_ hold the last step's ∇r
    double gradient_time_ = 0.0;                // the time gradients_ were estimated for
    std::vector<Vec3> sample_gradients_;        // ∇r at the gauge's samples before this step's estimate
    std::optional<GaugeFit> gauge_fit_;         // the last step's fit (at its midpoints)
    FoldRepair fold_repair_;
    // The try prepare_step() estimated (and moved into next_, and tested there),
    // for the step() from the same time by the same h.
    struct PreparedTry {
        double time, h, max_error;
        StepResult estimate;
        bool moved = false;
        bool tested = false;
        FoldTest test;
    };
    std::optional<PreparedTry> prepared_;
};

}  // namespace vfsd
