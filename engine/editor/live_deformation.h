#pragma once
// The deformation an editor shows while the user scrubs time: the engine's
// Deformation (CPU) or GpuDeformation behind one interface, so the session does
// not know which backend runs. The application supplies a factory for the GPU
// one when it has a GL context (editor/gpu_live_deformation.h).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scene/prepared_scene.h"

namespace vfsd::editor {

class LiveDeformation {
public:
    virtual ~LiveDeformation() = default;
    // Integrates toward `target` taking at most `max_steps` steps; returns how many.
    virtual int advance(double target, int max_steps) = 0;
    virtual double time() const = 0;
    // Positions at time() (the GPU reads them back on demand).
    virtual const std::vector<Vec3>& positions() const = 0;
    // Milliseconds per step of the recent advances (wall time, GPU work included).
    virtual double ms_per_step() const = 0;
    virtual std::string backend() const = 0;  // "cpu" or "gpu"
};

// Makes the deformation of a prepared scene from t = 0; throws (GpuUnavailable,
// InputError) when it cannot.
using DeformationFactory = std::function<std::unique_ptr<LiveDeformation>(const PreparedScene&)>;

std::unique_ptr<LiveDeformation> make_cpu_deformation(const PreparedScene& scene);

}  // namespace vfsd::editor
