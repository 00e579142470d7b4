#include "region/surface_point.h"

#include <cmath>
#include <string>

#include "base/error.h"

namespace vfsd {

void check_surface_point(const SurfacePoint& p, std::size_t triangle_count, const char* what) {
    if (p.triangle >= triangle_count)
        throw InputError(std::string(what) + ": triangle index " + std::to_string(p.triangle) +
                         " out of range (mesh has " + std::to_string(triangle_count) + " triangles)");
    const Vec3 b = p.barycentric;
    const bool finite = std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z);
    if (!finite || b.x < -1e-9 || b.y < -1e-9 || b.z < -1e-9 || std::abs(b.x + b.y + b.z - 1.0) > 1e-6)
        throw InputError(std::string(what) + ": barycentric coordinates must be non-negative and sum to 1");
}

Vec3 surface_position(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                      const SurfacePoint& p) {
    const Triangle& t = triangles[p.triangle];
    return p.barycentric.x * positions[t[0]] + p.barycentric.y * positions[t[1]] +
           p.barycentric.z * positions[t[2]];
}

SurfacePoint surface_point_at_vertex(const std::vector<Triangle>& triangles, std::size_t vertex_count,
                                     std::uint32_t v) {
    if (v >= vertex_count)
        throw InputError("vertex " + std::to_string(v) + " out of range (mesh has " +
                         std::to_string(vertex_count) + " vertices)");
    for (std::uint32_t f = 0; f < triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (triangles[f][k] == v) {
                SurfacePoint p{f, Vec3(0.0)};
                p.barycentric[k] = 1.0;
                return p;
            }
    throw InputError("vertex " + std::to_string(v) + " belongs to no triangle");
}

}  // namespace vfsd
