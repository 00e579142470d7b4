#pragma once
// How per-vertex (and per-ring-entry) arrays sit in 2D textures: item i lives at
// texel (i % width, i / width), with width = min(2048, max texture size) and as
// many rows as needed, so a few million items fit in one texture.

#include <algorithm>
#include <cstddef>

namespace vfsd::gpu {

struct TextureLayout {
    int width = 1, height = 1;

    static TextureLayout for_count(std::size_t count, int max_texture_size) {
        TextureLayout layout;
        layout.width = std::max(1, std::min(2048, max_texture_size));
        const std::size_t rows = (std::max<std::size_t>(count, 1) + layout.width - 1) / layout.width;
        layout.height = static_cast<int>(std::min<std::size_t>(rows, 1u << 30));
        return layout;
    }
    bool fits(int max_texture_size) const { return height <= max_texture_size; }
    std::size_t texels() const { return static_cast<std::size_t>(width) * height; }
};

}  // namespace vfsd::gpu
