#pragma once
// The GLSL files of shaders/, embedded into the binary at build time (see
// engine/gpu/CMakeLists.txt), so native, WebAssembly and tests run the same text.

#include <cstddef>
#include <string>
#include <vector>

namespace vfsd::gpu {

// The text of shaders/`file` (e.g. "normal.frag"); throws GpuError for an unknown name.
const std::string& shader_source(const std::string& file);
// The names of all embedded files.
std::vector<std::string> shader_files();

// The lines every stage starts with: "#version 300 es" and highp precision for
// floats, ints and both sampler kinds (GLSL ES 3.00, also accepted by desktop GL 4.3+).
const char* shader_prelude();

}  // namespace vfsd::gpu

namespace vfsd::gpu::detail {
struct EmbeddedShader {
    const char* name;
    const char* text;
};
// Defined in the generated embedded_shaders.cpp.
extern const EmbeddedShader kEmbeddedShaders[];
extern const std::size_t kEmbeddedShaderCount;
}  // namespace vfsd::gpu::detail
