#pragma once
// tinygltf as engine/io uses it: meshes only. Images are never decoded (no
// stb_image), so every file that includes tiny_gltf.h must see the same options:
// include this header instead of <tiny_gltf.h>.

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
