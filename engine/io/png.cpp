#include "io/png.h"

#include "io/mesh_file.h"  // write_file_atomically

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>

namespace vfsd {

void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgba) {
    std::string bytes;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
            static_cast<std::string*>(context)->append(static_cast<char*>(data), size);
        },
        &bytes, width, height, 4, rgba.data(), width * 4);
    write_file_atomically(path, bytes);
}

}  // namespace vfsd
