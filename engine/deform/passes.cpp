#include "deform/passes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "base/error.h"
#include "base/parallel.h"
#include "field/field_lanes.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"

namespace vfsd {
namespace {

// One classical RK4 step of dx/dt = velocity(x, sample) from x.
template <class Velocity>
Vec3 rk4(const StepMotion& m, const Vec3& x, const Velocity& velocity) {
    const double h = m.h;
    const Vec3 k1 = velocity(x, m.start);
    const Vec3 k2 = velocity(x + 0.5 * h * k1, m.middle);
    const Vec3 k3 = velocity(x + 0.5 * h * k2, m.middle);
    const Vec3 k4 = velocity(x + h * k3, m.end);
    return x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

// One step of the explicit midpoint rule (RK2): the midpoint predictor's.
template <class Velocity>
Vec3 midpoint_rule(const StepMotion& m, const Vec3& x, const Velocity& velocity) {
    const Vec3 k1 = velocity(x, m.start);
    return x + m.h * velocity(x + 0.5 * m.h * k1, m.middle);
}

// One RK4 step (or midpoint rule step) of the inner region, x ↦ x0′ + M (x − x0).
// With b = 0 and ∇b = 0 the field is the rigid velocity ċ + (ω + τ) × (x − c),
// affine in x, and either step of an affine field is an affine map of the start
// point: four points fix it, and every inner vertex then costs one matrix
// product instead of four (two) field evaluations.
struct AffineStep {
    Vec3 x0, image;     // a point and where the step takes it
    glm::dmat3 linear;  // M
    Vec3 operator()(const Vec3& x) const { return image + linear * (x - x0); }
};

// RK4's map of a rotation field is a rotation only up to O(h⁵) per step; over a
// strong bend or twist those errors add up to a shear of 1e-7 of the diagonal.
// The inner region is to move rigidly (sec. 3), so the step keeps the orthogonal
// factor of M, its polar decomposition by Higham's iteration R ← ½ (R + R⁻ᵀ),
// which converges quadratically from a matrix this close to a rotation.
glm::dmat3 nearest_rotation(glm::dmat3 r) {
    for (int i = 0; i < 5; ++i) r = 0.5 * (r + glm::transpose(glm::inverse(r)));
    return r;
}

enum class Stepper { rk4, midpoint_rule };

AffineStep rigid_step(const StepMotion& m, Stepper stepper) {
    const auto rigid = [](const Vec3& x, const MotionSample& sample) { return inner_velocity(sample, x); };
    const auto step_from = [&](const Vec3& x) {
        return stepper == Stepper::rk4 ? rk4(m, x, rigid) : midpoint_rule(m, x, rigid);
    };
    AffineStep step{m.start.position, step_from(m.start.position), glm::dmat3(1.0)};
    for (int axis = 0; axis < 3; ++axis) step.linear[axis] = step_from(step.x0 + step.linear[axis]) - step.image;
    step.linear = nearest_rotation(step.linear);
    return step;
}

// Calls body(first, count) for consecutive blocks of at most kFieldLanes of the
// indices [0, n), on all threads.
template <class Body>
void for_each_block(std::size_t n, const Body& body) {
    parallel_for(n, [&](std::size_t first, std::size_t last) {
        for (std::size_t begin = first; begin < last; begin += kFieldLanes)
            body(begin, static_cast<int>(std::min<std::size_t>(kFieldLanes, last - begin)));
    });
}

// The blend vertices blend[first .. first + count) as field lanes: position,
// 1 − b(s) and ∇b = b′(s) ∇r (eq. 4 with r_i = 0, r_o = 1, r = s).
struct BlendLanes {
    Lanes3 position, grad_b, keeper;
    double one_minus_b[kFieldLanes];
    bool has_keeper = false;  // the volume keeper's velocity, added at every stage

    [[gnu::always_inline]] void gather(const RegionParts& parts, std::size_t first, int count,
                                       const GradientRecords& gradients, const std::vector<Vec3>& positions,
                                       const KeeperVelocity& keeper_velocity) {
        has_keeper = keeper_velocity.area_vectors != nullptr;
        if (has_keeper)
            for (int j = 0; j < count; ++j) {
                const std::size_t i = first + j;
                const double scale = keeper_velocity.lambda / 6.0 * (parts.one_minus_b[i] * parts.b_slope[i]);
                const Vec3& a = (*keeper_velocity.area_vectors)[i];
                keeper.x[j] = scale * a.x, keeper.y[j] = scale * a.y, keeper.z[j] = scale * a.z;
            }
        for (int j = 0; j < count; ++j) {
            const std::uint32_t v = parts.blend[first + j];
            const Float4& r = gradients[first + j];
            const Vec3 g = parts.b_slope[first + j] * Vec3(r[0], r[1], r[2]);
            position.x[j] = positions[v].x, position.y[j] = positions[v].y, position.z[j] = positions[v].z;
            grad_b.x[j] = g.x, grad_b.y[j] = g.y, grad_b.z[j] = g.z;
            one_minus_b[j] = parts.one_minus_b[first + j];
        }
        for (int j = count; j < kFieldLanes; ++j)  // unused lanes, defined all the same
            position.x[j] = position.y[j] = position.z[j] = grad_b.x[j] = grad_b.y[j] = grad_b.z[j] = one_minus_b[j] = 0.0;
    }
};

// to = from + scale · k on the first count lanes.
[[gnu::always_inline]] inline void add_scaled(int count, const Lanes3& from, double scale, const Lanes3& k,
                                              Lanes3& to) {
    for (int j = 0; j < count; ++j) {
        to.x[j] = from.x[j] + scale * k.x[j];
        to.y[j] = from.y[j] + scale * k.y[j];
        to.z[j] = from.z[j] + scale * k.z[j];
    }
}

// The points stage positions and the step's end are taken from: the start
// positions, or with the keeper's velocity c (constant over the step) the start
// positions moved along it by half the step and by the whole step. So RK4 of
// v + c adds c to no stage's field: x + (h/2)(v + c) = (x + (h/2) c) + (h/2) v.
struct StageBases {
    Lanes3 half, full;
    const Lanes3 *to_half, *to_full;
    [[gnu::always_inline]] StageBases(const BlendLanes& in, int count, double h) {
        to_half = to_full = &in.position;
        if (!in.has_keeper) return;
        add_scaled(count, in.position, 0.5 * h, in.keeper, half);
        add_scaled(count, in.position, h, in.keeper, full);
        to_half = &half, to_full = &full;
    }
};

// Writes lane j to positions[blend[first + j]].
[[gnu::always_inline]] inline void scatter(const Lanes3& lanes, const std::vector<std::uint32_t>& blend,
                                           std::size_t first, int count, std::vector<Vec3>& positions) {
    for (int j = 0; j < count; ++j) positions[blend[first + j]] = Vec3(lanes.x[j], lanes.y[j], lanes.z[j]);
}

// rk4() above for a block of blend lanes, the field evaluated lane-wise; the
// sum k1 + 2 k2 + 2 k3 + k4 is formed in the same order.
[[gnu::always_inline]] inline void rk4_lanes(const StepMotion& motion, const PreparedMotion (&m)[3],
                                             const BlendLanes& in, int count, Lanes3& out) {
    const double h = motion.h;
    const StageBases base(in, count, h);
    Lanes3 k, x, sum;
    deformation_velocities(m[0], count, in.one_minus_b, in.grad_b, in.position, k);  // k1
    std::copy_n(k.x, count, sum.x), std::copy_n(k.y, count, sum.y), std::copy_n(k.z, count, sum.z);
    add_scaled(count, *base.to_half, 0.5 * h, k, x);
    deformation_velocities(m[1], count, in.one_minus_b, in.grad_b, x, k);  // k2
    add_scaled(count, sum, 2.0, k, sum);
    add_scaled(count, *base.to_half, 0.5 * h, k, x);
    deformation_velocities(m[1], count, in.one_minus_b, in.grad_b, x, k);  // k3
    add_scaled(count, sum, 2.0, k, sum);
    add_scaled(count, *base.to_full, h, k, x);
    deformation_velocities(m[2], count, in.one_minus_b, in.grad_b, x, k);  // k4
    add_scaled(count, sum, 1.0, k, sum);
    add_scaled(count, *base.to_full, h / 6.0, sum, out);
}

// midpoint_rule() above for a block of blend lanes.
[[gnu::always_inline]] inline void midpoint_lanes(const StepMotion& motion, const PreparedMotion (&m)[3],
                                                  const BlendLanes& in, int count, Lanes3& out) {
    const double h = motion.h;
    const StageBases base(in, count, h);
    Lanes3 k, x;
    deformation_velocities(m[0], count, in.one_minus_b, in.grad_b, in.position, k);
    add_scaled(count, *base.to_half, 0.5 * h, k, x);
    deformation_velocities(m[1], count, in.one_minus_b, in.grad_b, x, k);
    add_scaled(count, *base.to_full, h, k, out);
}

bool is_finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// The blend vertices blend[first .. first + n) through one step (RK4 or the
// midpoint rule), from `from` into `to`; returns how many it moved to a
// non-finite position. One function, with the lane helpers above inlined
// into it, so that its AVX2 clone (where the CPU has it; no FMA, so the same
// bits as the baseline) takes the lanes' gathering, stages, sums and checks
// four doubles at a time, as deformation_velocities does the field: 5 % off
// the 53k step on one thread (docs/benchmarks.md, "Rings unrolled by valence").
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
std::size_t
step_block(const StepMotion& motion, Stepper stepper, const PreparedMotion (&m)[3], const RegionParts& parts,
           const GradientRecords& gradients, const KeeperVelocity& keeper, const std::vector<Vec3>& from,
           std::size_t first, int n, std::vector<Vec3>& to) {
    BlendLanes lanes;
    Lanes3 next;
    lanes.gather(parts, first, n, gradients, from, keeper);
    if (stepper == Stepper::rk4)
        rk4_lanes(motion, m, lanes, n, next);
    else
        midpoint_lanes(motion, m, lanes, n, next);
    std::size_t count = 0;
    for (int j = 0; j < n; ++j)
        count += !(int(std::isfinite(next.x[j])) & int(std::isfinite(next.y[j])) & int(std::isfinite(next.z[j])));
    scatter(next, parts.blend, first, n, to);
    return count;
}

// Σ v · a over the blend vertices blend[first .. first + n), v the field there
// as step_block takes it and a = area_vectors[i].
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
double
flux_block(const PreparedMotion& m, const RegionParts& parts, const GradientRecords& gradients,
           const std::vector<Vec3>& at, const std::vector<Vec3>& area_vectors, std::size_t first, int n) {
    BlendLanes lanes;
    Lanes3 k;
    lanes.gather(parts, first, n, gradients, at, {});
    deformation_velocities(m, n, lanes.one_minus_b, lanes.grad_b, lanes.position, k);
    double sum = 0.0;
    for (int j = 0; j < n; ++j) {
        const Vec3& a = area_vectors[first + j];
        sum += k.x[j] * a.x + k.y[j] * a.y + k.z[j] * a.z;
    }
    return sum;
}

// One step (RK4 or the midpoint rule) of the inner and blend vertices from
// `from` into `to`, with r = s and ∇r fixed over the step; returns how many it
// moved to a non-finite position.
std::size_t step_vertices(const StepMotion& motion, Stepper stepper, const RegionParts& parts,
                          const GradientRecords& gradients, const KeeperVelocity& keeper, const std::vector<Vec3>& from,
                          std::vector<Vec3>& to) {
    std::atomic<std::size_t> non_finite{0};
    const AffineStep rigid = rigid_step(motion, stepper);
    parallel_for(parts.inner.size(), [&](std::size_t first, std::size_t last) {
        std::size_t count = 0;
        for (std::size_t i = first; i < last; ++i) {
            const std::uint32_t v = parts.inner[i];
            to[v] = rigid(from[v]);
            count += !is_finite(to[v]);
        }
        non_finite += count;
    });
    const PreparedMotion m[3] = {PreparedMotion(motion.start), PreparedMotion(motion.middle),
                                 PreparedMotion(motion.end)};
    parallel_for(parts.blend.size(), [&](std::size_t first, std::size_t last) {
        std::size_t count = 0;
        for (std::size_t begin = first; begin < last; begin += kFieldLanes) {
            const int n = static_cast<int>(std::min<std::size_t>(kFieldLanes, last - begin));
            count += step_block(motion, stepper, m, parts, gradients, keeper, from, begin, n, to);
        }
        non_finite += count;
    });
    return non_finite;
}

bool in_blend(double s) { return s > 0.0 && s < 1.0; }

// Eq. (6) at vertex v with unit normal n: in tangent coordinates p = ((y − x)·t1,
// (y − x)·t2), the least-squares fit of s(y) − s(x) ≈ g·p over the 1-ring solves
// the 2×2 normal equations Σ p pᵀ g = Σ p (s(y) − s(x)); g·n = 0 by construction.
// A ring that spans no plane (or a vertex without a normal) gives no gradient:
// the normal equations' determinant, over their trace squared, below
// kFlatRing (the ring's points within about 1e-3 of a line, relative to its size).
// The GPU's gradient pass tests the same quotient (shaders/gradient.frag): a
// threshold float resolves, so that both passes call the same rings singular.
constexpr double kFlatRing = 1e-6;

// The gradient pass on a block of blend vertices, in three parts, each in SIMD
// lanes: the tangent bases and the solutions (their divisions bound a loop that
// takes one vertex at a time), and between them the ring sums, four vertices
// side by side.
struct GradientLanes {
    Lanes3 normal, t1, t2, gradient;
    double a11[kFieldLanes], a12[kFieldLanes], a22[kFieldLanes], r1[kFieldLanes], r2[kFieldLanes];
};

// Two unit tangents t1, t2 with (t1, t2, n) orthonormal, for a unit n (Duff et
// al., "Building an orthonormal basis, revisited", 2017), in each lane.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void tangent_lanes(int count, GradientLanes& l) {
    static_assert(kFieldLanes % 4 == 0, "ring_sums_lanes reads the tangents four lanes at a time");
    for (int j = count; j < (count + 3) / 4 * 4; ++j)
        l.t1.x[j] = l.t1.y[j] = l.t1.z[j] = l.t2.x[j] = l.t2.y[j] = l.t2.z[j] = 0.0;
    for (int j = 0; j < count; ++j) {
        const double nx = l.normal.x[j], ny = l.normal.y[j], nz = l.normal.z[j];
        const double sign = std::copysign(1.0, nz);
        const double a = -1.0 / (sign + nz), b = nx * ny * a;
        l.t1.x[j] = 1.0 + sign * nx * nx * a, l.t1.y[j] = sign * b, l.t1.z[j] = -sign * nx;
        l.t2.x[j] = b, l.t2.y[j] = sign + ny * ny * a, l.t2.z[j] = -ny;
    }
}

// Σ p pᵀ and Σ p (s(y) − s(x)) over the rings of vertices[0 .. count), into
// lanes 0 .. count; zero sums (no gradient) for a vertex without a normal. Four
// vertices side by side: neighbour k of each of the four at once, a ring
// shorter than the longest of the four padded with the vertex itself (d = 0
// adds ±0 to every sum, which leaves it as it was), so that four rings' sums
// run in SIMD lanes instead of one ring's five chains of additions one after
// the other. Per vertex, the operations and their order are those of a loop
// over its ring alone. Two side by side in WebAssembly, whose simd128 holds
// two doubles: four took twice the vectors, more than stay in registers (the
// gradient pass on the 41k sphere's blend region 0.93 → 0.75 ms in node 20,
// the same bits; docs/web.md, "The page's SIMD").
#if defined(__wasm_simd128__)
constexpr int kRingLanes = 2;
#else
constexpr int kRingLanes = 4;
#endif
using RingDoubles = double __attribute__((vector_size(kRingLanes * sizeof(double))));  // as Float4 (deform/passes.h)

// out = get(w[j]) − minus in lane j.
template <class Get, std::size_t... J>
[[gnu::always_inline]] inline void ring_lanes(const std::uint32_t (&w)[kRingLanes], Get get, const RingDoubles& minus,
                                              RingDoubles& out, std::index_sequence<J...>) {
    out = RingDoubles{get(w[J])...} - minus;
}
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void ring_sums_lanes(const Vec3* positions, const double* s, const VertexRings& rings,
                     const std::uint32_t* vertices, int count, GradientLanes& l) {
    const std::uint32_t* neighbours = rings.neighbours.data();
    constexpr auto lanes = std::make_index_sequence<kRingLanes>();
    const auto x_of = [positions](std::uint32_t v) { return positions[v].x; };
    const auto y_of = [positions](std::uint32_t v) { return positions[v].y; };
    const auto z_of = [positions](std::uint32_t v) { return positions[v].z; };
    const auto s_of = [s](std::uint32_t v) { return s[v]; };
    for (int g = 0; g < count; g += kRingLanes) {
        std::uint32_t vertex[kRingLanes], begin[kRingLanes], size[kRingLanes], most = 0;
        RingDoubles x, y, z, sv, t1x, t1y, t1z, t2x, t2y, t2z;
        for (int j = 0; j < kRingLanes; ++j) {
            const int lane = g + j < count ? g + j : g;  // lanes past the end repeat the first, unused
            const std::uint32_t v = vertices[lane];
            const bool normal = l.normal.x[lane] != 0.0 || l.normal.y[lane] != 0.0 || l.normal.z[lane] != 0.0;
            vertex[j] = v, begin[j] = rings.offsets[v];
            size[j] = normal && g + j < count ? rings.offsets[v + 1] - begin[j] : 0;
            most = std::max(most, size[j]);
            x[j] = positions[v].x, y[j] = positions[v].y, z[j] = positions[v].z, sv[j] = s[v];
        }
        // The tangents of lanes g .. g + kRingLanes as they lie in the block's
        // arrays (lanes past count hold zeros, tangent_lanes'; their sums are not kept).
        std::memcpy(&t1x, l.t1.x + g, sizeof t1x), std::memcpy(&t1y, l.t1.y + g, sizeof t1y);
        std::memcpy(&t1z, l.t1.z + g, sizeof t1z), std::memcpy(&t2x, l.t2.x + g, sizeof t2x);
        std::memcpy(&t2y, l.t2.y + g, sizeof t2y), std::memcpy(&t2z, l.t2.z + g, sizeof t2z);
        RingDoubles a11{}, a12{}, a22{}, r1{}, r2{};
        for (std::uint32_t k = 0; k < most; ++k) {
            std::uint32_t w[kRingLanes];
            for (int j = 0; j < kRingLanes; ++j) w[j] = k < size[j] ? neighbours[begin[j] + k] : vertex[j];
            RingDoubles dx, dy, dz, ds;
            ring_lanes(w, x_of, x, dx, lanes), ring_lanes(w, y_of, y, dy, lanes);
            ring_lanes(w, z_of, z, dz, lanes), ring_lanes(w, s_of, sv, ds, lanes);
            const RingDoubles p1 = dx * t1x + dy * t1y + dz * t1z, p2 = dx * t2x + dy * t2y + dz * t2z;
            a11 += p1 * p1, a12 += p1 * p2, a22 += p2 * p2;
            r1 += p1 * ds, r2 += p2 * ds;
        }
        for (int j = 0; j < kRingLanes && g + j < count; ++j) {
            l.a11[g + j] = a11[j], l.a12[g + j] = a12[j], l.a22[g + j] = a22[j];
            l.r1[g + j] = r1[j], l.r2[g + j] = r2[j];
        }
    }
}

// The 2×2 systems' solutions g = c1 t1 + c2 t2 in each lane, or 0 where kFlatRing rejects it.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void solve_lanes(int count, GradientLanes& l) {
    for (int j = 0; j < count; ++j) {
        const double a11 = l.a11[j], a12 = l.a12[j], a22 = l.a22[j], r1 = l.r1[j], r2 = l.r2[j];
        const double scale = a11 + a22, det = a11 * a22 - a12 * a12;
        const bool spans = det > kFlatRing * scale * scale;
        const double divisor = spans ? det : 1.0;  // no division by zero in the lanes not taken
        const double c1 = a22 * r1 - a12 * r2, c2 = a11 * r2 - a12 * r1;
        const double gx = (c1 * l.t1.x[j] + c2 * l.t2.x[j]) / divisor, gy = (c1 * l.t1.y[j] + c2 * l.t2.y[j]) / divisor,
                     gz = (c1 * l.t1.z[j] + c2 * l.t2.z[j]) / divisor;
        l.gradient.x[j] = spans ? gx : 0.0, l.gradient.y[j] = spans ? gy : 0.0, l.gradient.z[j] = spans ? gz : 0.0;
    }
}

// Ring sizes up to this take w / size from a table in the smoothing pass.
constexpr int kTabledRing = 64;

// Σ of the records at byte offsets ring[k] from `records`, k = 0 .. size − 1, in
// that order from 0 (as a loop over the ring adds them); size a constant where
// with_ring_size makes it one.
template <class Size>
[[gnu::always_inline]] inline Float4 ring_sum(const Float4* records, const std::uint32_t* ring, Size size) {
    const char* bytes = reinterpret_cast<const char*>(records);
    Float4 sum{};
    const std::uint32_t n = size;
#pragma GCC unroll 8
    for (std::uint32_t k = 0; k < n; ++k) sum += *reinterpret_cast<const Float4*>(bytes + ring[k]);
    return sum;
}

// One smoothing step over the blend region, from `from` into scratch.next (smooth_gradients below); `tangent` a
// template argument, so that the loop does not test it per vertex.
template <bool tangent>
void smoothing_sweep(const RegionParts& parts, float w, const float (&share)[kTabledRing], const GradientRecords& from,
                     SmoothingScratch& scratch) {
    parallel_for(parts.blend.size(), [&](std::size_t first, std::size_t last) {
        // Local copies: the loop then keeps them in registers.
        const Float4* gradients = from.data();
        const std::uint32_t *rings = parts.blend_rings.data(), *offsets = parts.blend_ring_offsets.data();
        Float4* next = scratch.next.data();
        const float weight = w, *shares = share;
        for (std::size_t i = first; i < last; ++i) {
            // Average over the neighbours inside the blend region only: outside it
            // s is constant, ∇r there carries no information, and mixing it in
            // would shrink ∇r along the region's borders.
            const std::uint32_t begin = offsets[i], end = offsets[i + 1];
            Float4 g = gradients[i];
            if (end > begin) {
                const std::uint32_t count = end - begin;
                const Float4 sum = with_ring_size(count, [&](auto n) { return ring_sum(gradients, rings + begin, n); });
                g += (count < kTabledRing ? shares[count] : weight / float(count)) * sum - weight * g;
            }
            if (tangent) {
                const Float4 normal = scratch.normals[i];
                const Float4 product = g * normal;
                g -= (product[0] + product[1] + product[2]) * normal;
            }
            next[i] = g;
        }
    });
}

}  // namespace

void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& normals) {
    vertex_normals(positions, rings, normals);
}

void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                      const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals) {
    vertex_normals(positions, rings, vertices, normals);
}

void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                      const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals,
                      std::vector<Vec3>& area_vectors) {
    vertex_normals(positions, rings, vertices, normals, area_vectors);
}

std::vector<std::uint32_t> blend_vertices(const std::vector<double>& s) {
    std::vector<std::uint32_t> blend;
    for (std::size_t v = 0; v < s.size(); ++v)
        if (in_blend(s[v])) blend.push_back(static_cast<std::uint32_t>(v));
    return blend;
}

RegionParts RegionParts::of(const std::vector<double>& s, const VertexRings& rings) {
    RegionParts parts;
    parts.blend = blend_vertices(s);
    for (const std::uint32_t v : parts.blend) {
        parts.one_minus_b.push_back(1.0 - bernstein_blend(s[v]));
        parts.b_slope.push_back(bernstein_blend_derivative(s[v]));
    }
    for (std::size_t v = 0; v < s.size(); ++v)
        if (s[v] <= 0.0) parts.inner.push_back(static_cast<std::uint32_t>(v));
    // blend_rings holds byte offsets in 32 bits: 2^28 records of 16 bytes.
    if (parts.blend.size() >= (std::size_t(1) << 28))
        throw InputError("the blend region has " + std::to_string(parts.blend.size()) +
                         " vertices; at most 268435455 are supported");
    std::vector<std::uint32_t> position_in_blend(s.size(), 0);
    for (std::size_t i = 0; i < parts.blend.size(); ++i) position_in_blend[parts.blend[i]] = static_cast<std::uint32_t>(i);
    parts.blend_ring_offsets.reserve(parts.blend.size() + 1);
    parts.blend_ring_offsets.push_back(0);
    for (const std::uint32_t v : parts.blend) {
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
            if (in_blend(s[rings.neighbours[k]]))
                parts.blend_rings.push_back(position_in_blend[rings.neighbours[k]] * std::uint32_t(sizeof(Float4)));
        parts.blend_ring_offsets.push_back(static_cast<std::uint32_t>(parts.blend_rings.size()));
    }
    return parts;
}

void estimate_gradients(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                        const std::vector<double>& s, const VertexRings& rings, const std::vector<std::uint32_t>& blend,
                        GradientRecords& gradients) {
    gradients.resize(blend.size());
    for_each_block(blend.size(), [&](std::size_t first, int count) {
        GradientLanes lanes;
        for (int j = 0; j < count; ++j) {
            const Vec3& n = normals[blend[first + j]];
            lanes.normal.x[j] = n.x, lanes.normal.y[j] = n.y, lanes.normal.z[j] = n.z;
        }
        tangent_lanes(count, lanes);
        ring_sums_lanes(positions.data(), s.data(), rings, blend.data() + first, count, lanes);
        solve_lanes(count, lanes);
        for (int j = 0; j < count; ++j)
            gradients[first + j] =
                Float4{float(lanes.gradient.x[j]), float(lanes.gradient.y[j]), float(lanes.gradient.z[j]), 0.0f};
    });
}

void smooth_gradients(const std::vector<Vec3>& normals, const RegionParts& parts, int steps, double weight,
                      bool tangent, GradientRecords& gradients, SmoothingScratch& scratch) {
    const std::size_t n = parts.blend.size();
    scratch.next.resize(n);
    scratch.normals.resize(tangent ? n : 0);  // only the tangent smoothing takes the normals
    if (tangent)
        parallel_for(n, [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i < last; ++i) {
                const Vec3& normal = normals[parts.blend[i]];
                scratch.normals[i] = Float4{float(normal.x), float(normal.y), float(normal.z), 0.0f};
            }
        });
    const float w = static_cast<float>(weight);
    // w / (ring size) from a table rather than a division per vertex and sweep:
    // the same float quotient.
    float share[kTabledRing] = {};
    for (int count = 1; count < kTabledRing; ++count) share[count] = w / float(count);
    for (int step = 0; step < steps; ++step) {
        if (tangent)
            smoothing_sweep<true>(parts, w, share, gradients, scratch);
        else
            smoothing_sweep<false>(parts, w, share, gradients, scratch);
        gradients.swap(scratch.next);
    }
}

GradientRecords gradient_records(const std::vector<Vec3>& gradients, const std::vector<std::uint32_t>& blend) {
    GradientRecords records;
    for (const std::uint32_t v : blend)
        records.push_back(Float4{float(gradients[v].x), float(gradients[v].y), float(gradients[v].z), 0.0f});
    return records;
}

std::vector<Vec3> vertex_gradients(const GradientRecords& records, const std::vector<std::uint32_t>& blend,
                                   std::size_t vertex_count) {
    std::vector<Vec3> gradients(vertex_count, Vec3(0.0));
    for (std::size_t i = 0; i < blend.size(); ++i)
        gradients[blend[i]] = Vec3(records[i][0], records[i][1], records[i][2]);
    return gradients;
}

void predict_midpoints(const StepMotion& half, const RegionParts& parts, const GradientRecords& gradients,
                       const std::vector<Vec3>& positions, std::vector<Vec3>& midpoints, const KeeperVelocity& keeper) {
    if (midpoints.size() != positions.size()) midpoints = positions;
    step_vertices(half, Stepper::midpoint_rule, parts, gradients, keeper, positions, midpoints);
}

StepMotion StepMotion::sample(const InnerMotion& motion, double t, double h) {
    // A step that starts or ends on a join of the curve takes the segment it runs on.
    const JoinSide start = h >= 0.0 ? JoinSide::after : JoinSide::before;
    const JoinSide end = h >= 0.0 ? JoinSide::before : JoinSide::after;
    return {motion.at(t, start), motion.at(t + 0.5 * h), motion.at(t + h, end), h};
}

std::size_t deformation_step(const StepMotion& motion, const RegionParts& parts, const GradientRecords& gradients,
                             const std::vector<Vec3>& from, std::vector<Vec3>& to, const KeeperVelocity& keeper) {
    return step_vertices(motion, Stepper::rk4, parts, gradients, keeper, from, to);
}

double blend_flux(const MotionSample& sample, const RegionParts& parts, const GradientRecords& gradients,
                  const std::vector<Vec3>& at, const std::vector<Vec3>& area_vectors) {
    // Each block's sum into its own slot, then the slots in order: the same bits
    // on any number of threads.
    const PreparedMotion m(sample);
    const std::size_t n = parts.blend.size(), blocks = (n + kFieldLanes - 1) / kFieldLanes;
    std::vector<double> partial(blocks);
    parallel_for(
        blocks,
        [&](std::size_t first, std::size_t last) {
            for (std::size_t block = first; block < last; ++block) {
                const std::size_t begin = block * kFieldLanes;
                partial[block] = flux_block(m, parts, gradients, at, area_vectors, begin,
                                            static_cast<int>(std::min<std::size_t>(kFieldLanes, n - begin)));
            }
        },
        kParallelGrain / kFieldLanes);
    double total = 0.0;
    for (const double p : partial) total += p;
    return total;
}

double rigid_step_error(const StepMotion& full, const StepMotion& first_half, const StepMotion& second_half,
                        double reach) {
    const AffineStep one = rigid_step(full, Stepper::rk4), a = rigid_step(first_half, Stepper::rk4),
                     b = rigid_step(second_half, Stepper::rk4);
    double largest = 0.0;
    for (int axis = 0; axis < 3; ++axis)
        for (const double side : {-reach, reach}) {
            Vec3 x = full.start.position;
            x[axis] += side;
            largest = std::max(largest, glm::length(one(x) - b(a(x))));
        }
    return largest;
}

void deformation_step(const StepMotion& motion, const SphereTool& tool, std::vector<Vec3>& positions) {
    const double width = tool.r_outer - tool.r_inner;
    for (Vec3& position : positions) {
        position = rk4(motion, position, [&](const Vec3& x, const MotionSample& m) {
            const Vec3 d = x - tool.centre;
            const double r = glm::length(d);
            const double u = (r - tool.r_inner) / width;
            const Vec3 grad_b = r > 0.0 ? bernstein_blend_derivative(u) / width * (d / r) : Vec3(0.0);
            return deformation_velocity(m, x, bernstein_blend(u), grad_b);
        });
    }
}

}  // namespace vfsd
