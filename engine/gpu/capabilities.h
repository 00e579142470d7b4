#pragma once
// What the current GL context can do for the GPU path, and the one check that
// decides between the GPU and the CPU path.

#include <string>

namespace vfsd::gpu {

struct Capabilities {
    std::string version;      // GL_VERSION
    std::string renderer;     // GL_RENDERER
    bool es = false;          // OpenGL ES / WebGL2 rather than desktop GL
    int max_texture_size = 0; // GL_MAX_TEXTURE_SIZE
    bool float_render_targets = false;  // RGBA32F colour attachments (EXT_color_buffer_float on ES)
};

// Queries the current context.
Capabilities query_capabilities();

// Throws GpuUnavailable with one message saying what is missing and that the
// CPU path (--backend cpu) does the same work, when the context cannot run the
// passes for `vertex_count` vertices.
void require_gpu_support(const Capabilities& caps, std::size_t vertex_count = 0);

}  // namespace vfsd::gpu
