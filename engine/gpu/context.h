#pragma once
// A GL context the GPU path can run in. The passes and the renderer only need a
// current context; which kind it is (OSMesa or EGL headless, a GLFW window, a
// WebGL2 canvas) is the application's choice, behind this interface.

#include <memory>
#include <string>

namespace vfsd::gpu {

class Context {
public:
    virtual ~Context() = default;
    virtual void make_current() = 0;
    // What kind of context this is ("osmesa", "egl", "glfw", "webgl2").
    virtual std::string kind() const = 0;
    // GL_RENDERER of the context (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
    std::string renderer() const;
};

// A headless context of GL 4.5 core (or the best this build has): OSMesa natively.
// Throws GpuUnavailable with a message saying why, and that --backend cpu works,
// when no headless context can be made (or the build has none).
std::unique_ptr<Context> create_headless_context();

}  // namespace vfsd::gpu
