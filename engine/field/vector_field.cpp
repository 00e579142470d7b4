#include "field/vector_field.h"

#include <cmath>

namespace vfsd {
namespace {

// f ∇e − e ∇f for the rotation fields about an axis through the origin of y with
// angular velocity Ω. With e = λ â·y, f = λ² |y⊥|² and 2λ³ = |Ω| (so that
// ∇e × ∇f = Ω × y, eq. 5 scaled):  f ∇e − e ∇f = ½ |y⊥|² Ω − (Ω·y) y⊥,
// y⊥ being the part of y perpendicular to Ω; the plane e = 0 passes through
// the origin of y.
Vec3 rotation_stream(const Vec3& omega, const Vec3& y) {
    const double omega2 = glm::dot(omega, omega);
    if (omega2 == 0.0) return Vec3(0.0);
    const double along = glm::dot(omega, y);  // |Ω| times y's coordinate along the axis
    const Vec3 y_perp = y - (along / omega2) * omega;
    return 0.5 * glm::dot(y_perp, y_perp) * omega - along * y_perp;
}

}  // namespace

double bernstein_blend(double u) {
    if (u <= 0.0) return 0.0;
    if (u >= 1.0) return 1.0;
    return u * u * u * (4.0 - 3.0 * u);  // B_3^4 + B_4^4
}

double bernstein_blend_derivative(double u) {
    if (u <= 0.0 || u >= 1.0) return 0.0;
    return 12.0 * u * u * (1.0 - u);
}

Vec3 inner_velocity(const MotionSample& m, const Vec3& x) {
    return m.velocity + glm::cross(m.angular_velocity + m.twist, x - m.position);
}

Vec3 origin_velocity(const MotionSample& m) {
    return m.velocity + glm::cross(m.angular_velocity, m.stream_origin - m.position);
}

Vec3 stream_vector(const MotionSample& m, const Vec3& x) {
    // Translation, eqs. (9)–(10): e = a·z, f = b·z with z = x − o and a × b = U give
    // f ∇e − e ∇f = (b·z) a − (a·z) b = z × U, free of the choice of a, b.
    // Rotation, eqs. (11)–(13), with f shifted so that f(o) = 0 as eq. (10) does at
    // o = c: the curvature-centre terms cancel to z × U plus a rotation stream about
    // the axis through o, U = ċ + ω × (o − c) being the velocity at o (U = ċ at the
    // default o = c). The twist, eq. (14), is a rotation stream about the axis
    // c + λ ĉ, its plane ẽ = 0 through m.twist_origin (as printed: through c).
    // Then the gauge ∇φ fitted to the region (field/stream_gauge.h).
    const Vec3 z = x - m.stream_origin;
    return glm::cross(z, origin_velocity(m)) + rotation_stream(m.angular_velocity, z) +
           rotation_stream(m.twist, x - m.twist_origin) + gauge_gradient(m.gauge, x);
}

Vec3 deformation_velocity(const MotionSample& m, const Vec3& x, double b, const Vec3& grad_b) {
    if (b == 0.0 && grad_b == Vec3(0.0)) return inner_velocity(m, x);  // inner region: rigid
    const double a = 1.0 - b;
    return a * a * inner_velocity(m, x) - a * glm::cross(stream_vector(m, x), grad_b);
}

}  // namespace vfsd
