#pragma once
// The GPU's steps of a deformation: the CPU's steps (deform/cpu_steps.h) pass
// for pass, with the state in textures (sec. 5). With sec. 5's steps alone a step
// reads nothing back; the default scheme reads back the gauge's samples and the
// fold count (docs/gpu.md, "Read-backs"). The positions are read back from the
// vertex texture when asked for, and a renderer can draw the texture itself
// (Deformation::device_vertices()).
//
// Needs a current GL context for the deformation's whole life (gpu/context.h).

#include <memory>
#include <vector>

#include "deform/deformation.h"
#include "scene/prepared_scene.h"

namespace vfsd::gpu {

// What a GPU deformation sets up at rest (the passes' textures and programs, the
// gauge's samples, the fold test's checks, the rest volume), kept between
// deformations: one made with a shelf leaves its set-up there when it ends, and
// the next of the same mesh, region and options (the editors' curve edit) takes
// it instead of setting it up again, with the same steps. The set-up's GL
// objects belong to the context it was made in: clear() after losing it.
class GpuRestShelf {
public:
    GpuRestShelf();
    ~GpuRestShelf();
    GpuRestShelf(const GpuRestShelf&) = delete;
    GpuRestShelf& operator=(const GpuRestShelf&) = delete;
    void clear();
    // What is kept (opaque: the GPU deformation's own).
    struct Kept;
    Kept& kept() { return *kept_; }

private:
    std::unique_ptr<Kept> kept_;
};

// Throws InputError as the CPU's does; GpuUnavailable for the sphere tool region
// or coordinates beyond the float textures' range, and GpuError for the GPU itself.
Deformation make_gpu_deformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region,
                                 InnerMotion motion, DeformationOptions options,
                                 std::shared_ptr<GpuRestShelf> shelf = nullptr);
// The prepared scene's deformation on the GPU from t = 0.
Deformation start_gpu_deformation(const PreparedScene& scene, std::shared_ptr<GpuRestShelf> shelf = nullptr);

}  // namespace vfsd::gpu
