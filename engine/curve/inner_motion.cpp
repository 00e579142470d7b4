#include "curve/inner_motion.h"

#include <cmath>

namespace vfsd {
namespace {

// Below this speed (relative to the curve's size) ċ counts as zero: a cusp or a
// zero-length end tangent, where ω and ĉ are taken as their one-sided limits.
constexpr double kStationary = 1e-10;
constexpr double kLimitOffset = 1e-6;

// Eqs. (11)–(13) make the inner region rotate about the axis through the curvature
// centre z with direction ċ × c̈. Eq. (12) fixes only that direction; for (8),
// v(c) = ċ, the angular velocity must satisfy ω × (c − z) = ċ, i.e. |ω| = |ċ| κ
// with curvature κ = |ċ × c̈| / |ċ|³. Hence
//     ω = (ċ × c̈) / |ċ|²,
// which tends to zero where the curvature vanishes: the rotation mode degrades
// smoothly into translation, with no curvature centre at infinity ever formed.
Vec3 angular_velocity(const CurvePoint& c) { return glm::cross(c.d1, c.d2) / glm::dot(c.d1, c.d1); }

Vec3 unit_or_zero(const Vec3& v) {
    const double length = glm::length(v);
    return length > 0.0 ? v / length : Vec3(0.0);
}

}  // namespace

InnerMotion InnerMotion::along_curve(BezierCurve curve, InnerMotionMode mode, double alpha0, double alpha1) {
    InnerMotion m;
    m.curve_ = std::move(curve);
    m.mode_ = mode;
    m.alpha0_ = alpha0;
    m.alpha1_ = alpha1;
    return m;
}

InnerMotion InnerMotion::rotation_about(Vec3 centre, Vec3 axis_angle) {
    InnerMotion m;
    m.fixed_rotation_ = true;
    m.centre_ = centre;
    m.axis_angle_ = axis_angle;
    m.curve_ = BezierCurve({centre, centre, centre, centre});
    return m;
}

MotionSample InnerMotion::at(double t, JoinSide join_side) const {
    if (fixed_rotation_) {
        MotionSample s;
        s.position = centre_;
        s.angular_velocity = axis_angle_;
        s.stream_origin = stream_origin_.value_or(centre_);
        s.twist_origin = centre_;
        return s;
    }
    MotionSample s = curve_sample(t, join_side);
    const double scale = curve_.polygon_length();
    if (glm::length(s.velocity) > kStationary * scale || scale == 0.0) return s;
    // ċ vanishes at t: take ω and the tangent direction from just beside t, where
    // the motion heads (after t, or before it at the curve's end).
    const double side = t + kLimitOffset <= 1.0 ? t + kLimitOffset : t - kLimitOffset;
    const MotionSample beside = curve_sample(side, JoinSide::after);
    s.angular_velocity = beside.angular_velocity;
    s.twist = beside.twist;
    s.twist_origin = s.position + twist_plane_ * unit_or_zero(beside.velocity);
    return s;
}

std::vector<double> InnerMotion::joins() const {
    std::vector<double> joins;
    const std::size_t k = fixed_rotation_ ? 0 : curve_.segment_count();
    for (std::size_t j = 1; j < k; ++j) joins.push_back(double(j) / double(k));
    return joins;
}

Vec3 InnerMotion::start_tangent() const {
    if (fixed_rotation_) return Vec3(0.0);
    const Vec3 d1 = curve_.at(0.0).d1;
    const double scale = curve_.polygon_length();
    if (glm::length(d1) > kStationary * scale || scale == 0.0) return unit_or_zero(d1);
    return unit_or_zero(curve_.at(kLimitOffset).d1);
}

MotionSample InnerMotion::curve_sample(double t, JoinSide side) const {
    const CurvePoint c = curve_.at(t, side);
    MotionSample s;
    s.position = c.position;
    s.velocity = c.d1;
    s.stream_origin = stream_origin_.value_or(c.position);
    s.twist_origin = c.position;
    const double speed = glm::length(c.d1);
    if (speed == 0.0) return s;
    if (mode_ == InnerMotionMode::Rotation) s.angular_velocity = angular_velocity(c);
    // Eq. (14) with its scale derived: the twist field ∇ẽ × ∇f̃ with
    // ẽ = k (x − c)·ċ and f̃ = ((x − c) × ċ)² is a rotation about the tangent with
    // angular velocity 2 k |ċ|² ċ. The printed k = λ̇/2π does not make the inner
    // region turn by α(1) − α(0); k = α̇ / (2 |ċ|³) does, giving τ = α̇ ĉ.
    const double alpha_rate = alpha1_ - alpha0_;
    s.twist = alpha_rate * (c.d1 / speed);
    s.twist_origin = c.position + twist_plane_ * (c.d1 / speed);
    return s;
}

}  // namespace vfsd
