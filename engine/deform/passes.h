#pragma once
// The four per-step passes of sec. 5, each a function over flat per-vertex arrays
// with the name of its GPU shader (shaders/ mirrors them one to one):
//   1. normal pass       estimate_normals
//   2. gradient pass     estimate_gradients     (eq. 6)
//   3. smoothing pass    smooth_gradients
//   4. deformation pass  deformation_step       (one RK4 step of v + ṽ)
// None of them allocates once its output arrays have their size.

#include <vector>

#include "curve/inner_motion.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

// Normal pass: area-weighted vertex normals from the ordered 1-rings.
void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& normals);
// The same at the listed vertices only: the blend region, where the next passes use them.
void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                      const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals);
// The same, and each listed vertex's unnormalised sum in area_vectors[i]
// (mesh/geometry.h's ring_area_vector: 6 ∂V/∂x, which the volume keeper uses).
void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                      const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals,
                      std::vector<Vec3>& area_vectors);

// The vertices with 0 < s < 1. Only there does the field use ∇r: b′(s) = 0 for
// s = 0 and s = 1 (eq. 4), so the gradient and smoothing passes skip the rest.
std::vector<std::uint32_t> blend_vertices(const std::vector<double>& s);

// Four floats in one SIMD register (GCC/Clang vector extension: SSE on x86-64,
// simd128 in WebAssembly built with -msimd128, plain scalar code elsewhere).
using Float4 = float __attribute__((vector_size(16)));

// Which vertices each pass visits, found once per region. The blend region
// (0 < s < 1) needs the full field and ∇r; the inner region (s ≤ 0, b = 0) moves
// rigidly; the outer region (s ≥ 1, b = 1) does not move, so no pass touches it.
// Smoothing averages over blend neighbours only, so their rings are kept apart.
struct RegionParts {
    std::vector<std::uint32_t> blend, inner;
    // The neighbours y of blend[i] with 0 < s(y) < 1, as the byte offsets
    // j · sizeof(Float4) of their records in the blend region's packed arrays
    // (y = blend[j]): blend_rings[blend_ring_offsets[i] .. blend_ring_offsets[i + 1]).
    // Bytes, not positions: the smoothing's sums then load each record without
    // scaling its index, one instruction fewer per neighbour (docs/benchmarks.md,
    // "The smoothing's rings in bytes").
    std::vector<std::uint32_t> blend_ring_offsets, blend_rings;
    // 1 − b(s) and b′(s) at blend[i] (eq. 4 with r = s), taken once: the field
    // takes them at every stage, and they do not change.
    std::vector<double> one_minus_b, b_slope;

    static RegionParts of(const std::vector<double>& s, const VertexRings& rings);
};

// ∇r on the blend region as packed float records (x, y, z, 0), record i for
// vertex RegionParts::blend[i], as the passes hand it on: the gradient pass
// writes it, the smoothing pass smooths it in place, the predictor and the
// deformation pass read it (∇r is 0 elsewhere). Float, as the GPU's gradient
// texture holds it; one 16-byte load per neighbour in the smoothing's sums.
using GradientRecords = std::vector<Float4>;
// Between records and one Vec3 per vertex (0 outside the blend region).
GradientRecords gradient_records(const std::vector<Vec3>& gradients, const std::vector<std::uint32_t>& blend);
std::vector<Vec3> vertex_gradients(const GradientRecords& records, const std::vector<std::uint32_t>& blend,
                                   std::size_t vertex_count);

// Gradient pass, eq. (6): per vertex x of the blend region, the gradient g of the
// linear function r(y) = s(x) + g·(y − x) with g·n(x) = 0 that fits s best, in the
// least-squares sense, on the 1-ring of x; gradients[i] for x = blend[i].
void estimate_gradients(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                        const std::vector<double>& s, const VertexRings& rings, const std::vector<std::uint32_t>& blend,
                        GradientRecords& gradients);

// Work arrays of the smoothing pass: the next sweep's gradients and (for the
// tangent smoothing) the blend region's normals, as packed float records.
struct SmoothingScratch {
    std::vector<Float4> next, normals;
};

// Smoothing pass: `steps` Laplacian steps moving each gradient by `weight` toward
// the mean gradient of its 1-ring neighbours with 0 < s < 1, in place. With `tangent`,
// each step removes the normal part again (sec. 5 as printed); without, ∇r is
// smoothed as a vector in space, so that neighbours across a crease or a bump
// agree on one direction instead of each keeping to its own tangent plane
// (docs/method.md, "Keeping the promise").
void smooth_gradients(const std::vector<Vec3>& normals, const RegionParts& parts, int steps, double weight,
                      bool tangent, GradientRecords& gradients, SmoothingScratch& scratch);

// The motion at the three RK4 times of one step from t to t + h.
struct StepMotion {
    MotionSample start, middle, end;  // at t, t + h/2, t + h
    double h = 0.0;
    static StepMotion sample(const InnerMotion& motion, double t, double h);
};

// Midpoint predictor: where each vertex will be half-way through the step, by
// one step of the explicit midpoint rule (RK2) of half the step's length
// (`half`: the motion at t and t + h/4; its end sample is not used) along the
// field with the previous step's gradients. Its error, O(h³), is an order below
// the scheme's, and the RK4 half step it replaced gave the same steps and results
// within a few percent of their error (docs/method.md). The normal,
// gradient and smoothing passes then run on these positions, so ∇r is taken at
// the middle of the step instead of its start: second order in time instead of
// first, and integrating back retraces the way forward (see docs/method.md).
// Writes the inner and blend vertices; the outer region does not move, so a new
// `midpoints` array starts as a copy of `positions` and an old one must hold them.
// The volume keeper's velocity on the blend region (deform/volume_keeper.h),
// added to the field at every stage: λ (1 − b) b′(s) a / 6 at blend[i], a =
// (*area_vectors)[i] its ring's area vector (6 ∂V/∂x); none without area vectors.
struct KeeperVelocity {
    double lambda = 0.0;
    const std::vector<Vec3>* area_vectors = nullptr;
};

// `keeper`: the volume keeper's velocity (none by default).
void predict_midpoints(const StepMotion& half, const RegionParts& parts, const GradientRecords& gradients,
                       const std::vector<Vec3>& positions, std::vector<Vec3>& midpoints,
                       const KeeperVelocity& keeper = {});

// Deformation pass: one RK4 step of every vertex along v + ṽ (eqs. 1–4, 9–14)
// with r = s (the s that `parts` was made of) and ∇r = `gradients`, both held
// fixed over the step, from `from` into `to` (they may be the same array). Only
// the inner and blend vertices are written: the outer ones stay where `to` has
// them (v = 0 there). Returns how many of them it moved to a non-finite position.
// `keeper` as for predict_midpoints.
std::size_t deformation_step(const StepMotion& motion, const RegionParts& parts, const GradientRecords& gradients,
                             const std::vector<Vec3>& from, std::vector<Vec3>& to, const KeeperVelocity& keeper = {});

// Σ v · a over the blend vertices, v the field (v + ṽ) of `sample` at `at` with
// ∇r = `gradients`, a = area_vectors[i] at blend[i]: the blend region's share of
// 6 dV/dt (VolumeKeeper::rate).
double blend_flux(const MotionSample& sample, const RegionParts& parts, const GradientRecords& gradients,
                  const std::vector<Vec3>& at, const std::vector<Vec3>& area_vectors);

// RK4's own error over a step on the inner region's rigid motion, by step
// doubling: the largest distance between the step's map (`full`, from t by h)
// and two steps of half its length (`first_half`, `second_half`), over the six
// points `reach` from c(t) along the axes (the maps are affine: that bounds the
// ball of radius `reach` about c(t) to within √3). The ∇r estimate of
// deform/step_error.h does not see it; on a long step of a large turn it is
// what errs.
double rigid_step_error(const StepMotion& full, const StepMotion& first_half, const StepMotion& second_half,
                        double reach);

// The implicit sphere tool of VFSD [23] as region: r = |x − centre| with
// thresholds r_inner < r_outer, evaluated at every RK4 stage (no mesh needed).
struct SphereTool {
    Vec3 centre{0.0};
    double r_inner = 0.0, r_outer = 1.0;
};
void deformation_step(const StepMotion& motion, const SphereTool& tool, std::vector<Vec3>& positions);

}  // namespace vfsd
