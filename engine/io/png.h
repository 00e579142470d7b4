#pragma once
// PNG images: the renderer's pictures (vfsd render, the battery's worst scenes)
// and the desktop's screenshots.

#include <cstdint>
#include <string>
#include <vector>

namespace vfsd {

// Writes an RGBA8 image (top row first) as PNG, atomically.
void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgba);

}  // namespace vfsd
