#include "editor/tools.h"

#include "base/error.h"
#include "editor/picking.h"

namespace vfsd::editor {

const char* tool_name(Tool tool) {
    switch (tool) {
        case Tool::navigate: return "navigate";
        case Tool::geodesic: return "geodesic";
        case Tool::paint_inner: return "paint inner";
        case Tool::paint_outer: return "paint outer";
        case Tool::erase: return "erase";
        case Tool::paint_s: return "paint s";
        case Tool::loops: return "loops";
    }
    return "?";
}

void ToolController::adapt_to(const EditorSession& session) {
    const double d = session.diagonal();
    brush.radius = 0.06 * d;
    const RegionSource& r = session.region();
    if (r.kind == RegionSource::Kind::spec && r.spec.kind == RegionSpec::Kind::geodesic) {
        g_min = r.spec.g_min, g_max = r.spec.g_max;
    } else {
        g_min = 0.1 * d, g_max = 0.35 * d;
    }
    clear_loops();
    active_ = Active::none;
    point_.reset();
}

std::optional<std::size_t> ToolController::hovered_point(const EditorSession& session, const Camera& camera,
                                                         const Viewport& viewport, double x, double y) const {
    return pick_screen_point(session.control_points(), x, y, camera, viewport, 10.0);
}

void ToolController::press_control_point(EditorSession& session, std::size_t index) {
    const std::vector<Vec3> points = session.control_points();
    if (index >= points.size()) throw InputError("control point " + std::to_string(index) + " does not exist");
    session.begin_curve_gesture();
    active_ = Active::point;
    point_ = index;
    point_start_ = points[index];
}

bool ToolController::press(EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                           double y) {
    message.clear();
    if (tool == Tool::navigate) {
        const auto index = hovered_point(session, camera, viewport, x, y);
        if (!index) return false;
        press_control_point(session, *index);
        return true;
    }
    const auto hit = pick_surface(camera.ray(x, y, viewport), session.positions(), session.triangles());
    if (!hit) return false;
    try {
        switch (tool) {
            case Tool::geodesic: session.pick_geodesic(hit->nearest_vertex, g_min, g_max); return true;
            case Tool::loops: {
                if (loops_.size() < 2) {
                    // A click near the loop's first point closes it.
                    if (current_.size() >= 3) {
                        const glm::dvec3 first = camera.project(
                            surface_position(session.positions(), session.triangles(), current_.front()), viewport);
                        if (glm::length(glm::dvec2(first.x - x, first.y - y)) < 8.0) {
                            close_loop();
                            return true;
                        }
                    }
                    current_.push_back(hit->point);
                    return true;
                }
                session.set_region_from_loops(loops_[0], loops_[1], hit->point);
                clear_loops();
                return true;
            }
            default:
                session.begin_region_gesture();
                active_ = Active::stroke;
                last_dab_.reset();
                dab(session, *hit);
                return true;
        }
    } catch (const std::exception& e) {
        message = e.what();
        if (tool == Tool::loops) clear_loops();
        return true;
    }
}

void ToolController::dab(EditorSession& session, const SurfaceHit& hit) {
    // Dabs a quarter radius apart make a continuous stroke.
    if (last_dab_ && glm::length(hit.position - *last_dab_) < 0.25 * brush.radius) return;
    last_dab_ = hit.position;
    BrushSettings b = brush;
    b.tool = tool == Tool::paint_inner   ? BrushTool::paint_inner
             : tool == Tool::paint_outer ? BrushTool::paint_outer
             : tool == Tool::erase       ? BrushTool::erase
                                         : BrushTool::paint_s;
    session.brush(hit.point, b);
}

void ToolController::drag(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y) {
    try {
        if (active_ == Active::point) {
            session.move_control_point(*point_, drag_point(point_start_, x, y, camera, viewport, axis));
        } else if (active_ == Active::stroke) {
            const auto hit = pick_surface(camera.ray(x, y, viewport), session.positions(), session.triangles());
            if (hit) dab(session, *hit);
        }
    } catch (const std::exception& e) {
        message = e.what();
    }
}

void ToolController::release(EditorSession& session) {
    if (active_ == Active::point)
        session.end_curve_gesture("move control point " + std::to_string(*point_));
    else if (active_ == Active::stroke)
        session.end_region_gesture(tool_name(tool));
    active_ = Active::none;
    point_.reset();
}

void ToolController::close_loop() {
    if (current_.size() < 3) {
        message = "a loop needs at least 3 points";
        return;
    }
    loops_.push_back(std::move(current_));
    current_.clear();
    message = loops_.size() == 1 ? "inner loop closed: now draw the outer loop"
                                 : "outer loop closed: click the part that moves";
}

void ToolController::clear_loops() {
    loops_.clear();
    current_.clear();
}

}  // namespace vfsd::editor
