#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "base/error.h"
#include "gpu/capabilities.h"
#include "gpu/texture_layout.h"
#include "mesh/builtin_meshes.h"

namespace vfsd::render {

using gpu::Buffer;
using gpu::check_gl;
using gpu::check_gl_in_frame;
using gpu::Framebuffer;
using gpu::Texture;
using gpu::TextureLayout;
using gpu::VertexArray;

namespace {

constexpr int kCurveSamples = 256;

std::vector<glm::vec3> to_float(const std::vector<Vec3>& points) {
    std::vector<glm::vec3> out;
    out.reserve(points.size());
    for (const Vec3& p : points) out.emplace_back(p);
    return out;
}

// Every edge of the mesh once, as pairs of vertex indices.
std::vector<std::uint32_t> edge_indices(const std::vector<Triangle>& triangles) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    std::vector<std::uint32_t> out;
    for (const auto& [a, b] : edges) out.insert(out.end(), {a, b});
    return out;
}

// A vertex array with one vec3 attribute (location 0) and optionally indices.
void bind_points(const VertexArray& vao, const Buffer& points, const Buffer* indices) {
    vao.bind();
    glBindBuffer(GL_ARRAY_BUFFER, points.id());
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    if (indices) glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices->id());
    glBindVertexArray(0);
}

}  // namespace

Renderer::Renderer(const std::vector<Triangle>& triangles, InnerMotion motion)
    : motion_(std::move(motion)),
      triangles_(triangles),
      mesh_program_("mesh", {"mesh.vert"}, {"mesh.frag"}),
      solid_program_("curve and spheres", {"solid.vert"}, {"solid.frag"}) {
    // Mesh: triangle and edge indices into the vertex texture.
    triangle_index_count_ = static_cast<GLsizei>(3 * triangles.size());
    triangle_indices_ = Buffer(GL_ELEMENT_ARRAY_BUFFER, triangles.data(), triangles.size() * sizeof(Triangle));
    const std::vector<std::uint32_t> edges = edge_indices(triangles);
    edge_index_count_ = static_cast<GLsizei>(edges.size());
    upload_curve();
    // A unit icosphere for the time markers.
    const TriangleMesh sphere = make_builtin_mesh("sphere", 2);
    const std::vector<glm::vec3> sphere_f = to_float(sphere.positions);
    sphere_points_ = Buffer(GL_ARRAY_BUFFER, sphere_f.data(), sphere_f.size() * sizeof(glm::vec3));
    sphere_indices_ = Buffer(GL_ELEMENT_ARRAY_BUFFER, sphere.triangles.data(), sphere.triangles.size() * sizeof(Triangle));
    sphere_index_count_ = static_cast<GLsizei>(3 * sphere.triangles.size());
    bind_points(sphere_vao_, sphere_points_, &sphere_indices_);
    // The mesh's vertex array has no attributes: positions come from the texture.
    edge_indices_ = Buffer(GL_ELEMENT_ARRAY_BUFFER, edges.data(), edges.size() * sizeof(std::uint32_t));
    check_gl("setting up the renderer");
}

void Renderer::upload_curve() {
    // The curve, sampled.
    std::vector<Vec3> curve;
    if (!motion_.is_fixed_rotation())
        for (int i = 0; i <= kCurveSamples; ++i) curve.push_back(motion_.curve().at(double(i) / kCurveSamples).position);
    curve_point_count_ = static_cast<GLsizei>(curve.size());
    const std::vector<glm::vec3> curve_f = to_float(curve);
    curve_points_.update(GL_ARRAY_BUFFER, curve_f.data(), curve_f.size() * sizeof(glm::vec3));
    bind_points(curve_vao_, curve_points_, nullptr);
}

// A drawn frame's (every frame of a curve drag): checked as one, since in WebGL
// glGetError waits for the renderer to finish the last draw (in SwiftShader, 100 ms
// at 41k vertices).
void Renderer::set_motion(InnerMotion motion) {
    motion_ = std::move(motion);
    upload_curve();
    check_gl_in_frame("updating the curve");
}

void Renderer::draw(const Texture& vertex_texture, const Camera& camera, int width, int height,
                    const RenderOptions& options) const {
    const glm::mat4 view(camera.view()), projection(camera.projection(double(width) / double(height)));
    draw(vertex_texture, glm::value_ptr(view), glm::value_ptr(projection), 0.035 * camera.scene_radius, width, height,
         options);
}

void Renderer::draw(const Texture& vertex_texture, const float view[16], const float projection[16],
                    double marker_radius, int width, int height, const RenderOptions& options) const {
    glViewport(0, 0, width, height);
    glClearColor(0.94f, 0.94f, 0.95f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);

    // The mesh, from the vertex texture; pushed back a little so the wireframe shows.
    mesh_program_.use();
    // The texture's positions are relative to options.vertex_origin: moved there
    // in the view matrix, in double precision.
    float mesh_view[16];
    for (int i = 0; i < 16; ++i) mesh_view[i] = view[i];
    for (int row = 0; row < 4; ++row)  // view × translate(origin): column 3 += view's first three columns · origin
        mesh_view[12 + row] = float(double(view[12 + row]) + double(view[row]) * options.vertex_origin.x +
                                    double(view[4 + row]) * options.vertex_origin.y +
                                    double(view[8 + row]) * options.vertex_origin.z);
    mesh_program_.set_mat4("u_view", mesh_view);
    mesh_program_.set_mat4("u_projection", projection);
    mesh_program_.set("u_width", vertex_texture.width());
    mesh_program_.set("u_positions", 0);
    mesh_program_.set("u_wire", 0);
    vertex_texture.bind(0);
    mesh_vao_.bind();
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, triangle_indices_.id());
    glDrawElements(GL_TRIANGLES, triangle_index_count_, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (options.highlight && !options.highlight->empty()) {
        std::vector<Triangle> picked;
        for (const std::uint32_t t : *options.highlight)
            if (t < triangles_.size()) picked.push_back(triangles_[t]);
        highlight_indices_.update(GL_ELEMENT_ARRAY_BUFFER, picked.data(), picked.size() * sizeof(Triangle));
        mesh_program_.set("u_wire", 2);
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * picked.size()), GL_UNSIGNED_INT, nullptr);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, triangle_indices_.id());
    }
    if (options.wireframe) {
        mesh_program_.set("u_wire", 1);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, edge_indices_.id());
        glDrawElements(GL_LINES, edge_index_count_, GL_UNSIGNED_INT, nullptr);
    }

    // The curve and the two time spheres (white: current time, dark: target).
    solid_program_.use();
    solid_program_.set_mat4("u_view", view);
    solid_program_.set_mat4("u_projection", projection);
    const glm::mat4 identity(1.0f);
    if (options.show_curve && !motion_.is_fixed_rotation()) {
        solid_program_.set_mat4("u_model", glm::value_ptr(identity));
        solid_program_.set("u_colour", 0.1f, 0.1f, 0.1f);
        solid_program_.set("u_lit", 0);
        curve_vao_.bind();
        glDrawArrays(GL_LINE_STRIP, 0, curve_point_count_);
    }
    const float marker = float(marker_radius);
    solid_program_.set("u_lit", 1);
    sphere_vao_.bind();
    for (const auto& [time, grey] : {std::pair{options.target_time, 0.15f}, std::pair{options.current_time, 1.0f}}) {
        const glm::vec3 at(motion_.is_fixed_rotation() ? motion_.rotation_centre() : motion_.curve().at(time).position);
        const glm::mat4 model = glm::scale(glm::translate(identity, at), glm::vec3(marker));
        solid_program_.set_mat4("u_model", glm::value_ptr(model));
        solid_program_.set("u_colour", grey, grey, grey);
        glDrawElements(GL_TRIANGLES, sphere_index_count_, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
    check_gl_in_frame("drawing the scene");
}

Texture make_vertex_texture(const std::vector<Vec3>& positions, const std::vector<double>& s) {
    std::optional<Texture> texture;
    update_vertex_texture(texture, positions, s);
    return std::move(*texture);
}

void update_vertex_texture(std::optional<Texture>& texture, const std::vector<Vec3>& positions,
                           const std::vector<double>& s) {
    const TextureLayout layout = TextureLayout::for_count(positions.size(), gpu::query_capabilities().max_texture_size);
    std::vector<float> data(layout.texels() * 4, 0.0f);
    for (std::size_t v = 0; v < positions.size(); ++v) {
        data[4 * v] = float(positions[v].x);
        data[4 * v + 1] = float(positions[v].y);
        data[4 * v + 2] = float(positions[v].z);
        data[4 * v + 3] = v < s.size() ? float(s[v]) : 0.0f;
    }
    if (!texture || texture->width() != layout.width || texture->height() != layout.height)
        texture.emplace(GL_RGBA32F, layout.width, layout.height);
    texture->upload(data.data());
}

std::vector<std::uint8_t> render_image(const Renderer& renderer, const Texture& vertex_texture, const Camera& camera,
                                       int width, int height, const RenderOptions& options) {
    constexpr int kSuper = 2;
    const Texture colour(GL_RGBA8, kSuper * width, kSuper * height);
    const Framebuffer target(colour, true);
    target.bind();
    renderer.draw(vertex_texture, camera, kSuper * width, kSuper * height, options);
    const std::vector<std::uint8_t> big = target.read_rgba8();
    // Average 2 x 2 blocks, flipping rows so the top row comes first.
    std::vector<std::uint8_t> image(static_cast<std::size_t>(width) * height * 4);
    const int big_width = kSuper * width;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 4; ++c) {
                int sum = 0;
                for (int dy = 0; dy < kSuper; ++dy)
                    for (int dx = 0; dx < kSuper; ++dx)
                        sum += big[((std::size_t(kSuper * y + dy) * big_width) + kSuper * x + dx) * 4 + c];
                image[((std::size_t(height - 1 - y) * width) + x) * 4 + c] = std::uint8_t(sum / (kSuper * kSuper));
            }
    return image;
}

}  // namespace vfsd::render
