#pragma once
// The GPU backend of LiveDeformation: GpuDeformation in the application's current
// GL context (a window's or a canvas's). The renderer draws its vertex texture
// directly, so scrubbing needs no read-back; positions() reads back on demand.

#include "editor/live_deformation.h"
#include "gpu/gpu_deformation.h"

namespace vfsd::editor {

class GpuLiveDeformation final : public LiveDeformation {
public:
    // Throws GpuUnavailable (e.g. for the sphere tool region) or GpuError.
    explicit GpuLiveDeformation(const PreparedScene& scene);
    int advance(double target, int max_steps) override;
    double time() const override { return deformation_.time(); }
    const std::vector<Vec3>& positions() const override { return deformation_.positions(); }
    double ms_per_step() const override { return ms_per_step_; }
    std::string backend() const override { return "gpu"; }
    const gpu::Texture& vertex_texture() const { return deformation_.passes().vertex_texture(); }
    const Vec3& vertex_origin() const { return deformation_.passes().vertex_origin(); }

private:
    gpu::GpuDeformation deformation_;
    double ms_per_step_ = 0.0;
};

// The factory for EditorSession.
std::unique_ptr<LiveDeformation> make_gpu_deformation(const PreparedScene& scene);

}  // namespace vfsd::editor
