#pragma once
// A deformation in progress on the GPU: the same steps, time grid and interface
// as Deformation (deform/deformation.h), with the state in textures (sec. 5).
// advance() reads nothing back; positions() reads the vertex texture back on
// demand (one counted read-back, cached until the next advance()).
//
// Needs a current GL context for its whole life (gpu/context.h). The sphere tool
// region is not supported on the GPU (the constructor throws GpuUnavailable).

#include <vector>

#include "deform/deformation.h"
#include "gpu/gpu_passes.h"

namespace vfsd::gpu {

class GpuDeformation {
public:
    // Throws InputError as Deformation does, GpuUnavailable / GpuError for the GPU.
    GpuDeformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region, InnerMotion motion,
                   DeformationOptions options = {});

    // Integrates toward `target` (clamped to [0,1]) taking at most `max_steps`
    // steps on the grid k / steps; returns the number taken. No read-back.
    int advance(double target, int max_steps = 1 << 30);

    double time() const { return time_; }
    // The positions at time(), read back from the vertex texture. Throws
    // NumericalError if one is non-finite (the GPU cannot stop mid-loop to check).
    const std::vector<Vec3>& positions() const;
    const Region& region() const { return region_; }
    const InnerMotion& motion() const { return motion_; }
    const DeformationOptions& options() const { return options_; }
    // Time the CPU spent issuing each step (the GPU runs asynchronously; call
    // finish() before reading a clock for GPU time).
    const std::vector<double>& step_milliseconds() const { return step_ms_; }
    // Waits until the GPU has executed every step issued so far.
    void finish() const;

    GpuPasses& passes() { return passes_; }
    const GpuPasses& passes() const { return passes_; }

private:
    void step(double h);
    void estimate_surface_gradients(At at);

    Region region_;
    InnerMotion motion_;
    DeformationOptions options_;
    GpuPasses passes_;
    double time_ = 0.0;
    bool have_gradients_ = false;
    std::vector<double> step_ms_;
    mutable std::vector<Vec3> positions_;
    mutable bool positions_valid_ = false;
};

}  // namespace vfsd::gpu
