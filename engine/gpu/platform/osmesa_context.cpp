// Headless GL on the CPU: Mesa's OSMesa with a GL 4.5 core context (llvmpipe).
// The passes render into their own framebuffers, so the context's own buffer is
// a token 1 x 1 image.

#include <GL/osmesa.h>

#include <array>

#include "gpu/context.h"
#include "gpu/gpu_error.h"

namespace vfsd::gpu {
namespace {

class OsmesaContext final : public Context {
public:
    OsmesaContext() {
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                               OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = OSMesaCreateContextAttribs(attribs, nullptr);
        if (!context_)
            throw GpuUnavailable("no headless GL context: OSMesaCreateContextAttribs failed for GL 4.5 core; "
                                 "the CPU path (--backend cpu) computes the same deformation");
        make_current();
    }
    ~OsmesaContext() override { OSMesaDestroyContext(context_); }
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;

    void make_current() override {
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
            throw GpuUnavailable("no headless GL context: OSMesaMakeCurrent failed");
    }
    std::string kind() const override { return "osmesa"; }

private:
    OSMesaContext context_ = nullptr;
    std::array<unsigned char, 4> buffer_{};
};

}  // namespace

std::unique_ptr<Context> create_headless_context() { return std::make_unique<OsmesaContext>(); }

}  // namespace vfsd::gpu
