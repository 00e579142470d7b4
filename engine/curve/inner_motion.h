#pragma once
// The full deformation the inner region undergoes (sec. 4.2): it follows the curve
// c(t), either translating (eqs. 9–10) or rotating about the curvature centre
// (eqs. 11–13), and twists about the tangent by α(t) (eq. 14). At every time t the
// inner region moves rigidly with the velocity
//
//     u(x) = ċ(t) + (ω(t) + τ(t)) × (x − c(t)),
//
// where ω is the angular velocity of the rotation mode and τ = α̇(t) ĉ(t) the twist.
// MotionSample is what the vector field (field/vector_field.h) needs at one time.

#include <optional>

#include "curve/bezier_curve.h"
#include "field/stream_gauge.h"

namespace vfsd {

enum class InnerMotionMode {
    Rotation,     // eqs. (11)–(13): location and orientation follow the curve
    Translation,  // eqs. (9)–(10): location follows the curve, orientation is kept
};

struct MotionSample {
    Vec3 position{0.0};          // c(t)
    Vec3 velocity{0.0};          // ċ(t)
    Vec3 angular_velocity{0.0};  // ω(t), zero in translation mode
    Vec3 twist{0.0};             // τ(t) = α̇(t) ĉ(t)
    // The point about which the twist's stream is built: on the axis c + λ ĉ, where
    // its plane ẽ = 0 crosses it, c(t) + ζ0 ĉ(t). Eq. (14) puts it at c (ζ0 = 0);
    // see InnerMotion::set_twist_plane. A point, so that it turns and mirrors with
    // the scene whatever the twist's sign.
    Vec3 twist_origin{0.0};
    // Where the zero sets of e and f meet, i.e. the point about which the stream
    // f ∇e − e ∇f of translation and rotation is expanded. Eq. (10) puts it at c(t);
    // see InnerMotion::set_stream_origin.
    Vec3 stream_origin{0.0};
    // ∇φ added to the stream (field/stream_gauge.h): fitted to the blend region
    // by the deformation at each step; zero (the paper's gauge) from InnerMotion.
    StreamGauge gauge;
};

class InnerMotion {
public:
    // Inner region follows `curve`; α(t) = alpha0 + t (alpha1 − alpha0) in radians,
    // positive angles counter-clockwise about ċ (right-hand rule).
    static InnerMotion along_curve(BezierCurve curve, InnerMotionMode mode, double alpha0, double alpha1);
    // Inner region turns about the fixed point `centre` by the rotation vector
    // `axis_angle` (direction = axis, length = angle in radians) over t in [0,1]:
    // the pure handle rotation of sec. 6.2, eq. (5) with z = h.
    static InnerMotion rotation_about(Vec3 centre, Vec3 axis_angle);

    // At a join of the curve, the motion of the segment after it (or before it, BezierCurve::at).
    MotionSample at(double t, JoinSide side = JoinSide::after) const;
    // The times 0 < t < 1 where the curve's segments join (BezierCurve: j / k),
    // ascending: ċ may turn there, so a step ends on each rather than straddle it.
    std::vector<double> joins() const;

    // The twist's constant of integration. ẽ of eq. (14) may be shifted by any
    // constant without changing the inner region's motion, but the shift decides
    // how the blend region twists: with cross-sections at signed distance ζ along
    // ĉ turning at the rate α̇ (1 − b) ∂ζ[(1 − b)(ζ − ζ0)], the printed ζ0 = 0 (the
    // plane through c) makes the middle of the blend region turn backwards. Putting
    // the plane at the far end of the moving part (ζ0 < 0) keeps every section
    // turning forward. See docs/method.md.
    void set_twist_plane(double signed_distance) { twist_plane_ = signed_distance; }
    double twist_plane() const { return twist_plane_; }

    // The stream's origin o. The inner region's velocity ċ + ω × (x − c) is also
    // U + ω × (x − o) with U = ċ + ω × (o − c), so e, f may be built about any point
    // o (planes through o for U, eqs. 9–10; an axis through o for ω, eqs. 11–13):
    // the inner region moves the same and v stays divergence-free, but the blend
    // region's stream grows with the distance from o (linearly for U, squared for
    // ω). Eq. (10)'s o = c(t) suits moves that stay near the start; a point fixed
    // inside the blend region keeps the stream small there when c(t) travels far
    // (a loop, fig. 14). Unset: o = c(t). See docs/method.md.
    void set_stream_origin(std::optional<Vec3> fixed_point) { stream_origin_ = fixed_point; }
    const std::optional<Vec3>& stream_origin() const { return stream_origin_; }

    InnerMotionMode mode() const { return mode_; }
    const BezierCurve& curve() const { return curve_; }
    // The unit direction the inner region leaves c(0) in: ċ(0), or just after 0
    // where ċ(0) vanishes (a zero-length end tangent); 0 for a fixed rotation or a
    // curve that does not move.
    Vec3 start_tangent() const;
    bool is_fixed_rotation() const { return fixed_rotation_; }
    double alpha0() const { return alpha0_; }
    double alpha1() const { return alpha1_; }
    const Vec3& rotation_centre() const { return centre_; }
    const Vec3& rotation_vector() const { return axis_angle_; }

private:
    MotionSample curve_sample(double t, JoinSide side) const;

    InnerMotionMode mode_ = InnerMotionMode::Rotation;
    BezierCurve curve_;
    double alpha0_ = 0.0, alpha1_ = 0.0;
    bool fixed_rotation_ = false;
    double twist_plane_ = 0.0;
    std::optional<Vec3> stream_origin_;
    Vec3 centre_{0.0}, axis_angle_{0.0};
};

}  // namespace vfsd
