#pragma once
// The stream's gauge, fitted to the region at every step (beyond the paper).
//
// The field v = (1 − b)² u − (1 − b) S × ∇b (vector_field.h) is the curl of
// (1 − b)² A with A = −S/2, and all the inner region needs is ∇ × A = u. So S may
// be replaced by S + ∇φ for any φ: the inner region moves the same and v stays
// divergence-free, but the blend region moves otherwise. Eqs. (9)–(14) fix one
// S, which grows with the distance from c(t) (and from the twist's plane); every
// error of the per-vertex ∇r estimate is multiplied by it, and across a blend
// region far from c(t), or twisted, it makes the blend region overshoot and
// shear (docs/method.md). The stream origin and twist plane of InnerMotion are
// two hand-set cases of this freedom.
//
// StreamGauge is ∇φ for a cubic polynomial φ in d = (x − centre) / scale,
// fitted by least squares over samples x_i of the blend region with
// g_i = (1 − b_i) ∇b_i, the factor S meets in v:
//
//   Σ_i |(S + ∇φ)(x_i) × g_i|² + μ |g_i|² |(S + ∇φ)(x_i)|²  →  min.
//
// The first term keeps the blend region's motion close to the blended rigid
// motion (1 − b)² u (monotone: no overshoot, no backward turn); the second keeps
// the stream itself small where ∇r's errors would be multiplied by it.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace vfsd {

using Vec3 = glm::dvec3;

// ∇φ as three quadratic polynomials in d = (x − centre) · inverse_scale, with
// the coefficients of (1, dx, dy, dz, dx², dy², dz², dx dy, dx dz, dy dz).
// All zero (the default) is the paper's gauge.
struct StreamGauge {
    Vec3 centre{0.0};
    double inverse_scale = 1.0;
    double q[3][10] = {};
};

// ∇φ(x).
Vec3 gauge_gradient(const StreamGauge& gauge, const Vec3& x);

struct MotionSample;

// The stream vector S(x) + ∇φ(x) of m (vector_field.h's stream_vector, m's gauge
// included) is itself a quadratic polynomial in x: z × U is linear, the rotation
// streams of ω and τ and the gauge are quadratic. Its coefficients, as a
// StreamGauge about `centre` in d = (x − centre) · inverse_scale.
StreamGauge stream_polynomial(const MotionSample& m, const Vec3& centre, double inverse_scale);

// One sample of the blend region: its position and (1 − b) ∇b there.
struct GaugeSample {
    Vec3 position{0.0};
    Vec3 weight{0.0};
};

// The sample of a blend vertex at `position` with region value s and ∇r there:
// its weight is (1 − b(s)) b′(s) ∇r.
GaugeSample gauge_sample(const Vec3& position, double s, const Vec3& gradient);

// Which blend vertices the gauge is fitted to (`s` and `blend` in one vertex
// order, blend_vertices(s) of deform/passes.h): all of a blend region of at most
// kGaugeSamples vertices, else the vertices at kGaugeSamples even steps through
// the blend region ordered by s, each with every vertex of equal s (to 1e-9: a
// symmetric mesh's mirror images, whatever the rounding of s): a set that
// depends neither on the order of the input's vertices nor on where the mesh is
// placed. (The final shape differs between sample sets by up to a few percent of
// the diagonal, so the set must be canonical.) Where s takes so few values that
// this would be more than four times kGaugeSamples vertices (a mesh symmetric
// about the curve, such as a finely meshed cylinder), the steps' vertices alone
// are taken, and mirror images are told apart by the vertex order.
std::vector<std::uint32_t> gauge_samples(const std::vector<double>& s, const std::vector<std::uint32_t>& blend);

// The least-squares fit above over a set of samples: the normal matrix depends
// on the samples alone, so it is built and factored once and serves the three
// motion samples of an RK4 step. So does the right-hand side, but for S: with
// S = Σₘ Qₘ φₘ(d) (stream_polynomial, φₘ its ten monomials) it is a fixed linear
// map of the Qₘ, summed over the samples once; a gauge then costs no pass over them.
class GaugeFit {
public:
    // μ of the objective: how much a small stream counts against a small S × g.
    static constexpr double kStreamWeight = 10.0;
    explicit GaugeFit(std::vector<GaugeSample> samples);
    // The gauge for the motion at one time; the paper's (zero) gauge when there
    // are no samples or the system is singular. m's own gauge is ignored.
    StreamGauge gauge_for(const MotionSample& m) const;

private:
    static constexpr int kTerms = 19;      // gradients of the 3 linear, 6 quadratic and 10 cubic monomials
    static constexpr int kMonomials = 10;  // of a StreamGauge's quadratic polynomials (stream_gauge.cpp has both too)
    Vec3 centre_{0.0};
    double inverse_scale_ = 1.0;
    double cholesky_[kTerms][kTerms] = {};
    // The right-hand side's map: −Σ_i φₘ(dᵢ) ((1 + μ) |gᵢ|² b_k − (b_k · gᵢ) gᵢ), b_k at dᵢ.
    Vec3 rhs_[kTerms][kMonomials] = {};
    bool solvable_ = false;
};

}  // namespace vfsd
