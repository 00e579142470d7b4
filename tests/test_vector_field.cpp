// The field of eqs. (1)–(14): divergence-free, equal to ∇p × ∇q built from the
// paper's scalar fields, and v(c(t), t) = ċ(t) (eq. 8).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <iterator>
#include <optional>
#include <random>

#include "curve/inner_motion.h"
#include "field/field_lanes.h"
#include "field/stream_gauge.h"
#include "field/vector_field.h"

using namespace vfsd;

namespace {

using ScalarField = std::function<double(const Vec3&)>;

// Fourth-order central difference of a scalar function along one axis.
template <class F>
double derivative(const F& f, const Vec3& x, int axis, double h) {
    Vec3 d(0.0);
    d[axis] = h;
    return (-f(x + 2.0 * d) + 8.0 * f(x + d) - 8.0 * f(x - d) + f(x - 2.0 * d)) / (12.0 * h);
}

Vec3 central_gradient(const ScalarField& f, const Vec3& x, double h) {
    return {derivative(f, x, 0, h), derivative(f, x, 1, h), derivative(f, x, 2, h)};
}

// Blend of the implicit sphere tool of VFSD [23]: r = |x − centre|.
struct SphereBlend {
    Vec3 centre;
    double r_inner, r_outer;
    double u(const Vec3& x) const { return (glm::length(x - centre) - r_inner) / (r_outer - r_inner); }
    double b(const Vec3& x) const { return bernstein_blend(u(x)); }
    Vec3 grad_b(const Vec3& x) const {
        const Vec3 d = x - centre;
        return bernstein_blend_derivative(u(x)) / (r_outer - r_inner) * d / glm::length(d);
    }
};

Vec3 field_at(const MotionSample& m, const SphereBlend& s, const Vec3& x) {
    return deformation_velocity(m, x, s.b(x), s.grad_b(x));
}

double divergence(const MotionSample& m, const SphereBlend& s, const Vec3& x, double h) {
    double div = 0.0;
    for (int k = 0; k < 3; ++k) div += derivative([&](const Vec3& y) { return field_at(m, s, y)[k]; }, x, k, h);
    return div;
}

InnerMotion curved_motion(InnerMotionMode mode, double twist, std::optional<Vec3> stream_origin = {}) {
    // Two segments with a straight piece and an inflection.
    BezierCurve curve({{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 1, 4}, {1, 2, 3}, {2, 1, 5}});
    InnerMotion motion = InnerMotion::along_curve(curve, mode, 0.0, twist);
    motion.set_twist_plane(-0.7);  // any plane keeps the field divergence-free
    motion.set_stream_origin(stream_origin);
    return motion;
}

// A gauge ∇φ about an arbitrary centre and scale; its polynomials need not be a
// gradient for the tests that use it (they compare evaluations).
StreamGauge random_gauge(std::mt19937& rng) {
    std::uniform_real_distribution<double> coefficient(-1.0, 1.0);
    StreamGauge g;
    g.centre = Vec3(coefficient(rng), coefficient(rng), coefficient(rng));
    g.inverse_scale = 0.5 + std::abs(coefficient(rng));
    for (auto& row : g.q)
        for (double& q : row) q = coefficient(rng);
    return g;
}

// The stream's origins the field tests run with: c(t) (eq. 10) and a fixed point.
const std::optional<Vec3> kStreamOrigins[] = {std::nullopt, Vec3(0.4, -0.9, 1.3)};

}  // namespace

TEST_CASE("the field of the implicit sphere tool is divergence-free", "[field]") {
    const SphereBlend blend{{0.2, -0.1, 0.3}, 0.5, 1.5};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-1.6, 1.6);
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation})
    for (const auto& origin : kStreamOrigins) {
        const InnerMotion motion = curved_motion(mode, 2.0, origin);
        for (int i = 0; i < 200; ++i) {
            const MotionSample m = motion.at(i / 199.0);
            const Vec3 x = blend.centre + Vec3(coord(rng), coord(rng), coord(rng));
            // b is C¹ across the shells r = r_i, r_o: keep the stencil off them.
            const double r = glm::length(x - blend.centre);
            if (std::abs(r - blend.r_inner) < 0.01 || std::abs(r - blend.r_outer) < 0.01) continue;
            const Vec3 v = field_at(m, blend, x);
            const double diag = 2.0 * std::sqrt(3.0) * 1.6;
            CHECK(std::abs(divergence(m, blend, x, 1e-4)) <= 1e-6 * glm::length(v) / diag);
        }
    }
}

TEST_CASE("the closed form equals grad p x grad q of the paper's e and f", "[field]") {
    // Rotation mode at a curved sample: build e, f of eqs. (11)–(13) with the axis
    // t scaled so that (8) holds, f shifted to vanish at c, and compare.
    const InnerMotion motion = curved_motion(InnerMotionMode::Rotation, 0.0);
    const SphereBlend blend{{0.0, 0.5, 3.5}, 0.3, 1.2};
    for (double t : {0.55, 0.7, 0.9}) {
        const CurvePoint c = motion.curve().at(t);
        const MotionSample m = motion.at(t);
        const Vec3 cd = c.d1, cdd = c.d2;
        const double cc = glm::dot(cd, cd), cn = glm::dot(cd, cdd);
        // Eq. (11) with its numerator's second term read as ċ (ċ·ċ)(ċ·c̈): as printed,
        // ċ (ċ·c̈)(ċ·c̈) has the wrong dimension and misses the curvature centre.
        const Vec3 z = c.position + (cdd * cc * cc - cd * cc * cn) / (cc * glm::dot(cdd, cdd) - cn * cn);
        const Vec3 axis = glm::normalize(glm::cross(cd, cdd));                                             // eq. (12)
        const double lambda = std::cbrt(glm::length(m.angular_velocity) / 2.0);
        const Vec3 tt = lambda * axis;
        const double f_shift = glm::dot(glm::cross(tt, c.position - z), glm::cross(tt, c.position - z));
        ScalarField e = [&](const Vec3& x) { return glm::dot(tt, x - z); };  // eq. (13)
        ScalarField f = [&](const Vec3& x) {
            const Vec3 w = glm::cross(tt, x - z);
            return glm::dot(w, w) - f_shift;
        };
        ScalarField p = [&](const Vec3& x) { return (1.0 - blend.b(x)) * e(x); };  // eq. (2)
        ScalarField q = [&](const Vec3& x) { return (1.0 - blend.b(x)) * f(x); };  // eq. (3)
        for (const Vec3 offset : {Vec3(0.5, 0.2, 0.1), Vec3(-0.3, 0.6, 0.2), Vec3(0.1, -0.2, 0.7)}) {
            const Vec3 x = blend.centre + offset;
            const Vec3 expected = glm::cross(central_gradient(p, x, 1e-3), central_gradient(q, x, 1e-3));
            CHECK(glm::length(field_at(m, blend, x) - expected) <= 1e-6 * glm::length(expected));
        }
    }
}

TEST_CASE("eq. (8): the field at c(t) is the curve's velocity", "[field]") {
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation}) {
        const InnerMotion motion = curved_motion(mode, 1.0);
        for (int i = 0; i < 100; ++i) {
            const MotionSample m = motion.at(i / 99.0);
            const Vec3 cdot = motion.curve().at(i / 99.0).d1;
            const Vec3 v = deformation_velocity(m, m.position, 0.0, Vec3(0.0));
            CHECK(glm::length(v - cdot) <= 1e-6 * glm::length(cdot));
        }
    }
}

TEST_CASE("the rotation mode degrades smoothly to translation on straight pieces", "[field]") {
    const InnerMotion rotation = curved_motion(InnerMotionMode::Rotation, 0.0);
    // t in [0, 0.5) is the straight first segment: no rotation at all.
    for (int i = 0; i < 50; ++i) CHECK(glm::length(rotation.at(i / 100.0).angular_velocity) == 0.0);
    // Near the inflection the angular velocity stays bounded.
    double largest = 0.0;
    for (int i = 0; i <= 1000; ++i) largest = std::max(largest, glm::length(rotation.at(0.5 + i / 2000.0).angular_velocity));
    CHECK(std::isfinite(largest));
    CHECK(largest < 100.0);
}

TEST_CASE("the lane-wise field equals the reference field point by point", "[field]") {
    // deformation_velocities (the deformation pass's vectorised loop) against
    // deformation_velocity, with a twist plane off c and a partial last block.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-2.0, 2.0), unit(0.0, 1.0);
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation})
    for (const auto& origin : kStreamOrigins) {
        const InnerMotion motion = curved_motion(mode, 1.5, origin);
        for (double t : {0.2, 0.6, 0.75, 0.95}) {
            MotionSample m = motion.at(t);
            m.gauge = random_gauge(rng);
            const int n = kFieldLanes - 3;
            Lanes3 at, grad_b, out;
            double one_minus_b[kFieldLanes] = {};
            for (int j = 0; j < n; ++j) {
                at.x[j] = coord(rng), at.y[j] = coord(rng), at.z[j] = coord(rng);
                grad_b.x[j] = coord(rng), grad_b.y[j] = coord(rng), grad_b.z[j] = coord(rng);
                one_minus_b[j] = unit(rng);
            }
            deformation_velocities(PreparedMotion(m), n, one_minus_b, grad_b, at, out);
            for (int j = 0; j < n; ++j) {
                const Vec3 expected = deformation_velocity(m, Vec3(at.x[j], at.y[j], at.z[j]), 1.0 - one_minus_b[j],
                                                           Vec3(grad_b.x[j], grad_b.y[j], grad_b.z[j]));
                const Vec3 got(out.x[j], out.y[j], out.z[j]);
                CHECK(glm::length(got - expected) <= 1e-12 * std::max(1.0, glm::length(expected)));
            }
        }
    }
}

TEST_CASE("the stream's origin is c(t) by default or the fixed point, and changes the blend field", "[field]") {
    // Moving o is a gauge change: U + ω × (x − o) is the same rigid velocity and the
    // field stays divergence-free (tests above); the stream, and with it the blend
    // region's field, differs (test_deformation.cpp: the inner region moves the same).
    const SphereBlend blend{{0.2, -0.1, 0.3}, 0.5, 1.5};
    const Vec3 origin(0.4, -0.9, 1.3);
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation}) {
        const InnerMotion at_curve = curved_motion(mode, 1.0), fixed = curved_motion(mode, 1.0, origin);
        for (int i = 0; i < 50; ++i) {
            const double t = i / 49.0;
            const MotionSample a = at_curve.at(t), b = fixed.at(t);
            CHECK(a.stream_origin == a.position);
            CHECK(b.stream_origin == origin);
        }
        // In the blend region they differ: the option is not a no-op.
        const MotionSample a = at_curve.at(0.5), b = fixed.at(0.5);
        const Vec3 x = blend.centre + Vec3(0.0, 0.0, 1.0), grad_b(0.0, 0.0, 1.0);
        CHECK(glm::length(deformation_velocity(b, x, 0.5, grad_b) - deformation_velocity(a, x, 0.5, grad_b)) > 0.1);
    }
}

TEST_CASE("the stream vector is the quadratic polynomial stream_polynomial expands", "[field]") {
    // z × U is linear in x, the rotation streams and the gauge quadratic: the
    // expansion about any centre reproduces stream_vector everywhere, not only
    // at the ten points it was taken from.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-3.0, 3.0);
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation})
        for (const auto& origin : kStreamOrigins)
            for (double t : {0.1, 0.55, 0.8}) {
                MotionSample m = curved_motion(mode, 1.5, origin).at(t);
                m.gauge = random_gauge(rng);
                const Vec3 centre(coord(rng), coord(rng), coord(rng));
                const StreamGauge polynomial = stream_polynomial(m, centre, 0.7);
                for (int i = 0; i < 20; ++i) {
                    const Vec3 x = centre + Vec3(coord(rng), coord(rng), coord(rng));
                    const Vec3 expected = stream_vector(m, x);
                    CHECK(glm::length(gauge_gradient(polynomial, x) - expected) <=
                          1e-12 * std::max(1.0, glm::length(expected)));
                }
            }
}

namespace {

// The fit's objective (stream_gauge.h) for the gauge g: Σ |S′ × gᵢ|² + μ |gᵢ|² |S′|², S′ = S + ∇φ.
double gauge_objective(const MotionSample& motion, const StreamGauge& g, const std::vector<GaugeSample>& samples) {
    MotionSample m = motion;
    m.gauge = g;
    double sum = 0.0;
    for (const GaugeSample& s : samples) {
        const Vec3 stream = stream_vector(m, s.position);
        sum += glm::dot(glm::cross(stream, s.weight), glm::cross(stream, s.weight)) +
               GaugeFit::kStreamWeight * glm::dot(s.weight, s.weight) * glm::dot(stream, stream);
    }
    return sum;
}

// The gradients of the monomials of degree 1 to 3 as StreamGauge entries: per
// component, the coefficient of one of its quadratic monomials (1, x, y, z, x²,
// y², z², xy, xz, yz).
struct GaugeEntry {
    int component = 0, monomial = 0;
    double factor = 0.0;  // 0: unused
};
constexpr GaugeEntry kCubicGradients[19][3] = {
    {{0, 0, 1}},                        // ∇x = (1, 0, 0)
    {{1, 0, 1}},                        // ∇y
    {{2, 0, 1}},                        // ∇z
    {{0, 1, 1}},                        // ∇(x²/2) = (x, 0, 0)
    {{1, 2, 1}},                        // ∇(y²/2)
    {{2, 3, 1}},                        // ∇(z²/2)
    {{0, 2, 1}, {1, 1, 1}},             // ∇(xy) = (y, x, 0)
    {{0, 3, 1}, {2, 1, 1}},             // ∇(xz) = (z, 0, x)
    {{1, 3, 1}, {2, 2, 1}},             // ∇(yz) = (0, z, y)
    {{0, 4, 1}},                        // ∇(x³/3) = (x², 0, 0)
    {{1, 5, 1}},                        // ∇(y³/3)
    {{2, 6, 1}},                        // ∇(z³/3)
    {{0, 7, 2}, {1, 4, 1}},             // ∇(x²y) = (2xy, x², 0)
    {{0, 8, 2}, {2, 4, 1}},             // ∇(x²z) = (2xz, 0, x²)
    {{0, 5, 1}, {1, 7, 2}},             // ∇(y²x) = (y², 2xy, 0)
    {{1, 9, 2}, {2, 5, 1}},             // ∇(y²z) = (0, 2yz, y²)
    {{0, 6, 1}, {2, 8, 2}},             // ∇(z²x) = (z², 0, 2xz)
    {{1, 6, 1}, {2, 9, 2}},             // ∇(z²y) = (0, z², 2yz)
    {{0, 9, 1}, {1, 8, 1}, {2, 7, 1}},  // ∇(xyz) = (yz, xz, xy)
};

}  // namespace

TEST_CASE("the fitted gauge minimises its objective over the cubic gauges", "[field]") {
    // Samples of a blend band about a curved motion, away from the origin; the
    // fitted gauge must beat the paper's (zero) gauge and every small change of
    // it along the gradient of each of the 19 monomials of a cubic φ (in the
    // fit's coordinates). It would not if its normal matrix or its right-hand
    // side were wrong in any term.
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> coord(-1.0, 1.0);
    for (auto mode : {InnerMotionMode::Rotation, InnerMotionMode::Translation}) {
        const InnerMotion motion = curved_motion(mode, 1.5);
        std::vector<GaugeSample> samples;
        for (int i = 0; i < 300; ++i) {
            const Vec3 x = Vec3(0.3, 0.5, 3.2) + Vec3(coord(rng), coord(rng), 0.4 * coord(rng));
            samples.push_back({x, Vec3(0.3 * coord(rng), 0.3 * coord(rng), 2.0 + coord(rng))});
        }
        const GaugeFit fit(samples);
        for (double t : {0.3, 0.7}) {
            const MotionSample m = motion.at(t);
            const StreamGauge best = fit.gauge_for(m);
            const double at_best = gauge_objective(m, best, samples);
            CHECK(at_best < gauge_objective(m, StreamGauge{}, samples));
            for (std::size_t direction = 0; direction < std::size(kCubicGradients); ++direction)
                for (double step : {-1e-3, 1e-3}) {
                    StreamGauge g = best;
                    for (const GaugeEntry& e : kCubicGradients[direction])
                        if (e.factor != 0.0) g.q[e.component][e.monomial] += e.factor * step;
                    INFO("t " << t << ", direction " << direction << ", step " << step);
                    CHECK(gauge_objective(m, g, samples) > at_best);
                }
        }
    }
}
