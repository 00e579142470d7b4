#include "editor/gpu_live_deformation.h"

#include <chrono>

#include "gpu/gpu_error.h"

namespace vfsd::editor {

GpuLiveDeformation::GpuLiveDeformation(const PreparedScene& scene)
    : deformation_(scene.file.mesh.positions, scene.rings, scene.region, scene.motion, scene.scene.options) {}

int GpuLiveDeformation::advance(double target, int max_steps) {
    // The GPU runs asynchronously: time the steps with the finish included.
    const auto start = std::chrono::steady_clock::now();
    const int taken = deformation_.advance(target, max_steps);
    if (taken > 0) {
        deformation_.finish();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        ms_per_step_ = ms / taken;
    }
    return taken;
}

std::unique_ptr<LiveDeformation> make_gpu_deformation(const PreparedScene& scene) {
    if (scene.region.sphere_tool) throw gpu::GpuUnavailable("the sphere tool region runs on the CPU only");
    return std::make_unique<GpuLiveDeformation>(scene);
}

}  // namespace vfsd::editor
