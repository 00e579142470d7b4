// The one compiled copy of tinygltf (a header-only library), built from source
// so the same code serves native and WebAssembly builds.
#define TINYGLTF_IMPLEMENTATION
#include "io/tinygltf.h"
