#include "deform/fold_repair.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "base/parallel.h"
#include "base/rigid_fit.h"
#include "mesh/geometry.h"

namespace vfsd {
namespace {

constexpr int kRounds = 20;               // rounds per step: half ring fits, half patch fits
constexpr int kRingIterations = 3;        // Jacobi iterations of the ring fits per round, each a half step
constexpr int kHarmonicIterations = 200;  // Gauss–Seidel iterations of a patch's residual, at most
constexpr double kRegularisation = 1.0;   // of the affine fit toward the rotation, per mean squared radius
constexpr int kGrowth = 3;                // rings around the folded triangles' corners, at most
constexpr double kReach = 1.0;            // the most a vertex moves in a step, in its ring's mean edges
constexpr double kAffineTests = 5.0;      // affine fold tests per unit time
constexpr double kStarWeight = 1e-3;      // of the star fit's normal term, per squared radius
constexpr int kSearchPasses = 4;          // passes of the vertex search over the folded triangles' corners, at most
constexpr double kSearchMargin = 0.05;    // a nearly folded entry: n·Σm below this share of its value at rest
constexpr double kSearchGain = 0.1;       // the least share of its margins' shortfall a search move takes off
constexpr int kSearchScales = 4;          // its moves: 1/64, 1/16, 1/4 and 1 of the vertex's shortest edge,
constexpr int kCentroidParts = 4;         // and 1/4, 1/2, 3/4 and all of the way to its ring's centroid
constexpr std::uint32_t kNone = ~std::uint32_t(0);
constexpr double kLiftMargin = 0.1;      // the lift's target: N·Ŝ ≥ |N| times this share of its cosine at rest
constexpr double kLiftArea = 0.05;       // plus its area at rest times this share of that cosine
constexpr double kLiftSlack = 1e-3;      // the share of the area term an entry may stay short
constexpr int kLiftSweeps = 40;          // Jacobi sweeps of the lift, at most
constexpr double kLiftRelaxation = 0.5;  // of each sweep's summed moves
constexpr double kLiftStep = 0.25;       // the most a vertex moves in a sweep, in its ring's mean edges
constexpr double kLiftSettle = 0.25;     // a lifted vertex settles fully once it moved this many mean edges

// The gradients of N·w, N the area vector of triangle (a, b, c) and w fixed,
// with respect to a, b and c, added to ga, gb and gc.
void add_area_gradient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w, Vec3& ga, Vec3& gb, Vec3& gc) {
    ga += glm::cross(b - c, w), gb += glm::cross(c - a, w), gc += glm::cross(a - b, w);
}

// The gradients of n·w, n the unit normal of triangle (a, b, c) and w fixed,
// with respect to a, b and c, added to ga, gb and gc.
void add_facing_gradient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w, Vec3& ga, Vec3& gb, Vec3& gc) {
    const Vec3 cross = glm::cross(b - a, c - a);
    const double length = glm::length(cross);
    if (!(length > 0.0)) return;
    const Vec3 n = cross / length;
    const Vec3 pw = (w - n * glm::dot(n, w)) / length;
    ga += glm::cross(b - c, pw), gb += glm::cross(c - a, pw), gc += glm::cross(a - b, pw);
}

// The mean of v's ring in x.
Vec3 ring_centroid(const std::vector<Vec3>& x, const VertexRings& rings, std::uint32_t v) {
    Vec3 sum(0.0);
    for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) sum += x[rings.neighbours[k]];
    return rings.end(v) > rings.begin(v) ? sum / double(rings.end(v) - rings.begin(v)) : x[v];
}

// The mean length of v's ring edges in x.
double mean_edge(const std::vector<Vec3>& x, const VertexRings& rings, std::uint32_t v) {
    double sum = 0.0;
    for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) sum += glm::length(x[rings.neighbours[k]] - x[v]);
    return rings.end(v) > rings.begin(v) ? sum / double(rings.end(v) - rings.begin(v)) : 0.0;
}

// The affine map y ↦ to_centre + a (y − from_centre) that best takes `from` to
// `to`, regularised toward their best rotation R:
// Σ |a pᵢ − qᵢ|² + λ |a − R|² → min, pᵢ and qᵢ the points about their centres,
// λ = kRegularisation · mean |pᵢ|². A ring or a patch boundary is nearly flat, so
// its own points leave a's action on the normal free; R fills it in.
struct AffineFit {
    Vec3 from_centre{0.0}, to_centre{0.0};
    glm::dmat3 a{1.0};
    Vec3 apply(const Vec3& y) const { return to_centre + a * (y - from_centre); }
};

AffineFit fit_affine(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
    AffineFit f;
    for (std::size_t i = 0; i < from.size(); ++i) f.from_centre += from[i], f.to_centre += to[i];
    f.from_centre /= double(from.size()), f.to_centre /= double(from.size());
    const glm::dmat3 rotation = fit_rigid(from, to).rotation;
    glm::dmat3 qp(0.0), pp(0.0);
    double radius2 = 0.0;
    for (std::size_t i = 0; i < from.size(); ++i) {
        const Vec3 p = from[i] - f.from_centre, q = to[i] - f.to_centre;
        qp += glm::outerProduct(q, p), pp += glm::outerProduct(p, p), radius2 += glm::dot(p, p);
    }
    const double lambda = kRegularisation * radius2 / double(from.size());
    if (!(lambda > 0.0)) return f;
    f.a = (qp + lambda * rotation) * glm::inverse(pp + lambda * glm::dmat3(1.0));
    return f;
}

}  // namespace

FoldRepair::FoldRepair(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
                       std::vector<std::uint32_t> input_index)
    : FoldRepair(rest, s, rings, std::move(input_index), InParts{}) {
    while (build_part(rings)) continue;
}

bool FoldRepair::build_part(const VertexRings& rings) {
    if (built()) return false;
    if (parts_built_ == 1)
        prepare_lift();
    else
        prepare_affine_test(rings);
    ++parts_built_;
    return true;
}

FoldRepair::FoldRepair(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
                       std::vector<std::uint32_t> input_index, InParts)
    : at_rest_(std::make_shared<AtRest>()), parts_built_(1) {
    at_rest_->rest = rest;
    at_rest_->input_index = std::move(input_index);
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    at_rest_->movable.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) at_rest_->movable[v] = s[v] > 0.0 && s[v] < 1.0;
    // Every triangle needed below has a corner in the blend region or its 1-ring
    // (an edge neighbour's edge neighbour of a triangle with a blend corner still
    // shares a vertex with that corner's ring), so only those are gathered: the
    // cost follows the blend region, not the mesh.
    std::vector<std::uint8_t> near(at_rest_->movable.begin(), at_rest_->movable.end());
    for (std::uint32_t v = 0; v < n; ++v)
        if (at_rest_->movable[v])
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) near[rings.neighbours[k]] = 1;
    std::vector<Triangle> all;
    all.reserve(rings.neighbours.size() / 3 + 1);
    for (std::uint32_t v = 0; v < n; ++v)
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            const std::uint32_t a = rings.neighbours[k], b = rings.neighbours[rings.next(v, k)];
            if (rings.wedge[k] && v < a && v < b && (near[v] || near[a] || near[b]))
                all.push_back(Triangle(v, a, b));  // each once
        }
    const TriangleNeighbours neighbours = triangle_neighbours(all);
    // Checked: the triangles with a blend corner and their edge neighbours (whose
    // mean normal a turned blend triangle can reverse); needed: those and theirs.
    std::vector<std::uint8_t> level(all.size(), 0);  // 3 blend corner, 2 checked, 1 needed
    for (std::size_t t = 0; t < all.size(); ++t)
        if (at_rest_->movable[all[t][0]] || at_rest_->movable[all[t][1]] || at_rest_->movable[all[t][2]]) level[t] = 3;
    for (std::uint8_t lower : {2, 1})
        for (std::size_t t = 0; t < all.size(); ++t)
            if (level[t] > lower)
                for (std::uint32_t k = neighbours.offsets[t]; k < neighbours.offsets[t + 1]; ++k)
                    level[neighbours.list[k]] = std::max(level[neighbours.list[k]], lower);
    std::vector<std::uint32_t> local(all.size(), 0);
    for (std::size_t t = 0; t < all.size(); ++t)
        if (level[t] > 0)
            local[t] = static_cast<std::uint32_t>(at_rest_->triangles.size()), at_rest_->triangles.push_back(all[t]);
    at_rest_->neighbour_offsets.push_back(0);
    for (std::size_t t = 0; t < all.size(); ++t) {
        if (level[t] < 2) continue;
        at_rest_->check.push_back(local[t]);
        for (std::uint32_t k = neighbours.offsets[t]; k < neighbours.offsets[t + 1]; ++k)
            at_rest_->neighbours.push_back(local[neighbours.list[k]]);
        at_rest_->neighbour_offsets.push_back(static_cast<std::uint32_t>(at_rest_->neighbours.size()));
    }
    mark_.assign(n, 0);
    at_rest_->against_at_rest.assign(at_rest_->check.size(), 0);
    for (const std::uint32_t t : folded(at_rest_->rest)) at_rest_->against_at_rest[t] = 1;
    at_rest_->rest_facing = facings(at_rest_->rest);
}

// The lift's data at rest (normals_ at rest): per vertex, the entries whose
// measure its move changes (those with it on their triangle or a neighbour),
// and per entry its cosine and area at rest and its test for the GPU.
void FoldRepair::prepare_lift() {
    const auto n = static_cast<std::uint32_t>(at_rest_->rest.size());
    const std::vector<Vec3>& rest = at_rest_->rest;
    // Each entry's vertices (its triangle's and its neighbours', each once), in
    // two passes: the counts per vertex, then the lists.
    const auto support = [&](std::uint32_t i, std::uint32_t(&out)[12]) {
        int count = 0;
        const auto add = [&](const Triangle& t) {
            for (int c = 0; c < 3; ++c)
                if (std::find(out, out + count, t[c]) == out + count) out[count++] = t[c];
        };
        add(at_rest_->triangles[at_rest_->check[i]]);
        for (std::uint32_t k = at_rest_->neighbour_offsets[i]; k < at_rest_->neighbour_offsets[i + 1]; ++k)
            add(at_rest_->triangles[at_rest_->neighbours[k]]);
        return count;
    };
    std::vector<std::uint32_t>& offsets = at_rest_->entry_offsets;
    offsets.assign(n + 1, 0);
    std::uint32_t vertices[12];
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i)
        for (int k = 0, count = support(i, vertices); k < count; ++k) ++offsets[vertices[k] + 1];
    for (std::uint32_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    at_rest_->entries_of_vertex.resize(offsets[n]);
    std::vector<std::uint32_t> filled(offsets.begin(), offsets.end() - 1);
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i)
        for (int k = 0, count = support(i, vertices); k < count; ++k)
            at_rest_->entries_of_vertex[filled[vertices[k]]++] = i;
    at_rest_->rest_cosine.resize(at_rest_->check.size());
    at_rest_->rest_area.resize(at_rest_->check.size());
    for (std::size_t i = 0; i < at_rest_->check.size(); ++i) {
        const Triangle& t = at_rest_->triangles[at_rest_->check[i]];
        at_rest_->rest_area[i] = glm::length(glm::cross(rest[t[1]] - rest[t[0]], rest[t[2]] - rest[t[0]]));
        const Vec3 sum = neighbour_normal_sum(i);
        const double length = glm::length(sum);
        at_rest_->rest_cosine[i] = length > 0.0 ? glm::dot(normals_[at_rest_->check[i]], sum) / length : 0.0;
    }
    // The same test in floats for the GPU: neighbour_lift < −slack ⇔ N·Ŝ − margin |N| < floor.
    for (std::size_t i = 0; i < at_rest_->check.size(); ++i) {
        const double cosine = at_rest_->rest_cosine[i];
        const bool tested = !at_rest_->against_at_rest[i] && cosine > 0.0;
        at_rest_->margin.push_back(float(kLiftMargin * cosine));
        at_rest_->floor.push_back(tested ? float((1.0 - kLiftSlack) * kLiftArea * cosine * at_rest_->rest_area[i])
                                         : std::numeric_limits<float>::lowest());
    }
}

// Star v's sums in x (about x[v]): its count, Σ yᵢ and Σ yᵢ pᵢᵀ over v and its
// ring, pᵢ = at_rest_->rest[i] − at_rest_->rest[v], yᵢ = x[i] − x[v], and its
// unit normal, vertex_normal's in the same walk: its wedges' cross products
// yᵢ × yᵢ₊₁ summed in the same order (mesh/geometry.cpp, wedge_sum), so the
// same bits.
FoldRepair::StarSums FoldRepair::star_sums(const std::vector<Vec3>& rest, const std::vector<Vec3>& x,
                                           const VertexRings& rings, std::uint32_t v) {
    FoldRepair::StarSums sums;
    const std::uint32_t begin = rings.begin(v), n = rings.end(v) - begin;
    sums.count = double(n + 1);
    if (n == 0) return sums;
    const std::uint32_t* ring = rings.neighbours.data() + begin;
    const std::uint8_t* wedge = rings.wedge.data() + begin;
    const Vec3 centre = x[v], rest_centre = rest[v];
    Vec3 area(0.0), a = x[ring[0]] - centre;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Vec3 b = x[ring[i + 1 == n ? 0 : i + 1]] - centre;
        sums.sum += a, sums.product += glm::outerProduct(a, rest[ring[i]] - rest_centre);
        const bool closed = wedge[i];  // −0 where the wedge is open, as wedge_sum adds
        area.x += closed ? a.y * b.z - b.y * a.z : -0.0;
        area.y += closed ? a.z * b.x - b.z * a.x : -0.0;
        area.z += closed ? a.x * b.y - b.x * a.y : -0.0;
        a = b;
    }
    const double length = glm::length(area);
    sums.normal = length > 0.0 ? area / length : Vec3(0.0);
    return sums;
}

namespace {

// The moments of the three stars of triangle t together (points shared by two
// stars counted twice, as reversed_triangle_list does) about their centres:
// Σ (yᵢ − ȳ)(pᵢ − p̄)ᵀ, from each star's sums now and its Σ pᵢ at rest, moved to
// the origins x[t[0]] and rest[t[0]].
glm::dmat3 joint_moment(const Triangle& t, const std::vector<Vec3>& rest, const std::vector<Vec3>& x,
                        const FoldRepair::StarSums* const star[3], const Vec3* const rest_sum[3]) {
    double count = 0.0;
    Vec3 sum_y(0.0), sum_p(0.0);
    glm::dmat3 product(0.0);
    for (int c = 0; c < 3; ++c) {
        const Vec3 dy = x[t[c]] - x[t[0]], dp = rest[t[c]] - rest[t[0]];
        const FoldRepair::StarSums& now = *star[c];
        product += now.product + glm::outerProduct(now.sum, dp) + glm::outerProduct(dy, *rest_sum[c]) +
                   now.count * glm::outerProduct(dy, dp);
        sum_y += now.sum + now.count * dy, sum_p += *rest_sum[c] + now.count * dp, count += now.count;
    }
    return product - glm::outerProduct(sum_y, sum_p) / count;
}

}  // namespace

// The fit of at_rest_->check entry i's stars minimises Σ |A pᵢ − qᵢ|² + λ |A n − m|² over
// their points about their centres, n the triangle's unit normal at rest, m the
// mean of its corners' star normals now, λ = 10⁻³ Σ |pᵢ|²: the stars are nearly
// flat, their points leave A's action on n free, and the normal term fills it in
// (reversed_triangle_list takes m from the points' best rotation instead). The
// solution A = (Σ qᵢ pᵢᵀ + λ m nᵀ) (Σ pᵢ pᵢᵀ + λ n nᵀ)⁻¹ has its inverse fixed at
// rest, and on flat stars A's action on their plane, all a triangle's image
// needs, is the points' own least squares: any affine map is found exactly.
// The test needs A only on the triangle's edges u and w at rest, so what is
// kept is S u and S w, S the inverse, and their parts along n.
void FoldRepair::prepare_affine_test(const VertexRings& rings) {
    at_rest_->fit_of.assign(at_rest_->rest.size(), kNone);
    for (const std::uint32_t i : at_rest_->check)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = at_rest_->triangles[i][c];
            if (at_rest_->fit_of[v] == kNone)
                at_rest_->fit_of[v] = static_cast<std::uint32_t>(at_rest_->fit_vertices.size()),
                at_rest_->fit_vertices.push_back(v);
        }
    std::vector<StarSums> at_rest(at_rest_->fit_vertices.size());
    parallel_for(at_rest_->fit_vertices.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t j = first; j < last; ++j)
            at_rest[j] = star_sums(at_rest_->rest, at_rest_->rest, rings, at_rest_->fit_vertices[j]);
    });
    for (const StarSums& star : at_rest) at_rest_->rest_sums.push_back(star.sum);
    at_rest_->rest_fits.resize(at_rest_->check.size());
    affine_flags_.assign(at_rest_->check.size(), 0);
    near_.assign(at_rest_->rest.size(), 0);
    parallel_for(at_rest_->check.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const Triangle& t = at_rest_->triangles[at_rest_->check[i]];
            const std::uint32_t j[3] = {at_rest_->fit_of[t[0]], at_rest_->fit_of[t[1]], at_rest_->fit_of[t[2]]};
            const StarSums* stars[3] = {&at_rest[j[0]], &at_rest[j[1]], &at_rest[j[2]]};
            const Vec3* sums[3] = {&at_rest_->rest_sums[j[0]], &at_rest_->rest_sums[j[1]], &at_rest_->rest_sums[j[2]]};
            const glm::dmat3 moment = joint_moment(t, at_rest_->rest, at_rest_->rest, stars, sums);
            const Vec3 area =
                glm::cross(at_rest_->rest[t[1]] - at_rest_->rest[t[0]], at_rest_->rest[t[2]] - at_rest_->rest[t[0]]);
            if (!(glm::length(area) > 0.0)) continue;  // weight 0: a triangle of no area is not tested
            const Vec3 normal = glm::normalize(area);
            const double weight = kStarWeight * (moment[0][0] + moment[1][1] + moment[2][2]);
            const glm::dmat3 regularised = moment + weight * glm::outerProduct(normal, normal);
            if (!(glm::determinant(regularised) != 0.0)) continue;
            const glm::dmat3 inverse = glm::inverse(regularised);
            const Vec3 u = inverse * (at_rest_->rest[t[1]] - at_rest_->rest[t[0]]),
                       w = inverse * (at_rest_->rest[t[2]] - at_rest_->rest[t[0]]);
            at_rest_->rest_fits[i] = {u, w, glm::dot(normal, u), glm::dot(normal, w), weight};
        }
    });
}

namespace {
// Whether a step from `from` to `to` (either way) passes a multiple of 1/per_unit.
bool passes_multiple(double from, double to, double per_unit) {
    const double a = std::min(from, to) * per_unit, b = std::max(from, to) * per_unit;
    return std::floor(b + 1e-9) > std::floor(a + 1e-9);
}
}  // namespace

bool FoldRepair::repair_due(double from, double to) { return passes_multiple(from, to, kRepairTimes); }

bool FoldRepair::affine_test_due(double from, double to) { return passes_multiple(from, to, kAffineTests); }

double FoldRepair::next_repair_time(double time) {
    const double next = (std::floor(time * kRepairTimes + 1e-9) + 1.0) / kRepairTimes;
    return next < 1.0 - 1e-9 ? next : -1.0;
}

double FoldRepair::repair_time_within(double from, double to) {
    const double first = next_repair_time(from);
    return to > from && first > 0.0 && first < to - 1e-9 ? first : -1.0;
}

std::vector<std::uint32_t> FoldRepair::affine_folded(const std::vector<Vec3>& x, const VertexRings& rings) {
    test_affine(x, rings, nullptr);
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i)
        if (affine_flags_[i]) out.push_back(i);
    return out;
}

// The affine test of every at_rest_->check entry into affine_flags_, or with `moved` of
// those a move of these vertices can change: the entries with a corner whose
// star holds one of them. With `fit_measures`, also the lift's measure against
// the fit (fit_lift) of each entry tested, from the same fit. Returns the
// entries tested with `moved`.
std::vector<std::uint32_t> FoldRepair::test_affine(const std::vector<Vec3>& x, const VertexRings& rings,
                                                   const std::vector<std::uint32_t>* moved,
                                                   std::vector<double>* fit_measures) {
    std::vector<std::uint32_t> stars, entries;  // at_rest_->fit_vertices and at_rest_->check positions to test again
    if (moved) {
        for (const std::uint32_t v : *moved) {
            near_[v] = 1;
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) near_[rings.neighbours[k]] = 1;
        }
        for (std::uint32_t j = 0; j < at_rest_->fit_vertices.size(); ++j)
            if (near_[at_rest_->fit_vertices[j]]) stars.push_back(j);
        for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i) {
            const Triangle& t = at_rest_->triangles[at_rest_->check[i]];
            if (near_[t[0]] || near_[t[1]] || near_[t[2]]) entries.push_back(i);
        }
        for (const std::uint32_t j : stars) near_[at_rest_->fit_vertices[j]] = 0;
        for (const std::uint32_t v : *moved) {
            near_[v] = 0;
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) near_[rings.neighbours[k]] = 0;
        }
    }
    if (!moved) sums_.resize(at_rest_->fit_vertices.size());
    const std::size_t star_count = moved ? stars.size() : at_rest_->fit_vertices.size();
    parallel_for(star_count, [&](std::size_t first, std::size_t last) {
        for (std::size_t k = first; k < last; ++k) {
            const std::uint32_t j = moved ? stars[k] : static_cast<std::uint32_t>(k);
            sums_[j] = star_sums(at_rest_->rest, x, rings, at_rest_->fit_vertices[j]);
        }
    });
    const std::size_t entry_count = moved ? entries.size() : at_rest_->check.size();
    parallel_for(entry_count, [&](std::size_t first, std::size_t last) {
        FitLanes lanes;
        std::uint32_t index[kEntryLanes];
        for (std::size_t begin = first; begin < last; begin += kEntryLanes) {
            const int count = static_cast<int>(std::min<std::size_t>(kEntryLanes, last - begin));
            for (int j = 0; j < count; ++j)
                index[j] = moved ? entries[begin + j] : static_cast<std::uint32_t>(begin + j);
            gather_fit(index, count, x, lanes);
            fit_lanes(count, lanes);
            for (int j = 0; j < count; ++j) {
                const std::uint32_t i = index[j];
                const bool tested = at_rest_->rest_fits[i].weight != 0.0;
                const Vec3 fitted = lanes.fitted(j), image = lanes.image(j);
                affine_flags_[i] = tested && glm::dot(fitted, image) <= 0.0;
                if (fit_measures)
                    (*fit_measures)[i] = tested ? fit_lift(i, fitted, image) : std::numeric_limits<double>::infinity();
            }
        }
    });
    return entries;
}

// Whether at_rest_->check entry i's image in x faces against the one its fit gives it.
bool FoldRepair::reversed_by_fit(std::uint32_t i, const std::vector<Vec3>& x) const {
    if (at_rest_->rest_fits[i].weight == 0.0) return false;
    Vec3 fitted, image;
    fit_images(i, x, fitted, image);
    return glm::dot(fitted, image) <= 0.0;
}

// Check entry i's area vector in x, and the one its fit gives it (fit_lanes, one lane).
void FoldRepair::fit_images(std::uint32_t i, const std::vector<Vec3>& x, Vec3& fitted, Vec3& image) const {
    FitLanes lanes;
    gather_fit(&i, 1, x, lanes);
    fit_lanes(1, lanes);
    fitted = lanes.fitted(0), image = lanes.image(0);
}

// What fit_lanes takes of check entries[0 .. count) (count ≤ kEntryLanes), lane j
// for entries[j]: its fit at rest, and per corner c of its triangle the star's
// sums now (with its Σ qᵢ pᵢᵀ applied to S u and S w) and at rest, and the
// corner about corner 0, now (dy) and at rest (dp).
void FoldRepair::gather_fit(const std::uint32_t* entries, int count, const std::vector<Vec3>& x, FitLanes& l) const {
    const AtRest& rest = *at_rest_;
    for (int j = 0; j < count; ++j) {
        const RestFit& fit = rest.rest_fits[entries[j]];
        const Triangle& t = rest.triangles[rest.check[entries[j]]];
        for (int a = 0; a < 3; ++a) l.u[a][j] = fit.u[a], l.w[a][j] = fit.w[a];
        l.u_normal[j] = fit.u_normal, l.w_normal[j] = fit.w_normal, l.weight[j] = fit.weight;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t star = rest.fit_of[t[c]];
            const StarSums& now = sums_[star];
            const Vec3 dy = c == 0 ? Vec3(0.0) : x[t[c]] - x[t[0]];
            const Vec3 dp = c == 0 ? Vec3(0.0) : rest.rest[t[c]] - rest.rest[t[0]];
            // P u and P w here: fewer loads and stores than moving P's nine terms to the lanes.
            const Vec3 pu = now.product * fit.u, pw = now.product * fit.w;
            l.count[c][j] = now.count;
            for (int a = 0; a < 3; ++a) {
                l.sum[c][a][j] = now.sum[a], l.normal[c][a][j] = now.normal[a];
                l.rest_sum[c][a][j] = rest.rest_sums[star][a];
                l.dy[c][a][j] = dy[a], l.dp[c][a][j] = dp[a];
                l.pu[c][a][j] = pu[a], l.pw[c][a][j] = pw[a];
            }
        }
    }
}

namespace {

// a · b in lane j, in glm::dot's order.
[[gnu::always_inline]] inline double lane_dot(const double (&a)[3][FoldRepair::kEntryLanes],
                                              const double (&b)[3][FoldRepair::kEntryLanes], int j) {
    return a[0][j] * b[0][j] + a[1][j] * b[1][j] + a[2][j] * b[2][j];
}

// a × b into lane j of out, in glm::cross's order.
[[gnu::always_inline]] inline void lane_cross(const double (&a)[3], const double (&b)[3],
                                              double (&out)[3][FoldRepair::kEntryLanes], int j) {
    out[0][j] = a[1] * b[2] - b[1] * a[2];
    out[1][j] = a[2] * b[0] - b[2] * a[0];
    out[2][j] = a[0] * b[1] - b[0] * a[1];
}

}  // namespace

// The affine test's images of lanes 0 .. count: A u × A w with A = (J + λ/|m| m nᵀ) S
// (prepare_affine_test), J the stars' joint moment now (joint_moment) applied to
// S u and S w term by term, without forming J:
//   J a = Σ_c (P_c a + σ_c (dp_c·a) + dy_c (ρ_c·a + k_c dp_c·a)) − Σy (Σp·a) / K,
// for a = S u and S w together. Each lane takes glm's operations in glm's
// order (the bits of a loop over Vec3 and dmat3), so that the loop runs in SIMD
// lanes: four doubles with AVX2 (no FMA), two in WebAssembly.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void FoldRepair::fit_lanes(int count, FitLanes& l) {
    for (int j = 0; j < count; ++j) {
        double sum_y[3] = {0.0, 0.0, 0.0}, ju[3] = {0.0, 0.0, 0.0}, jw[3] = {0.0, 0.0, 0.0};
        double stars = 0.0, sum_pu = 0.0, sum_pw = 0.0;
#pragma GCC unroll 3
        for (int c = 0; c < 3; ++c) {
            const double along_u = lane_dot(l.dp[c], l.u, j), along_w = lane_dot(l.dp[c], l.w, j);
            const double rest_u = lane_dot(l.rest_sum[c], l.u, j) + l.count[c][j] * along_u,
                         rest_w = lane_dot(l.rest_sum[c], l.w, j) + l.count[c][j] * along_w;
#pragma GCC unroll 3
            for (int a = 0; a < 3; ++a) {
                ju[a] += l.pu[c][a][j] + l.sum[c][a][j] * along_u + l.dy[c][a][j] * rest_u;
                jw[a] += l.pw[c][a][j] + l.sum[c][a][j] * along_w + l.dy[c][a][j] * rest_w;
                sum_y[a] += l.sum[c][a][j] + l.count[c][j] * l.dy[c][a][j];
            }
            sum_pu += rest_u, sum_pw += rest_w, stars += l.count[c][j];
        }
        const double per_count = 1.0 / stars;
        double turned[3], dy1[3], dy2[3], u[3], w[3];
        for (int a = 0; a < 3; ++a)
            turned[a] = l.normal[0][a][j] + l.normal[1][a][j] + l.normal[2][a][j], dy1[a] = l.dy[1][a][j],
            dy2[a] = l.dy[2][a][j];
        const double length = std::sqrt(turned[0] * turned[0] + turned[1] * turned[1] + turned[2] * turned[2]);
        const bool positive = length > 0.0;
        const double scale = l.weight[j] / (positive ? length : 1.0);  // no division by zero in lanes not taken
        for (int a = 0; a < 3; ++a) {
            const double normal_term = positive ? turned[a] * scale : 0.0;
            u[a] = ju[a] - sum_y[a] * (sum_pu * per_count) + normal_term * l.u_normal[j];
            w[a] = jw[a] - sum_y[a] * (sum_pw * per_count) + normal_term * l.w_normal[j];
        }
        lane_cross(dy1, dy2, l.image_lanes, j);
        lane_cross(u, w, l.fitted_lanes, j);
    }
}

// The entries folded by the neighbour test (`neighbour` of them), and by the
// affine test when asked: all of them, or with `moved` those near the moved
// vertices (the others keep their last result).
std::vector<std::uint32_t> FoldRepair::folded(const std::vector<Vec3>& x, const VertexRings& rings, bool affine_test,
                                              const std::vector<std::uint32_t>* moved, std::size_t& neighbour) {
    std::vector<std::uint32_t> out = folded(x, moved);
    neighbour = out.size();
    if (!affine_test) return out;
    test_affine(x, rings, moved);
    return with_affine(out);
}

// The same as folded(x, rings, affine_test, nullptr, neighbour) right after
// lift(x, rings, affine_test), which left normals_ and flags_ (and with the
// affine test, sums_ and affine_flags_) fresh for x.
std::vector<std::uint32_t> FoldRepair::folded_as_lifted(bool affine_test, std::size_t& neighbour) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i)
        if (flags_[i]) out.push_back(i);
    neighbour = out.size();
    return affine_test ? with_affine(out) : out;
}

// The entries in `by_neighbours` (ascending) or flagged by the affine test.
std::vector<std::uint32_t> FoldRepair::with_affine(const std::vector<std::uint32_t>& out) const {
    std::vector<std::uint32_t> both;
    std::size_t k = 0;
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i) {
        const bool by_neighbours = k < out.size() && out[k] == i;
        k += by_neighbours;
        if (by_neighbours || affine_flags_[i]) both.push_back(i);
    }
    return both;
}

std::size_t FoldRepair::count_folds(const std::vector<Vec3>& x, const VertexRings& rings, bool affine_test,
                                    bool keep_measures) {
    if (!active()) return 0;
    measure_lift(x, rings, affine_test, keep_measures);
    return count_short(affine_test);
}

std::size_t FoldRepair::count_folds_with_affine(const std::vector<Vec3>& x, const VertexRings& rings) {
    if (!active()) return 0;
    // measure_lift(x, rings, true, true)'s affine part, after its neighbour part.
    lift_by_fit_.assign(at_rest_->check.size(), std::numeric_limits<double>::infinity());
    test_affine(x, rings, nullptr, &lift_by_fit_);
    return count_short(true);
}

// The entries short of the lift's target by the measures measure_lift left
// (with `affine_test`, by either).
std::size_t FoldRepair::count_short(bool affine_test) const {
    std::vector<std::uint8_t> short_of(at_rest_->check.size());
    parallel_for(short_of.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i)
            short_of[i] = short_of_target(i, lift_by_neighbours_[i],
                                          affine_test ? lift_by_fit_[i] : std::numeric_limits<double>::infinity());
    });
    return std::size_t(std::count(short_of.begin(), short_of.end(), std::uint8_t(1)));
}

// The lift's measures of every check entry in x (neighbour_lift into
// lift_by_neighbours_, and with `affine_test` fit_lift into lift_by_fit_), with
// the affine test's sums and flags, and with `flags` the neighbour test's (what
// a repair needs besides).
void FoldRepair::measure_lift(const std::vector<Vec3>& x, const VertexRings& rings, bool affine_test, bool flags) {
    const std::size_t n = at_rest_->check.size();
    take_normals(x);
    lift_by_neighbours_.resize(n);
    if (flags) flags_.resize(n);
    parallel_for(n, [&](std::size_t first, std::size_t last) {
        NeighbourLanes lanes;
        for (std::size_t begin = first; begin < last; begin += kEntryLanes) {
            const int count = static_cast<int>(std::min<std::size_t>(kEntryLanes, last - begin));
            for (int j = 0; j < count; ++j) {
                const Vec3 sum = neighbour_normal_sum(begin + j);
                gather_neighbour_lift(begin + j, x, sum, lanes, j);
                if (flags) flags_[begin + j] = faces_against(begin + j, sum);
            }
            neighbour_lift_lanes(count, lanes);
            std::copy_n(lanes.lift, count, lift_by_neighbours_.begin() + static_cast<std::ptrdiff_t>(begin));
        }
    });
    lift_by_fit_.assign(affine_test ? n : 0, std::numeric_limits<double>::infinity());
    if (affine_test) test_affine(x, rings, nullptr, &lift_by_fit_);
}

// The at_rest_->check entries (positions in at_rest_->check) whose triangle faces against the mean
// normal of its edge neighbours in x and did not at rest. With `moved`, x differs
// from the positions of the last call only at those vertices (as in a repair's
// rounds): only the triangles with a moved corner take their normals again, and
// only the entries of those triangles or bordering them are tested again; the
// others keep their flags. The same bits as testing every entry.
std::vector<std::uint32_t> FoldRepair::folded(const std::vector<Vec3>& x, const std::vector<std::uint32_t>* moved) {
    const AtRest& rest = *at_rest_;
    if (!moved || normals_.size() != rest.triangles.size() || flags_.size() != rest.check.size()) {
        normals_.resize(rest.triangles.size());
        parallel_for(rest.triangles.size(), [&](std::size_t first, std::size_t last) {
            unit_normals(x, rest.triangles, first, last, normals_);
        });
        flags_.resize(rest.check.size());
        parallel_for(rest.check.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i < last; ++i) flags_[i] = faces_against_neighbours(i);
        });
    } else {
        for (const std::uint32_t v : *moved) near_[v] = 1;
        touched_.resize(rest.triangles.size());
        parallel_for(rest.triangles.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t t = first; t < last; ++t) {
                const Triangle& triangle = rest.triangles[t];
                touched_[t] = near_[triangle[0]] | near_[triangle[1]] | near_[triangle[2]];
                if (touched_[t]) normals_[t] = unit_normal(x, triangle);
            }
        });
        for (const std::uint32_t v : *moved) near_[v] = 0;
        parallel_for(rest.check.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i < last; ++i) {
                bool touched = touched_[rest.check[i]];
                for (std::uint32_t k = rest.neighbour_offsets[i]; k < rest.neighbour_offsets[i + 1] && !touched; ++k)
                    touched = touched_[rest.neighbours[k]];
                if (touched) flags_[i] = faces_against_neighbours(i);
            }
        });
    }
    // The flagged entries, eight flags at a time: on most steps none is set, and
    // this runs on one thread.
    std::vector<std::uint32_t> out;
    const std::size_t n = rest.check.size();
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, flags_.data() + i, sizeof word);
        if (word == 0) continue;
        for (std::size_t k = i; k < i + 8; ++k)
            if (flags_[k]) out.push_back(static_cast<std::uint32_t>(k));
    }
    for (; i < n; ++i)
        if (flags_[i]) out.push_back(static_cast<std::uint32_t>(i));
    return out;
}

// Whether at_rest_->check entry i's triangle faces against the sum of its
// neighbours' unit normals in normals_, and did not at rest.
bool FoldRepair::faces_against_neighbours(std::size_t i) const { return faces_against(i, neighbour_normal_sum(i)); }

// The same with that sum given (neighbour_normal_sum).
bool FoldRepair::faces_against(std::size_t i, const Vec3& sum) const {
    const AtRest& rest = *at_rest_;
    if (rest.against_at_rest[i] || rest.neighbour_offsets[i] == rest.neighbour_offsets[i + 1]) return false;
    const Vec3& n = normals_[rest.check[i]];
    return n.x * sum.x + n.y * sum.y + n.z * sum.z < 0.0;
}

// Every triangle's unit normal in x, into normals_.
void FoldRepair::take_normals(const std::vector<Vec3>& x) {
    normals_.resize(at_rest_->triangles.size());
    parallel_for(at_rest_->triangles.size(), [&](std::size_t first, std::size_t last) {
        unit_normals(x, at_rest_->triangles, first, last, normals_);
    });
}

// Per at_rest_->check entry, n·Σm in x: its triangle's unit normal against the sum of
// its neighbours' (as folded(x) tests it; 0 without neighbours).
std::vector<float> FoldRepair::facings(const std::vector<Vec3>& x) {
    take_normals(x);
    std::vector<float> out(at_rest_->check.size());
    parallel_for(at_rest_->check.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            Vec3 mean(0.0);
            for (std::uint32_t k = at_rest_->neighbour_offsets[i]; k < at_rest_->neighbour_offsets[i + 1]; ++k)
                mean += normals_[at_rest_->neighbours[k]];
            out[i] = float(glm::dot(normals_[at_rest_->check[i]], mean));
        }
    });
    return out;
}

// The blend corners of the folded triangles and the blend vertices up to
// `rings_out` rings around them, marked in mark_.
std::vector<std::uint32_t> FoldRepair::vertices_to_move(const std::vector<std::uint32_t>& folded, int rings_out,
                                                        const VertexRings& rings) {
    std::vector<std::uint32_t> out;
    const auto take = [&](std::uint32_t v) {
        if (at_rest_->movable[v] && !mark_[v]) mark_[v] = 1, out.push_back(v);
    };
    for (const std::uint32_t i : folded)
        for (int c = 0; c < 3; ++c) take(at_rest_->triangles[at_rest_->check[i]][c]);
    for (int r = 0; r < rings_out; ++r) {
        const std::size_t count = out.size();
        for (std::size_t i = 0; i < count; ++i)
            for (std::uint32_t k = rings.begin(out[i]); k < rings.end(out[i]); ++k) take(rings.neighbours[k]);
    }
    return out;
}

// Step 1: every vertex halfway toward its ring's affine image of its rest position
// (with `weights`, each by its weight times half: the lift's settling).
void FoldRepair::refit_rings(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x, const VertexRings& rings,
                             const std::vector<double>* weights) const {
    std::vector<Vec3> from, to, moved(vertices.size());
    for (int iteration = 0; iteration < kRingIterations; ++iteration) {
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            const std::uint32_t v = vertices[i];
            from.clear(), to.clear();
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
                from.push_back(at_rest_->rest[rings.neighbours[k]]), to.push_back(x[rings.neighbours[k]]);
            const double share = weights ? 0.5 * (*weights)[i] : 0.5;
            moved[i] = x[v] + share * (fit_affine(from, to).apply(at_rest_->rest[v]) - x[v]);
        }
        for (std::size_t i = 0; i < vertices.size(); ++i) x[vertices[i]] = moved[i];
    }
}

// Step 2: per connected patch of marked vertices, the affine map fitted to the
// patch's boundary plus the harmonic interpolant of the boundary's residuals.
void FoldRepair::refit_patches(const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& x,
                               const VertexRings& rings) {
    std::vector<std::uint8_t> seen(x.size(), 0);
    for (const std::uint32_t seed : vertices) {
        if (seen[seed]) continue;
        std::vector<std::uint32_t> patch{seed}, boundary;
        seen[seed] = 1;
        for (std::size_t i = 0; i < patch.size(); ++i)
            for (std::uint32_t k = rings.begin(patch[i]); k < rings.end(patch[i]); ++k) {
                const std::uint32_t y = rings.neighbours[k];
                if (seen[y]) continue;
                seen[y] = 1;
                (mark_[y] ? patch : boundary).push_back(y);
            }
        for (const std::uint32_t b : boundary) seen[b] = 0;  // a boundary vertex may border another patch
        std::vector<Vec3> from, to;
        for (const std::uint32_t b : boundary) from.push_back(at_rest_->rest[b]), to.push_back(x[b]);
        if (from.empty()) continue;
        const AffineFit fit = fit_affine(from, to);
        double size2 = 0.0;
        for (const Vec3& p : from) size2 += glm::dot(p - fit.from_centre, p - fit.from_centre);
        const double tolerance = 1e-12 * std::sqrt(size2 / double(from.size()));
        for (const std::uint32_t v : patch) x[v] = fit.apply(at_rest_->rest[v]);
        for (int iteration = 0; iteration < kHarmonicIterations; ++iteration) {
            double change = 0.0;
            for (const std::uint32_t v : patch) {
                Vec3 residual(0.0);  // the ring's mean of x − A(rest)
                for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                    const std::uint32_t y = rings.neighbours[k];
                    residual += x[y] - fit.apply(at_rest_->rest[y]);
                }
                const Vec3 next = fit.apply(at_rest_->rest[v]) + residual / double(rings.end(v) - rings.begin(v));
                change = std::max(change, glm::length(next - x[v]));
                x[v] = next;
            }
            if (change <= tolerance) break;
        }
    }
}

namespace {

// A vertex search move's score: the entries it leaves folded by either test
// (and by the neighbour test alone), how far short of their margins
// (Σ max(0, m − n·Σm)), the move's size, and the least n·Σm; `against` orders
// two (−1 better, 0 as good to rounding).
struct SearchScore {
    static constexpr double kRounding = 1e-9;
    std::size_t folded = 0, neighbour = 0;
    double short_of = 0.0;
    int scale = 0;
    double least = std::numeric_limits<double>::max();
    // Whether a move to this is worth taking from `here`: it folds none more by
    // the neighbour test, and fewer by either test, or as many but a tenth or
    // more less short of the margins (a smaller gain is taken by rounding as
    // readily as by the geometry: it made a scene placed 3e9 of its diagonals
    // from the origin, whose input carries 3e-7 of noise, differ by 1e-4 D).
    bool gains_on(const SearchScore& here) const {
        if (neighbour > here.neighbour) return false;
        return folded < here.folded || (folded == here.folded && short_of < (1.0 - kSearchGain) * here.short_of);
    }
    int against(const SearchScore& o) const {
        if (folded != o.folded) return folded < o.folded ? -1 : 1;
        if (std::abs(short_of - o.short_of) > kRounding) return short_of < o.short_of ? -1 : 1;
        if (scale != o.scale) return scale < o.scale ? -1 : 1;
        if (std::abs(least - o.least) > kRounding) return least > o.least ? -1 : 1;
        return 0;
    }
};

}  // namespace

// Step 3, what the fits could not untangle: the blend corners of the folded and
// nearly folded entries (n·Σm below kSearchMargin of its value at rest, or
// reversed by the affine test after a step it runs after), one at a time in the
// input's vertex order, try moves along their star's normal and toward and away
// from each neighbour in the star's plane (a set that turns and mirrors with the
// mesh) of 1/64, 1/16, 1/4 and 1 of their shortest edge, and where none of
// those gains, toward their ring's centroid by 1/4 to all of the way (a corner
// pushed through its fan further than that: docs/method.md, "Moves toward the
// ring's centroid"). A vertex moves only to leave fewer entries about it folded
// by either test (the affine one's sums taken here between the steps it runs
// after), or as many but a tenth less short of the margins, and never more by
// the neighbour test; of such moves it takes the one that leaves the fewest,
// then the least short of the margins, then the smallest, then the widest least
// margin. A needle's corner has to move by the needle's tiny height, which no
// ring's or patch's fit resolves.
std::vector<std::uint32_t> FoldRepair::search_vertices(const std::vector<std::uint32_t>& near_folded,
                                                       std::vector<Vec3>& x, const VertexRings& rings, bool affine_test,
                                                       std::vector<std::pair<std::uint32_t, Vec3>>& undo) {
    std::vector<std::uint32_t> vertices;
    for (const std::uint32_t i : near_folded)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = at_rest_->triangles[at_rest_->check[i]][c];
            if (at_rest_->movable[v] && !mark_[v]) mark_[v] = 1, vertices.push_back(v);
        }
    // The input's order: no turn or mirror image of the mesh changes it (the
    // order of at_rest_->check follows the triangles' winding, the steps' order the rings).
    std::sort(vertices.begin(), vertices.end(), [&](std::uint32_t a, std::uint32_t b) {
        return at_rest_->input_index.empty() ? a < b : at_rest_->input_index[a] < at_rest_->input_index[b];
    });
    // The entries a move of v can change: by the neighbour test those with v a
    // corner of their triangle or of a neighbour's (entries_of[v]); by the affine
    // test those with a corner u whose star holds v (entries_at[u], u = v or in
    // its ring, which near_ marks).
    for (const std::uint32_t v : vertices)
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) near_[rings.neighbours[k]] = 1;
    std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> entries_of, entries_at;
    const auto add = [](std::vector<std::uint32_t>& list, std::uint32_t i) {
        if (list.empty() || list.back() != i) list.push_back(i);
    };
    for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i) {
        const Triangle& t = at_rest_->triangles[at_rest_->check[i]];
        for (int c = 0; c < 3; ++c) {
            if (mark_[t[c]]) add(entries_of[t[c]], i);
            if (mark_[t[c]] || near_[t[c]]) add(entries_at[t[c]], i);
        }
        for (std::uint32_t k = at_rest_->neighbour_offsets[i]; k < at_rest_->neighbour_offsets[i + 1]; ++k)
            for (int c = 0; c < 3; ++c)
                if (mark_[at_rest_->triangles[at_rest_->neighbours[k]][c]])
                    add(entries_of[at_rest_->triangles[at_rest_->neighbours[k]][c]], i);
    }
    for (const std::uint32_t v : vertices) {
        mark_[v] = 0;
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) near_[rings.neighbours[k]] = 0;
    }
    if (!affine_test) {  // the sums of every star the affine test of those entries reads
        sums_.resize(at_rest_->fit_vertices.size());
        std::vector<std::uint32_t> needed;
        for (const auto& [u, list] : entries_at)
            for (const std::uint32_t i : list)
                for (int c = 0; c < 3; ++c)
                    needed.push_back(at_rest_->fit_of[at_rest_->triangles[at_rest_->check[i]][c]]);
        std::sort(needed.begin(), needed.end());
        needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
        for (const std::uint32_t j : needed) sums_[j] = star_sums(at_rest_->rest, x, rings, at_rest_->fit_vertices[j]);
    }
    std::vector<std::uint32_t> moved, entries, stars;
    std::vector<Vec3> directions, ties;
    for (const std::uint32_t v : vertices) {
        entries = entries_of[v];
        stars.clear();
        for (std::uint32_t k = rings.begin(v); k <= rings.end(v); ++k) {
            const std::uint32_t u = k < rings.end(v) ? rings.neighbours[k] : v;
            if (at_rest_->fit_of[u] != kNone) stars.push_back(at_rest_->fit_of[u]);
            const std::vector<std::uint32_t>& at = entries_at[u];
            entries.insert(entries.end(), at.begin(), at.end());
        }
        std::sort(entries.begin(), entries.end());
        entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
        const auto score = [&](int scale) {
            for (const std::uint32_t j : stars)
                sums_[j] = star_sums(at_rest_->rest, x, rings, at_rest_->fit_vertices[j]);
            SearchScore out;
            out.scale = scale;
            for (const std::uint32_t i : entries) {
                double facing = 1.0;
                if (!at_rest_->against_at_rest[i] &&
                    at_rest_->neighbour_offsets[i] < at_rest_->neighbour_offsets[i + 1]) {
                    Vec3 mean(0.0);
                    for (std::uint32_t k = at_rest_->neighbour_offsets[i]; k < at_rest_->neighbour_offsets[i + 1]; ++k)
                        mean += unit_normal(x, at_rest_->triangles[at_rest_->neighbours[k]]);
                    facing = glm::dot(unit_normal(x, at_rest_->triangles[at_rest_->check[i]]), mean);
                    out.least = std::min(out.least, facing);
                    out.short_of += std::max(0.0, kSearchMargin * double(at_rest_->rest_facing[i]) - facing);
                }
                out.neighbour += facing < 0.0;
                out.folded += facing < 0.0 || reversed_by_fit(i, x);
            }
            return out;
        };
        const Vec3 normal = vertex_normal(x, rings, v);
        double shortest = std::numeric_limits<double>::max();
        directions.clear();
        if (glm::dot(normal, normal) > 0.0) directions = {normal, -normal};
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            const Vec3 edge = x[rings.neighbours[k]] - x[v];
            shortest = std::min(shortest, glm::length(edge));
            const Vec3 along = edge - glm::dot(edge, normal) * normal;
            if (glm::length(along) > 0.0)
                directions.push_back(glm::normalize(along)), directions.push_back(-directions.back());
        }
        if (!(shortest > 0.0)) continue;
        const Vec3 from = x[v];
        const SearchScore here = score(0);
        SearchScore best = here;
        ties.assign(1, from);
        const auto consider = [&](const SearchScore& candidate) {  // the move to x[v]
            if (!candidate.gains_on(here)) return;
            const int order = candidate.against(best);
            if (order < 0) best = candidate, ties.assign(1, x[v]);
            if (order == 0) ties.push_back(x[v]);
        };
        for (int scale = 1; scale <= kSearchScales; ++scale)
            for (const Vec3& d : directions) {
                x[v] = from + std::ldexp(shortest, 2 * (scale - kSearchScales)) * d;
                consider(score(scale));
            }
        // Where none of those gains: toward the ring's centroid, a quarter to all
        // of the way (a corner pushed through its fan by more than its shortest
        // edge).
        if (ties.front() == from) {
            const Vec3 centroid = ring_centroid(x, rings, v);
            for (int part = 1; part <= kCentroidParts; ++part) {
                x[v] = from + (double(part) / kCentroidParts) * (centroid - from);
                consider(score(kSearchScales + 1));
            }
        }
        // Moves as good as each other to rounding (mirror images in a symmetric
        // star): their mean if it does as well, else none, so that rounding
        // does not choose.
        Vec3 kept = ties.front();
        if (ties.size() > 1) {
            Vec3 mean(0.0);
            for (const Vec3& p : ties) mean += p;
            x[v] = mean / double(ties.size());
            const SearchScore at_mean = score(best.scale);
            const bool as_good = at_mean.folded <= best.folded && at_mean.neighbour <= here.neighbour &&
                                 at_mean.short_of <= best.short_of + SearchScore::kRounding;
            kept = as_good ? x[v] : from;
        }
        x[v] = kept;
        score(0);  // the stars' sums where it stays
        if (kept != from) moved.push_back(v), undo.emplace_back(v, from);
    }
    return moved;
}

// The sum of check entry i's neighbours' unit normals in normals_. Inlined,
// as gather_neighbour_lift below, into measure_lift's loop over every checked
// entry: a call per entry there was 4 % of the fold repair's instructions on
// the claw's edits (docs/benchmarks.md, "The smoothing's rings in bytes").
[[gnu::always_inline]] inline Vec3 FoldRepair::neighbour_normal_sum(std::size_t i) const {
    const AtRest& rest = *at_rest_;
    Vec3 sum(0.0);
    for (std::uint32_t k = rest.neighbour_offsets[i]; k < rest.neighbour_offsets[i + 1]; ++k)
        sum += normals_[rest.neighbours[k]];
    return sum;
}

// The lift's measure of check entry i against its neighbours (normals_ for
// theirs; neighbour_lift_lanes, one lane). `sum` is neighbour_normal_sum(i).
double FoldRepair::neighbour_lift(std::size_t i, const std::vector<Vec3>& x, const Vec3& sum) const {
    NeighbourLanes lanes;
    gather_neighbour_lift(i, x, sum, lanes, 0);
    neighbour_lift_lanes(1, lanes);
    return lanes.lift[0];
}

// Lane j of `lanes` for check entry i: its area vector in x, `sum` and its measures at rest.
[[gnu::always_inline]] inline void FoldRepair::gather_neighbour_lift(std::size_t i, const std::vector<Vec3>& x,
                                                                     const Vec3& sum, NeighbourLanes& l, int j) const {
    const AtRest& rest = *at_rest_;
    const Triangle& t = rest.triangles[rest.check[i]];
    const Vec3 area = glm::cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
    for (int a = 0; a < 3; ++a) l.sum[a][j] = sum[a], l.area[a][j] = area[a];
    l.cosine[j] = rest.rest_cosine[i], l.rest_area[j] = rest.rest_area[i];
    l.tested[j] = !rest.against_at_rest[i] && rest.rest_cosine[i] > 0.0 ? 1.0 : 0.0;
}

// The lift's measure against the neighbours in lanes 0 .. count:
// N·Ŝ − c (kLiftMargin |N| + kLiftArea A), N the triangle's area vector in x, Ŝ
// the unit sum of its neighbours' normals, c its cosine n·Ŝ at rest and A its
// area at rest; +inf where not tested (facing against its neighbours at rest,
// or not toward them) or where the sum is 0. Below 0 it is short of its
// target. It is linear in each corner and, unlike n·Ŝ, steep for a corner
// pushed through its triangle's base: the lift moves it back across. In SIMD
// lanes, each in glm's order of operations.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void FoldRepair::neighbour_lift_lanes(int count, NeighbourLanes& l) {
    for (int j = 0; j < count; ++j) {
        const double length =
            std::sqrt(l.sum[0][j] * l.sum[0][j] + l.sum[1][j] * l.sum[1][j] + l.sum[2][j] * l.sum[2][j]);
        const double area =
            std::sqrt(l.area[0][j] * l.area[0][j] + l.area[1][j] * l.area[1][j] + l.area[2][j] * l.area[2][j]);
        const bool taken = l.tested[j] != 0.0 && length > 0.0;
        const double along = l.area[0][j] * l.sum[0][j] + l.area[1][j] * l.sum[1][j] + l.area[2][j] * l.sum[2][j];
        const double lift =
            along / (taken ? length : 1.0) - l.cosine[j] * (kLiftMargin * area + kLiftArea * l.rest_area[j]);
        l.lift[j] = taken ? lift : std::numeric_limits<double>::infinity();
    }
}

// The same against the image its affine fit gives it (`fitted`, with `image`
// its area vector, from fit_images): N·F̂ − kLiftMargin |N| − kLiftArea A;
// +inf where the fit has no area.
double FoldRepair::fit_lift(std::size_t i, const Vec3& fitted, const Vec3& image) const {
    const double length = glm::length(fitted);
    if (!(length > 0.0)) return std::numeric_limits<double>::infinity();
    return glm::dot(image, fitted) / length - kLiftMargin * glm::length(image) - kLiftArea * at_rest_->rest_area[i];
}

// Whether check entry i, with these measures, is short of the lift's targets by
// more than the slack: what the lift and count_folds act on.
bool FoldRepair::short_of_target(std::size_t i, double by_neighbours, double by_fit) const {
    const double slack = kLiftSlack * kLiftArea * at_rest_->rest_area[i];
    return by_neighbours < -slack * at_rest_->rest_cosine[i] || by_fit < -slack;
}

// Normals and the lift's measures again where `moved` moved: returns the
// entries about those vertices (ascending), whose measures were taken again.
std::vector<std::uint32_t> FoldRepair::refresh_lift(const std::vector<Vec3>& x, const VertexRings& rings,
                                                    const std::vector<std::uint32_t>& moved, bool affine_test) {
    const AtRest& rest = *at_rest_;
    std::vector<std::uint32_t> again;
    for (const std::uint32_t v : moved)
        for (std::uint32_t k = rest.entry_offsets[v]; k < rest.entry_offsets[v + 1]; ++k)
            if (!entry_mark_[rest.entries_of_vertex[k]])
                entry_mark_[rest.entries_of_vertex[k]] = 1, again.push_back(rest.entries_of_vertex[k]);
    for (const std::uint32_t i : again) {
        entry_mark_[i] = 0;
        normals_[rest.check[i]] = unit_normal(x, rest.triangles[rest.check[i]]);
        for (std::uint32_t k = rest.neighbour_offsets[i]; k < rest.neighbour_offsets[i + 1]; ++k)
            normals_[rest.neighbours[k]] = unit_normal(x, rest.triangles[rest.neighbours[k]]);
    }
    for (const std::uint32_t i : again) {
        const Vec3 sum = neighbour_normal_sum(i);
        lift_by_neighbours_[i] = neighbour_lift(i, x, sum), flags_[i] = faces_against(i, sum);
    }
    if (affine_test)
        for (const std::uint32_t i : test_affine(x, rings, &moved, &lift_by_fit_)) again.push_back(i);
    std::sort(again.begin(), again.end());
    again.erase(std::unique(again.begin(), again.end()), again.end());
    return again;
}

// Adds to `sum` the lift's moves for check entry i, short of a target: for each
// measure below 0, −value / |∇|² ∇ over the movable vertices, ∇ its gradient.
void FoldRepair::add_lift_moves(std::uint32_t i, const std::vector<Vec3>& x, bool affine_test,
                                std::unordered_map<std::uint32_t, Vec3>& sum) const {
    const AtRest& rest = *at_rest_;
    const Triangle& t = rest.triangles[rest.check[i]];
    std::uint32_t vertex[12];
    Vec3 gradient[12];
    int count = 0;
    const auto slot = [&](std::uint32_t v) -> Vec3& {
        for (int k = 0; k < count; ++k)
            if (vertex[k] == v) return gradient[k];
        vertex[count] = v, gradient[count] = Vec3(0.0);
        return gradient[count++];
    };
    // Adds −value / |∇|² ∇ over the movable vertices, the gradient in `gradient`.
    const auto project = [&](double value) {
        double norm2 = 0.0;
        for (int k = 0; k < count; ++k)
            if (rest.movable[vertex[k]]) norm2 += glm::dot(gradient[k], gradient[k]);
        if (!(norm2 > 0.0)) return;
        for (int k = 0; k < count; ++k)
            if (rest.movable[vertex[k]]) sum[vertex[k]] -= (value / norm2) * gradient[k];
    };
    const Vec3 area = glm::cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
    const double area_length = glm::length(area);
    const Vec3 normal = area_length > 0.0 ? area / area_length : Vec3(0.0);
    if (lift_by_neighbours_[i] < 0.0) {
        const Vec3 s = neighbour_normal_sum(i);
        const double length = glm::length(s);
        const Vec3 unit = s / length;
        add_area_gradient(x[t[0]], x[t[1]], x[t[2]], unit - (kLiftMargin * rest.rest_cosine[i]) * normal, slot(t[0]),
                          slot(t[1]), slot(t[2]));
        // Through Ŝ: d(N·Ŝ) = (N − (N·Ŝ)Ŝ)/|S| · Σ dm.
        const Vec3 w = (area - unit * glm::dot(unit, area)) / length;
        for (std::uint32_t k = rest.neighbour_offsets[i]; k < rest.neighbour_offsets[i + 1]; ++k) {
            const Triangle& o = rest.triangles[rest.neighbours[k]];
            Vec3 &g0 = slot(o[0]), &g1 = slot(o[1]), &g2 = slot(o[2]);
            add_facing_gradient(x[o[0]], x[o[1]], x[o[2]], w, g0, g1, g2);
        }
        project(lift_by_neighbours_[i]);
    }
    if (affine_test && lift_by_fit_[i] < 0.0) {
        count = 0;
        Vec3 fitted, image;
        fit_images(i, x, fitted, image);
        add_area_gradient(x[t[0]], x[t[1]], x[t[2]], glm::normalize(fitted) - kLiftMargin * normal, slot(t[0]),
                          slot(t[1]), slot(t[2]));
        project(lift_by_fit_[i]);
    }
}

// Step 0, the lift: Jacobi sweeps of a projection of each entry short of its
// targets (neighbour_lift ≥ 0 and, with the affine test, fit_lift ≥ 0) toward
// them along the gradient. Each sweep's moves are continuous in x, so two runs
// that reach a repair time a little apart leave it a little apart. With
// `moved_since`, x differs from where the last lift left it only at those
// vertices. Returns the vertices it moved, each with where it started.
std::vector<std::pair<std::uint32_t, Vec3>> FoldRepair::lift(std::vector<Vec3>& x, const VertexRings& rings,
                                                             bool affine_test,
                                                             const std::vector<std::uint32_t>* moved_since,
                                                             bool measured) {
    const AtRest& rest = *at_rest_;
    const std::size_t n = rest.check.size();
    std::vector<double>& by_neighbours = lift_by_neighbours_;
    std::vector<double>& by_fit = lift_by_fit_;
    entry_mark_.resize(n, 0);  // refresh_lift leaves it all 0
    if (moved_since)
        refresh_lift(x, rings, *moved_since, affine_test);
    else if (!measured)
        measure_lift(x, rings, affine_test, true);
    const auto is_low = [&](std::size_t i) {
        return short_of_target(i, by_neighbours[i], affine_test ? by_fit[i] : std::numeric_limits<double>::infinity());
    };
    std::vector<std::uint32_t> low;
    for (std::uint32_t i = 0; i < n; ++i)
        if (is_low(i)) low.push_back(i);
    std::vector<std::uint32_t> moved_all, moved;
    std::unordered_map<std::uint32_t, Vec3> sum;
    std::unordered_map<std::uint32_t, std::pair<Vec3, double>> start;
    for (int sweep = 0; sweep < kLiftSweeps && !low.empty(); ++sweep) {
        sum.clear();
        for (const std::uint32_t i : low) add_lift_moves(i, x, affine_test, sum);
        moved.clear();
        for (const auto& entry : sum) moved.push_back(entry.first);
        std::sort(moved.begin(), moved.end());
        if (moved.empty()) break;
        std::vector<Vec3> step(moved.size());
        for (std::size_t k = 0; k < moved.size(); ++k) {
            step[k] = kLiftRelaxation * sum.at(moved[k]);
            const double length = glm::length(step[k]);
            const double reach = kLiftStep * mean_edge(x, rings, moved[k]);
            if (length > reach) step[k] *= reach / length;
        }
        for (std::size_t k = 0; k < moved.size(); ++k) {
            const std::uint32_t v = moved[k];
            if (!mark_[v])
                mark_[v] = 2, moved_all.push_back(v),
                start.emplace(v, std::make_pair(x[v], kReach * mean_edge(x, rings, v)));
            const auto& [from, reach] = start.at(v);
            x[v] += step[k];
            const Vec3 move = x[v] - from;  // no further than the discrete repair's reach from where it started
            const double length = glm::length(move);
            if (length > reach) x[v] = from + (reach / length) * move;
        }
        // The low entries and those whose measures the moves changed.
        const std::vector<std::uint32_t> again = refresh_lift(x, rings, moved, affine_test);
        std::vector<std::uint32_t> candidates;
        std::set_union(low.begin(), low.end(), again.begin(), again.end(), std::back_inserter(candidates));
        low.clear();
        for (const std::uint32_t i : candidates)
            if (is_low(i)) low.push_back(i);
    }
    std::sort(moved_all.begin(), moved_all.end());
    std::vector<std::pair<std::uint32_t, Vec3>> out;
    for (const std::uint32_t v : moved_all) mark_[v] = 0, out.emplace_back(v, start.at(v).first);
    return out;
}

// Each lifted vertex toward its ring's affine image of its rest position (three
// half steps, as the rounds' ring fits), by a weight that grows from 0 with how
// far the lift moved it and is 1 from kLiftSettle of its mean edge: a corner
// the lift pulled back across its base, at its target's edge, is placed as a
// smooth field would place it, and one the lift touched is hardly moved.
void FoldRepair::settle(const std::vector<std::pair<std::uint32_t, Vec3>>& lifted, std::vector<Vec3>& x,
                        const VertexRings& rings) const {
    std::vector<std::uint32_t> vertices;
    std::vector<double> weights;
    for (const auto& [v, from] : lifted) {
        vertices.push_back(v);
        weights.push_back(std::min(1.0, glm::length(x[v] - from) / (kLiftSettle * mean_edge(x, rings, v))));
    }
    refit_rings(vertices, x, rings, &weights);
}

std::size_t FoldRepair::repair(std::vector<Vec3>& x, const VertexRings& rings, bool affine_test, bool new_step,
                               bool measured) {
    acted_ = false;
    if (!active()) return 0;
    // Step 0: the lift, the lifted vertices' settling, and the lift again for
    // what settling left short.
    const std::vector<std::pair<std::uint32_t, Vec3>> lifted = lift(x, rings, affine_test, nullptr, measured);
    if (!lifted.empty()) {
        settle(lifted, x, rings);
        std::vector<std::uint32_t> settled;
        for (const auto& [v, from] : lifted) settled.push_back(v);
        lift(x, rings, affine_test, &settled);
        acted_ = true;
        stats_.steps_repaired += new_step;
        for (const auto& [v, from] : lifted) stats_.max_shift = std::max(stats_.max_shift, glm::length(x[v] - from));
    }
    // A round's folds: the neighbour test's first (the count the fold guard and
    // the battery report), then those of both tests.
    using Score = std::pair<std::size_t, std::size_t>;
    std::size_t neighbour = 0;
    std::vector<std::uint32_t> bad = folded_as_lifted(affine_test, neighbour);
    if (bad.empty()) return 0;
    const Score found{neighbour, bad.size()};
    stats_.steps_repaired += new_step && !acted_;
    stats_.steps_untangled += new_step;
    acted_ = true;
    struct Start {
        Vec3 position;
        double reach;  // how far the repair may move the vertex: kReach of its ring's mean edge
    };
    std::unordered_map<std::uint32_t, Start> start;
    // The positions after the round that left the fewest folds: the step keeps
    // those (on a mesh of slivers a ring fit can be ill-posed, and a round that
    // folds more than it unfolds must not start a cascade), or its start when
    // no round left fewer than it found.
    std::unordered_map<std::uint32_t, Vec3> best;
    Score fewest = found, last = found;
    for (int round = 0; round < kRounds && !bad.empty(); ++round) {
        const std::vector<std::uint32_t> vertices = vertices_to_move(bad, std::min(kGrowth, 1 + round / 3), rings);
        for (const std::uint32_t v : vertices) start.emplace(v, Start{x[v], kReach * mean_edge(x, rings, v)});
        stats_.vertex_moves += vertices.size();
        if (round < kRounds / 2)
            refit_rings(vertices, x, rings);
        else
            refit_patches(vertices, x, rings);
        for (const std::uint32_t v : vertices) {
            mark_[v] = 0;
            const Start& s = start.at(v);
            const Vec3 move = x[v] - s.position;
            const double length = glm::length(move);
            if (length > s.reach) x[v] = s.position + (s.reach / length) * move;
        }
        bad = folded(x, rings, affine_test, &vertices, neighbour);
        last = {neighbour, bad.size()};
        if (last < fewest) {
            fewest = last;
            best.clear();
            for (const auto& [v, s] : start) best.emplace(v, x[v]);
        }
    }
    if (fewest < last || best.empty()) {
        for (const auto& [v, s] : start) {
            const auto kept = best.find(v);
            x[v] = kept != best.end() ? kept->second : s.position;
        }
    }
    if (fewest.second > 0) {
        bad = folded(x, rings, affine_test, nullptr, neighbour);  // the kept round's folds, every test fresh
        for (int pass = 0; pass < kSearchPasses; ++pass) {
            // The folded entries and those nearly so (a symmetric scene's mirror
            // image of a fold, which rounding left unfolded, is treated alike).
            const std::vector<float> now_facing = facings(x);
            std::vector<std::uint32_t> near_folded;
            for (std::uint32_t i = 0; i < at_rest_->check.size(); ++i)
                if ((!at_rest_->against_at_rest[i] && now_facing[i] < kSearchMargin * at_rest_->rest_facing[i]) ||
                    (affine_test && affine_flags_[i]))
                    near_folded.push_back(i);
            std::vector<std::pair<std::uint32_t, Vec3>> undo;
            const std::vector<std::uint32_t> moved = search_vertices(near_folded, x, rings, affine_test, undo);
            if (moved.empty()) break;
            for (const auto& [v, from] : undo) start.emplace(v, Start{from, 0.0});
            stats_.vertex_moves += moved.size();
            bad = folded(x, rings, affine_test, &moved, neighbour);
            const Score now{neighbour, bad.size()};
            if (now <= fewest) {
                fewest = now;
                continue;
            }
            for (const auto& [v, from] : undo) x[v] = from;
            break;
        }
    }
    double shift = 0.0;
    for (const auto& [v, s] : start) shift = std::max(shift, glm::length(x[v] - s.position));
    stats_.max_shift = std::max(stats_.max_shift, shift);
    return fewest.second;
}

void FoldRepair::release_scratch() { std::vector<StarSums>().swap(sums_); }

std::size_t FoldRepair::bytes(bool shared) const {
    const auto capacity = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    const std::size_t scratch = capacity(normals_) + capacity(flags_) + capacity(touched_) + capacity(mark_) +
                                capacity(sums_) + capacity(affine_flags_) + capacity(near_) + capacity(entry_mark_) +
                                capacity(lift_by_neighbours_) + capacity(lift_by_fit_);
    if (!shared) return scratch;
    const AtRest& r = *at_rest_;
    return scratch + capacity(r.rest) + capacity(r.input_index) + capacity(r.movable) + capacity(r.triangles) +
           capacity(r.check) + capacity(r.neighbour_offsets) + capacity(r.neighbours) + capacity(r.against_at_rest) +
           capacity(r.rest_facing) + capacity(r.rest_cosine) + capacity(r.rest_area) + capacity(r.margin) +
           capacity(r.floor) + capacity(r.entry_offsets) + capacity(r.entries_of_vertex) + capacity(r.fit_vertices) +
           capacity(r.fit_of) + capacity(r.rest_sums) + capacity(r.rest_fits);
}

}  // namespace vfsd
