#pragma once
// Beyond the paper: the fold repair. Sec. 7.2's promise is about the flow of one
// smooth field; the engine samples it at the vertices (each with its own ∇r from
// its ring), and on scenes nobody tuned the sampled map can still fold a
// triangle where it varies by order one across a few rings (docs/method.md,
// "Keeping the promise"). At every 1/20 of unit time:
//
// 0. the lift: every checked triangle short of a target, N·Ŝ ≥ c (0.1 |N| +
//    0.05 A) (N its area vector, Ŝ the unit sum of its edge neighbours' normals,
//    c its cosine to that sum at rest and A its area at rest; at every 1/5 also
//    N·F̂ ≥ 0.1 |N| + 0.05 A against the affine test's image F), which every
//    folded triangle is, is projected toward it along the measure's gradient,
//    in Jacobi sweeps over the blend vertices. Each sweep is continuous in the
//    positions, so that runs which reach a repair time a little apart leave it
//    a little apart; the measure is linear in each corner, so a corner pushed
//    through its triangle's base is moved back across it. Each lifted vertex
//    then settles toward its ring's affine image of its rest position (as in
//    1.) by a weight growing from 0 with how far the lift moved it, and the
//    lift runs again for what settling left short (docs/method.md, "The lift").
//
// What the lift leaves folded (a deep fold it could not reach in its sweeps),
// the blend vertices of each triangle that still faces against its edge
// neighbours (deform/quality.h's measure) are placed again by the map a smooth
// field makes there to first order:
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
// folds, by the neighbour test first and then by both tests (none if no round
// did better than the step found), so a repair never leaves more folds than it
// found.
//
// 3. what the rounds leave folded: a vertex search. The blend corners of the
//    folded and nearly folded triangles, one at a time, try small moves (along
//    the star's normal and toward and away from each neighbour, 1/64 to 1 of
//    the shortest edge, and where none of those gains, toward the ring's
//    centroid, 1/4 to all of the way) and take the one that leaves the fewest
//    triangles about them folded by either test, if fewer than before (or as
//    many, and they are a tenth less short of a margin), up to four passes. A
//    needle or a sliver on a crease of the rest surface folds when its corner
//    crosses its base by its tiny height; no fit of a ring or a patch places a
//    vertex that closely. The search takes the vertices in the input's order
//    and settles ties by their mean, so a turned or mirrored scene is repaired
//    alike.
//
// The volume keeper's Newton steps follow a repair, and can push a needle's
// corner across its base again: the step then repairs again, up to
// kRepairCycles times (deform/cpu_steps.cpp).
//
// Only blend vertices move: the outer region stays exactly put and the inner
// region rigid. It acts only where a test finds a fold, and the repaired
// vertices leave their path lines by the shifts the stats report
// (docs/method.md, "The fold repair").
//
// It acts at fixed times, after the step that reaches or passes a multiple of
// 1/kRepairTimes. An error-controlled step that passes one and leaves a
// triangle short of the lift's target (a fold, in what follows) is
// tried again to end on it (repair_time_within), as fixed steps do at 20, 40,
// ... steps per unit time; one that leaves none goes on, so that a scene that
// does not fold takes no more steps. At those times runs of any step count
// hold the same shape to within their integration error, and the repair then
// moves it alike. Acting after every step that folded instead, it acted after
// 126 of 2,000 fixed steps and 42 of 79 error-controlled ones on one battery
// scene, and the two results lay 0.16 of the size apart (docs/method.md, "When
// the repair acts").
//
// At each multiple of 1/5 (every fourth repair time) the repair also acts on a
// second fold test, exact for affine maps: deform/quality.h's reversed
// triangles (the affine map that best takes the triangle's corners' stars from
// rest to now; folded when the triangle's image faces against the one that map
// gives it), with each star's sums shared by its triangles. The neighbour test
// misses a strip of triangles that turns over together and counts a rough
// surface's bumps tipped by a stretch; this one does neither (docs/method.md,
// "Does the fold count measure folds?").

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <glm/mat3x3.hpp>

#include "deform/quality.h"
#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

// The fold test's data, as FoldRepair built it: the triangles with a blend corner
// (check) and their edge neighbours, indices into `triangles`. Entry i is folded
// when its triangle's unit normal faces against the sum of its neighbours' (those
// of neighbours[neighbour_offsets[i] .. neighbour_offsets[i + 1]]) and it did not
// at rest (against_at_rest[i]); it is short of the lift's target when
// N·Ŝ − margin[i] |N| < floor[i], N its area vector and Ŝ its neighbours' unit
// normal sum (floor the lowest float where not tested), which a fold always is. The GPU's
// fold pass counts those (gpu/gpu_passes.h), as count_folds does.
struct FoldChecks {
    const std::vector<Triangle>& triangles;
    const std::vector<std::uint32_t>& check;
    const std::vector<std::uint32_t>& neighbour_offsets;
    const std::vector<std::uint32_t>& neighbours;
    const std::vector<std::uint8_t>& against_at_rest;
    const std::vector<float>& margin;
    const std::vector<float>& floor;
};

struct FoldRepairStats {
    std::size_t steps_repaired = 0;   // steps after which the repair moved vertices (step 0 or the rounds)
    std::size_t steps_untangled = 0;  // of those, the steps a triangle was still folded after step 0
    std::size_t vertex_moves = 0;    // Σ over rounds of the vertices placed again
    double max_shift = 0.0;          // the largest move of one vertex in one step, in the positions' units
};

class FoldRepair {
public:
    FoldRepair() = default;  // inactive: repair() does nothing
    // `rest`, `s` and `rings` in one vertex order; the blend region is 0 < s < 1.
    // `input_index`: each vertex's index in the input mesh, the order the vertex
    // search takes them in (empty: this order).
    FoldRepair(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
               std::vector<std::uint32_t> input_index = {});
    // The same, built in parts so that an editor's frame takes one (in a
    // profile of the 53k bend's edits each about a third of the whole, which
    // took 13-14 ms natively): this builds the first (the checked triangles and
    // their neighbours), and each build_part() with the same rings one more.
    // Nothing else is called before built().
    struct InParts {};
    FoldRepair(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
               std::vector<std::uint32_t> input_index, InParts);
    // Builds the next part; false when none was left.
    bool build_part(const VertexRings& rings);
    bool built() const { return parts_built_ == kParts; }

    bool active() const { return !at_rest_->check.empty(); }
    // The repair acts at the multiples of 1/kRepairTimes in time.
    static constexpr int kRepairTimes = 20;
    // Whether the repair runs after the step from time `from` to `to`: when it
    // passes a multiple of 1/kRepairTimes (either way), so that it follows how far
    // the deformation went, not how many steps it took, and scrubbing back and
    // forth repairs as a direct run does.
    static bool repair_due(double from, double to);
    // Whether the affine test runs too: when the step passes a multiple of 1/5.
    static bool affine_test_due(double from, double to);
    // The first repair time strictly between `from` and `to` (forward), or −1.
    // An error-controlled step that passes one and leaves a fold (count_folds,
    // with the affine test where it is due by then) is tried again to end
    // there, so that the repair acts on the shape at that time; one that leaves
    // none goes on.
    static double repair_time_within(double from, double to);
    // The first repair time after `time` (forward), or −1 from the last.
    static double next_repair_time(double time);
    // How many checked triangles in `positions` are short of the lift's target
    // (with `affine_test`, of either), every folded one among them: what
    // repair() would act on (none: repair() would leave them as they are).
    // `keep_measures`: for a repair() of the same positions with the same
    // `affine_test` that follows with `measured` (its lift then starts from them).
    std::size_t count_folds(const std::vector<Vec3>& positions, const VertexRings& rings, bool affine_test,
                            bool keep_measures = false);
    // After count_folds(positions, rings, false, true) on the same positions:
    // the affine test's measures too, and the count by both tests, the same as
    // count_folds(positions, rings, true, true) (its measures kept likewise) at
    // the cost of the affine test alone.
    std::size_t count_folds_with_affine(const std::vector<Vec3>& positions, const VertexRings& rings);
    // Repairs the folds of `positions` (the same order as at construction) as
    // described above, by the neighbour test and, when `affine_test`, the affine
    // one; returns the number of triangles still folded after the last round.
    // `new_step`: false when it repairs the same step again (after the volume
    // keeper's moves), which stats() then does not count as another step.
    // `measured`: count_folds(positions, rings, affine_test, true) was the last
    // call, on these positions; the same bits as without, one test fewer.
    std::size_t repair(std::vector<Vec3>& positions, const VertexRings& rings, bool affine_test, bool new_step = true,
                       bool measured = false);
    // Whether the last repair() found folds and acted on them.
    bool acted() const { return acted_; }
    // Repairs per step at most: after each, the volume keeper's Newton steps can
    // fold a needle again (deform/cpu_steps.cpp).
    static constexpr int kRepairCycles = 3;
    // The check entries (as in checks()) the affine test finds folded in `positions`.
    std::vector<std::uint32_t> affine_folded(const std::vector<Vec3>& positions, const VertexRings& rings);
    const FoldRepairStats& stats() const { return stats_; }
    // Frees the affine test's sums of every star (128 bytes a checked vertex):
    // they are kept from one test to the next while a run goes on, so that each
    // test does not allocate them again (at 2M vertices about 100 MB a test).
    void release_scratch();
    FoldChecks checks() const {
        const AtRest& r = *at_rest_;
        return {r.triangles, r.check, r.neighbour_offsets, r.neighbours, r.against_at_rest, r.margin, r.floor};
    }
    // Bytes held; `shared`: with what copies share (the state at rest).
    std::size_t bytes(bool shared = true) const;

    // The affine test's sums of one star, and its fit of one triangle at rest:
    // the triangle's edges u, w at rest through the inverse S of its regularised
    // second moment, their normal parts n·S u and n·S w, and the regularisation's
    // weight (0: not tested).
    struct StarSums {
        double count = 0.0;
        Vec3 sum{0.0};            // Σ yᵢ, each about the star's vertex
        glm::dmat3 product{0.0};  // Σ yᵢ pᵢᵀ: at rest yᵢ = pᵢ, now yᵢ = qᵢ
        Vec3 normal{0.0};         // the star's unit normal
    };
    struct RestFit {
        Vec3 u{0.0}, w{0.0};
        double u_normal = 0.0, w_normal = 0.0;
        double weight = 0.0;
    };
    // Star v's sums in x against rest (about v), its normal vertex_normal's bit for bit.
    static StarSums star_sums(const std::vector<Vec3>& rest, const std::vector<Vec3>& x, const VertexRings& rings,
                              std::uint32_t v);
    static constexpr int kEntryLanes = 16;  // check entries the lift's measures take at once, in SIMD lanes

private:
    std::vector<std::uint32_t> folded(const std::vector<Vec3>& x, const std::vector<std::uint32_t>* moved = nullptr);
    std::vector<std::uint32_t> folded_as_lifted(bool affine_test, std::size_t& neighbour);
    std::vector<std::uint32_t> with_affine(const std::vector<std::uint32_t>& by_neighbours) const;
    std::vector<std::pair<std::uint32_t, Vec3>> lift(std::vector<Vec3>& x, const VertexRings& rings, bool affine_test,
                                                     const std::vector<std::uint32_t>* moved_since = nullptr,
                                                     bool measured = false);
    void measure_lift(const std::vector<Vec3>& x, const VertexRings& rings, bool affine_test, bool flags);
    std::size_t count_short(bool affine_test) const;
    void add_lift_moves(std::uint32_t entry, const std::vector<Vec3>& x, bool affine_test,
                        std::unordered_map<std::uint32_t, Vec3>& sum) const;
    std::vector<std::uint32_t> refresh_lift(const std::vector<Vec3>& x, const VertexRings& rings,
                                            const std::vector<std::uint32_t>& moved, bool affine_test);
    void settle(const std::vector<std::pair<std::uint32_t, Vec3>>& lifted, std::vector<Vec3>& x,
                const VertexRings& rings) const;
    Vec3 neighbour_normal_sum(std::size_t entry) const;
    // The neighbour measure's inputs and results for up to kEntryLanes check entries.
    struct NeighbourLanes {
        double sum[3][kEntryLanes], area[3][kEntryLanes];  // [coordinate]: the neighbours' normals summed, N
        double cosine[kEntryLanes], rest_area[kEntryLanes], tested[kEntryLanes];  // tested: 1 or 0
        double lift[kEntryLanes];                                                 // neighbour_lift_lanes' results
    };
    double neighbour_lift(std::size_t entry, const std::vector<Vec3>& x, const Vec3& sum) const;
    void gather_neighbour_lift(std::size_t entry, const std::vector<Vec3>& x, const Vec3& sum, NeighbourLanes& lanes,
                               int lane) const;
    static void neighbour_lift_lanes(int count, NeighbourLanes& lanes);
    double fit_lift(std::size_t entry, const Vec3& fitted, const Vec3& image) const;
    bool short_of_target(std::size_t entry, double by_neighbours, double by_fit) const;
    bool faces_against_neighbours(std::size_t entry) const;
    bool faces_against(std::size_t entry, const Vec3& sum) const;
    void take_normals(const std::vector<Vec3>& x);
    std::vector<float> facings(const std::vector<Vec3>& x);
    std::vector<std::uint32_t> folded(const std::vector<Vec3>& x, const VertexRings& rings, bool affine_test,
                                      const std::vector<std::uint32_t>* moved, std::size_t& neighbour);
    void prepare_affine_test(const VertexRings& rings);
    void prepare_lift();
    std::vector<std::uint32_t> test_affine(const std::vector<Vec3>& x, const VertexRings& rings,
                                           const std::vector<std::uint32_t>* moved,
                                           std::vector<double>* fit_measures = nullptr);
    // The affine test's inputs and images for up to kEntryLanes check entries, one
    // array per coordinate (lane j last), so that its arithmetic runs in SIMD lanes.
    struct FitLanes {
        double u[3][kEntryLanes], w[3][kEntryLanes], u_normal[kEntryLanes], w_normal[kEntryLanes], weight[kEntryLanes];
        double count[3][kEntryLanes];                                                           // per corner c
        double sum[3][3][kEntryLanes], normal[3][3][kEntryLanes], rest_sum[3][3][kEntryLanes];  // [c][coordinate]
        double dy[3][3][kEntryLanes], dp[3][3][kEntryLanes];                                    // [c][coordinate]
        double pu[3][3][kEntryLanes], pw[3][3][kEntryLanes];               // [c][coordinate]: P_c u, P_c w
        double fitted_lanes[3][kEntryLanes], image_lanes[3][kEntryLanes];  // fit_lanes' results
        Vec3 fitted(int j) const { return Vec3(fitted_lanes[0][j], fitted_lanes[1][j], fitted_lanes[2][j]); }
        Vec3 image(int j) const { return Vec3(image_lanes[0][j], image_lanes[1][j], image_lanes[2][j]); }
    };
    bool reversed_by_fit(std::uint32_t entry, const std::vector<Vec3>& x) const;
    void fit_images(std::uint32_t entry, const std::vector<Vec3>& x, Vec3& fitted, Vec3& image) const;
    void gather_fit(const std::uint32_t* entries, int count, const std::vector<Vec3>& x, FitLanes& lanes) const;
    static void fit_lanes(int count, FitLanes& lanes);
    std::vector<std::uint32_t> vertices_to_move(const std::vector<std::uint32_t>& folded, int rings_out,
                                                const VertexRings& rings);
    void refit_rings(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x, const VertexRings& rings,
                     const std::vector<double>* weights = nullptr) const;
    std::vector<std::uint32_t> search_vertices(const std::vector<std::uint32_t>& near_folded, std::vector<Vec3>& x,
                                               const VertexRings& rings, bool affine_test,
                                               std::vector<std::pair<std::uint32_t, Vec3>>& undo);
    void refit_patches(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x, const VertexRings& rings);

    // What the constructor finds at rest: shared by copies (a deformation started
    // from another's rest state, deform/cpu_steps.h), written by the constructor only.
    struct AtRest {
        std::vector<Vec3> rest;
        std::vector<std::uint32_t> input_index;
        std::vector<std::uint8_t> movable;  // 1 on the blend region
        // The triangles with a blend corner (check) and their edge neighbours; the
        // neighbours of check[i] are triangles[neighbours[neighbour_offsets[i] ..]].
        std::vector<Triangle> triangles;
        std::vector<std::uint32_t> check, neighbour_offsets, neighbours;
        std::vector<std::uint8_t> against_at_rest;  // per check entry
        std::vector<float> rest_facing;             // per check entry: facings(rest)
        std::vector<double> rest_cosine, rest_area;  // per check entry: n·Ŝ and |N| at rest (the lift's)
        std::vector<float> margin, floor;            // per check entry: the lift's test as FoldChecks gives it
        // Per vertex v, the entries entries_of_vertex[entry_offsets[v] .. entry_offsets[v + 1]]
        // with v on their triangle or a neighbour.
        std::vector<std::uint32_t> entry_offsets, entries_of_vertex;
        // The affine test's data (see prepare_affine_test): its vertices (the
        // corners of the checked triangles; fit_of[v] indexes them, or kNone) with
        // their stars' sums at rest, and per check entry what its fit keeps from rest.
        std::vector<std::uint32_t> fit_vertices, fit_of;
        std::vector<Vec3> rest_sums;     // per fit vertex: its star's Σ pᵢ at rest
        std::vector<RestFit> rest_fits;  // per check entry
    };
    std::shared_ptr<AtRest> at_rest_ = std::make_shared<AtRest>();
    static constexpr int kParts = 3;  // the checks, the lift's data, the affine test's
    int parts_built_ = kParts;
    std::vector<Vec3> normals_;                  // per triangles entry: unit normals in the last tested positions
    std::vector<std::uint8_t> flags_;            // per check entry: the neighbour test's last result
    std::vector<std::uint8_t> touched_;          // per triangles entry, scratch
    std::vector<std::uint8_t> mark_;             // per vertex, scratch
    std::vector<StarSums> sums_;                 // per fit vertex, now: held until release_scratch()
    std::vector<std::uint8_t> affine_flags_;     // per check entry: the affine test's last result
    std::vector<std::uint8_t> near_;             // per vertex, scratch
    std::vector<std::uint8_t> entry_mark_;       // per check entry, scratch
    // The lift's measures per check entry (neighbour_lift, fit_lift) in the last
    // positions it saw: held between its two runs in a repair.
    std::vector<double> lift_by_neighbours_, lift_by_fit_;
    FoldRepairStats stats_;
    bool acted_ = false;
};

}  // namespace vfsd
