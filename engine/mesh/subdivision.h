#pragma once
// Midpoint subdivision: every triangle split into four at its edge midpoints
// (one new vertex per edge, shared by the two triangles on it), so a closed
// manifold stays closed and manifold. The surface keeps its shape exactly (the
// new vertices lie on the old edges) unless `place` moves them, as the icosphere
// does onto the sphere.

#include <functional>

#include "mesh/triangle_mesh.h"

namespace vfsd {

// Where the new vertex of edge (a, b) goes; by default the midpoint.
using EdgePoint = std::function<Vec3(const Vec3& a, const Vec3& b)>;

// One level: V + E vertices, 4 F triangles, the old vertices keep their indices.
TriangleMesh subdivide_midpoints(const TriangleMesh& mesh, const EdgePoint& place = {});

}  // namespace vfsd
