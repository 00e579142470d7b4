#pragma once
// The editor's tools: what a press, drag and release of the pointer do in the
// viewport. The shell (GLFW or a browser) forwards pointer events here and
// navigates the camera itself when press() declines; scripts drive the same calls.
//
//   navigate  drag a control point (screen plane, or along one axis); the curve's
//             end knot, dragged free over the mesh, lands on the surface under the
//             pointer, its segment turned and scaled along (dragged_point_position,
//             tools.cpp); in handle
//             mode drag the target's gizmo (editor/handle_gizmo.h); elsewhere orbit
//   geodesic  click a vertex: the geodesic level region (eq. 15) with g_min / g_max
//   inner / outer / erase   paint labels with a geodesic brush (eq. 16 region)
//   paint s   pull s toward a value with a smooth brush
//   loops     click points of the inner loop, close it, the outer loop, close it,
//             then click the seed on the part that moves
//   handle    click the surface: a handle there (sec. 6.2), then back to navigate

#include <optional>
#include <string>
#include <vector>

#include "view/camera.h"
#include "editor/handle_gizmo.h"
#include "editor/picking.h"
#include "editor/session.h"

namespace vfsd::editor {

enum class Tool { navigate, geodesic, paint_inner, paint_outer, erase, paint_s, loops, handle };
inline constexpr Tool kAllTools[] = {Tool::navigate, Tool::geodesic, Tool::paint_inner, Tool::paint_outer,
                                     Tool::erase,    Tool::paint_s,  Tool::loops,       Tool::handle};

const char* tool_name(Tool tool);

class ToolController {
public:
    Tool tool = Tool::navigate;
    BrushSettings brush;
    double g_min = 0.1, g_max = 0.4;  // mesh units
    int axis = -1;                    // control point drags: -1 screen plane, 0/1/2 along x/y/z
    std::string message;              // the last error or hint for the user
    std::string hint;                 // what the drag under way does (shown while it lasts)

    // Sizes the brush and geodesic thresholds to a newly opened mesh.
    void adapt_to(const EditorSession& session);

    // Returns true when the press starts a tool action (otherwise: camera navigation).
    bool press(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y);
    // Whether press() at (x, y) would start one, now, without starting it.
    bool takes_press(const EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                     double y) const;
    void drag(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y);
    void release(EditorSession& session);
    bool active() const { return active_ != Active::none; }
    // Starts dragging control point `index` directly (scripts; the pointer finds it by pixel).
    void press_control_point(EditorSession& session, std::size_t index);

    // The control point under the pointer (for highlighting), if any.
    std::optional<std::size_t> hovered_point(const EditorSession& session, const Camera& camera,
                                             const Viewport& viewport, double x, double y) const;
    std::optional<std::size_t> dragged_point() const { return point_; }

    // Handle mode: the gizmo on the target pose (none otherwise), and the part to
    // highlight: the one dragged, else the one under the pointer.
    std::optional<HandleGizmo> gizmo(const EditorSession& session, const Camera& camera, const Viewport& viewport) const;
    GizmoPart highlighted_gizmo_part(const EditorSession& session, const Camera& camera, const Viewport& viewport,
                                     double x, double y) const;

    // Loops tool: the loops drawn so far and the one in progress.
    const std::vector<SurfaceLoop>& loops() const { return loops_; }
    const SurfaceLoop& loop_in_progress() const { return current_; }
    // Closes the loop in progress (the seed click follows after two loops).
    void close_loop();
    void clear_loops();

private:
    enum class Active { none, point, stroke, gizmo };
    bool press_navigate(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y);
    bool press_on_surface(EditorSession& session, const Camera& camera, const Viewport& viewport,
                          const SurfaceHit& hit, double x, double y);
    bool click_loop_point(EditorSession& session, const Camera& camera, const Viewport& viewport,
                          const SurfaceHit& hit, double x, double y);
    void place_handle(EditorSession& session, const Camera& camera, const SurfaceHit& hit);
    void drag_gizmo(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y);
    void dab(EditorSession& session, const SurfaceHit& hit);
    Vec3 dragged_point_position(const EditorSession& session, const Camera& camera, const Viewport& viewport,
                                double x, double y);

    Active active_ = Active::none;
    std::optional<std::size_t> point_;
    GizmoPart gizmo_part_ = GizmoPart::none;
    glm::dvec2 gizmo_last_{0.0};
    Vec3 point_start_{0.0};
    std::vector<Vec3> curve_start_;  // the control points when the drag began
    std::optional<Vec3> last_dab_;
    std::vector<SurfaceLoop> loops_;
    SurfaceLoop current_;
};

}  // namespace vfsd::editor
