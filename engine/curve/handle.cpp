#include "curve/handle.h"

#include <algorithm>
#include <cmath>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "base/error.h"

namespace vfsd {
namespace {

constexpr double kFrameTolerance = 1e-6;

void check_frame(const HandleFrame& f, const char* which) {
    const bool unit = std::abs(glm::length(f.normal) - 1.0) < kFrameTolerance &&
                      std::abs(glm::length(f.binormal) - 1.0) < kFrameTolerance;
    if (!unit || std::abs(glm::dot(f.normal, f.binormal)) > kFrameTolerance)
        throw InputError(std::string("handle '") + which + "': normal and binormal must be unit length and perpendicular");
}

// Unit tangent at t, falling back to a one-sided difference where ċ vanishes.
Vec3 unit_tangent(const BezierCurve& curve, double t) {
    Vec3 d = curve.at(t).d1;
    if (glm::length(d) < 1e-12) d = curve.at(std::min(1.0, t + 1e-6)).position - curve.at(std::max(0.0, t - 1e-6)).position;
    return glm::normalize(d);
}

// Signed angle from a to b about the unit axis n (a, b perpendicular to n).
double signed_angle(const Vec3& a, const Vec3& b, const Vec3& n) {
    return std::atan2(glm::dot(glm::cross(a, b), n), glm::dot(a, b));
}

// Rotation vector (axis · angle) of the rotation taking frame `from` onto `to`.
Vec3 relative_rotation(const HandleFrame& from, const HandleFrame& to) {
    const glm::dmat3 a(from.normal, from.binormal, glm::cross(from.normal, from.binormal));
    const glm::dmat3 b(to.normal, to.binormal, glm::cross(to.normal, to.binormal));
    const glm::dmat3 r = b * glm::transpose(a);
    const double angle = std::acos(std::clamp(0.5 * (r[0][0] + r[1][1] + r[2][2] - 1.0), -1.0, 1.0));
    if (angle < 1e-12) return Vec3(0.0);
    Vec3 axis(r[1][2] - r[2][1], r[2][0] - r[0][2], r[0][1] - r[1][0]);  // 2 sin(angle) · axis
    if (glm::length(axis) < 1e-9) {
        // angle ≈ π: the axis is the column of r + I with the largest norm.
        const glm::dmat3 s = r + glm::dmat3(1.0);
        axis = s[0];
        for (int k = 1; k < 3; ++k)
            if (glm::length(s[k]) > glm::length(axis)) axis = s[k];
    }
    return angle * glm::normalize(axis);
}

}  // namespace

Vec3 transport_along_curve(const BezierCurve& curve, const Vec3& u, int samples) {
    Vec3 r = u;
    Vec3 x0 = curve.at(0.0).position, t0 = unit_tangent(curve, 0.0);
    for (int i = 1; i <= samples; ++i) {
        const double t = static_cast<double>(i) / samples;
        const Vec3 x1 = curve.at(t).position, t1 = unit_tangent(curve, t);
        // Reflect across the bisector plane of x0, x1, then across the one that maps the tangent.
        const Vec3 v1 = x1 - x0;
        const double c1 = glm::dot(v1, v1);
        if (c1 > 0.0) {
            r -= (2.0 / c1) * glm::dot(v1, r) * v1;
            const Vec3 tl = t0 - (2.0 / c1) * glm::dot(v1, t0) * v1;
            const Vec3 v2 = t1 - tl;
            const double c2 = glm::dot(v2, v2);
            if (c2 > 0.0) r -= (2.0 / c2) * glm::dot(v2, r) * v2;
        }
        x0 = x1;
        t0 = t1;
    }
    return r;
}

InnerMotion handle_motion(const HandleFrame& from, const HandleFrame& to) {
    check_frame(from, "from");
    check_frame(to, "to");
    const Vec3 delta = to.position - from.position;
    const double distance = glm::length(delta);
    const Vec3 rotation = relative_rotation(from, to);
    if (distance == 0.0) return InnerMotion::rotation_about(from.position, rotation);
    if (glm::length(rotation) == 0.0) {
        BezierCurve line({from.position, from.position + delta / 3.0, to.position - delta / 3.0, to.position});
        return InnerMotion::along_curve(line, InnerMotionMode::Rotation, 0.0, 0.0);
    }
    // Eq. (17), leaving along m and arriving along m̂.
    const double lead = std::max(std::abs(glm::dot(from.normal, delta)), 0.25 * distance) / 3.0;
    const double trail = std::max(std::abs(glm::dot(to.normal, delta)), 0.25 * distance) / 3.0;
    BezierCurve curve({from.position, from.position + lead * from.normal, to.position - trail * to.normal, to.position});
    // The twist closes the gap between w carried along the frame and ŵ.
    const Vec3 carried = transport_along_curve(curve, from.binormal);
    const double twist = signed_angle(carried, to.binormal, to.normal);
    return InnerMotion::along_curve(curve, InnerMotionMode::Rotation, 0.0, twist);
}

}  // namespace vfsd
