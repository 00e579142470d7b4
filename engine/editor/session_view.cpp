#include "editor/session_view.h"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include "gpu/gl.h"

namespace vfsd::editor {

void SessionView::draw(const EditorSession& session, Camera& camera, const Viewport& viewport) {
    // The renderer follows the mesh and the curve.
    if (!renderer_ || drawn_mesh_ != session.mesh_revision()) {
        renderer_ = std::make_unique<render::Renderer>(session.triangles(), session.motion());
        drawn_mesh_ = session.mesh_revision();
        drawn_curve_ = session.curve_revision();
        drawn_revision_ = 0;
    }
    if (drawn_curve_ != session.curve_revision()) {
        renderer_->set_motion(session.motion());
        drawn_curve_ = session.curve_revision();
    }
    // The GPU path's vertex texture as it is; the CPU path's positions uploaded on change.
    const std::optional<DeviceVertices> on_gpu =
        session.deformation() && !session.holding_result() ? session.deformation()->device_vertices() : std::nullopt;
    if (!on_gpu && drawn_revision_ != session.revision()) {
        render::update_vertex_texture(cpu_vertices_, session.positions(), session.s());
        drawn_revision_ = session.revision();
    }
    if (on_gpu) drawn_revision_ = 0;
    camera.scene_radius = std::max(camera.scene_radius, 0.5 * session.diagonal());
    const glm::mat4 view(camera.view()), projection(camera.projection(viewport.aspect()));
    render::RenderOptions options;
    options.current_time = session.time();
    options.target_time = session.target_time();
    options.wireframe = wireframe;
    if (on_gpu) options.vertex_origin = on_gpu->origin;
    options.highlight = &session.folded_triangles();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    renderer_->draw(on_gpu ? *on_gpu->texture : *cpu_vertices_, glm::value_ptr(view),
                    glm::value_ptr(projection), 0.018 * session.diagonal(), viewport.width, viewport.height, options);
}

void SessionView::reset() {
    renderer_.reset();
    cpu_vertices_.reset();
    drawn_mesh_ = drawn_curve_ = drawn_revision_ = 0;
}

}  // namespace vfsd::editor
