#pragma once
// A point on the surface of a triangle mesh: a triangle and barycentric coordinates.
// Positions are passed explicitly, so the same surface point can be evaluated on the
// rest shape and on a deformed shape.

#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct SurfacePoint {
    std::uint32_t triangle = 0;
    Vec3 barycentric{1.0 / 3.0};  // weights of triangles[triangle][0..2], summing to 1
};

// Throws InputError (naming `what`) unless the triangle index is valid and the
// barycentric coordinates are finite, non-negative (to -1e-9) and sum to 1 (to 1e-6).
void check_surface_point(const SurfacePoint& p, std::size_t triangle_count, const char* what);

// The 3D position of p: the barycentric combination of its triangle's corners.
Vec3 surface_position(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                      const SurfacePoint& p);

// The surface point at vertex v: a triangle of its fan with weight 1 at v.
// Throws InputError when v is out of range or belongs to no triangle.
SurfacePoint surface_point_at_vertex(const std::vector<Triangle>& triangles, std::size_t vertex_count,
                                     std::uint32_t v);

}  // namespace vfsd
