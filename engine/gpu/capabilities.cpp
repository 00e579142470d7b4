#include "gpu/capabilities.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "gpu/gl.h"
#include "gpu/gpu_error.h"
#include "gpu/texture_layout.h"

namespace vfsd::gpu {
namespace {

std::string gl_string(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

bool has_extension(const char* wanted) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (e && std::strcmp(e, wanted) == 0) return true;
    }
    return false;
}

}  // namespace

Capabilities query_capabilities() {
    Capabilities caps;
    caps.version = gl_string(GL_VERSION);
    caps.renderer = gl_string(GL_RENDERER);
    caps.es = caps.version.rfind("OpenGL ES", 0) == 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &caps.max_texture_size);
    // Desktop GL 3.0+ renders to float textures in core; ES 3.0 / WebGL2 needs the extension.
    caps.float_render_targets = !caps.es || has_extension("GL_EXT_color_buffer_float") ||
                                has_extension("EXT_color_buffer_float");
    return caps;
}

void require_gpu_support(const Capabilities& caps, std::size_t vertex_count) {
    const std::string fallback = "; the CPU path (--backend cpu) computes the same deformation";
    if (!caps.float_render_targets)
        throw GpuUnavailable("GPU path unavailable on '" + caps.renderer +
                             "': no float render targets (EXT_color_buffer_float)" + fallback);
    if (caps.max_texture_size < 64)
        throw GpuUnavailable("GPU path unavailable on '" + caps.renderer + "': maximum texture size " +
                             std::to_string(caps.max_texture_size) + fallback);
    const TextureLayout layout = TextureLayout::for_count(vertex_count, caps.max_texture_size);
    if (!layout.fits(caps.max_texture_size))
        throw GpuUnavailable("GPU path unavailable on '" + caps.renderer + "': " + std::to_string(vertex_count) +
                             " vertices need " + std::to_string(layout.height) + " texture rows, more than the maximum " +
                             std::to_string(caps.max_texture_size) + fallback);
}

std::string software_renderer(const std::string& renderer) {
    std::string lower = renderer;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    for (const std::string word : {"swiftshader", "llvmpipe", "softpipe", "software"})
        if (const std::size_t at = lower.find(word); at != std::string::npos) return renderer.substr(at, word.size());
    return "";
}

bool multisample_view(const std::string& renderer, const std::string& requested) {
    if (requested == "on" || requested == "off") return requested == "on";
    return software_renderer(renderer).empty();
}

std::string cpu_path_reason(const Capabilities& caps, const std::string& requested) {
    if (requested == "cpu") return "CPU chosen (backend cpu)";
    try {
        require_gpu_support(caps);
    } catch (const GpuUnavailable& e) {
        return e.what();
    }
    const std::string software = software_renderer(caps.renderer);
    if (requested != "gpu" && !software.empty())
        return "software renderer (" + software +
               ") runs the GPU passes slower than the CPU path (ask for the GPU backend to use it anyway)";
    return "";
}

}  // namespace vfsd::gpu
