#include "gpu/shader_sources.h"

#include <map>

#include "gpu/gpu_error.h"

namespace vfsd::gpu {
namespace {

const std::map<std::string, std::string>& table() {
    static const std::map<std::string, std::string> files = [] {
        std::map<std::string, std::string> m;
        for (std::size_t i = 0; i < detail::kEmbeddedShaderCount; ++i)
            m.emplace(detail::kEmbeddedShaders[i].name, detail::kEmbeddedShaders[i].text);
        return m;
    }();
    return files;
}

}  // namespace

const std::string& shader_source(const std::string& file) {
    const auto it = table().find(file);
    if (it == table().end()) throw GpuError("no embedded shader named '" + file + "' (shaders/" + file + ")");
    return it->second;
}

std::vector<std::string> shader_files() {
    std::vector<std::string> names;
    for (const auto& entry : table()) names.push_back(entry.first);
    return names;
}

const char* shader_prelude() {
    return "#version 300 es\n"
           "precision highp float;\n"
           "precision highp int;\n"
           "precision highp sampler2D;\n"
           "precision highp isampler2D;\n";
}

}  // namespace vfsd::gpu
