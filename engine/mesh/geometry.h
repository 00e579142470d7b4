#pragma once
// Geometric quantities of a triangle mesh.

#include <vector>

#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

BoundingBox bounding_box(const std::vector<Vec3>& positions);

// Twice the largest distance of a position from their mean: the diagonal of a
// cube's bounding box, and, unlike a bounding box's diagonal, the same however
// the positions are turned (0 for none).
double centred_diameter(const std::vector<Vec3>& positions);

// Signed volume as sec. 7.2 defines it: the sum of the signed volumes of the
// tetrahedra spanned by each triangle and the origin. Exact for closed meshes;
// for open meshes it depends on the origin (see is_closed in the validation report).
double signed_volume(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles);
// The same with the tetrahedra's apex at `origin` instead of (0,0,0): equal for a
// closed mesh, but without the cancellation of large terms when the mesh lies far
// from (0,0,0) (a unit cube 1e9 away keeps 7 digits instead of none).
double signed_volume(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles, const Vec3& origin);
// 6 × the signed volume of the tetrahedron of triangle t (its corners in p)
// with c: (a − c) · ((b − c) × (d − c)).
double six_volume(const Vec3* p, const Triangle& t, const Vec3& c);
// Σ six_volume over t[0 .. count), summed as parallel_sum sums a block of
// terms (base/parallel.h): the same bits, four triangles at a time in SIMD lanes.
double six_volume_block(const Vec3* p, const Triangle* t, std::size_t count, const Vec3& c);

// Area-weighted vertex normals: the normalised sum of the (unnormalised) normals of
// the triangles in each vertex's fan, gathered over the ordered ring as the normal
// pass of sec. 5 does. Vertices with a zero sum get (0,0,0).
void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& normals);
// The same, computed only at the listed vertices (the others are left as they are).
void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals);
// The same, and the sums themselves: area_vectors[i] for vertices[i].
void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals,
                    std::vector<Vec3>& area_vectors);

// Each of the n vectors (x[j], y[j], z[j]) divided by its length, (0,0,0) where
// that is 0 or not a number: in SIMD lanes (the square roots and divisions bound
// the normal passes done one at a time), with the same bits as glm's
// v / glm::length(v). On x86-64 with GCC an AVX2 clone is picked at load time
// where the CPU has it (square roots and divisions are exact in any width).
void normalise_lanes(int n, double* __restrict x, double* __restrict y, double* __restrict z);

// Σ (a − x) × (b − x) over the triangles (x, a, b) of v's fan: twice its fan's
// area along its normal. On a closed mesh it is 6 ∂V/∂x_v, the enclosed volume's
// gradient with respect to v (sec. 7.2's V as a sum of tetrahedra).
Vec3 ring_area_vector(const std::vector<Vec3>& positions, const VertexRings& rings, std::uint32_t v);
// ring_area_vector normalised: v's area-weighted unit normal, as vertex_normals
// gives it ((0,0,0) for a zero sum).
Vec3 vertex_normal(const std::vector<Vec3>& positions, const VertexRings& rings, std::uint32_t v);
// ring_area_vector of each listed vertex: area_vectors[i] for vertices[i].
void ring_area_vectors(const std::vector<Vec3>& positions, const VertexRings& rings,
                       const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& area_vectors);

}  // namespace vfsd
