#pragma once
// Draws an EditorSession with the engine's renderer through an editor Camera: the
// part of the view both shells (desktop, web) share. It follows the session's
// revisions: a new mesh makes a new renderer, an edited curve is handed on, and the
// CPU path's positions are uploaded when they change; the GPU path's vertex
// texture is drawn directly (no read-back). Needs the application's current GL
// context; after a context loss, reset() drops every GL object.

#include <cstdint>
#include <memory>
#include <optional>

#include "view/camera.h"
#include "editor/session.h"
#include "render/renderer.h"

namespace vfsd::editor {

class SessionView {
public:
    bool wireframe = false;

    // Draws into the bound framebuffer (viewport size), clearing it first. Widens
    // the camera's clip planes to the mesh.
    void draw(const EditorSession& session, Camera& camera, const Viewport& viewport);
    void reset();

private:
    std::unique_ptr<render::Renderer> renderer_;
    std::optional<gpu::Texture> cpu_vertices_;
    std::uint64_t drawn_mesh_ = 0, drawn_curve_ = 0, drawn_revision_ = 0;
};

}  // namespace vfsd::editor
