#pragma once
// The CPU's steps of a deformation (sec. 5), the readable reference the GPU's
// passes mirror: every step runs the four passes of deform/passes.h in order.
// The region is either a surface field s (sec. 3, r = s) or the implicit sphere
// tool of [23]. Deformation (deform/deformation.h) walks the time grid over it.

#include <vector>

#include "deform/deformation.h"
#include "deform/fold_repair.h"
#include "deform/local_frame.h"
#include "deform/passes.h"
#include "deform/volume_keeper.h"
#include "field/stream_gauge.h"

namespace vfsd {

class CpuSteps final : public StepBackend {
public:
    // Throws InputError when sizes disagree.
    CpuSteps(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
             DeformationOptions options);

    const char* name() const override { return "cpu"; }
    StepResult step(double time, double h, int step, double max_error) override;
    bool estimates_error() const override { return !region_.sphere_tool && options_.gradients_at_midpoint; }
    std::vector<double> motion_joins() const override { return motion_.joins(); }
    bool prepare_first_step() override;
    const std::vector<Vec3>& positions() const override;
    FoldRepairStats fold_repairs() const override;

    // Bytes held by the deformation state: positions, work arrays, s, rings, region parts.
    std::size_t state_bytes() const;
    // The volume drift the keeper undid over all steps so far, in percent of the
    // volume before (0 with keep_volume off or on an open surface): the error the
    // field's discretisation alone would have left.
    double volume_restored_percent() const;

private:
    void check_finite(const std::vector<Vec3>& candidate, int step, double time) const;
    void estimate_surface_gradients(const std::vector<Vec3>& at);
    void estimate_at_start(double time);
    double estimate_error(const MotionSample& middle, double h, double span) const;
    double motion_error(const StepMotion& full, const StepMotion& first_half, double time, double h) const;
    bool build_keepers();
    GaugeFit fit_stream_gauge(const std::vector<Vec3>& at) const;

    // positions_, rings_ and s_ are in the work order: vertex i is input vertex
    // order_[i] (mesh/vertex_order.h); order_ is empty for the sphere tool.
    // positions_ are in frame_'s local coordinates (deform/local_frame.h), the
    // identity for the sphere tool; input_order_ holds the input's positions, of
    // which positions() overwrites the moving ones, so the outer region is
    // handed back bit for bit.
    LocalFrame frame_;
    std::vector<Vec3> positions_;
    VertexRings rings_;
    std::vector<std::uint32_t> order_;
    std::vector<double> s_;
    mutable std::vector<Vec3> input_order_;  // positions() for a work order
    mutable bool input_order_current_ = false;
    Region region_;
    InnerMotion motion_;
    DeformationOptions options_;
    // Per-step work arrays, sized once. The outer region never moves, so
    // positions_, next_ and midpoints_ hold the same outer positions throughout.
    RegionParts parts_;
    std::vector<Vec3> normals_, gradients_, next_, midpoints_;
    std::vector<Vec3> area_vectors_;  // per blend vertex, where normals_ were taken: the volume keeper's ∂V/∂x
    SmoothingScratch smoothing_;
    bool have_gradients_ = false;               // gradients_ hold the last step's ∇r
    double gradient_time_ = 0.0;                // the time gradients_ were estimated for
    double size_ = 0.0;                         // centred_diameter at rest, in frame_'s units
    std::vector<Vec3> sample_gradients_;        // ∇r at gauge_samples_ before this step's estimate
    std::vector<std::uint32_t> gauge_samples_;  // the blend vertices the stream's gauge is fitted to
    std::optional<GaugeFit> gauge_fit_;         // the last step's fit (at its midpoints)
    bool keepers_built_ = false;  // volume_ and fold_repair_, at rest (build_keepers)
    VolumeKeeper volume_;
    FoldRepair fold_repair_;
    double volume_restored_ = 0.0;  // Σ |drift undone|
};

}  // namespace vfsd
