#pragma once
// Best rigid motion between two point sets (Horn's closed-form quaternion method,
// "Closed-form solution of absolute orientation using unit quaternions", 1987).

#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace vfsd {

struct RigidFit {
    glm::dmat3 rotation{1.0};
    glm::dvec3 translation{0.0};
    double rms_residual = 0.0;  // RMS of |R from_i + T − to_i|
    glm::dvec3 apply(const glm::dvec3& p) const { return rotation * p + translation; }
};

// Minimises Σ |R from_i + T − to_i|² over rotations R and translations T.
// Both sets must have the same size; an empty set gives the identity.
RigidFit fit_rigid(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to);

// Angle of a rotation matrix in radians, in [0, π].
double rotation_angle(const glm::dmat3& rotation);

}  // namespace vfsd
