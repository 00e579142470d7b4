#pragma once
// Regions from boundaries drawn on the surface (figs. 2a, 9, 10, 11): closed polylines
// of surface points cut the mesh; a seed point says which side is inner.
//
// Each segment between consecutive loop points (and from the last point back to the
// first: loops are closed implicitly; repeating the first point at the end is allowed)
// is traced across the surface as a straight walk: in each triangle the direction to
// the next point is projected into the triangle's plane and followed to the edge it
// leaves by. Every mesh edge crossed an odd number of times is cut; the seed's side is
// the set of vertices reachable from the seed without crossing a cut edge. Consecutive
// points should lie a few triangles apart (as a drawing tool samples them); the mesh
// must be edge-manifold along the loops.
//
// Positions are explicit, so loops drawn on a deformed shape are traced on it.

#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"
#include "region/surface_point.h"

namespace vfsd {

using SurfaceLoop = std::vector<SurfacePoint>;

// The vertices (mask, 1 = on the seed's side) reachable from `seed` without crossing
// any of the loops. A seed with a barycentric weight of 1 is that vertex; any other
// seed must lie in a triangle no loop passes through.
// Throws InputError when a loop has fewer than 3 points, a segment cannot be traced
// (points on different components, across a mesh boundary, or too far apart), the seed
// lies on a loop, or the loops do not separate the seed's connected part of the mesh
// (the seed's side would be all of it).
std::vector<std::uint8_t> seed_side_of_loops(const std::vector<Vec3>& positions,
                                             const std::vector<Triangle>& triangles, const VertexRings& rings,
                                             const std::vector<SurfaceLoop>& loops, const SurfacePoint& seed);

struct LoopRegions {
    std::vector<std::uint8_t> inner;  // the seed's side of the inner loop
    std::vector<std::uint8_t> outer;  // beyond the outer loop, plus other connected parts
};

// Three regions from two loops (sec. 6.2 via drawn boundaries): inner = seed side of
// `inner_loop`; outer = everything not on the seed side of `outer_loop`; the
// intermediate region is what lies between. The masks feed painted_region_field.
// Throws InputError as seed_side_of_loops does, and when the inner loop does not lie on
// the seed's side of the outer loop (crossing or swapped loops) or nothing lies between.
LoopRegions regions_from_loops(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                               const VertexRings& rings, const SurfaceLoop& inner_loop,
                               const SurfaceLoop& outer_loop, const SurfacePoint& seed);

}  // namespace vfsd
