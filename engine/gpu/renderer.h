#pragma once
// The view both apps share, as in the paper's figures: the mesh with s colour-coded
// blue (0) to red (1) and the separation lines between the three regions
// highlighted, the curve c(t), a small white sphere at the current time and a dark
// one at the target time, optionally the wireframe. The mesh is drawn straight
// from a vertex texture (xyz + s) by gl_VertexID, so display needs no read-back.

#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "curve/inner_motion.h"
#include "gpu/gl_objects.h"
#include "mesh/triangle_mesh.h"

namespace vfsd::gpu {

// A camera looking at a bounding sphere from a fixed 3/4 direction (z up).
struct Camera {
    Vec3 centre{0.0};
    double radius = 1.0;
    double fov_degrees = 30.0;
    // From the centre towards the eye (unit), and the world direction that is up
    // on the screen: a 3/4 view from front right, above, with z up.
    Vec3 direction = glm::normalize(Vec3(1.0, -1.6, 0.9));
    Vec3 up{0.0, 0.0, 1.0};
    // Frames `points` (e.g. the mesh and the curve) from above front right.
    static Camera framing(const std::vector<Vec3>& points);
    // Looks from a named side: front, back, right, left, top, bottom or iso (the
    // default 3/4 view), with `up_axis` 'z' (z up, front = from −y, as the editors)
    // or 'y' (y up, front = from +z). Throws InputError for another name.
    void look_from(const std::string& view, char up_axis);
    // Column-major view and projection matrices for an image of the given aspect.
    void matrices(double aspect, float view[16], float projection[16]) const;
};

struct RenderOptions {
    double current_time = 0.0;  // white sphere at c(current_time)
    double target_time = 1.0;   // dark sphere at c(target_time)
    bool wireframe = false;
    bool show_curve = true;
    Vec3 vertex_origin{0.0};  // what the vertex texture's positions are relative to (GpuPasses::vertex_origin)
    // Triangles to draw in magenta (indices into the renderer's triangles): the
    // folds the editors highlight. Not owned; null or empty for none.
    const std::vector<std::uint32_t>* highlight = nullptr;
};

class Renderer {
public:
    // Needs a current GL context. `triangles` index the vertex texture's texels.
    Renderer(const std::vector<Triangle>& triangles, InnerMotion motion);

    // Draws into the bound framebuffer (viewport width x height), clearing it first.
    void draw(const Texture& vertex_texture, const Camera& camera, int width, int height,
              const RenderOptions& options) const;
    // The same with the caller's column-major view and projection matrices (an
    // editor's camera) and the radius of the time spheres in scene units.
    void draw(const Texture& vertex_texture, const float view[16], const float projection[16], double marker_radius,
              int width, int height, const RenderOptions& options) const;
    // Draws this motion's curve and time spheres from now on (an edited curve),
    // keeping the mesh's buffers.
    void set_motion(InnerMotion motion);

private:
    void upload_curve();

    InnerMotion motion_;
    std::vector<Triangle> triangles_;
    Program mesh_program_, solid_program_;
    Buffer triangle_indices_, edge_indices_, curve_points_, sphere_points_, sphere_indices_;
    VertexArray mesh_vao_, curve_vao_, sphere_vao_;
    GLsizei triangle_index_count_ = 0, edge_index_count_ = 0, curve_point_count_ = 0, sphere_index_count_ = 0;
};

// A vertex texture (xyz + s, RGBA32F, TextureLayout) holding given positions: how
// the CPU path's result is drawn by the same renderer.
Texture make_vertex_texture(const std::vector<Vec3>& positions, const std::vector<double>& s);

// Renders off-screen at `width` x `height` (supersampled 2 x 2) and returns the
// RGBA8 image, top row first (one counted read-back).
std::vector<std::uint8_t> render_image(const Renderer& renderer, const Texture& vertex_texture,
                                       const Camera& camera, int width, int height, const RenderOptions& options);

// Writes an RGBA8 image (top row first) as PNG, atomically.
void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgba);

}  // namespace vfsd::gpu
