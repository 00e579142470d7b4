#include "mesh/ray_cast.h"

#include <cmath>
#include <limits>

namespace vfsd {
namespace {

// Whether the ray runs within about 1e-9 rad of the triangle's plane (or the
// triangle is degenerate): det = e1 · (direction × e2) against |e1| |e2| |direction|.
// Closer to the plane the hit is lost in rounding (t and u, v would be off by more
// than the slack TriangleBvh grants its boxes), so it counts as a miss.
bool nearly_parallel(double det, const Vec3& e1, const Vec3& e2, const Vec3& direction) {
    constexpr double kMinSine = 1e-9;
    return det * det <= kMinSine * kMinSine * glm::dot(e1, e1) * glm::dot(e2, e2) * glm::dot(direction, direction);
}

}  // namespace

std::optional<RayHit> intersect_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c,
                                         std::uint32_t index) {
    // Möller–Trumbore: solve origin + t·direction = a + u·(b - a) + v·(c - a) by Cramer's rule.
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 p = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, p);
    if (nearly_parallel(det, e1, e2, ray.direction)) return std::nullopt;
    const double inv = 1.0 / det;
    const Vec3 q = ray.origin - a;
    const double u = glm::dot(q, p) * inv;
    // Written so that NaN (a non-finite corner) fails each test.
    if (!(u >= 0.0 && u <= 1.0)) return std::nullopt;
    const Vec3 r = glm::cross(q, e1);
    const double v = glm::dot(ray.direction, r) * inv;
    if (!(v >= 0.0 && u + v <= 1.0)) return std::nullopt;
    const double t = glm::dot(e2, r) * inv;
    if (!(t > 0.0 && t < std::numeric_limits<double>::infinity())) return std::nullopt;
    return RayHit{index, u, v, t};
}

std::optional<RayHit> first_hit_brute_force(const Ray& ray, const std::vector<Vec3>& positions,
                                            const std::vector<Triangle>& triangles) {
    std::optional<RayHit> best;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& tri = triangles[i];
        keep_first(best, intersect_triangle(ray, positions[tri[0]], positions[tri[1]], positions[tri[2]],
                                            static_cast<std::uint32_t>(i)));
    }
    return best;
}

}  // namespace vfsd
