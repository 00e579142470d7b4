#pragma once
// Beyond the paper: the fold repair. Sec. 7.2's promise is about the flow of one
// smooth field; the engine samples it at the vertices (each with its own ∇r from
// its ring), and on scenes nobody tuned the sampled map can still fold a
// triangle where it varies by order one across a few rings (docs/method.md,
// "Keeping the promise"). After every step, the blend vertices of each triangle
// that turned to face against its edge neighbours (deform/quality.h's measure)
// are placed again by the map a smooth field makes there to first order:
//
// 1. rounds 1–10: each vertex moves halfway, three times, toward the image of its
//    rest position under the affine map that best takes its ring's rest positions
//    to their current ones (regularised toward the ring's rotation, since a ring
//    is nearly flat);
// 2. rounds 11–20 (what the rings could not untangle): one such affine map per
//    connected patch, fitted to the patch's boundary, plus the harmonic
//    interpolant of the boundary's residuals: Δx = A Δx_rest inside the patch,
//    which keeps the rest shape's detail turned and stretched as A does.
//
// Each round takes the folded triangles' blend corners and the blend vertices
// up to min(3, 1 + round / 3) rings around them; no vertex moves further than its
// ring's mean edge in one step. The step keeps the round that left the fewest
// folds (none if no round did better than the step found), so a repair never
// leaves more folds than it found. Only blend vertices move: the outer region
// stays exactly put and the inner region rigid. It acts only after a step that
// folded something, and the repaired vertices leave their path lines by the
// shifts the stats report (docs/method.md, "The fold repair").

#include <cstdint>
#include <vector>

#include "deform/quality.h"
#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

// The fold test's data, as FoldRepair built it: the triangles with a blend corner
// (check) and their edge neighbours, indices into `triangles`. Entry i is folded
// when its triangle's unit normal faces against the sum of its neighbours' (those
// of neighbours[neighbour_offsets[i] .. neighbour_offsets[i + 1]]) and it did not
// at rest (against_at_rest[i]). The GPU's fold pass takes it (gpu/gpu_passes.h).
struct FoldChecks {
    const std::vector<Triangle>& triangles;
    const std::vector<std::uint32_t>& check;
    const std::vector<std::uint32_t>& neighbour_offsets;
    const std::vector<std::uint32_t>& neighbours;
    const std::vector<std::uint8_t>& against_at_rest;
};

struct FoldRepairStats {
    std::size_t steps_repaired = 0;  // steps after which some triangle was folded
    std::size_t vertex_moves = 0;    // Σ over rounds of the vertices placed again
    double max_shift = 0.0;          // the largest move of one vertex in one step, in the positions' units
};

class FoldRepair {
public:
    FoldRepair() = default;  // inactive: repair() does nothing
    // `rest`, `s` and `rings` in one vertex order; the blend region is 0 < s < 1.
    FoldRepair(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings);

    bool active() const { return !check_.empty(); }
    // Repairs the folds of `positions` (the same order as at construction) as
    // described above; returns the number of triangles still folded after the
    // last round (0 almost always).
    std::size_t repair(std::vector<Vec3>& positions, const VertexRings& rings);
    const FoldRepairStats& stats() const { return stats_; }
    FoldChecks checks() const { return {triangles_, check_, neighbour_offsets_, neighbours_, against_at_rest_}; }
    std::size_t bytes() const;

private:
    std::vector<std::uint32_t> folded(const std::vector<Vec3>& x);
    std::vector<std::uint32_t> vertices_to_move(const std::vector<std::uint32_t>& folded, int rings_out,
                                                const VertexRings& rings);
    void refit_rings(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x, const VertexRings& rings) const;
    void refit_patches(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x, const VertexRings& rings);

    std::vector<Vec3> rest_;
    std::vector<std::uint8_t> movable_;  // 1 on the blend region
    // The triangles with a blend corner (check_) and their edge neighbours; the
    // neighbours of check_[i] are triangles_[neighbours_[neighbour_offsets_[i] ..]].
    std::vector<Triangle> triangles_;
    std::vector<std::uint32_t> check_, neighbour_offsets_, neighbours_;
    std::vector<std::uint8_t> against_at_rest_;  // per check_ entry
    std::vector<Vec3> normals_;                  // per triangles_ entry, scratch
    std::vector<std::uint8_t> flags_;            // per check_ entry, scratch
    std::vector<std::uint8_t> mark_;             // per vertex, scratch
    FoldRepairStats stats_;
};

}  // namespace vfsd
