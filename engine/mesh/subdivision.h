#pragma once
// Midpoint subdivision, everywhere or where asked: a triangle split into four at
// its edge midpoints (one new vertex per edge, shared by the two triangles on
// it), and, to keep the mesh conforming, a neighbour with one split edge cut in
// two across it (red-green refinement). A closed manifold stays closed and
// manifold. The surface keeps its shape exactly (the new vertices lie on the old
// edges) unless `place` moves them, as the icosphere does onto the sphere.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

// Where the new vertex of edge (a, b) goes; by default the midpoint.
using EdgePoint = std::function<Vec3(const Vec3& a, const Vec3& b)>;

// One level: V + E vertices, 4 F triangles, the old vertices keep their indices.
TriangleMesh subdivide_midpoints(const TriangleMesh& mesh, const EdgePoint& place = {});

struct RefinedMesh {
    TriangleMesh mesh;  // the old vertices first, with their indices; a scalar is interpolated
    // New vertex mesh.vertex_count() - parents.size() + k is the midpoint of edge parents[k]
    // (lower index first).
    std::vector<std::array<std::uint32_t, 2>> parents;
};

// Splits every edge of `triangles` at its midpoint, and each edge a triangle
// needs split too so that no triangle has exactly two split edges; a triangle
// then has 0, 1 (cut in two from the midpoint to the opposite corner) or 3 split
// edges (four children). Every choice follows the vertex and triangle indices, so
// a moved or mirrored mesh is refined the same way; a triangle's children keep
// its winding, next to each other where it was. New vertices are numbered in
// the order of their edges (lower index, then higher).
RefinedMesh refine_triangles(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                             const EdgePoint& place = {});

}  // namespace vfsd
