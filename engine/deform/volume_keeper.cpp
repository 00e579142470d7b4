#include "deform/volume_keeper.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "base/parallel.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"

namespace vfsd {

namespace {

// Whether every edge at v borders two of its triangles: v is on no border,
// though it may join several fans (a pinch, where two closed parts of the
// surface touch at a vertex). Each wedge (v, a, b) holds the edges va and vb.
bool all_edges_shared(const VertexRings& rings, std::uint32_t v) {
    std::vector<std::pair<std::uint32_t, int>> edges;  // neighbour, wedges holding its edge
    const auto add = [&](std::uint32_t a) {
        for (auto& e : edges)
            if (e.first == a) return void(++e.second);
        edges.emplace_back(a, 1);
    };
    for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
        if (rings.wedge[k]) add(rings.neighbours[k]), add(rings.neighbours[rings.next(v, k)]);
    return !edges.empty() && std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

}  // namespace

VolumeKeeper::VolumeKeeper(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
                           const std::vector<std::uint32_t>& blend)
    : blend_(blend) {
    if (!applies_to(rings)) return;
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    centre_ = bounding_box(rest).centre();
    double fixed = 0.0;
    for (std::uint32_t v = 0; v < n; ++v) {
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            if (!rings.wedge[k]) continue;  // between two fans of a pinched vertex
            const std::uint32_t a = rings.neighbours[k], b = rings.neighbours[rings.next(v, k)];
            if (v > a || v > b) continue;  // each triangle once, from its lowest corner
            if (s[v] < 1.0 || s[a] < 1.0 || s[b] < 1.0) moving_.push_back(Triangle(v, a, b));
            else
                fixed += six_volume(rest.data(), Triangle(v, a, b), centre_);
        }
    }
    find_inner_border(s, rings);
    fixed_volume_ = fixed / 6.0;
    for (const std::uint32_t v : blend_)
        weight_.push_back((1.0 - bernstein_blend(s[v])) * bernstein_blend_derivative(s[v]));
    rest_volume_ = fixed_volume_ + moving_volume(rest);
    active_ = true;
}

// The inner region's triangles with a corner outside it, and the directed edges
// (a → b, as a triangle of the inner region alone runs) between those triangles
// and the others: rate() needs no more of the inner region.
void VolumeKeeper::find_inner_border(const std::vector<double>& s, const VertexRings& rings) {
    // The third corner of the triangle on the other side of a → b: the one that runs b → a.
    const auto across = [&](std::uint32_t a, std::uint32_t b) {
        for (std::uint32_t k = rings.begin(b); k < rings.end(b); ++k)
            if (rings.wedge[k] && rings.neighbours[k] == a) return rings.neighbours[rings.next(b, k)];
        return b;  // not reached on a surface whose every edge borders two triangles
    };
    for (const Triangle& t : moving_) {
        const std::uint32_t c[3] = {t.x, t.y, t.z};
        const int inner = (s[t.x] <= 0.0) + (s[t.y] <= 0.0) + (s[t.z] <= 0.0);
        if (inner == 0) continue;
        if (inner < 3) {
            for (int i = 0; i < 3; ++i)
                if (s[c[i]] <= 0.0) inner_terms_.push_back(Triangle(c[i], c[(i + 1) % 3], c[(i + 2) % 3]));
            continue;
        }
        for (int i = 0; i < 3; ++i)
            if (s[across(c[i], c[(i + 1) % 3])] > 0.0) inner_border_.push_back({c[i], c[(i + 1) % 3]});
    }
}

bool VolumeKeeper::applies_to(const VertexRings& rings) {
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    if (n == 0) return false;
    for (std::uint32_t v = 0; v < n; ++v)
        if (!rings.is_closed(v) && !all_edges_shared(rings, v)) return false;
    return true;
}

double VolumeKeeper::moving_volume(const std::vector<Vec3>& p) const {
    const Triangle* moving = moving_.data();
    return parallel_block_sum(moving_.size(),
                              [&](std::size_t begin, std::size_t end) {
                                  return six_volume_block(p.data(), moving + begin, end - begin, centre_);
                              }) /
           6.0;
}

double VolumeKeeper::volume(const std::vector<Vec3>& positions) const {
    return fixed_volume_ + moving_volume(positions);
}

double VolumeKeeper::rate(const std::vector<Vec3>& p, double blend_flux, const MotionSample& sample) const {
    if (!active_) return 0.0;
    // 6 dV/dt = Σ over triangles of d/dt (a − c) · ((b − c) × (d − c)), c the centre.
    // Summed by corner: a blend vertex's terms are u · its ring area vector (the
    // blend flux); an inner vertex's are taken per triangle where the triangle has
    // a corner outside the inner region; a triangle of the inner region alone
    // moves rigidly, and moving its tetrahedron's apex c along would keep the
    // tetrahedron, so its rate is u(c) · ((b − a) × (d − a)): summed over the
    // region, u(c) · Σ (a − c) × (b − c) over its border's edges a → b (the
    // inner edges cancel). The outer region does not move.
    double six_rate = blend_flux;
    for (const Triangle& t : inner_terms_)
        six_rate += glm::dot(inner_velocity(sample, p[t.x]), glm::cross(p[t.y] - centre_, p[t.z] - centre_));
    Vec3 border(0.0);
    for (const auto& [a, b] : inner_border_) border += glm::cross(p[a] - centre_, p[b] - centre_);
    return (six_rate + glm::dot(inner_velocity(sample, centre_), border)) / 6.0;
}

void VolumeKeeper::require_one_per_blend_vertex(const std::vector<Vec3>& area_vectors, const char* caller) const {
    if (area_vectors.size() != blend_.size())
        throw std::invalid_argument(std::string("VolumeKeeper::") + caller + ": " +
                                    std::to_string(area_vectors.size()) + " area vectors for " +
                                    std::to_string(blend_.size()) + " blend vertices");
}

double VolumeKeeper::area_norm(const std::vector<Vec3>& area_vectors) const {
    if (!active_) return 0.0;
    require_one_per_blend_vertex(area_vectors, "area_norm");
    const auto weighted_square = [&](std::size_t i) {  // w |6 ∂V/∂x|² at blend vertex i
        return weight_[i] * glm::dot(area_vectors[i], area_vectors[i]);
    };
    return parallel_sum(blend_.size(), weighted_square) / 36.0;
}

double VolumeKeeper::lambda(double rate, double area_norm) const {
    if (!active_) return 0.0;
    // None where the sums are not finite (a position already so, which the step
    // then names; the keeper does not spread it over the blend region).
    return area_norm > 0.0 && std::isfinite(area_norm) && std::isfinite(rate) ? -rate / area_norm : 0.0;
}

double VolumeKeeper::restore(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors) const {
    return restore(positions, area_vectors, area_norm(area_vectors));
}

double VolumeKeeper::restore(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors,
                             double area_norm) const {
    if (!active_) return 0.0;
    require_one_per_blend_vertex(area_vectors, "restore");
    const double drift = volume(positions) - rest_volume_;
    if (!(area_norm > 0.0)) return 0.0;
    move_by(positions, area_vectors, area_norm, drift);
    return drift;
}

void VolumeKeeper::move_by(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors, double area_norm,
                           double drift) const {
    const double step = -drift / area_norm / 6.0;  // ∂V/∂x is a sixth of the area vector
    parallel_for(blend_.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) positions[blend_[i]] += (step * weight_[i]) * area_vectors[i];
    });
}

int VolumeKeeper::restore_after_repair(std::vector<Vec3>& positions, const VertexRings& rings,
                                       std::vector<Vec3>& area_vectors, double& area_norm) const {
    if (!active_) return 0;
    int steps = 0;
    for (; steps < kStepsAfterRepair; ++steps) {
        // Newton's method converges quadratically here: after a repair's drift
        // of 1e-7 of the volume the second step's is about 1e-13, the third's
        // the sum's rounding. So the drift is taken before the area vectors.
        const double drift = volume(positions) - rest_volume_;
        if (!(std::abs(drift) > kSettledDrift * std::abs(rest_volume_))) break;
        ring_area_vectors(positions, rings, blend_, area_vectors);
        area_norm = this->area_norm(area_vectors);
        if (!(area_norm > 0.0)) break;
        move_by(positions, area_vectors, area_norm, drift);
    }
    return steps;
}

}  // namespace vfsd
