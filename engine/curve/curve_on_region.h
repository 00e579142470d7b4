#pragma once
// Sec. 3 wants c(0) in the inner region. When the user repaints the region, the
// curve should follow it: its start at the inner region's centroid, leaving along
// the region's axis (away from the blend region), the rest of the curve carried
// along rigidly so that its shape is kept.

#include <vector>

#include <glm/mat3x3.hpp>

#include "mesh/triangle_mesh.h"

namespace vfsd {

// The rotation by the smallest angle that takes unit a onto unit b (a half turn
// about an axis across a when b = −a).
glm::dmat3 turn_onto(const Vec3& a, const Vec3& b);

// The way out of the mesh at the inner region (s ≤ 0): from the blend region's
// centroid (0 < s < 1) to the inner region's, or, where the blend region surrounds
// the inner one evenly, the inner region's mean vertex normal `normals` (unit
// length; zero vector when neither gives a direction).
Vec3 inner_region_axis(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                       const std::vector<double>& s);

// The control points moved rigidly so that the first lies at the inner region's
// centroid and the curve leaves along inner_region_axis: the turn that takes the
// curve's start direction (the first control point apart from the start) onto
// the axis, then the move. Unchanged where there is no inner region; a curve of
// one repeated point is moved without turning.
std::vector<Vec3> curve_on_region(const std::vector<Vec3>& control_points, const std::vector<Vec3>& positions,
                                  const std::vector<Vec3>& normals, const std::vector<double>& s);

}  // namespace vfsd
