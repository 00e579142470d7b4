#pragma once
// Errors of the GPU path. GpuUnavailable means the CPU path should be used
// instead (no context, or the device lacks float render targets or texture
// size); GpuError is any other GL failure (a shader that does not compile, an
// incomplete framebuffer).

#include "base/error.h"

namespace vfsd::gpu {

struct GpuError : Error {
    using Error::Error;
};

struct GpuUnavailable : GpuError {
    using GpuError::GpuError;
};

}  // namespace vfsd::gpu
