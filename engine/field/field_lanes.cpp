#include "field/field_lanes.h"

#include <cmath>

#include "field/vector_field.h"

namespace vfsd {
namespace {

void copy3(const Vec3& from, double* to) { to[0] = from.x, to[1] = from.y, to[2] = from.z; }

double inverse_square_length(const Vec3& v) {
    const double length2 = glm::dot(v, v);
    return length2 == 0.0 ? 0.0 : 1.0 / length2;
}

// rotation_stream of vector_field.cpp for one point y, added to s: with
// 1/|Ω|² = 0 where Ω = 0 the terms vanish without a branch.
inline void add_rotation_stream(const double* omega, double inv2, double y0, double y1, double y2,
                                double& s0, double& s1, double& s2) {
    const double along = omega[0] * y0 + omega[1] * y1 + omega[2] * y2;
    const double k = along * inv2;
    const double p0 = y0 - k * omega[0], p1 = y1 - k * omega[1], p2 = y2 - k * omega[2];
    const double half = 0.5 * (p0 * p0 + p1 * p1 + p2 * p2), lever = along;
    s0 += half * omega[0] - lever * p0;
    s1 += half * omega[1] - lever * p1;
    s2 += half * omega[2] - lever * p2;
}

}  // namespace

PreparedMotion::PreparedMotion(const MotionSample& m) {
    copy3(m.position, c);
    copy3(m.velocity, v);
    copy3(m.angular_velocity + m.twist, w);
    copy3(m.angular_velocity, omega);
    omega_inv2 = inverse_square_length(m.angular_velocity);
    copy3(m.twist, twist);
    twist_inv2 = inverse_square_length(m.twist);
    copy3(m.twist_origin, twist_origin);
    copy3(m.stream_origin, o);
    copy3(origin_velocity(m), u);
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
    for (int j = 0; j < n; ++j) {
        const double y0 = px[j] - m.c[0], y1 = py[j] - m.c[1], y2 = pz[j] - m.c[2];
        // Rigid velocity ∇e × ∇f = ċ + (ω + τ) × y.
        const double i0 = m.v[0] + (m.w[1] * y2 - m.w[2] * y1);
        const double i1 = m.v[1] + (m.w[2] * y0 - m.w[0] * y2);
        const double i2 = m.v[2] + (m.w[0] * y1 - m.w[1] * y0);
        // Stream vector f ∇e − e ∇f = z × U + rotation streams of ω (about o) and τ (about its origin).
        const double z0 = px[j] - m.o[0], z1 = py[j] - m.o[1], z2 = pz[j] - m.o[2];
        double s0 = z1 * m.u[2] - z2 * m.u[1];
        double s1 = z2 * m.u[0] - z0 * m.u[2];
        double s2 = z0 * m.u[1] - z1 * m.u[0];
        add_rotation_stream(m.omega, m.omega_inv2, z0, z1, z2, s0, s1, s2);
        const double q0 = px[j] - m.twist_origin[0], q1 = py[j] - m.twist_origin[1], q2 = pz[j] - m.twist_origin[2];
        add_rotation_stream(m.twist, m.twist_inv2, q0, q1, q2, s0, s1, s2);
        // v = (1 − b)² ∇e × ∇f − (1 − b) (f ∇e − e ∇f) × ∇b  (eqs. 1–3 expanded).
        const double a = one_minus_b[j];
        ox[j] = a * a * i0 - a * (s1 * gz[j] - s2 * gy[j]);
        oy[j] = a * a * i1 - a * (s2 * gx[j] - s0 * gz[j]);
        oz[j] = a * a * i2 - a * (s0 * gy[j] - s1 * gx[j]);
    }
}

}  // namespace vfsd
