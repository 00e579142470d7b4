#pragma once
// The one camera: orbit about a target point, pan, zoom toward the cursor, frame
// a set of points, and the standard views of modelling tools, with z or y up. It
// gives the view and projection matrices the renderer draws with (the editors'
// view, `vfsd render`'s images) and the ray under a screen point that picking
// follows. Screen coordinates are pixels with the origin at the top left, as
// windows and browsers report the pointer.

#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "mesh/ray_cast.h"  // Ray

namespace vfsd {

struct Viewport {
    int width = 1;
    int height = 1;
    double aspect() const { return double(width) / double(height > 0 ? height : 1); }
};

enum class StandardView { front, back, left, right, top, bottom, iso };
// "front", "back", "left", "right", "top", "bottom" or "iso"; throws InputError
// naming them for another name.
StandardView standard_view_named(const std::string& name);

// Which world axis is up on the screen. With z up (the default) front looks from
// −y; with y up the same views are turned so that z becomes y: (x, y, z) →
// (x, z, −y), and front looks from +z.
enum class UpAxis { z, y };
// "z" or "y"; throws InputError for another name.
UpAxis up_axis_named(const std::string& name);

// Camera::orbit turns this far per pixel the pointer moves.
inline constexpr double kOrbitRadiansPerPixel = 0.01;

class Camera {
public:
    Vec3 target{0.0};
    double distance = 4.0;
    double yaw = 0.0;    // radians about the up axis, 0 = looking from +x
    double pitch = 0.0;  // radians above the plane normal to the up axis
    double fov_degrees = 30.0;
    double scene_radius = 1.0;  // sets the clip planes
    UpAxis up_axis = UpAxis::z;

    // The renderer's default 3/4 view from front right, above.
    Camera();
    // The default view of `points` framed for an image of the given aspect.
    static Camera framing(const std::vector<Vec3>& points, double aspect);

    Vec3 eye() const;
    Vec3 forward() const;  // unit, from the eye toward the target
    Vec3 right() const;
    Vec3 up() const;        // on the screen
    Vec3 world_up() const;  // the up axis
    glm::dmat4 view() const;
    glm::dmat4 projection(double aspect) const;

    // Rotates about the target by pixel deltas (kOrbitRadiansPerPixel); pitch stays
    // short of the poles.
    void orbit(double dx, double dy);
    // Moves target and eye so the point under the cursor follows it (pixel deltas).
    void pan(double dx, double dy, const Viewport& viewport);
    // Scales the distance by `factor` (< 1 zooms in) keeping the point of the
    // target's plane under (x, y) fixed on screen.
    void zoom(double factor, double x, double y, const Viewport& viewport);
    // Looks at the bounding sphere of `points` so it fits the narrower side.
    void frame(const std::vector<Vec3>& points, double aspect);
    void set_view(StandardView view);

    // The ray from the eye through pixel (x, y).
    Ray ray(double x, double y, const Viewport& viewport) const;
    // Pixel coordinates of `p` (z: NDC depth, > 1 or < -1 when clipped; w < 0 behind).
    glm::dvec3 project(const Vec3& p, const Viewport& viewport) const;
    // World-space length of one pixel at the target's depth.
    double pixel_size(const Viewport& viewport) const;
};

}  // namespace vfsd
