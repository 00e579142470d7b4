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

// A software rasteriser (SwiftShader, llvmpipe, softpipe) runs the GPU passes on
// the CPU, many times slower than the CPU path itself (docs/web.md, "Speed"):
// the matched name as `renderer` writes it ("SwiftShader"), or "" for hardware.
std::string software_renderer(const std::string& renderer);

// Whether a view drawn by `renderer` should be multisampled. A software
// rasteriser shades every sample on the CPU: SwiftShader drew the page's frame
// of the 41k sphere in about 100 ms with 4x multisampling and 50 ms without
// (docs/web.md, "Edit to final shape"), time the steps on the same cores lose.
// `requested`: "auto" (all but a software renderer), "on" or "off".
bool multisample_view(const std::string& renderer, const std::string& requested = "auto");

// Why an editor in this context runs the CPU path, or "" for the GPU path.
// `requested`: "auto" (the GPU where it can, unless it renders in software),
// "gpu" (wherever it can) or "cpu". The one rule both shells follow.
std::string cpu_path_reason(const Capabilities& caps, const std::string& requested);

}  // namespace vfsd::gpu
