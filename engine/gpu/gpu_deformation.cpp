#include "gpu/gpu_deformation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "base/error.h"
#include "gpu/gpu_error.h"
#include "mesh/geometry.h"

namespace vfsd::gpu {
namespace {

const std::vector<double>& checked_s(const Region& region, std::size_t vertex_count) {
    if (region.sphere_tool)
        throw GpuUnavailable("the GPU path takes a surface field s; the implicit sphere tool runs on the CPU "
                             "(--backend cpu)");
    if (region.s.size() != vertex_count)
        throw InputError("region: " + std::to_string(region.s.size()) + " values of s for " +
                         std::to_string(vertex_count) + " vertices");
    return region.s;
}

// The GPU's textures hold positions relative to the mesh's centre in float; the
// field's terms grow like |x − c|³, so a mesh much smaller or larger than a unit
// would underflow or lose its digits there. The CPU works in a local frame of
// any size (deform/local_frame.h) and runs those.
const std::vector<Vec3>& checked_size(const std::vector<Vec3>& positions) {
    constexpr double kSmallest = 1e-6, kLargest = 1e6;
    const double diagonal = bounding_box(positions).diagonal();
    if (!positions.empty() && !(diagonal >= kSmallest && diagonal <= kLargest)) {
        char message[200];
        std::snprintf(message, sizeof message,
                      "coordinates too %s for the GPU's float textures: the mesh is %.3g units across, the GPU "
                      "takes %g to %g; the CPU runs it (--backend cpu)",
                      diagonal < kSmallest ? "small" : "large", diagonal, kSmallest, kLargest);
        throw GpuUnavailable(message);
    }
    return positions;
}

}  // namespace

GpuDeformation::GpuDeformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region,
                               InnerMotion motion, DeformationOptions options)
    : region_(std::move(region)),
      motion_(std::move(motion)),
      options_(options),
      passes_(checked_size(positions), checked_s(region_, positions.size()), rings) {
    if (options_.steps < 1) throw InputError("steps must be at least 1");
    if (options_.smoothing_steps < 0) throw InputError("smoothing_steps must not be negative");
    if (!gpu_mirrors(options_)) throw GpuUnavailable(kGpuUnmirroredReason);
}

int GpuDeformation::advance(double target, int max_steps) {
    target = std::clamp(target, 0.0, 1.0);
    int taken = 0;
    while (taken < max_steps && time_ != target) {
        const double next = next_time_on_grid(time_, target, options_.steps);  // the CPU's grid walk
        step(next - time_);
        time_ = next;
        ++taken;
    }
    if (taken > 0) positions_valid_ = false;
    return taken;
}

// The step of Deformation::step, pass for pass, without read-back.
void GpuDeformation::step(double h) {
    const auto start = std::chrono::steady_clock::now();
    const StepMotion motion = StepMotion::sample(motion_, time_, h);
    if (options_.gradients_at_midpoint) {
        if (!have_gradients_) estimate_surface_gradients(At::positions);
        passes_.predict_midpoints(motion.start, h);
        estimate_surface_gradients(At::midpoints);
    } else {
        estimate_surface_gradients(At::positions);
    }
    passes_.deformation_step(motion);
    step_ms_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

// Normal, gradient (eq. 6) and smoothing passes on the positions or midpoints.
void GpuDeformation::estimate_surface_gradients(At at) {
    passes_.estimate_normals(at);
    passes_.estimate_gradients(at);
    passes_.smooth_gradients(options_.smoothing_steps, options_.smoothing_weight, options_.tangent_smoothing);
    have_gradients_ = true;
}

const std::vector<Vec3>& GpuDeformation::positions() const {
    if (positions_valid_) return positions_;
    positions_ = passes_.read_positions();
    positions_valid_ = true;
    for (std::size_t v = 0; v < positions_.size(); ++v) {
        const Vec3& p = positions_[v];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
        throw NumericalError("GPU integration made vertex " + std::to_string(v) + " non-finite by t = " +
                             std::to_string(time_));
    }
    return positions_;
}

void GpuDeformation::finish() const { glFinish(); }

}  // namespace vfsd::gpu
