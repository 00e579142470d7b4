#include "field/stream_gauge.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "base/parallel.h"
#include "curve/inner_motion.h"
#include "field/vector_field.h"

namespace vfsd {
namespace {

constexpr int kTerms = 19;      // gradients of the 3 linear, 6 quadratic and 10 cubic monomials
constexpr int kMonomials = 10;  // of a StreamGauge's quadratic polynomials

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

// StreamGauge's quadratic monomials at d, in its order.
void quadratic_monomials(const Vec3& d, double (&m)[kMonomials]) {
    const double values[kMonomials] = {1.0,       d.x,       d.y,       d.z,       d.x * d.x,
                                       d.y * d.y, d.z * d.z, d.x * d.y, d.x * d.z, d.y * d.z};
    for (int k = 0; k < kMonomials; ++k) m[k] = values[k];
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
    double m[kMonomials];
    quadratic_monomials((x - g.centre) * g.inverse_scale, m);
    Vec3 out(0.0);
    for (int k = 0; k < kMonomials; ++k) out += m[k] * Vec3(g.q[0][k], g.q[1][k], g.q[2][k]);
    return out;
}

StreamGauge stream_polynomial(const MotionSample& m, const Vec3& centre, double inverse_scale) {
    // From its values at d = 0, ±eᵢ and eᵢ + eⱼ, which a quadratic takes exactly.
    const auto f = [&](const Vec3& d) { return stream_vector(m, centre + d / inverse_scale); };
    const Vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Vec3 f0 = f(Vec3(0.0));
    Vec3 plus[3], minus[3], coefficient[10];
    coefficient[0] = f0;
    for (int i = 0; i < 3; ++i) {
        plus[i] = f(e[i]), minus[i] = f(-e[i]);
        coefficient[1 + i] = 0.5 * (plus[i] - minus[i]);
        coefficient[4 + i] = 0.5 * (plus[i] + minus[i]) - f0;
    }
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int k = 0; k < 3; ++k) {
        const int i = pairs[k][0], j = pairs[k][1];
        coefficient[7 + k] = f(e[i] + e[j]) - plus[i] - plus[j] + f0;
    }
    StreamGauge g;
    g.centre = centre;
    g.inverse_scale = inverse_scale;
    for (int k = 0; k < 10; ++k)
        g.q[0][k] = coefficient[k].x, g.q[1][k] = coefficient[k].y, g.q[2][k] = coefficient[k].z;
    return g;
}

namespace {

// One block of samples' share of the normal matrix (lower triangle) and of the
// right-hand side's map.
struct FitSums {
    double a[kTerms][kTerms] = {};
    Vec3 rhs[kTerms][kMonomials] = {};
};

}  // namespace

GaugeFit::GaugeFit(std::vector<GaugeSample> samples) {
    if (samples.empty()) return;
    for (const GaugeSample& s : samples) centre_ += s.position;
    centre_ /= double(samples.size());
    double spread = 0.0;
    for (const GaugeSample& s : samples) spread += glm::dot(s.position - centre_, s.position - centre_);
    spread = std::sqrt(spread / double(samples.size()));
    if (!(spread > 0.0)) return;
    inverse_scale_ = 1.0 / spread;
    // Normal matrix Σ Jᵀ J, lower triangle, and the right-hand side's map, per
    // block of kBlock samples on all threads, then the blocks in order (the same
    // sums on any number of threads).
    constexpr std::size_t kBlock = 64;
    std::vector<FitSums> blocks((samples.size() + kBlock - 1) / kBlock);
    parallel_for(
        blocks.size(),
        [&](std::size_t first, std::size_t last) {
            for (std::size_t block = first; block < last; ++block) {
                FitSums& sums = blocks[block];
                for (std::size_t i = block * kBlock; i < std::min(samples.size(), (block + 1) * kBlock); ++i) {
                    const SampleBasis r = sample_basis(samples[i], centre_, inverse_scale_);
                    double phi[kMonomials];
                    quadratic_monomials((samples[i].position - centre_) * inverse_scale_, phi);
                    for (int k = 0; k < kTerms; ++k) {
                        for (int l = 0; l <= k; ++l)
                            sums.a[k][l] += r.g2 * glm::dot(r.b[k], r.b[l]) - r.bg[k] * r.bg[l];
                        const Vec3 row = r.g2 * r.b[k] - r.bg[k] * samples[i].weight;
                        for (int j = 0; j < kMonomials; ++j) sums.rhs[k][j] -= phi[j] * row;
                    }
                }
            }
        },
        2);
    double a[kTerms][kTerms] = {};
    for (const FitSums& sums : blocks)
        for (int k = 0; k < kTerms; ++k) {
            for (int l = 0; l <= k; ++l) a[k][l] += sums.a[k][l];
            for (int j = 0; j < kMonomials; ++j) rhs_[k][j] += sums.rhs[k][j];
        }
    // The ridge (1e-6 of the mean diagonal) settles the directions no sample
    // constrains, e.g. a gauge term parallel to every g_i when μ = 0.
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
    // Right-hand side −Σ Jᵀ r0, r0 the residual of the paper's stream S = Σₘ Qₘ φₘ.
    const StreamGauge stream = stream_polynomial(m, centre_, inverse_scale_);
    double c[kTerms] = {};
    for (int k = 0; k < kTerms; ++k)
        for (int j = 0; j < kMonomials; ++j)
            c[k] += glm::dot(rhs_[k][j], Vec3(stream.q[0][j], stream.q[1][j], stream.q[2][j]));
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

std::vector<std::uint32_t> gauge_samples(const std::vector<double>& s, const std::vector<std::uint32_t>& blend) {
    constexpr std::size_t kGaugeSamples = 512;
    if (blend.size() <= kGaugeSamples) return blend;
    std::vector<std::pair<long long, std::uint32_t>> keyed;
    for (const std::uint32_t v : blend) keyed.push_back({std::llround(s[v] * 1e9), v});
    std::sort(keyed.begin(), keyed.end());
    std::vector<long long> chosen;  // the keys at kGaugeSamples even steps through the order
    for (std::size_t k = 0; k < kGaugeSamples; ++k) chosen.push_back(keyed[k * keyed.size() / kGaugeSamples].first);
    std::vector<std::uint32_t> samples;
    for (const auto& [key, v] : keyed)
        if (std::binary_search(chosen.begin(), chosen.end(), key)) samples.push_back(v);
    if (samples.size() <= 4 * kGaugeSamples) return samples;
    samples.clear();
    for (std::size_t k = 0; k < kGaugeSamples; ++k) samples.push_back(keyed[k * keyed.size() / kGaugeSamples].second);
    return samples;
}

GaugeSample gauge_sample(const Vec3& position, double s, const Vec3& gradient) {
    return {position, (1.0 - bernstein_blend(s)) * bernstein_blend_derivative(s) * gradient};
}

}  // namespace vfsd
