#include "field/stream_gauge.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "curve/inner_motion.h"
#include "field/vector_field.h"

namespace vfsd {
namespace {

constexpr int kTerms = 19;

// ∇ of the monomials of degree 1–3 in d: x, y, z; x²/2, y²/2, z²/2, xy, xz, yz;
// x³/3, y³/3, z³/3, x²y, x²z, y²x, y²z, z²x, z²y, xyz.
void monomial_gradients(const Vec3& d, Vec3 (&b)[kTerms]) {
    const double x = d.x, y = d.y, z = d.z;
    b[0] = {1, 0, 0}, b[1] = {0, 1, 0}, b[2] = {0, 0, 1};
    b[3] = {x, 0, 0}, b[4] = {0, y, 0}, b[5] = {0, 0, z}, b[6] = {y, x, 0}, b[7] = {z, 0, x}, b[8] = {0, z, y};
    b[9] = {x * x, 0, 0}, b[10] = {0, y * y, 0}, b[11] = {0, 0, z * z};
    b[12] = {2 * x * y, x * x, 0}, b[13] = {2 * x * z, 0, x * x}, b[14] = {y * y, 2 * x * y, 0};
    b[15] = {0, 2 * y * z, y * y}, b[16] = {z * z, 0, 2 * x * z}, b[17] = {0, z * z, 2 * y * z};
    b[18] = {y * z, x * z, x * y};
}

// The gauge with coefficients c of the monomial gradients, as StreamGauge's
// quadratic polynomials (1, dx, dy, dz, dx², dy², dz², dx dy, dx dz, dy dz).
StreamGauge expand(const Vec3& centre, double inverse_scale, const double (&c)[kTerms]) {
    StreamGauge g;
    g.centre = centre;
    g.inverse_scale = inverse_scale;
    const double x[10] = {c[0], c[3], c[6], c[7], c[9], c[14], c[16], 2 * c[12], 2 * c[13], c[18]};
    const double y[10] = {c[1], c[6], c[4], c[8], c[12], c[10], c[17], 2 * c[14], c[18], 2 * c[15]};
    const double z[10] = {c[2], c[7], c[8], c[5], c[13], c[15], c[11], c[18], 2 * c[16], 2 * c[17]};
    for (int k = 0; k < 10; ++k) g.q[0][k] = x[k], g.q[1][k] = y[k], g.q[2][k] = z[k];
    return g;
}

// Per sample: the monomial gradients b_k at it and its weight g. The residual
// rows of term k are J_k = (b_k × g, √μ |g| b_k), so with
// (b × g)·(b' × g) = |g|² b·b' − (b·g)(b'·g) both the normal matrix and the
// right-hand side need only b_k·b_l, b_k·g and b_k·v.
struct SampleBasis {
    Vec3 b[kTerms];
    double bg[kTerms];  // b_k · g
    double g2 = 0.0;    // (1 + μ) |g|²
};

SampleBasis sample_basis(const GaugeSample& s, const Vec3& centre, double inverse_scale) {
    SampleBasis r;
    monomial_gradients((s.position - centre) * inverse_scale, r.b);
    r.g2 = (1.0 + GaugeFit::kStreamWeight) * glm::dot(s.weight, s.weight);
    for (int k = 0; k < kTerms; ++k) r.bg[k] = glm::dot(r.b[k], s.weight);
    return r;
}

}  // namespace

Vec3 gauge_gradient(const StreamGauge& g, const Vec3& x) {
    const Vec3 d = (x - g.centre) * g.inverse_scale;
    const double m[10] = {1.0, d.x, d.y, d.z, d.x * d.x, d.y * d.y, d.z * d.z, d.x * d.y, d.x * d.z, d.y * d.z};
    Vec3 out(0.0);
    for (int k = 0; k < 10; ++k) out += m[k] * Vec3(g.q[0][k], g.q[1][k], g.q[2][k]);
    return out;
}

GaugeFit::GaugeFit(std::vector<GaugeSample> samples) : samples_(std::move(samples)) {
    if (samples_.empty()) return;
    for (const GaugeSample& s : samples_) centre_ += s.position;
    centre_ /= double(samples_.size());
    double spread = 0.0;
    for (const GaugeSample& s : samples_) spread += glm::dot(s.position - centre_, s.position - centre_);
    spread = std::sqrt(spread / double(samples_.size()));
    if (!(spread > 0.0)) return;
    inverse_scale_ = 1.0 / spread;
    // Normal matrix Σ Jᵀ J, lower triangle, then its Cholesky factor. The ridge
    // (1e-6 of the mean diagonal) settles the directions no sample constrains,
    // e.g. a gauge term parallel to every g_i when μ = 0.
    double a[kTerms][kTerms] = {};
    for (const GaugeSample& s : samples_) {
        const SampleBasis r = sample_basis(s, centre_, inverse_scale_);
        for (int k = 0; k < kTerms; ++k)
            for (int l = 0; l <= k; ++l) a[k][l] += r.g2 * glm::dot(r.b[k], r.b[l]) - r.bg[k] * r.bg[l];
    }
    double trace = 0.0;
    for (int k = 0; k < kTerms; ++k) trace += a[k][k];
    if (!(trace > 0.0)) return;
    for (int k = 0; k < kTerms; ++k) a[k][k] += 1e-6 * trace / kTerms;
    for (int j = 0; j < kTerms; ++j) {
        double d = a[j][j];
        for (int k = 0; k < j; ++k) d -= cholesky_[j][k] * cholesky_[j][k];
        if (!(d > 0.0)) return;
        cholesky_[j][j] = std::sqrt(d);
        for (int i = j + 1; i < kTerms; ++i) {
            double v = a[i][j];
            for (int k = 0; k < j; ++k) v -= cholesky_[i][k] * cholesky_[j][k];
            cholesky_[i][j] = v / cholesky_[j][j];
        }
    }
    solvable_ = true;
}

StreamGauge GaugeFit::gauge_for(const MotionSample& motion) const {
    if (!solvable_) return {};
    MotionSample m = motion;
    m.gauge = StreamGauge{};
    // Right-hand side −Σ Jᵀ r0, r0 the residual of the paper's stream.
    double c[kTerms] = {};
    for (const GaugeSample& s : samples_) {
        const Vec3 stream = stream_vector(m, s.position);
        const SampleBasis r = sample_basis(s, centre_, inverse_scale_);
        const Vec3 v = r.g2 * stream - glm::dot(s.weight, stream) * s.weight;
        for (int k = 0; k < kTerms; ++k) c[k] -= glm::dot(r.b[k], v);
    }
    for (int i = 0; i < kTerms; ++i) {  // L y = rhs
        for (int k = 0; k < i; ++k) c[i] -= cholesky_[i][k] * c[k];
        c[i] /= cholesky_[i][i];
    }
    for (int i = kTerms - 1; i >= 0; --i) {  // Lᵀ x = y
        for (int k = i + 1; k < kTerms; ++k) c[i] -= cholesky_[k][i] * c[k];
        c[i] /= cholesky_[i][i];
    }
    return expand(centre_, inverse_scale_, c);
}

}  // namespace vfsd
