#pragma once
// The blend region's s as the harmonic interpolation between the inner region
// (s = 0) and the outer region (s = 1): the default profile of the painted
// (eq. 16) and geodesic (eq. 15) regions (docs/regions.md, "The blend profile").
//
// Eqs. (15) and (16) build s from geodesic distances. A distance field has a
// kink wherever two shortest paths meet (its cut locus: across a face the paths
// to the outer region round the head on both sides), and its discrete
// approximation wobbles from vertex to vertex. The field differentiates s twice
// over (∇r, then the stream term), so a kink in s is a crease in the velocity,
// and the crease folds the surface (docs/method.md, "Keeping the promise"). The
// harmonic function with the same inner and outer regions has no kinks: it is
// the smoothest interpolation between them, lies in [0, 1], and keeps the
// regions' borders where the user put them. It is solved once, on the rest
// mesh; s stays a property of each vertex as sec. 3 says.
//
// The Laplacian is the cotangent one with negative weights set to zero, so that
// the solution obeys the maximum principle on any mesh (an obtuse triangle
// cannot push s out of [0, 1]).

#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/vertex_rings.h"

namespace vfsd {

// s with the values of its blend vertices (0 < s < 1) replaced by the discrete
// harmonic function that is 0 on the vertices with s <= 0 and 1 on those with
// s >= 1. The given blend values start the solver, so eq. (15) or (16) makes it
// quick. The result stays in (0, 1) on the blend vertices, so every region keeps
// its vertices. A blend vertex with no path to a fixed vertex keeps its value.
std::vector<double> harmonic_blend(const std::vector<Vec3>& positions, const VertexRings& rings,
                                   std::vector<double> s);

// The same solve in parts, for an editor that spreads it over frames: the
// constructor sets up the system, each iterate() runs its conjugate-gradient
// iterations for about a budget. The result is harmonic_blend's, bit for bit,
// however the iterations fall into parts (harmonic_blend is this, run to the end).
class HarmonicBlend {
public:
    // After `max_iterations` (0: max(1000, unknowns)) a direct factorisation solves
    // the system instead, where the iteration does not converge.
    HarmonicBlend(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<double> s,
                  long max_iterations = 0);
    // Iterates for about `budget_ms` (at least one iteration; infinity: to the end).
    // True once s is final.
    bool iterate(double budget_ms);
    bool done() const { return done_; }
    // Conjugate-gradient iterations so far.
    long iterations() const { return iterations_; }
    // s: final once done(), the starting values before.
    const std::vector<double>& s() const { return s_; }
    std::vector<double> take() { return std::move(s_); }

private:
    void finish();
    double product_with_direction();  // product_ = A · direction_; returns direction_ · product_
    void solve_directly();
    void build_coarse_space();
    double precondition();  // preconditioned_ = M⁻¹ residual_; returns residual_ · preconditioned_

    // The coarse space of the two-level preconditioner: aggregates of about a
    // vertex's ring and the system on them, factorised (harmonic_blend.cpp);
    // none where that system did not factorise (Jacobi alone).
    struct CoarseSpace;
    std::shared_ptr<const CoarseSpace> coarse_;

    std::vector<double> s_;
    std::vector<std::uint32_t> unknowns_;  // the blend vertices solved for, in the system's order
    // The system A x = rhs by rows: A's diagonal, and its off-diagonal entries
    // (−w_ij) as columns and weights from row_offsets_[i] to row_offsets_[i + 1].
    std::vector<double> diagonal_, weights_;
    std::vector<std::uint32_t> row_offsets_, columns_;
    // Conjugate gradients with a two-level preconditioner, Jacobi plus a coarse
    // correction on aggregates (harmonic_blend.cpp): the iterate, the right-hand
    // side, the residual, the search direction, its product with A, the
    // preconditioned residual z, the residual summed by aggregates and the
    // coarse system's solution for it, and r·z.
    std::vector<double> x_, rhs_, residual_, direction_, product_, inverse_diagonal_, preconditioned_;
    std::vector<double> coarse_residual_, coarse_correction_;
    double rz_ = 0.0, threshold_ = 0.0;
    long iterations_ = 0, max_iterations_ = 0;
    bool done_ = false;
};

}  // namespace vfsd
