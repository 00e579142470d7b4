#include "gpu/gpu_deformation.h"

#include <cstdio>
#include <string>

#include "base/error.h"
#include "gpu/gl.h"
#include "gpu/gpu_error.h"
#include "gpu/gpu_passes.h"
#include "mesh/geometry.h"

namespace vfsd::gpu {
namespace {

const std::vector<double>& checked_s(const Region& region, std::size_t vertex_count) {
    if (region.sphere_tool)
        throw GpuUnavailable(
            "the GPU path takes a surface field s; the implicit sphere tool runs on the CPU "
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

// The step of CpuSteps::step, pass for pass, without read-back.
class GpuSteps final : public StepBackend {
public:
    GpuSteps(const std::vector<Vec3>& positions, const VertexRings& rings, const Region& region, InnerMotion motion,
             DeformationOptions options)
        : motion_(std::move(motion)),
          options_(options),
          passes_(checked_size(positions), checked_s(region, positions.size()), rings) {
        if (!gpu_mirrors(options_)) throw GpuUnavailable(kGpuUnmirroredReason);
    }

    const char* name() const override { return "gpu"; }
    bool asynchronous() const override { return true; }
    void finish() const override { glFinish(); }
    std::optional<DeviceVertices> device_vertices() const override {
        return DeviceVertices{&passes_.vertex_texture(), passes_.vertex_origin()};
    }

    void step(double time, double h, int) override {
        const StepMotion motion = StepMotion::sample(motion_, time, h);
        if (options_.gradients_at_midpoint) {
            if (!have_gradients_) estimate_surface_gradients(At::positions);
            passes_.predict_midpoints(motion.start, h);
            estimate_surface_gradients(At::midpoints);
        } else {
            estimate_surface_gradients(At::positions);
        }
        passes_.deformation_step(motion);
        positions_valid_ = false;
    }

    const std::vector<Vec3>& positions() const override {
        if (!positions_valid_) positions_ = passes_.read_positions();
        positions_valid_ = true;
        return positions_;
    }

private:
    // Normal, gradient (eq. 6) and smoothing passes on the positions or midpoints.
    void estimate_surface_gradients(At at) {
        passes_.estimate_normals(at);
        passes_.estimate_gradients(at);
        passes_.smooth_gradients(options_.smoothing_steps, options_.smoothing_weight, options_.tangent_smoothing);
        have_gradients_ = true;
    }

    InnerMotion motion_;
    DeformationOptions options_;
    GpuPasses passes_;
    bool have_gradients_ = false;
    mutable std::vector<Vec3> positions_;
    mutable bool positions_valid_ = false;
};

}  // namespace

Deformation make_gpu_deformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region,
                                 InnerMotion motion, DeformationOptions options) {
    check_options(options);
    return Deformation(std::make_unique<GpuSteps>(positions, rings, region, std::move(motion), options), options);
}

Deformation start_gpu_deformation(const PreparedScene& scene) {
    return make_gpu_deformation(scene.file.mesh.positions, scene.rings, scene.region, scene.motion,
                                scene.scene.options);
}

}  // namespace vfsd::gpu
