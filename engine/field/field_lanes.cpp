#include "field/field_lanes.h"

#include <cmath>

#include "field/stream_gauge.h"
#include "field/vector_field.h"

namespace vfsd {
namespace {

void copy3(const Vec3& from, double* to) { to[0] = from.x, to[1] = from.y, to[2] = from.z; }

}  // namespace

PreparedMotion::PreparedMotion(const MotionSample& m) {
    copy3(m.position, c);
    copy3(m.velocity, v);
    copy3(m.angular_velocity + m.twist, w);
    // About the gauge's centre and in its scale, where the blend region is (the
    // paper's gauge: the local frame's origin, within a diagonal of the mesh).
    const StreamGauge s =
        stream_polynomial(m, m.gauge.centre, m.gauge.inverse_scale > 0.0 ? m.gauge.inverse_scale : 1.0);
    copy3(s.centre, stream_centre);
    stream_inverse_scale = s.inverse_scale;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 10; ++k) stream[i][k] = s.q[i][k];
}

// On x86-64 with GCC, an AVX2 clone (four doubles per instruction, no FMA, so
// the same bits as the baseline SSE2 one) is picked at load time where the CPU
// has it.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void deformation_velocities(const PreparedMotion& m, int n, const double* __restrict one_minus_b,
                            const Lanes3& grad_b, const Lanes3& at, Lanes3& out) {
    const double* __restrict px = at.x;
    const double* __restrict py = at.y;
    const double* __restrict pz = at.z;
    const double* __restrict gx = grad_b.x;
    const double* __restrict gy = grad_b.y;
    const double* __restrict gz = grad_b.z;
    double* __restrict ox = out.x;
    double* __restrict oy = out.y;
    double* __restrict oz = out.z;
    const double(&q)[3][10] = m.stream;
    for (int j = 0; j < n; ++j) {
        const double y0 = px[j] - m.c[0], y1 = py[j] - m.c[1], y2 = pz[j] - m.c[2];
        // Rigid velocity ∇e × ∇f = ċ + (ω + τ) × y.
        const double i0 = m.v[0] + (m.w[1] * y2 - m.w[2] * y1);
        const double i1 = m.v[1] + (m.w[2] * y0 - m.w[0] * y2);
        const double i2 = m.v[2] + (m.w[0] * y1 - m.w[1] * y0);
        // Stream vector f ∇e − e ∇f + ∇φ, the polynomial PreparedMotion expanded.
        const double d0 = (px[j] - m.stream_centre[0]) * m.stream_inverse_scale;
        const double d1 = (py[j] - m.stream_centre[1]) * m.stream_inverse_scale;
        const double d2 = (pz[j] - m.stream_centre[2]) * m.stream_inverse_scale;
        const double d00 = d0 * d0, d11 = d1 * d1, d22 = d2 * d2, d01 = d0 * d1, d02 = d0 * d2, d12 = d1 * d2;
        const double s0 = q[0][0] + q[0][1] * d0 + q[0][2] * d1 + q[0][3] * d2 + q[0][4] * d00 + q[0][5] * d11 +
                          q[0][6] * d22 + q[0][7] * d01 + q[0][8] * d02 + q[0][9] * d12;
        const double s1 = q[1][0] + q[1][1] * d0 + q[1][2] * d1 + q[1][3] * d2 + q[1][4] * d00 + q[1][5] * d11 +
                          q[1][6] * d22 + q[1][7] * d01 + q[1][8] * d02 + q[1][9] * d12;
        const double s2 = q[2][0] + q[2][1] * d0 + q[2][2] * d1 + q[2][3] * d2 + q[2][4] * d00 + q[2][5] * d11 +
                          q[2][6] * d22 + q[2][7] * d01 + q[2][8] * d02 + q[2][9] * d12;
        // v = (1 − b)² ∇e × ∇f − (1 − b) (f ∇e − e ∇f) × ∇b  (eqs. 1–3 expanded).
        const double a = one_minus_b[j];
        ox[j] = a * a * i0 - a * (s1 * gz[j] - s2 * gy[j]);
        oy[j] = a * a * i1 - a * (s2 * gx[j] - s0 * gz[j]);
        oz[j] = a * a * i2 - a * (s0 * gy[j] - s1 * gx[j]);
    }
}

}  // namespace vfsd
