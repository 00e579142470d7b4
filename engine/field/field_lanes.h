#pragma once
// The field of vector_field.h (eqs. 1–4 with e, f of eqs. 9–13 and the twist
// of eq. 14) for many points at once: the same formulas over
// structure-of-arrays lanes, with the motion's divisions and square roots done
// once per sample, in a loop the compiler vectorises (SSE2 or AVX on x86-64,
// simd128 in WebAssembly). deformation_velocity stays the readable reference;
// tests/test_vector_field.cpp holds the two together.

#include "curve/inner_motion.h"

namespace vfsd {

constexpr int kFieldLanes = 64;

// Three coordinates of up to kFieldLanes points, one array per coordinate.
struct Lanes3 {
    alignas(64) double x[kFieldLanes];
    alignas(64) double y[kFieldLanes];
    alignas(64) double z[kFieldLanes];
};

// One MotionSample ready for the lane loop.
struct PreparedMotion {
    double c[3], v[3], w[3];                      // c(t), ċ(t), ω + τ
    double omega[3], omega_inv2;                  // ω, 1/|ω|² (0 where ω = 0)
    double twist[3], twist_inv2, twist_origin[3]; // τ, 1/|τ|², the twist stream's origin
    double o[3], u[3];                            // the stream's origin o, U = ċ + ω × (o − c)
    double gauge_centre[3], gauge_inverse_scale;  // the gauge ∇φ (field/stream_gauge.h)
    double gauge[3][10];
    explicit PreparedMotion(const MotionSample& m);
};

// out = v + ṽ at the first n points of `at` (n ≤ kFieldLanes), given 1 − b and ∇b
// per point: deformation_velocity(m, at[j], 1 − one_minus_b[j], grad_b[j]).
void deformation_velocities(const PreparedMotion& m, int n, const double* one_minus_b, const Lanes3& grad_b,
                            const Lanes3& at, Lanes3& out);

}  // namespace vfsd
