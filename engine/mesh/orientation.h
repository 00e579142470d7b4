#pragma once
// Consistent winding: two triangles that share an edge traverse it in opposite
// directions. Meshes from CAD exports and hand-made fixes often break this for
// some triangles; their normals then point inward there, and every measure that
// compares a triangle with its neighbours (the fold tests, ∇r's constrained fit,
// the enclosed volume) reads them as folded.

#include <cstddef>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

// Turns triangles (swapping two corners) so that the winding is consistent
// across every edge of exactly two triangles, over each edge-connected part of
// the mesh, keeping in each part the winding most of its triangles had (ties:
// its first triangle's). A consistently wound mesh is left as it is. An edge of
// three or more triangles does not connect them; a part that cannot be wound
// consistently (a Möbius strip) keeps the winding that a walk from its first
// triangle gives, inconsistent across the edges where the walk met itself.
// Returns the number of triangles turned. Deterministic: it depends on the
// triangles and their order, not on where the mesh lies.
std::size_t orient_consistently(std::vector<Triangle>& triangles);

}  // namespace vfsd
