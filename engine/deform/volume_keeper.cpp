#include "deform/volume_keeper.h"

#include <glm/geometric.hpp>

#include "base/parallel.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"

namespace vfsd {

VolumeKeeper::VolumeKeeper(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
                           const std::vector<std::uint32_t>& blend)
    : blend_(blend) {
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    if (n == 0) return;
    for (std::uint32_t v = 0; v < n; ++v)
        if (!rings.is_closed(v)) return;
    centre_ = bounding_box(rest).centre();
    double fixed = 0.0;
    for (std::uint32_t v = 0; v < n; ++v) {
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
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

double VolumeKeeper::moving_volume(const std::vector<Vec3>& p) const {
    // Per triangle in parallel, summed in one order: the same sum on any number of threads.
    scratch_.resize(moving_.size());
    parallel_for(moving_.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const Triangle& t = moving_[i];
            scratch_[i] = glm::dot(p[t.x] - centre_, glm::cross(p[t.y] - centre_, p[t.z] - centre_));
        }
    });
    double sum = 0.0;
    for (const double v : scratch_) sum += v;
    return sum / 6.0;
}

double VolumeKeeper::volume(const std::vector<Vec3>& positions) const {
    return fixed_volume_ + moving_volume(positions);
}

double VolumeKeeper::restore(std::vector<Vec3>& positions, const VertexRings& rings) const {
    if (!active_) return 0.0;
    const double drift = volume(positions) - rest_volume_;
    direction_.resize(blend_.size());
    scratch_.resize(blend_.size());
    parallel_for(blend_.size(), [&](std::size_t first, std::size_t last) {
        const std::vector<Vec3>& p = positions;
        for (std::size_t i = first; i < last; ++i) {
            const std::uint32_t v = blend_[i];
            const Vec3 x = p[v];
            Vec3 gradient(0.0);  // 6 ∂V/∂x_v = Σ over v's triangles (v, a, b) of (a − v) × (b − v)
            for (std::uint32_t k = rings.begin(v), end = rings.end(v); k < end; ++k)
                gradient += glm::cross(p[rings.neighbours[k]] - x, p[rings.neighbours[k + 1 == end ? rings.begin(v) : k + 1]] - x);
            direction_[i] = (weight_[i] / 6.0) * gradient;
            scratch_[i] = weight_[i] * glm::dot(gradient, gradient) / 36.0;  // w |∂V/∂x|²
        }
    });
    double norm = 0.0;
    for (const double v : scratch_) norm += v;
    if (!(norm > 0.0)) return 0.0;
    const double step = -drift / norm;
    parallel_for(blend_.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) positions[blend_[i]] += step * direction_[i];
    });
    return drift;
}

}  // namespace vfsd
