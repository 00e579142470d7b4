#pragma once
// The field of vector_field.h (eqs. 1–4 with e, f of eqs. 9–13 and the twist
// of eq. 14) for many points at once: the same formulas over
// structure-of-arrays lanes, with the motion's divisions and square roots done
// once per sample, in SIMD lanes (four doubles on x86-64 with AVX2, two in
// WebAssembly's simd128). deformation_velocity stays the readable reference;
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

// One MotionSample ready for the lane loop. The stream vector f ∇e − e ∇f plus
// the gauge ∇φ is a quadratic polynomial in x (z × U is linear in x, the
// rotation streams of ω and τ and the gauge are quadratic), so it is expanded
// once per sample, about the gauge's centre and in its scale, into the
// coefficients StreamGauge holds: the loop then evaluates one polynomial per
// coordinate instead of the four terms.
struct PreparedMotion {
    double c[3], v[3], w[3];                        // c(t), ċ(t), ω + τ
    double stream_centre[3], stream_inverse_scale;  // the stream vector about its centre:
    double stream[3][10];                           // StreamGauge's coefficients
    explicit PreparedMotion(const MotionSample& m);
};

// out = v + ṽ at the first n points of `at` (n ≤ kFieldLanes), given 1 − b and ∇b
// per point: deformation_velocity(m, at[j], 1 − one_minus_b[j], grad_b[j]).
void deformation_velocities(const PreparedMotion& m, int n, const double* one_minus_b, const Lanes3& grad_b,
                            const Lanes3& at, Lanes3& out);

}  // namespace vfsd
