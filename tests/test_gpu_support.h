#pragma once
// One headless GL context (OSMesa) for all GPU tests. Where none can be made the
// GPU tests report why and return without checking (Catch2 v2 has no SKIP).

#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/gpu_error.h"

namespace vfsd::test {

// The shared context, made current; nullptr when none can be made (`why` says why).
inline gpu::Context* gpu_context(std::string* why = nullptr) {
    static std::string reason;
    static std::unique_ptr<gpu::Context> context = [] {
        try {
            return gpu::create_headless_context();
        } catch (const gpu::GpuUnavailable& e) {
            reason = e.what();
            return std::unique_ptr<gpu::Context>();
        }
    }();
    if (context) context->make_current();
    if (why) *why = reason;
    return context.get();
}

// Largest distance between corresponding points.
inline double max_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    REQUIRE(a.size() == b.size());
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
    return d;
}

inline double max_length(const std::vector<Vec3>& a) {
    double d = 0.0;
    for (const Vec3& v : a) d = std::max(d, glm::length(v));
    return d;
}

}  // namespace vfsd::test

// Returns from the test case, with a warning, when no headless context exists.
#define VFSD_REQUIRE_GPU_CONTEXT()                                                 \
    do {                                                                            \
        std::string why_no_gpu;                                                     \
        if (!vfsd::test::gpu_context(&why_no_gpu)) {                                \
            WARN("SKIPPED: no headless GL context (" << why_no_gpu << ")");          \
            return;                                                                 \
        }                                                                           \
    } while (0)
