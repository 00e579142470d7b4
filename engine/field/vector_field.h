#pragma once
// The divergence-free deformation field of sec. 2 and sec. 4:
//     v = ∇p × ∇q,  p = (1 − b) e,  q = (1 − b) f            (eqs. 1–3)
// with the blend b of eq. (4), e, f of eqs. (9)–(13) and the twist field of
// eq. (14) added on top. Expanding the gradients,
//     v = (1 − b)² ∇e × ∇f − (1 − b) (f ∇e − e ∇f) × ∇b,
// where ∇e × ∇f is the rigid velocity of the inner region and f ∇e − e ∇f is a
// "stream vector" that depends only on the motion. Both are evaluated in closed
// form (see vector_field.cpp), which stays finite where the curvature vanishes.

#include "curve/inner_motion.h"

namespace vfsd {

// b(u) = Σ w_i B_i^4(u) with w = (0,0,0,1,1), eq. (4): 4u³ − 3u⁴ on [0,1],
// 0 below and 1 above; u = (r − r_i)/(r_o − r_i) = s for the surface field.
double bernstein_blend(double u);
// db/du: 12 u² (1 − u) on [0,1], 0 outside.
double bernstein_blend_derivative(double u);

// Rigid velocity of the inner region at x: ∇e × ∇f (+ ∇ẽ × ∇f̃).
Vec3 inner_velocity(const MotionSample& m, const Vec3& x);
// The inner region's velocity without the twist at the stream's origin o:
// U = ċ + ω × (o − c).
Vec3 origin_velocity(const MotionSample& m);
// f ∇e − e ∇f (+ f̃ ∇ẽ − ẽ ∇f̃) at x, e and f built about m.stream_origin.
Vec3 stream_vector(const MotionSample& m, const Vec3& x);

// v + ṽ at x, given the blend b(x) and its spatial gradient ∇b(x).
Vec3 deformation_velocity(const MotionSample& m, const Vec3& x, double b, const Vec3& grad_b);

}  // namespace vfsd
