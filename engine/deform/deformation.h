#pragma once
// A deformation in progress: the mesh's positions at the current time t, moved
// toward a target time by fixed RK4 steps (sec. 5). Forward and backward both
// work; the time grid is k / steps, so integrating back returns along it.
//
// Every step runs the four passes of deform/passes.h in order. The region is
// either a surface field s (sec. 3, r = s) or the implicit sphere tool of [23].

#include <optional>
#include <vector>

#include "curve/inner_motion.h"
#include "deform/local_frame.h"
#include "deform/passes.h"
#include "deform/volume_keeper.h"
#include "field/stream_gauge.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

struct DeformationOptions {
    int steps = 250;               // RK4 steps from t = 0 to t = 1 (sec. 7.1: 200–300)
    int smoothing_steps = 10;      // Laplacian steps on ∇r per integration step
    double smoothing_weight = 0.5; // how far each step moves ∇r toward its ring mean
    // Estimate normals and ∇r at the predicted middle of each step (second order)
    // rather than at its start as sec. 5 does (first order in time).
    bool gradients_at_midpoint = true;
    // Beyond the paper, to keep its promise on any scene (docs/method.md,
    // "Keeping the promise"); all three false is sec. 5 as printed:
    bool fit_stream_gauge = true;    // fit the stream's gauge to the blend region every step (field/stream_gauge.h)
    bool tangent_smoothing = false;  // keep ∇r tangent while smoothing it (sec. 5) instead of smoothing it in space
    bool keep_volume = true;         // undo the scheme's volume drift after every step (deform/volume_keeper.h)
};

// Whether the GPU passes (engine/gpu) take every step these options ask for: they
// mirror sec. 5 with either smoothing, not the stream gauge fit or the volume keeper.
bool gpu_mirrors(const DeformationOptions& options);
// Why the GPU does not take options it does not mirror (for messages).
extern const char* const kGpuUnmirroredReason;
// The options with the steps only the CPU takes turned off.
DeformationOptions gpu_mirrored(DeformationOptions options);

// Which part of the shape moves: s per vertex (0 full, 1 none), or the sphere tool.
struct Region {
    std::vector<double> s;
    std::optional<SphereTool> sphere_tool;
};

// The next time after `time` on the way to `target`: the neighbouring grid point
// k / steps, or `target` itself when that comes first. Both backends step so.
double next_time_on_grid(double time, double target, int steps);

class Deformation {
public:
    // Throws InputError when sizes disagree or options are out of range.
    Deformation(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                DeformationOptions options = {});

    // Integrates toward `target` (clamped to [0,1]) taking at most `max_steps`
    // steps; returns the number taken. Throws NumericalError naming the step and
    // vertex if a position becomes non-finite (the positions before that step are kept).
    int advance(double target, int max_steps = 1 << 30);

    double time() const { return time_; }
    // In the input's vertex order (the steps work in a breadth-first order).
    const std::vector<Vec3>& positions() const;
    const Region& region() const { return region_; }
    const InnerMotion& motion() const { return motion_; }
    const DeformationOptions& options() const { return options_; }
    // Bytes held by the deformation state: positions, work arrays, s, rings, region parts.
    std::size_t state_bytes() const;
    // Wall time of every step taken so far, in milliseconds.
    const std::vector<double>& step_milliseconds() const { return step_ms_; }
    // The volume drift the keeper undid over all steps so far, in percent of the
    // volume before (0 with keep_volume off or on an open surface): the error the
    // field's discretisation alone would have left.
    double volume_restored_percent() const;

private:
    void step(double h);
    void check_finite(const std::vector<Vec3>& candidate) const;
    void estimate_surface_gradients(const std::vector<Vec3>& at);
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
    double time_ = 0.0;
    // Per-step work arrays, sized once. The outer region never moves, so
    // positions_, next_ and midpoints_ hold the same outer positions throughout.
    RegionParts parts_;
    std::vector<Vec3> normals_, gradients_, next_, midpoints_;
    SmoothingScratch smoothing_;
    bool have_gradients_ = false;  // gradients_ hold the last step's ∇r
    std::vector<double> step_ms_;
    std::vector<std::uint32_t> gauge_samples_;  // the blend vertices the stream's gauge is fitted to
    std::optional<GaugeFit> gauge_fit_;         // the last step's fit (at its midpoints)
    VolumeKeeper volume_;
    double volume_restored_ = 0.0;  // Σ |drift undone|
};

}  // namespace vfsd
