#pragma once
// Picking: the surface point under a ray (ray–triangle intersection on the
// positions the caller passes, normally the ones on screen: the deformation's
// current positions), and the nearest of a few 3D points to a pixel (control
// points, handles). The editors pick the surface through EditorSession's
// SurfacePicker; pick_surface is the plain loop it must agree with.

#include <optional>
#include <vector>

#include "view/camera.h"
#include "mesh/triangle_bvh.h"
#include "region/surface_point.h"

namespace vfsd::editor {

struct SurfaceHit {
    SurfacePoint point;     // triangle + barycentric coordinates
    Vec3 position{0.0};     // where the ray meets the surface
    double distance = 0.0;  // along the ray
    std::uint32_t nearest_vertex = 0;  // the triangle's corner closest to the hit
};

// The first triangle the ray meets (either side faces it), if any, by testing
// every triangle: about 10 ms per million triangles.
std::optional<SurfaceHit> pick_surface(const Ray& ray, const std::vector<Vec3>& positions,
                                       const std::vector<Triangle>& triangles);

// pick_surface's hit through a TriangleBvh (mesh/triangle_bvh.h), in microseconds
// on millions of triangles. The hierarchy is built on the first pick after
// `topology` changes and refit, O(n), on the first pick after `shape` changes: the
// caller numbers its triangles and its positions (EditorSession's revisions).
class SurfacePicker {
public:
    std::optional<SurfaceHit> pick(const Ray& ray, const std::vector<Vec3>& positions,
                                   const std::vector<Triangle>& triangles, std::uint64_t topology, std::uint64_t shape);
    // The hierarchy built or refit as the next pick would, without picking.
    void follow(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles, std::uint64_t topology,
                std::uint64_t shape);

private:
    TriangleBvh bvh_;
    std::uint64_t topology_ = 0, shape_ = 0;
};

// The index of the point whose projection lies nearest to pixel (x, y), within
// `radius` pixels; points behind the eye are never picked.
std::optional<std::size_t> pick_screen_point(const std::vector<Vec3>& points, double x, double y,
                                             const Camera& camera, const Viewport& viewport, double radius = 10.0);

// The point under pixel (x, y) of the plane through `on` facing the camera (`on`
// itself when the ray runs along that plane).
Vec3 point_in_view_plane(const Vec3& on, double x, double y, const Camera& camera, const Viewport& viewport);

// The parameter s of the point on + s·direction (direction unit length) closest to
// the ray through pixel (x, y); none when the line points at the eye.
std::optional<double> line_parameter_at_pixel(const Vec3& on, const Vec3& direction, double x, double y,
                                              const Camera& camera, const Viewport& viewport);

// Where a point that started at `from` goes when dragged to pixel (x, y): in the
// plane through `from` facing the camera, or along one axis (0 = x, 1 = y, 2 = z)
// through `from` to the point of that line closest to the pixel's ray.
Vec3 drag_point(const Vec3& from, double x, double y, const Camera& camera, const Viewport& viewport, int axis = -1);

}  // namespace vfsd::editor
