#include "editor/picking.h"

#include <cmath>

namespace vfsd::editor {

namespace {

std::optional<SurfaceHit> surface_hit(const std::optional<RayHit>& hit, const Ray& ray,
                                      const std::vector<Triangle>& triangles) {
    if (!hit) return std::nullopt;
    SurfaceHit out;
    out.point.triangle = hit->triangle;
    out.point.barycentric = Vec3(1.0 - hit->u - hit->v, hit->u, hit->v);
    out.position = ray.origin + hit->t * ray.direction;
    out.distance = hit->t;
    const Vec3& w = out.point.barycentric;
    out.nearest_vertex = triangles[hit->triangle][w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2)];
    return out;
}

}  // namespace

std::optional<SurfaceHit> pick_surface(const Ray& ray, const std::vector<Vec3>& positions,
                                       const std::vector<Triangle>& triangles) {
    return surface_hit(first_hit_brute_force(ray, positions, triangles), ray, triangles);
}

std::optional<SurfaceHit> SurfacePicker::pick(const Ray& ray, const std::vector<Vec3>& positions,
                                              const std::vector<Triangle>& triangles, std::uint64_t topology,
                                              std::uint64_t shape) {
    follow(positions, triangles, topology, shape);
    return surface_hit(bvh_.first_hit(ray, positions), ray, triangles);
}

void SurfacePicker::follow(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                           std::uint64_t topology, std::uint64_t shape) {
    if (topology != topology_ || bvh_.triangle_count() != triangles.size()) {
        bvh_ = TriangleBvh(positions, triangles);
        topology_ = topology, shape_ = shape;
    } else if (shape != shape_) {
        bvh_.refit(positions);
        shape_ = shape;
    }
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
