#include "view/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "base/error.h"

namespace vfsd {
namespace {

constexpr double kPitchLimit = 1.55;  // just short of ±90°, so "up" stays defined

double half_fov(const Camera& c) { return glm::radians(0.5 * c.fov_degrees); }

// A direction of the z-up frame the angles are measured in, in the world.
Vec3 to_world(const Vec3& v, UpAxis up) { return up == UpAxis::z ? v : Vec3(v.x, v.z, -v.y); }

}  // namespace

StandardView standard_view_named(const std::string& name) {
    static const std::pair<const char*, StandardView> kViews[] = {
        {"front", StandardView::front}, {"back", StandardView::back},     {"left", StandardView::left},
        {"right", StandardView::right}, {"top", StandardView::top},       {"bottom", StandardView::bottom},
        {"iso", StandardView::iso}};
    for (const auto& [n, view] : kViews)
        if (name == n) return view;
    throw InputError("unknown view '" + name + "' (front, back, right, left, top, bottom or iso)");
}

UpAxis up_axis_named(const std::string& name) {
    if (name == "z") return UpAxis::z;
    if (name == "y") return UpAxis::y;
    throw InputError("unknown up axis '" + name + "' (y or z)");
}

Camera::Camera() {
    const Vec3 d = glm::normalize(Vec3(1.0, -1.6, 0.9));  // from front right, above
    yaw = std::atan2(d.y, d.x);
    pitch = std::asin(d.z);
}

Camera Camera::framing(const std::vector<Vec3>& points, double aspect) {
    Camera camera;
    camera.frame(points, aspect);
    return camera;
}

Vec3 Camera::eye() const {
    const Vec3 from(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
    return target + distance * to_world(from, up_axis);
}
Vec3 Camera::forward() const { return glm::normalize(target - eye()); }
Vec3 Camera::right() const { return glm::normalize(glm::cross(forward(), world_up())); }
Vec3 Camera::up() const { return glm::cross(right(), forward()); }
Vec3 Camera::world_up() const { return to_world(Vec3(0.0, 0.0, 1.0), up_axis); }

glm::dmat4 Camera::view() const { return glm::lookAt(eye(), target, world_up()); }

glm::dmat4 Camera::projection(double aspect) const {
    // Clip planes around the scene's sphere as seen from the current distance.
    const double near_plane = std::max(1e-3 * distance, distance - 2.5 * scene_radius);
    const double far_plane = distance + 2.5 * scene_radius;
    return glm::perspective(2.0 * half_fov(*this), aspect, std::max(near_plane, 1e-4 * far_plane), far_plane);
}

void Camera::orbit(double dx, double dy) {
    yaw -= kOrbitRadiansPerPixel * dx;
    pitch = std::clamp(pitch + kOrbitRadiansPerPixel * dy, -kPitchLimit, kPitchLimit);
}

void Camera::pan(double dx, double dy, const Viewport& viewport) {
    const double size = pixel_size(viewport);
    target += size * (-dx * right() + dy * up());
}

void Camera::zoom(double factor, double x, double y, const Viewport& viewport) {
    // The point under the cursor on the plane through the target facing the eye.
    const Ray r = ray(x, y, viewport);
    const Vec3 f = forward();
    const double along = glm::dot(target - r.origin, f) / glm::dot(r.direction, f);
    const Vec3 under = r.origin + along * r.direction;
    target = under + factor * (target - under);
    distance *= factor;
}

void Camera::frame(const std::vector<Vec3>& points, double aspect) {
    if (points.empty()) return;
    Vec3 lo = points.front(), hi = points.front();
    for (const Vec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
    target = 0.5 * (lo + hi);
    double radius = 0.0;
    for (const Vec3& p : points) radius = std::max(radius, glm::length(p - target));
    if (!(radius > 0.0)) radius = 1.0;
    scene_radius = radius;
    // The sphere fits the narrower side of the image.
    distance = 1.05 * radius / std::sin(half_fov(*this) * std::min(1.0, aspect));
}

void Camera::set_view(StandardView view) {
    const double pi = glm::pi<double>();
    switch (view) {
        case StandardView::front: yaw = -0.5 * pi, pitch = 0.0; break;
        case StandardView::back: yaw = 0.5 * pi, pitch = 0.0; break;
        case StandardView::right: yaw = 0.0, pitch = 0.0; break;
        case StandardView::left: yaw = pi, pitch = 0.0; break;
        case StandardView::top: yaw = -0.5 * pi, pitch = kPitchLimit; break;
        case StandardView::bottom: yaw = -0.5 * pi, pitch = -kPitchLimit; break;
        case StandardView::iso: *this = [&] { Camera c; c.target = target, c.distance = distance;
                                               c.scene_radius = scene_radius; c.fov_degrees = fov_degrees;
                                               c.up_axis = up_axis; return c; }();
                                break;
    }
}

Ray Camera::ray(double x, double y, const Viewport& viewport) const {
    const double ndc_x = 2.0 * (x + 0.5) / viewport.width - 1.0;
    const double ndc_y = 1.0 - 2.0 * (y + 0.5) / viewport.height;
    const double t = std::tan(half_fov(*this));
    Ray r;
    r.origin = eye();
    r.direction = glm::normalize(forward() + ndc_x * t * viewport.aspect() * right() + ndc_y * t * up());
    return r;
}

glm::dvec3 Camera::project(const Vec3& p, const Viewport& viewport) const {
    const glm::dvec4 clip = projection(viewport.aspect()) * view() * glm::dvec4(p, 1.0);
    const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
    return {0.5 * (ndc.x + 1.0) * viewport.width - 0.5, 0.5 * (1.0 - ndc.y) * viewport.height - 0.5,
            clip.w > 0.0 ? ndc.z : 2.0};
}

double Camera::pixel_size(const Viewport& viewport) const {
    return 2.0 * distance * std::tan(half_fov(*this)) / viewport.height;
}

}  // namespace vfsd
