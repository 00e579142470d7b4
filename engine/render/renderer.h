#pragma once
// The view both apps share, as in the paper's figures: the mesh with s colour-coded
// blue (0) to red (1) and the separation lines between the three regions
// highlighted, the curve c(t), a small white sphere at the current time and a dark
// one at the target time, optionally the wireframe. The mesh is drawn straight
// from a vertex texture (xyz + s) by gl_VertexID, so display needs no read-back.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "curve/inner_motion.h"
#include "gpu/gl_objects.h"
#include "mesh/triangle_mesh.h"
#include "view/camera.h"

namespace vfsd::render {

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

    // Draws into the bound framebuffer (viewport width x height), clearing it first,
    // with time markers sized to the camera's scene radius.
    void draw(const gpu::Texture& vertex_texture, const Camera& camera, int width, int height,
              const RenderOptions& options) const;
    // The same with the caller's column-major view and projection matrices (an
    // editor's camera) and the radius of the time spheres in scene units.
    void draw(const gpu::Texture& vertex_texture, const float view[16], const float projection[16], double marker_radius,
              int width, int height, const RenderOptions& options) const;
    // Draws this motion's curve and time spheres from now on (an edited curve),
    // keeping the mesh's buffers.
    void set_motion(InnerMotion motion);

private:
    void upload_curve();

    InnerMotion motion_;
    std::vector<Triangle> triangles_;
    gpu::Program mesh_program_, solid_program_;
    gpu::Buffer triangle_indices_, edge_indices_, curve_points_, sphere_points_, sphere_indices_;
    mutable gpu::Buffer highlight_indices_;  // the folded triangles, refilled by each draw that shows them
    gpu::VertexArray mesh_vao_, curve_vao_, sphere_vao_;
    GLsizei triangle_index_count_ = 0, edge_index_count_ = 0, curve_point_count_ = 0, sphere_index_count_ = 0;
};

// A vertex texture (xyz + s, RGBA32F, TextureLayout) holding given positions: how
// the CPU path's result is drawn by the same renderer.
gpu::Texture make_vertex_texture(const std::vector<Vec3>& positions, const std::vector<double>& s);
// The same into `texture`, reused while its size fits: a new GL texture every frame
// costs a synchronous round trip in WebGL (the page's frames while a run plays).
void update_vertex_texture(std::optional<gpu::Texture>& texture, const std::vector<Vec3>& positions,
                           const std::vector<double>& s);

// Renders off-screen at `width` x `height` (supersampled 2 x 2) and returns the
// RGBA8 image, top row first (one counted read-back).
std::vector<std::uint8_t> render_image(const Renderer& renderer, const gpu::Texture& vertex_texture,
                                       const Camera& camera, int width, int height, const RenderOptions& options);

}  // namespace vfsd::render
