#pragma once
// The gizmo on a handle's target pose (ĥ, m̂, ŵ) (sec. 6.2): a centre disk that
// moves ĥ in the screen plane, three axes that move it along the handle's own
// axes, and three rings that rotate m̂ and ŵ about those axes. The target pose is
// what eq. (17) turns into the cubic curve's end b3 = ĥ and its last leg along m̂,
// and ŵ sets the end of the linear twist α(t), so each drag reshapes both.
//
// The handle's axes: x = ŵ (binormal), y = m̂ × ŵ, z = m̂ (normal), a right-handed
// frame. The gizmo keeps a constant size in pixels and gives its shapes in screen
// pixels (origin top left); the shells draw them, it knows nothing of ImGui or HTML.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "curve/handle.h"
#include "view/camera.h"

namespace vfsd::editor {

enum class GizmoPart { none, centre, axis_x, axis_y, axis_z, ring_x, ring_y, ring_z };
inline constexpr GizmoPart kGizmoParts[] = {GizmoPart::centre, GizmoPart::axis_x, GizmoPart::axis_y, GizmoPart::axis_z,
                                            GizmoPart::ring_x, GizmoPart::ring_y, GizmoPart::ring_z};

// "centre", "x", "y", "z", "ring-x", "ring-y", "ring-z" ("none"); parse throws InputError.
const char* gizmo_part_name(GizmoPart part);
GizmoPart parse_gizmo_part(const std::string& name);
bool is_ring(GizmoPart part);

struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
};

struct GizmoSegment {
    GizmoPart part = GizmoPart::none;
    glm::dvec2 from{0.0}, to{0.0};
    Rgb colour;
};

struct GizmoRing {
    GizmoPart part = GizmoPart::none;
    std::vector<glm::dvec2> points;  // a closed polyline
    Rgb colour;
};

struct GizmoShapes {
    std::vector<GizmoSegment> axes;  // only those not seen end-on
    std::vector<GizmoRing> rings;
    glm::dvec2 centre{0.0};
    double centre_radius = 0.0;
    Rgb centre_colour;
};

// The handle's axes x, y, z (see above), unit length.
std::array<Vec3, 3> handle_axes(const HandleFrame& frame);

// The frame turned by `radians` about `axis` (unit) through its position, made
// orthonormal again so repeated turns keep it a valid HandleFrame.
HandleFrame rotate_frame(const HandleFrame& frame, const Vec3& axis, double radians);

class HandleGizmo {
public:
    HandleGizmo(const HandleFrame& target, const Camera& camera, const Viewport& viewport);

    // False when the handle is behind the eye: nothing to draw or pick.
    bool visible() const { return visible_; }
    // The pixel of the target position ĥ, the rings' centre.
    glm::dvec2 centre() const { return centre_; }
    // World lengths of the axes and the rings' radius (constant on screen).
    double axis_length() const;
    double ring_radius() const;
    // The shapes to draw, `hot` in the highlight colour.
    GizmoShapes shapes(GizmoPart hot = GizmoPart::none) const;
    // The part under pixel (x, y): the centre disk, else the nearest axis or ring
    // within a few pixels, else none.
    GizmoPart hit(double x, double y) const;
    // A pixel on `part` that hit() maps to it, as far as possible from the other
    // parts (scripts and tests aim the pointer with it); none if it is not visible.
    std::optional<glm::dvec2> grab_point(GizmoPart part) const;

    // The target after the pointer moved from a to b with `part` held: the centre
    // moves ĥ in the plane facing the camera, an axis moves it along that axis by
    // the pointer's motion along the axis's projection, a ring turns m̂ and ŵ about
    // its axis by the angle a→b sweeps around the projected centre (counter-
    // clockwise as seen from the axis's tip is positive).
    HandleFrame drag(GizmoPart part, glm::dvec2 a, glm::dvec2 b) const;
    // That ring's angle in radians (wrapped to (−π, π]).
    double swept_angle(GizmoPart ring, glm::dvec2 a, glm::dvec2 b) const;

private:
    glm::dvec2 pixel(const Vec3& p) const;
    std::vector<glm::dvec2> ring_points(int axis) const;
    std::vector<glm::dvec2> make_outline(GizmoPart part) const;
    const std::vector<glm::dvec2>& outline(GizmoPart part) const { return outlines_[int(part)]; }
    double distance_to(GizmoPart part, glm::dvec2 p) const;

    HandleFrame frame_;
    Camera camera_;
    Viewport viewport_;
    std::array<Vec3, 3> axes_;
    glm::dvec2 centre_{0.0};
    double world_per_pixel_ = 0.0;
    bool visible_ = false;
    // Per part (indexed by GizmoPart): its pixels, a point or a polyline; empty when hidden.
    std::array<std::vector<glm::dvec2>, 8> outlines_;
};

}  // namespace vfsd::editor
