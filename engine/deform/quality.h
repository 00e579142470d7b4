#pragma once
// What the evaluation of sec. 7 measures about a finished deformation: volume
// change (sec. 7.1, volume as in sec. 7.2), local foldovers, and whether the
// outer region stayed put and the inner region moved rigidly.

#include <cmath>
#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct DeformationQuality {
    // The volume is that of a closed surface: false when some edge does not have
    // exactly two triangles (an open boundary, a non-manifold edge). The volume
    // numbers are then sums over the triangles (sec. 7.2's formula) with no meaning
    // as an enclosed volume.
    bool volume_defined = true;
    double volume_before = 0.0;
    double volume_after = 0.0;
    double volume_error_percent = 0.0;    // 100 |after − before| / |before|
    double volume_change_percent = 0.0;   // signed: 100 (after − before) / |before|
    double outer_max_displacement = 0.0;  // largest move of an outer vertex (s = 1)
    double inner_rigid_residual = 0.0;  // RMS distance of inner vertices (s = 0) from their best rigid fit, / diagonal
    std::size_t inner_vertices = 0;
    std::size_t outer_vertices = 0;
    std::size_t flipped_triangles = 0;
    std::size_t reversed_triangles = 0;  // reversed_triangle_list's count
    std::size_t nonfinite_vertices = 0;
};

// `s` is the region field at the start (0 inner, 1 outer).
DeformationQuality measure_quality(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                   const std::vector<Triangle>& triangles, const std::vector<double>& s);

// True when every edge of `triangles` belongs to exactly two triangles.
bool is_closed_surface(const std::vector<Triangle>& triangles);

// Triangle t's unit normal in x (0 for a degenerate triangle). Inline and in
// scalars: the fold test takes it for every triangle near the blend region on
// every step, and glm's Vec3 temporaries went through the stack (the same
// operations in the same order as glm's cross, length and division).
inline Vec3 unit_normal(const std::vector<Vec3>& x, const Triangle& t) {
    const Vec3 &a = x[t[0]], &b = x[t[1]], &c = x[t[2]];
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, wx = c.x - a.x, wy = c.y - a.y, wz = c.z - a.z;
    const double nx = uy * wz - wy * uz, ny = uz * wx - wz * ux, nz = ux * wy - wx * uy;
    const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
    return length > 0.0 ? Vec3(nx / length, ny / length, nz / length) : Vec3(0.0);
}

// unit_normal of triangles[first .. last) into normals[first .. last): the same
// bits, with the square roots and divisions of a block of triangles in SIMD
// lanes instead of one at a time (they bound the scalar loop: the fold test's
// pass over the triangles near the blend region, every step).
void unit_normals(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles, std::size_t first,
                  std::size_t last, std::vector<Vec3>& normals);

// The indices of the triangles count_flipped_triangles counts.
std::vector<std::uint32_t> flipped_triangle_list(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                                 const std::vector<Triangle>& triangles);

// The same count in parts, for a caller that checks many deformed positions of one
// mesh (an editor, every frame): the triangles' edge neighbours found once, and
// which triangles already face against them in the positions before.
struct TriangleNeighbours {
    std::vector<std::uint32_t> offsets;  // triangle t's neighbours: list[offsets[t]] .. list[offsets[t + 1] - 1]
    std::vector<std::uint32_t> list;
};
TriangleNeighbours triangle_neighbours(const std::vector<Triangle>& triangles);
// 1 for each triangle whose normal points against the mean normal of its edge neighbours in x.
std::vector<std::uint8_t> facing_against_neighbours(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles,
                                                    const TriangleNeighbours& neighbours);
// The triangles facing against their neighbours after but not before.
std::vector<std::uint32_t> newly_facing_against(const std::vector<std::uint8_t>& before,
                                                const std::vector<std::uint8_t>& after);

// Where folded triangles lie on the mesh before the deformation: the centroid of
// their corners and the range of s over them.
struct FoldWhere {
    Vec3 centre{0.0};
    double s_min = 0.0, s_max = 0.0;
};
FoldWhere locate_folds(const std::vector<Vec3>& before, const std::vector<Triangle>& triangles,
                       const std::vector<double>& s, const std::vector<std::uint32_t>& folded);

// Triangles whose normal points against the mean normal of their edge neighbours
// in `after` but not in `before`: local foldovers the deformation created.
std::size_t count_flipped_triangles(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                    const std::vector<Triangle>& triangles);

// A second measure of local folds, exact for affine maps: the triangles whose
// image in `after` faces against the image that the best affine map of their
// corners' 1-rings (before → after, least squares) gives them. An affine map with
// positive determinant folds nothing, and this counts 0 under any such map on any
// mesh, where count_flipped_triangles also counts triangles of a rough surface
// that a stretch tips past their neighbours' mean (docs/method.md, "What the
// remaining folds are"). A triangle of zero area before is not counted.
std::vector<std::uint32_t> reversed_triangle_list(const std::vector<Vec3>& before, const std::vector<Vec3>& after,
                                                  const std::vector<Triangle>& triangles);

}  // namespace vfsd
