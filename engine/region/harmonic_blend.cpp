#include "region/harmonic_blend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <glm/geometric.hpp>

#include "base/parallel.h"

namespace vfsd {
namespace {

bool in_blend(double s) { return s > 0.0 && s < 1.0; }

// cot of the angle at `apex` in the triangle (apex, a, b), clamped to [0, 1e3]:
// an obtuse angle gives no weight, a degenerate triangle a bounded one.
double clamped_cot(const Vec3& apex, const Vec3& a, const Vec3& b) {
    Vec3 u = a - apex, v = b - apex;
    // Scaled to about 1 first, so that the products neither overflow (a mesh
    // 1e200 across) nor underflow (1e-200 across): the cotangent has no unit.
    const Vec3 largest = glm::max(glm::abs(u), glm::abs(v));
    const double size = std::max({largest.x, largest.y, largest.z});
    if (!(size > 0.0) || !std::isfinite(size)) return 0.0;
    u /= size, v /= size;
    const double sine = glm::length(glm::cross(u, v)), cosine = glm::dot(u, v);
    if (!(cosine > 0.0)) return 0.0;
    return sine > cosine * 1e-3 ? cosine / sine : 1e3;
}

// The cotangent weight of ring entry k of vertex v: half the cotangents of the
// angles facing the edge in the (one or two) triangles beside it.
double edge_weight(const std::vector<Vec3>& x, const VertexRings& rings, std::uint32_t v, std::uint32_t k) {
    const std::uint32_t a = rings.neighbours[k];
    const std::uint32_t before = k == rings.begin(v) ? rings.end(v) - 1 : k - 1;
    double w = 0.0;
    if (rings.wedge[k]) w += clamped_cot(x[rings.neighbours[rings.next(v, k)]], x[v], x[a]);
    if (rings.wedge[before]) w += clamped_cot(x[rings.neighbours[before]], x[v], x[a]);
    return 0.5 * w;
}

// Marks the blend vertices that a path through blend vertices joins to a vertex
// of fixed s; the others (a part of the mesh that is blend throughout) have no
// harmonic function to take and keep their values.
std::vector<std::uint8_t> anchored(const std::vector<double>& s, const VertexRings& rings) {
    std::vector<std::uint8_t> reached(s.size(), 0);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t v = 0; v < s.size(); ++v) {
        if (in_blend(s[v])) continue;
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            const std::uint32_t a = rings.neighbours[k];
            if (in_blend(s[a]) && !reached[a]) reached[a] = 1, queue.push_back(a);
        }
    }
    for (std::size_t i = 0; i < queue.size(); ++i)
        for (std::uint32_t k = rings.begin(queue[i]); k < rings.end(queue[i]); ++k) {
            const std::uint32_t a = rings.neighbours[k];
            if (in_blend(s[a]) && !reached[a]) reached[a] = 1, queue.push_back(a);
        }
    return reached;
}

// Aggregates of the unknowns for the coarse space, on the system's graph
// (rows `offsets`, `columns`): each unknown whose neighbours are all free
// starts one with them, in order; each left over joins the aggregate of the
// first neighbour in its row that has one, or starts its own. Returns each
// unknown's aggregate and sets `count`.
std::vector<std::uint32_t> aggregate(const std::vector<std::uint32_t>& offsets,
                                     const std::vector<std::uint32_t>& columns, std::uint32_t& count) {
    constexpr std::uint32_t kFree = ~std::uint32_t(0);
    const std::size_t n = offsets.size() - 1;
    std::vector<std::uint32_t> of(n, kFree);
    count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        bool free = of[i] == kFree;
        for (std::uint32_t k = offsets[i]; k < offsets[i + 1] && free; ++k) free = of[columns[k]] == kFree;
        if (!free) continue;
        of[i] = count;
        for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) of[columns[k]] = count;
        ++count;
    }
    std::vector<std::uint32_t> joined(of);
    for (std::size_t i = 0; i < n; ++i) {
        if (of[i] != kFree) continue;
        for (std::uint32_t k = offsets[i]; k < offsets[i + 1] && joined[i] == kFree; ++k) joined[i] = of[columns[k]];
        if (joined[i] == kFree) joined[i] = count++;
    }
    return joined;
}

}  // namespace

// The coarse correction P A_c⁻¹ Pᵀ r of the two-level preconditioner: P takes
// each aggregate's value to its unknowns (piecewise constant) and A_c = Pᵀ A P
// is the system on the aggregates, factorised once.
struct HarmonicBlend::CoarseSpace {
    std::vector<std::uint32_t> of;  // per unknown, its aggregate
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factors;
};

std::vector<double> harmonic_blend(const std::vector<Vec3>& positions, const VertexRings& rings,
                                   std::vector<double> s) {
    HarmonicBlend blend(positions, rings, std::move(s));
    blend.iterate(std::numeric_limits<double>::infinity());
    return blend.take();
}

HarmonicBlend::HarmonicBlend(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<double> s,
                             long max_iterations)
    : s_(std::move(s)) {
    const std::vector<std::uint8_t> solve_at = anchored(s_, rings);
    std::vector<std::int32_t> index(s_.size(), -1);
    for (std::uint32_t v = 0; v < s_.size(); ++v)
        if (solve_at[v]) index[v] = static_cast<std::int32_t>(unknowns_.size()), unknowns_.push_back(v);
    if (unknowns_.empty()) {
        done_ = true;
        return;
    }

    // The unknowns' ring entries' weights, in order, taken once. A small
    // multiple of the graph Laplacian keeps every row of the system positive
    // where all of a vertex's cotangents are clamped to zero.
    std::vector<std::size_t> first_entry(unknowns_.size() + 1, 0);
    for (std::size_t i = 0; i < unknowns_.size(); ++i)
        first_entry[i + 1] = first_entry[i] + (rings.end(unknowns_[i]) - rings.begin(unknowns_[i]));
    std::vector<double> edge_weights(first_entry.back());
    parallel_for(unknowns_.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const std::uint32_t v = unknowns_[i];
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
                edge_weights[first_entry[i] + (k - rings.begin(v))] = edge_weight(positions, rings, v, k);
        }
    });
    double mean_weight = 0.0;
    for (const double w : edge_weights) mean_weight += w;
    const std::size_t entries = edge_weights.size();
    const double floor_weight = 1e-10 * (entries > 0 && mean_weight > 0.0 ? mean_weight / double(entries) : 1.0);

    // Σ_j w_ij (s_j − s_i) = 0 on the unknowns, the fixed neighbours' terms on the right.
    const std::size_t n = unknowns_.size();
    diagonal_.assign(n, 0.0);
    rhs_.assign(n, 0.0);
    x_.resize(n);
    row_offsets_.assign(1, 0);
    const double* weight = edge_weights.data();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t v = unknowns_[i];
        x_[i] = s_[v];  // eq. (15) or (16) starts the solver
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k, ++weight) {
            const std::uint32_t a = rings.neighbours[k];
            if (a == v) continue;
            const double w = *weight + floor_weight;
            diagonal_[i] += w;
            if (index[a] >= 0)
                columns_.push_back(static_cast<std::uint32_t>(index[a])), weights_.push_back(w);
            else
                rhs_[i] += w * std::clamp(s_[a], 0.0, 1.0);
        }
        row_offsets_.push_back(static_cast<std::uint32_t>(columns_.size()));
    }

    // Conjugate gradients to a relative residual of 1e-12, with a two-level
    // preconditioner (precondition()), set up by the first iterate().
    constexpr double kTolerance = 1e-12;
    max_iterations_ = max_iterations > 0 ? max_iterations : std::max<long>(1000, static_cast<long>(n));
    inverse_diagonal_.resize(n);
    residual_.resize(n);
    product_.resize(n);
    double rhs_norm2 = 0.0, residual_norm2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        double ax = diagonal_[i] * x_[i];
        for (std::uint32_t k = row_offsets_[i]; k < row_offsets_[i + 1]; ++k) ax -= weights_[k] * x_[columns_[k]];
        residual_[i] = rhs_[i] - ax;
        inverse_diagonal_[i] = 1.0 / diagonal_[i];
        rhs_norm2 += rhs_[i] * rhs_[i];
        residual_norm2 += residual_[i] * residual_[i];
    }
    if (rhs_norm2 == 0.0) {
        std::fill(x_.begin(), x_.end(), 0.0);
        finish();
        return;
    }
    threshold_ = std::max(kTolerance * kTolerance * rhs_norm2, std::numeric_limits<double>::min());
    if (residual_norm2 < threshold_) finish();
}

double HarmonicBlend::product_with_direction() {
    double dot = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
        double q = diagonal_[i] * direction_[i];
        for (std::uint32_t k = row_offsets_[i]; k < row_offsets_[i + 1]; ++k)
            q -= weights_[k] * direction_[columns_[k]];
        product_[i] = q;
        dot += direction_[i] * q;
    }
    return dot;
}

// Two levels: the Jacobi step D⁻¹ r takes out the residual's rapid variation
// from vertex to vertex, the coarse correction on aggregates of about a ring
// (P A_c⁻¹ Pᵀ r) its slow variation across the region, which Jacobi alone
// removes only over as many iterations as the region is rings across: z =
// D⁻¹ r + P A_c⁻¹ Pᵀ r (additive, so symmetric and positive definite, as
// conjugate gradients need). On the raised claw's 7,442 blend vertices 64
// iterations instead of Jacobi's 335 (docs/regions.md, "The harmonic blend's
// solver").
double HarmonicBlend::precondition() {
    const std::size_t n = residual_.size();
    double rz = 0.0;
    if (!coarse_) {
        for (std::size_t i = 0; i < n; ++i)
            preconditioned_[i] = inverse_diagonal_[i] * residual_[i], rz += residual_[i] * preconditioned_[i];
        return rz;
    }
    const CoarseSpace& c = *coarse_;
    std::fill(coarse_residual_.begin(), coarse_residual_.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) coarse_residual_[c.of[i]] += residual_[i];
    const auto m = static_cast<Eigen::Index>(coarse_residual_.size());
    Eigen::Map<Eigen::VectorXd>(coarse_correction_.data(), m) =
        c.factors.solve(Eigen::Map<const Eigen::VectorXd>(coarse_residual_.data(), m));
    for (std::size_t i = 0; i < n; ++i) {
        preconditioned_[i] = inverse_diagonal_[i] * residual_[i] + coarse_correction_[c.of[i]];
        rz += residual_[i] * preconditioned_[i];
    }
    return rz;
}

// The aggregates and A_c = Pᵀ A P: A's entries summed by the aggregates of
// their row and column. Where A_c does not factorise, Jacobi alone.
void HarmonicBlend::build_coarse_space() {
    auto coarse = std::make_shared<CoarseSpace>();
    std::uint32_t count = 0;
    coarse->of = aggregate(row_offsets_, columns_, count);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(x_.size() + columns_.size());
    for (std::size_t i = 0; i < x_.size(); ++i) {
        const auto row = static_cast<Eigen::Index>(coarse->of[i]);
        triplets.emplace_back(row, row, diagonal_[i]);
        for (std::uint32_t k = row_offsets_[i]; k < row_offsets_[i + 1]; ++k)
            triplets.emplace_back(row, static_cast<Eigen::Index>(coarse->of[columns_[k]]), -weights_[k]);
    }
    Eigen::SparseMatrix<double> system(count, count);
    system.setFromTriplets(triplets.begin(), triplets.end());
    coarse->factors.compute(system);
    if (coarse->factors.info() != Eigen::Success) return;
    coarse_residual_.resize(count);
    coarse_correction_.resize(count);
    coarse_ = std::move(coarse);
}

bool HarmonicBlend::iterate(double budget_ms) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto out_of_time = [&] {
        return std::chrono::duration<double, std::milli>(Clock::now() - start).count() >= budget_ms;
    };
    const std::size_t n = x_.size();
    if (!done_ && direction_.empty()) {  // the first call: the preconditioner, and the first direction
        build_coarse_space();
        preconditioned_.resize(n);
        rz_ = precondition();
        direction_ = preconditioned_;
    }
    while (!done_) {
        const double alpha = rz_ / product_with_direction();
        double residual_norm2 = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            x_[i] += alpha * direction_[i];
            residual_[i] -= alpha * product_[i];
            residual_norm2 += residual_[i] * residual_[i];
        }
        if (residual_norm2 < threshold_) return finish(), true;
        const double rz = precondition();
        const double beta = rz / rz_;
        rz_ = rz;
        for (std::size_t i = 0; i < n; ++i) direction_[i] = preconditioned_[i] + beta * direction_[i];
        if (++iterations_ >= max_iterations_) {  // a direct factorisation where the iteration does not converge
            solve_directly();
            return finish(), true;
        }
        if (out_of_time()) break;
    }
    return done_;
}

void HarmonicBlend::solve_directly() {
    const auto n = static_cast<Eigen::Index>(x_.size());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(x_.size() + columns_.size());
    for (std::size_t i = 0; i < x_.size(); ++i) {
        const auto row = static_cast<Eigen::Index>(i);
        triplets.emplace_back(row, row, diagonal_[i]);
        for (std::uint32_t k = row_offsets_[i]; k < row_offsets_[i + 1]; ++k)
            triplets.emplace_back(row, static_cast<Eigen::Index>(columns_[k]), -weights_[k]);
    }
    Eigen::SparseMatrix<double> laplacian(n, n);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct(laplacian);
    if (direct.info() != Eigen::Success) {
        std::fill(x_.begin(), x_.end(), std::numeric_limits<double>::quiet_NaN());
        return;
    }
    const Eigen::VectorXd solved = direct.solve(Eigen::Map<const Eigen::VectorXd>(rhs_.data(), n));
    for (Eigen::Index i = 0; i < n; ++i) x_[static_cast<std::size_t>(i)] = solved[i];
}

void HarmonicBlend::finish() {
    // Strictly inside (0, 1): a blend vertex stays a blend vertex. A value that is
    // not finite (no factorisation either) leaves the vertex as it was.
    constexpr double kInside = 1e-12;
    for (std::size_t i = 0; i < unknowns_.size(); ++i)
        if (std::isfinite(x_[i])) s_[unknowns_[i]] = std::clamp(x_[i], kInside, 1.0 - kInside);
    done_ = true;
    coarse_.reset();
    for (auto* v : {&preconditioned_, &coarse_residual_, &coarse_correction_, &diagonal_, &weights_, &x_, &rhs_,
                    &residual_, &direction_, &product_, &inverse_diagonal_})
        *v = std::vector<double>();
    row_offsets_ = columns_ = std::vector<std::uint32_t>();
}

}  // namespace vfsd
