#pragma once
// Handle mode (sec. 6.2): a 6-DOF handle (h, m, w) — position, normal, binormal —
// moved to (ĥ, m̂, ŵ) becomes a curve c(t) and a linear twist α(t).

#include "curve/inner_motion.h"

namespace vfsd {

struct HandleFrame {
    Vec3 position{0.0};
    Vec3 normal{0.0, 0.0, 1.0};    // m, unit length
    Vec3 binormal{1.0, 0.0, 0.0};  // w, unit length, w·m = 0
};

// Builds the motion that carries `from` onto `to` in rotation mode:
// - a pure translation (same frame) is the straight line with constant α;
// - a pure rotation (same position) is the rotation field (5) about h;
// - otherwise the cubic Bézier of eq. (17) and α(t) linear.
// Eq. (17) is used with |m·(ĥ − h)| and |m̂·(ĥ − h)| so the curve always leaves
// along m and arrives along m̂ (as printed, a handle moved against its normal would
// arrive along −m̂), and with a floor of |ĥ − h| / 4 on both, so that m ⟂ ĥ − h
// gives no zero-length tangent. α(1) − α(0) is not taken from the projections of
// fig. 12 (exact only for planar curves) but from transporting w along the curve's
// rotation-minimising frame, which is what rotation mode realises, so the handle
// lands on ŵ exactly. Throws InputError for non-unit or non-orthogonal frames.
InnerMotion handle_motion(const HandleFrame& from, const HandleFrame& to);

// Transports the vector `u` (perpendicular to the start tangent) along the
// rotation-minimising frame of `curve` (double reflection, Wang et al. 2008).
Vec3 transport_along_curve(const BezierCurve& curve, const Vec3& u, int samples = 2048);

}  // namespace vfsd
