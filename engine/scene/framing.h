#pragma once
// What a camera should frame to show a whole deformation without reading
// positions back (the editors, `vfsd render`, the battery's pictures).

#include <vector>

#include "curve/inner_motion.h"

namespace vfsd {

// The undeformed mesh, plus a sphere around c(t) for t along the curve as large
// as the inner region (s = 0) is around c(0).
std::vector<Vec3> deformation_frame_points(const std::vector<Vec3>& positions, const std::vector<double>& s,
                                          const InnerMotion& motion);

}  // namespace vfsd
