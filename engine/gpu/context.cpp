#include "gpu/context.h"

#include "gpu/gl.h"

namespace vfsd::gpu {

std::string Context::renderer() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return s ? s : "unknown";
}

}  // namespace vfsd::gpu
