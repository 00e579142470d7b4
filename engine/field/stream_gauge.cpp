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

// The gauge's terms b_k: ∇ of the monomials of degree 1–3 in d (x, y, z; x²/2,
// y²/2, z²/2, xy, xz, yz; x³/3, y³/3, z³/3, x²y, x²z, y²x, y²z, z²x, z²y, xyz),
// component by component: each nonzero component is one monomial c x^a y^b z^e
// of degree at most 2.
struct Monomial {
    double coefficient = 0.0;  // 0: the component is zero
    int x = 0, y = 0, z = 0;   // exponents
};
constexpr Monomial kGradientTerms[kTerms][3] = {
    {{1, 0, 0, 0}, {}, {}},
    {{}, {1, 0, 0, 0}, {}},
    {{}, {}, {1, 0, 0, 0}},
    {{1, 1, 0, 0}, {}, {}},
    {{}, {1, 0, 1, 0}, {}},
    {{}, {}, {1, 0, 0, 1}},
    {{1, 0, 1, 0}, {1, 1, 0, 0}, {}},
    {{1, 0, 0, 1}, {}, {1, 1, 0, 0}},
    {{}, {1, 0, 0, 1}, {1, 0, 1, 0}},
    {{1, 2, 0, 0}, {}, {}},
    {{}, {1, 0, 2, 0}, {}},
    {{}, {}, {1, 0, 0, 2}},
    {{2, 1, 1, 0}, {1, 2, 0, 0}, {}},
    {{2, 1, 0, 1}, {}, {1, 2, 0, 0}},
    {{1, 0, 2, 0}, {2, 1, 1, 0}, {}},
    {{}, {2, 0, 1, 1}, {1, 0, 2, 0}},
    {{1, 0, 0, 2}, {}, {2, 1, 0, 1}},
    {{}, {1, 0, 0, 2}, {2, 0, 1, 1}},
    {{1, 0, 1, 1}, {1, 1, 0, 1}, {1, 1, 1, 0}},
};
// quadratic_monomials' exponents, in its order.
constexpr Monomial kQuadraticMonomials[kMonomials] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 0, 1, 0}, {1, 0, 0, 1},
                                                      {1, 2, 0, 0}, {1, 0, 2, 0}, {1, 0, 0, 2}, {1, 1, 1, 0},
                                                      {1, 1, 0, 1}, {1, 0, 1, 1}};

// The fit's sums are moments Σᵢ wᵢ dᵢ^α of the samples' positions up to degree
// 4 (a product of two of the monomials above), for seven weights per sample:
// (1 + μ) |g|² and the six products g_c g_e (c ≤ e). With them a sample costs
// 7 × 35 products instead of the normal matrix's and the right-hand side's
// ~2,000 flops; the sums, and so the fit, are the same up to rounding.
constexpr int kDegree = 4;
constexpr int kMoments = 35;  // monomials of degree ≤ 4 in three variables
constexpr int kWeights = 7;   // (1 + μ) |g|², then g_c g_e for (c, e) = xx, yy, zz, xy, xz, yz

// The moments' index of x^a y^b z^e, a + b + e ≤ kDegree.
struct MomentIndex {
    int of[kDegree + 1][kDegree + 1][kDegree + 1] = {};
    int exponents[kMoments][3] = {};
    constexpr MomentIndex() {
        int n = 0;
        for (int a = 0; a <= kDegree; ++a)
            for (int b = 0; a + b <= kDegree; ++b)
                for (int e = 0; a + b + e <= kDegree; ++e) {
                    of[a][b][e] = n, exponents[n][0] = a, exponents[n][1] = b, exponents[n][2] = e;
                    ++n;
                }
    }
    int operator()(const Monomial& p, const Monomial& q) const { return of[p.x + q.x][p.y + q.y][p.z + q.z]; }
};
constexpr MomentIndex kMomentIndex;

// The weight index of g_c g_e.
constexpr int weight_of(int c, int e) {
    constexpr int pair[3][3] = {{1, 4, 5}, {4, 2, 6}, {5, 6, 3}};
    return pair[c][e];
}

struct Moments {
    double sum[kWeights][kMoments] = {};

    void add(const Vec3& d, const Vec3& g) {
        double px[kDegree + 1], py[kDegree + 1], pz[kDegree + 1];
        px[0] = py[0] = pz[0] = 1.0;
        for (int k = 1; k <= kDegree; ++k) px[k] = px[k - 1] * d.x, py[k] = py[k - 1] * d.y, pz[k] = pz[k - 1] * d.z;
        const double w[kWeights] = {(1.0 + GaugeFit::kStreamWeight) * glm::dot(g, g),
                                    g.x * g.x,
                                    g.y * g.y,
                                    g.z * g.z,
                                    g.x * g.y,
                                    g.x * g.z,
                                    g.y * g.z};
        double power[kMoments];
        for (int m = 0; m < kMoments; ++m) {
            const int* e = kMomentIndex.exponents[m];
            power[m] = px[e[0]] * py[e[1]] * pz[e[2]];
        }
        for (int k = 0; k < kWeights; ++k)
            for (int m = 0; m < kMoments; ++m) sum[k][m] += w[k] * power[m];
    }
};

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

GaugeFit::GaugeFit(std::vector<GaugeSample> samples) {
    if (samples.empty()) return;
    for (const GaugeSample& s : samples) centre_ += s.position;
    centre_ /= double(samples.size());
    double spread = 0.0;
    for (const GaugeSample& s : samples) spread += glm::dot(s.position - centre_, s.position - centre_);
    spread = std::sqrt(spread / double(samples.size()));
    if (!(spread > 0.0)) return;
    inverse_scale_ = 1.0 / spread;
    // The moments per block of kBlock samples on all threads, then the blocks in
    // order (the same sums on any number of threads).
    constexpr std::size_t kBlock = 256;
    std::vector<Moments> blocks((samples.size() + kBlock - 1) / kBlock);
    parallel_for(
        blocks.size(),
        [&](std::size_t first, std::size_t last) {
            for (std::size_t block = first; block < last; ++block)
                for (std::size_t i = block * kBlock; i < std::min(samples.size(), (block + 1) * kBlock); ++i)
                    blocks[block].add((samples[i].position - centre_) * inverse_scale_, samples[i].weight);
        },
        2);
    Moments moments;
    for (const Moments& block : blocks)
        for (int k = 0; k < kWeights; ++k)
            for (int m = 0; m < kMoments; ++m) moments.sum[k][m] += block.sum[k][m];
    const auto& M = moments.sum;
    // The residual rows of term k are J_k = (b_k × g, √μ |g| b_k), and
    // (b × g)·(b′ × g) = |g|² b·b′ − (b·g)(b′·g): the normal matrix Σ Jᵀ J (lower
    // triangle) is Σᵢ (1 + μ) |g|² b_k·b_l − (b_k·g)(b_l·g), and the right-hand
    // side's map −Σᵢ φⱼ ((1 + μ) |g|² b_k − (b_k·g) g), both from the moments.
    double a[kTerms][kTerms] = {};
    for (int k = 0; k < kTerms; ++k)
        for (int c = 0; c < 3; ++c) {
            const Monomial& p = kGradientTerms[k][c];
            if (p.coefficient == 0.0) continue;
            for (int l = 0; l <= k; ++l)
                for (int e = 0; e < 3; ++e) {
                    const Monomial& q = kGradientTerms[l][e];
                    if (q.coefficient == 0.0) continue;
                    const double pq = p.coefficient * q.coefficient;
                    if (c == e) a[k][l] += pq * M[0][kMomentIndex(p, q)];
                    a[k][l] -= pq * M[weight_of(c, e)][kMomentIndex(p, q)];
                }
            for (int j = 0; j < kMonomials; ++j) {
                const Monomial& phi = kQuadraticMonomials[j];
                rhs_[k][j][c] -= p.coefficient * M[0][kMomentIndex(p, phi)];
                for (int e = 0; e < 3; ++e)  // −(b_k·g) g: b_k's component c times g_c g_e, into component e
                    rhs_[k][j][e] += p.coefficient * M[weight_of(c, e)][kMomentIndex(p, phi)];
            }
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
