#include "editor/handle_gizmo.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include "base/error.h"
#include "editor/picking.h"

namespace vfsd::editor {
namespace {

// Sizes in screen pixels, whatever the zoom.
constexpr double kAxisPixels = 110.0;
constexpr double kRingPixels = 60.0;
constexpr double kCentrePixels = 9.0;
constexpr double kPickPixels = 7.0;
constexpr double kMinAxisPixels = 12.0;  // shorter: the axis points at the eye, hidden
constexpr int kRingSegments = 72;

constexpr Rgb kAxisColours[3] = {{215, 45, 45}, {40, 160, 60}, {45, 95, 230}};
constexpr Rgb kHotColour{255, 200, 40};
constexpr Rgb kCentreColour{245, 245, 245};

constexpr GizmoPart kAxisParts[3] = {GizmoPart::axis_x, GizmoPart::axis_y, GizmoPart::axis_z};
constexpr GizmoPart kRingParts[3] = {GizmoPart::ring_x, GizmoPart::ring_y, GizmoPart::ring_z};

// 0, 1, 2 for the x, y, z axis or ring; -1 for the centre and none.
int axis_index(GizmoPart part) {
    for (int k = 0; k < 3; ++k)
        if (part == kAxisParts[k] || part == kRingParts[k]) return k;
    return -1;
}

double distance_to_segment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double length2 = glm::dot(ab, ab);
    const double t = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

double distance_to_polyline(glm::dvec2 p, const std::vector<glm::dvec2>& line) {
    if (line.size() == 1) return glm::length(p - line[0]);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distance_to_segment(p, line[i], line[i + 1]));
    return best;
}

// Angle of p around c, counter-clockwise as the screen shows it (pixel y points down).
double screen_angle(glm::dvec2 p, glm::dvec2 c) { return std::atan2(-(p.y - c.y), p.x - c.x); }

double wrap_angle(double radians) {
    const double pi = glm::pi<double>();
    while (radians > pi) radians -= 2.0 * pi;
    while (radians <= -pi) radians += 2.0 * pi;
    return radians;
}

}  // namespace

const char* gizmo_part_name(GizmoPart part) {
    switch (part) {
        case GizmoPart::none: return "none";
        case GizmoPart::centre: return "centre";
        case GizmoPart::axis_x: return "x";
        case GizmoPart::axis_y: return "y";
        case GizmoPart::axis_z: return "z";
        case GizmoPart::ring_x: return "ring-x";
        case GizmoPart::ring_y: return "ring-y";
        case GizmoPart::ring_z: return "ring-z";
    }
    return "?";
}

GizmoPart parse_gizmo_part(const std::string& name) {
    for (const GizmoPart part : kGizmoParts)
        if (name == gizmo_part_name(part)) return part;
    throw InputError("gizmo part: expected centre, x, y, z, ring-x, ring-y or ring-z, not '" + name + "'");
}

bool is_ring(GizmoPart part) { return std::find(std::begin(kRingParts), std::end(kRingParts), part) != std::end(kRingParts); }

std::array<Vec3, 3> handle_axes(const HandleFrame& frame) {
    return {frame.binormal, glm::cross(frame.normal, frame.binormal), frame.normal};
}

HandleFrame rotate_frame(const HandleFrame& frame, const Vec3& axis, double radians) {
    const glm::dquat turn = glm::angleAxis(radians, axis);
    HandleFrame out = frame;
    out.normal = glm::normalize(turn * frame.normal);
    const Vec3 w = turn * frame.binormal;
    out.binormal = glm::normalize(w - glm::dot(w, out.normal) * out.normal);
    return out;
}

HandleGizmo::HandleGizmo(const HandleFrame& target, const Camera& camera, const Viewport& viewport)
    : frame_(target), camera_(camera), viewport_(viewport), axes_(handle_axes(target)) {
    // One pixel in world units at the handle's depth keeps the gizmo's size on screen.
    const double depth = glm::dot(target.position - camera.eye(), camera.forward());
    world_per_pixel_ = camera.pixel_size(viewport) * depth / camera.distance;
    visible_ = depth > 0.0 && camera.project(target.position, viewport).z <= 1.0;
    centre_ = pixel(target.position);
    for (const GizmoPart part : kGizmoParts) outlines_[int(part)] = make_outline(part);
}

double HandleGizmo::axis_length() const { return kAxisPixels * world_per_pixel_; }
double HandleGizmo::ring_radius() const { return kRingPixels * world_per_pixel_; }

glm::dvec2 HandleGizmo::pixel(const Vec3& p) const {
    const glm::dvec3 s = camera_.project(p, viewport_);
    return {s.x, s.y};
}

std::vector<glm::dvec2> HandleGizmo::ring_points(int axis) const {
    // The circle about the axis through ĥ, in the plane of the other two axes.
    const Vec3 u = axes_[(axis + 1) % 3], v = axes_[(axis + 2) % 3];
    const double radius = ring_radius();
    std::vector<glm::dvec2> points;
    for (int i = 0; i <= kRingSegments; ++i) {
        const double angle = 2.0 * glm::pi<double>() * i / kRingSegments;
        points.push_back(pixel(frame_.position + radius * (std::cos(angle) * u + std::sin(angle) * v)));
    }
    return points;
}

std::vector<glm::dvec2> HandleGizmo::make_outline(GizmoPart part) const {
    if (!visible_) return {};
    const int k = axis_index(part);
    if (part == GizmoPart::centre) return {centre_};
    if (is_ring(part)) return ring_points(k);
    if (k < 0) return {};
    const glm::dvec2 tip = pixel(frame_.position + axis_length() * axes_[k]);
    if (glm::length(tip - centre_) < kMinAxisPixels) return {};
    return {centre_, tip};
}

double HandleGizmo::distance_to(GizmoPart part, glm::dvec2 p) const {
    const std::vector<glm::dvec2>& line = outline(part);
    if (line.empty()) return std::numeric_limits<double>::infinity();
    const double d = distance_to_polyline(p, line);
    return part == GizmoPart::centre ? std::max(0.0, d - kCentrePixels) : d;
}

GizmoShapes HandleGizmo::shapes(GizmoPart hot) const {
    GizmoShapes out;
    if (!visible_) return out;
    for (int k = 0; k < 3; ++k) {
        const Rgb colour = kAxisParts[k] == hot ? kHotColour : kAxisColours[k];
        const std::vector<glm::dvec2>& line = outline(kAxisParts[k]);
        if (line.size() == 2) out.axes.push_back({kAxisParts[k], line[0], line[1], colour});
        out.rings.push_back({kRingParts[k], outline(kRingParts[k]), kRingParts[k] == hot ? kHotColour : kAxisColours[k]});
    }
    out.centre = centre_;
    out.centre_radius = kCentrePixels;
    out.centre_colour = hot == GizmoPart::centre ? kHotColour : kCentreColour;
    return out;
}

GizmoPart HandleGizmo::hit(double x, double y) const {
    const glm::dvec2 p(x, y);
    GizmoPart best = GizmoPart::none;
    double best_distance = kPickPixels;
    for (const GizmoPart part : kGizmoParts) {
        const double d = distance_to(part, p);
        if (part == GizmoPart::centre && d == 0.0) return part;  // the disk covers what crosses it
        if (d <= best_distance) best_distance = d, best = part;
    }
    return best;
}

std::optional<glm::dvec2> HandleGizmo::grab_point(GizmoPart part) const {
    // Candidates along the part; the one farthest from every other part wins.
    const std::vector<glm::dvec2>& line = outline(part);
    std::vector<glm::dvec2> candidates = line.size() == 1 ? line : std::vector<glm::dvec2>{};
    for (std::size_t i = 0; i + 1 < line.size(); ++i)
        for (int k = 0; k < 8; ++k) candidates.push_back(glm::mix(line[i], line[i + 1], k / 8.0));
    std::optional<glm::dvec2> best;
    double best_margin = -1.0;
    for (const glm::dvec2& c : candidates) {
        if (hit(c.x, c.y) != part) continue;
        double margin = std::numeric_limits<double>::infinity();
        for (const GizmoPart other : kGizmoParts)
            if (other != part) margin = std::min(margin, distance_to(other, c));
        if (margin > best_margin) best_margin = margin, best = c;
    }
    return best;
}

double HandleGizmo::swept_angle(GizmoPart ring, glm::dvec2 a, glm::dvec2 b) const {
    // Counter-clockwise on screen is positive about an axis whose tip faces the eye.
    const double on_screen = wrap_angle(screen_angle(b, centre_) - screen_angle(a, centre_));
    const bool tip_faces_eye = glm::dot(axes_[axis_index(ring)], camera_.eye() - frame_.position) > 0.0;
    return tip_faces_eye ? on_screen : -on_screen;
}

HandleFrame HandleGizmo::drag(GizmoPart part, glm::dvec2 a, glm::dvec2 b) const {
    HandleFrame out = frame_;
    const int k = axis_index(part);
    if (part == GizmoPart::centre) {
        out.position += point_in_view_plane(frame_.position, b.x, b.y, camera_, viewport_) -
                        point_in_view_plane(frame_.position, a.x, a.y, camera_, viewport_);
    } else if (is_ring(part)) {
        out = rotate_frame(frame_, axes_[k], swept_angle(part, a, b));
    } else if (k >= 0) {
        const auto from = line_parameter_at_pixel(frame_.position, axes_[k], a.x, a.y, camera_, viewport_);
        const auto to = line_parameter_at_pixel(frame_.position, axes_[k], b.x, b.y, camera_, viewport_);
        if (from && to) out.position += (*to - *from) * axes_[k];
    }
    return out;
}

}  // namespace vfsd::editor
