#include "field/field_lanes.h"

#include <cmath>
#include <cstring>

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

namespace {

// The lanes are run one point at a time (V = double), a loop GCC vectorises,
// or in WebAssembly two points at a time (V = Doubles, simd128's two doubles):
// there clang vectorised the scalar loop but loaded and splatted the motion's
// 43 coefficients again for every pair of points (too many to keep in
// registers), and the field took 9.3 ns a point against 6.0 in explicit
// vectors (node 20; the same bits; docs/web.md, "The page's SIMD"). On x86-64
// the explicit vectors were 7 % slower than GCC's own loop.
#if defined(__wasm_simd128__)
#define VFSD_FIELD_IN_VECTORS 1
using Doubles = double __attribute__((vector_size(2 * sizeof(double))));
#endif

// x in every lane of V (x − 0 is x, −0 too).
template <class V>
[[gnu::always_inline]] inline V splat(double x) {
    return x - V{};
}

// The motion's coefficients, each in every lane of V.
template <class V>
struct Coefficients {
    V c[3], v[3], w[3], centre[3], inverse_scale, q[3][10];
    [[gnu::always_inline]] explicit Coefficients(const PreparedMotion& m) {
        for (int i = 0; i < 3; ++i) {
            c[i] = splat<V>(m.c[i]), v[i] = splat<V>(m.v[i]), w[i] = splat<V>(m.w[i]);
            centre[i] = splat<V>(m.stream_centre[i]);
            for (int k = 0; k < 10; ++k) q[i][k] = splat<V>(m.stream[i][k]);
        }
        inverse_scale = splat<V>(m.stream_inverse_scale);
    }
};

template <class V>
[[gnu::always_inline]] inline V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <class V>
[[gnu::always_inline]] inline void store(double* p, const V& v) {
    std::memcpy(p, &v, sizeof v);
}

// deformation_velocities at the points j .. j + lanes of V, each lane on its
// own: the same operations in the same order for a double and for Doubles, so
// the same bits either way.
template <class V>
[[gnu::always_inline]] inline void field_at(const Coefficients<V>& m, int j, const double* one_minus_b,
                                            const Lanes3& grad_b, const Lanes3& at, Lanes3& out) {
    const V px = load<V>(at.x + j), py = load<V>(at.y + j), pz = load<V>(at.z + j);
    const V y0 = px - m.c[0], y1 = py - m.c[1], y2 = pz - m.c[2];
    // Rigid velocity ∇e × ∇f = ċ + (ω + τ) × y.
    const V i0 = m.v[0] + (m.w[1] * y2 - m.w[2] * y1);
    const V i1 = m.v[1] + (m.w[2] * y0 - m.w[0] * y2);
    const V i2 = m.v[2] + (m.w[0] * y1 - m.w[1] * y0);
    // Stream vector f ∇e − e ∇f + ∇φ, the polynomial PreparedMotion expanded.
    const V d0 = (px - m.centre[0]) * m.inverse_scale;
    const V d1 = (py - m.centre[1]) * m.inverse_scale;
    const V d2 = (pz - m.centre[2]) * m.inverse_scale;
    const V d00 = d0 * d0, d11 = d1 * d1, d22 = d2 * d2, d01 = d0 * d1, d02 = d0 * d2, d12 = d1 * d2;
    const V(&q)[3][10] = m.q;
    const V s0 = q[0][0] + q[0][1] * d0 + q[0][2] * d1 + q[0][3] * d2 + q[0][4] * d00 + q[0][5] * d11 + q[0][6] * d22 +
                 q[0][7] * d01 + q[0][8] * d02 + q[0][9] * d12;
    const V s1 = q[1][0] + q[1][1] * d0 + q[1][2] * d1 + q[1][3] * d2 + q[1][4] * d00 + q[1][5] * d11 + q[1][6] * d22 +
                 q[1][7] * d01 + q[1][8] * d02 + q[1][9] * d12;
    const V s2 = q[2][0] + q[2][1] * d0 + q[2][2] * d1 + q[2][3] * d2 + q[2][4] * d00 + q[2][5] * d11 + q[2][6] * d22 +
                 q[2][7] * d01 + q[2][8] * d02 + q[2][9] * d12;
    // v = (1 − b)² ∇e × ∇f − (1 − b) (f ∇e − e ∇f) × ∇b  (eqs. 1–3 expanded).
    const V a = load<V>(one_minus_b + j);
    const V gx = load<V>(grad_b.x + j), gy = load<V>(grad_b.y + j), gz = load<V>(grad_b.z + j);
    store(out.x + j, a * a * i0 - a * (s1 * gz - s2 * gy));
    store(out.y + j, a * a * i1 - a * (s2 * gx - s0 * gz));
    store(out.z + j, a * a * i2 - a * (s0 * gy - s1 * gx));
}

}  // namespace

// On x86-64 with GCC, an AVX2 clone (four doubles per instruction, no FMA, so
// the same bits as the baseline SSE2 one) is picked at load time where the CPU
// has it.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void deformation_velocities(const PreparedMotion& m, int n, const double* one_minus_b, const Lanes3& grad_b,
                            const Lanes3& at, Lanes3& out) {
    int j = 0;
#ifdef VFSD_FIELD_IN_VECTORS
    const Coefficients<Doubles> pairs(m);
    for (; j + 2 <= n; j += 2) field_at(pairs, j, one_minus_b, grad_b, at, out);
#endif
    const Coefficients<double> one(m);
    for (; j < n; ++j) field_at(one, j, one_minus_b, grad_b, at, out);
}

}  // namespace vfsd
