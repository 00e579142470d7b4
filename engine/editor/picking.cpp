#include "editor/picking.h"

#include <cmath>
#include <limits>

namespace vfsd::editor {

std::optional<SurfaceHit> pick_surface(const Ray& ray, const std::vector<Vec3>& positions,
                                       const std::vector<Triangle>& triangles) {
    // Möller–Trumbore against every triangle; the nearest hit in front of the eye wins.
    std::optional<SurfaceHit> best;
    double best_t = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& tri = triangles[i];
        const Vec3& a = positions[tri[0]];
        const Vec3 e1 = positions[tri[1]] - a, e2 = positions[tri[2]] - a;
        const Vec3 p = glm::cross(ray.direction, e2);
        const double det = glm::dot(e1, p);
        if (std::abs(det) < 1e-300) continue;
        const double inv = 1.0 / det;
        const Vec3 q = ray.origin - a;
        const double u = glm::dot(q, p) * inv;
        if (u < 0.0 || u > 1.0) continue;
        const Vec3 r = glm::cross(q, e1);
        const double v = glm::dot(ray.direction, r) * inv;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t = glm::dot(e2, r) * inv;
        if (t <= 0.0 || t >= best_t) continue;
        best_t = t;
        SurfaceHit hit;
        hit.point.triangle = static_cast<std::uint32_t>(i);
        hit.point.barycentric = Vec3(1.0 - u - v, u, v);
        hit.position = ray.origin + t * ray.direction;
        hit.distance = t;
        const Vec3& w = hit.point.barycentric;
        hit.nearest_vertex = tri[w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2)];
        best = hit;
    }
    return best;
}

std::optional<std::size_t> pick_screen_point(const std::vector<Vec3>& points, double x, double y,
                                             const Camera& camera, const Viewport& viewport, double radius) {
    std::optional<std::size_t> best;
    double best_d = radius * radius;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::dvec3 s = camera.project(points[i], viewport);
        if (s.z > 1.0) continue;
        const double d = (s.x - x) * (s.x - x) + (s.y - y) * (s.y - y);
        if (d <= best_d) best_d = d, best = i;
    }
    return best;
}

Vec3 point_in_view_plane(const Vec3& on, double x, double y, const Camera& camera, const Viewport& viewport) {
    const Ray r = camera.ray(x, y, viewport);
    const Vec3 n = camera.forward();
    const double denom = glm::dot(r.direction, n);
    if (std::abs(denom) < 1e-12) return on;
    return r.origin + (glm::dot(on - r.origin, n) / denom) * r.direction;
}

std::optional<double> line_parameter_at_pixel(const Vec3& on, const Vec3& direction, double x, double y,
                                              const Camera& camera, const Viewport& viewport) {
    // Closest points of two lines: on + s·direction and the ray.
    const Ray r = camera.ray(x, y, viewport);
    const Vec3 w = on - r.origin;
    const double b = glm::dot(direction, r.direction), d = glm::dot(direction, w), f = glm::dot(r.direction, w);
    const double denom = 1.0 - b * b;
    if (denom < 1e-9) return std::nullopt;  // the line points at the eye
    return (b * f - d) / denom;
}

Vec3 drag_point(const Vec3& from, double x, double y, const Camera& camera, const Viewport& viewport, int axis) {
    if (axis < 0 || axis > 2) return point_in_view_plane(from, x, y, camera, viewport);
    Vec3 e(0.0);
    e[axis] = 1.0;
    return from + line_parameter_at_pixel(from, e, x, y, camera, viewport).value_or(0.0) * e;
}

}  // namespace vfsd::editor
