#include "deform/volume_keeper.h"

#include <algorithm>
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
            else fixed += glm::dot(rest[v] - centre_, glm::cross(rest[a] - centre_, rest[b] - centre_));
        }
    }
    fixed_volume_ = fixed / 6.0;
    for (const std::uint32_t v : blend_)
        weight_.push_back((1.0 - bernstein_blend(s[v])) * bernstein_blend_derivative(s[v]));
    rest_volume_ = fixed_volume_ + moving_volume(rest);
    active_ = true;
}

bool VolumeKeeper::applies_to(const VertexRings& rings) {
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    if (n == 0) return false;
    for (std::uint32_t v = 0; v < n; ++v)
        if (!rings.is_closed(v) && !all_edges_shared(rings, v)) return false;
    return true;
}

double VolumeKeeper::moving_volume(const std::vector<Vec3>& p) const {
    // Of triangle i's tetrahedron with the centre: (a − c) · ((b − c) × (d − c)), in
    // scalars (glm's Vec3 temporaries went through the stack; the same operations
    // in the same order).
    const double cx = centre_.x, cy = centre_.y, cz = centre_.z;
    const auto six_volume = [&](std::size_t i) {
        const Triangle& t = moving_[i];
        const Vec3 &a = p[t.x], &b = p[t.y], &d = p[t.z];
        const double ax = a.x - cx, ay = a.y - cy, az = a.z - cz;
        const double bx = b.x - cx, by = b.y - cy, bz = b.z - cz, dx = d.x - cx, dy = d.y - cy, dz = d.z - cz;
        return ax * (by * dz - dy * bz) + ay * (bz * dx - dz * bx) + az * (bx * dy - dx * by);
    };
    return parallel_sum(moving_.size(), six_volume) / 6.0;
}

double VolumeKeeper::volume(const std::vector<Vec3>& positions) const {
    return fixed_volume_ + moving_volume(positions);
}

double VolumeKeeper::restore(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors) const {
    if (!active_) return 0.0;
    if (area_vectors.size() != blend_.size())
        throw std::invalid_argument("VolumeKeeper::restore: " + std::to_string(area_vectors.size()) +
                                    " area vectors for " + std::to_string(blend_.size()) + " blend vertices");
    const double drift = volume(positions) - rest_volume_;
    const auto weighted_square = [&](std::size_t i) {  // w |6 ∂V/∂x|² at blend vertex i
        return weight_[i] * glm::dot(area_vectors[i], area_vectors[i]);
    };
    const double norm = parallel_sum(blend_.size(), weighted_square) / 36.0;  // Σ w |∂V/∂x|²
    if (!(norm > 0.0)) return 0.0;
    const double step = -drift / norm;
    parallel_for(blend_.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) positions[blend_[i]] += (step * weight_[i] / 6.0) * area_vectors[i];
    });
    return drift;
}

}  // namespace vfsd
