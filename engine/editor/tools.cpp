#include "editor/tools.h"

#include <cmath>

#include "base/error.h"
#include "curve/curve_on_region.h"
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
        case Tool::handle: return "handle";
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
    gizmo_part_ = GizmoPart::none;
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
    curve_start_ = points;
}

bool ToolController::press(EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                           double y) {
    message.clear();
    if (tool == Tool::navigate) return press_navigate(session, camera, viewport, x, y);
    const auto hit = session.pick_surface(camera.ray(x, y, viewport));
    if (!hit) return false;
    try {
        return press_on_surface(session, camera, viewport, *hit, x, y);
    } catch (const std::exception& e) {
        message = e.what();
        if (tool == Tool::loops) clear_loops();
        return true;
    }
}

bool ToolController::takes_press(const EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                                 double y) const {
    if (tool != Tool::navigate) return session.pick_surface(camera.ray(x, y, viewport)).has_value();
    const auto g = gizmo(session, camera, viewport);
    return (g && g->hit(x, y) != GizmoPart::none) || hovered_point(session, camera, viewport, x, y).has_value();
}

bool ToolController::press_navigate(EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                                    double y) {
    // The gizmo lies over the target point: it takes the press first.
    const auto g = gizmo(session, camera, viewport);
    const GizmoPart part = g ? g->hit(x, y) : GizmoPart::none;
    if (part != GizmoPart::none) {
        session.begin_curve_gesture();
        active_ = Active::gizmo;
        gizmo_part_ = part;
        gizmo_last_ = {x, y};
        return true;
    }
    const auto index = hovered_point(session, camera, viewport, x, y);
    if (!index) return false;
    press_control_point(session, *index);
    return true;
}

bool ToolController::press_on_surface(EditorSession& session, const Camera& camera, const Viewport& viewport,
                                      const SurfaceHit& hit, double x, double y) {
    switch (tool) {
        case Tool::geodesic: session.pick_geodesic(hit.nearest_vertex, g_min, g_max); return true;
        case Tool::loops: return click_loop_point(session, camera, viewport, hit, x, y);
        case Tool::handle: place_handle(session, camera, hit); return true;
        default:
            session.begin_region_gesture();
            active_ = Active::stroke;
            last_dab_.reset();
            dab(session, hit);
            return true;
    }
}

bool ToolController::click_loop_point(EditorSession& session, const Camera& camera, const Viewport& viewport,
                                      const SurfaceHit& hit, double x, double y) {
    if (loops_.size() >= 2) {
        // Both loops drawn: this click is the seed on the part that moves.
        session.set_region_from_loops(loops_[0], loops_[1], hit.point);
        clear_loops();
        return true;
    }
    // A click near the loop's first point closes it.
    if (current_.size() >= 3) {
        const glm::dvec3 first =
            camera.project(surface_position(session.positions(), session.triangles(), current_.front()), viewport);
        if (glm::length(glm::dvec2(first.x - x, first.y - y)) < 8.0) {
            close_loop();
            return true;
        }
    }
    current_.push_back(hit.point);
    return true;
}

void ToolController::place_handle(EditorSession& session, const Camera& camera, const SurfaceHit& hit) {
    // Handle mode (sec. 6.2): the handle sits on the surface, its normal along the
    // surface normal (toward the eye); its target starts a quarter diagonal further out.
    const Triangle& t = session.triangles()[hit.point.triangle];
    const auto& p = session.positions();
    Vec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    if (glm::length(n) == 0.0) throw InputError("handle: the surface has no normal here");
    n = glm::normalize(n);
    if (glm::dot(n, camera.forward()) > 0.0) n = -n;
    const Vec3 any = std::abs(n.x) < 0.9 ? Vec3(1.0, 0.0, 0.0) : Vec3(0.0, 1.0, 0.0);
    HandleFrame from;
    from.position = hit.position;
    from.normal = n;
    from.binormal = glm::normalize(glm::cross(n, any));
    HandleFrame to = from;
    to.position += 0.25 * session.diagonal() * n;
    session.use_handle(from, to);
    // The next drags move the target with the gizmo.
    tool = Tool::navigate;
    message = "handle placed: drag the gizmo on its target";
}

std::optional<HandleGizmo> ToolController::gizmo(const EditorSession& session, const Camera& camera,
                                                 const Viewport& viewport) const {
    const CurveSpec& c = session.curve().curve;
    if (!c.is_handle) return std::nullopt;
    return HandleGizmo(c.to, camera, viewport);
}

GizmoPart ToolController::highlighted_gizmo_part(const EditorSession& session, const Camera& camera,
                                                 const Viewport& viewport, double x, double y) const {
    if (active_ == Active::gizmo) return gizmo_part_;
    if (tool != Tool::navigate || active_ != Active::none) return GizmoPart::none;
    const auto g = gizmo(session, camera, viewport);
    return g ? g->hit(x, y) : GizmoPart::none;
}

void ToolController::drag_gizmo(EditorSession& session, const Camera& camera, const Viewport& viewport, double x,
                                double y) {
    // Each pointer move turns the current target by its own small step, so a ring
    // can be swept round more than half a turn.
    const HandleFrame from = session.curve().curve.from;
    const HandleGizmo g(session.curve().curve.to, camera, viewport);
    const HandleFrame to = g.drag(gizmo_part_, gizmo_last_, {x, y});
    gizmo_last_ = {x, y};
    session.use_handle(from, to);
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

// Where the dragged point goes. A control point moves on the plane through its
// start facing the view (or along the chosen axis). The curve's end knot, dragged
// free, lands on the surface under the pointer when there is one outside the
// inner region (which moves with the end): one drag puts the end, where the inner
// region's centre goes, onto or next to what it should reach; off the mesh it stays
// on the view plane through its start.
Vec3 ToolController::dragged_point_position(const EditorSession& session, const Camera& camera,
                                            const Viewport& viewport, double x, double y) {
    const CurveSpec& c = session.curve().curve;
    const bool end_knot = !c.is_handle && *point_ + 1 == c.bezier.size();
    if (end_knot && axis < 0) {
        if (const auto hit = session.pick_surface(camera.ray(x, y, viewport))) {
            const Triangle& t = session.triangles()[hit->point.triangle];
            const std::vector<double>& s = session.s();
            const Vec3& w = hit->point.barycentric;
            // s = 0 in the inner region (eq. 16): it moves with the end, no place to land.
            const double s_hit = s.size() == session.base_positions().size()
                                     ? w[0] * s[t[0]] + w[1] * s[t[1]] + w[2] * s[t[2]]
                                     : 1.0;
            if (s_hit > 1e-9) {
                hint = "curve end on the surface under the pointer";
                return hit->position;
            }
        }
        hint = "curve end on the view plane (over the mesh it lands on the surface)";
    }
    return drag_point(point_start_, x, y, camera, viewport, axis);
}

namespace {

// The control points as they were, the last segment turned and scaled about its
// first knot so that its end goes from where it was to `end`: the curve keeps its
// shape, so one drag of the end makes a whole new path.
std::vector<Vec3> end_segment_moved(std::vector<Vec3> b, const Vec3& end) {
    const std::size_t n = b.size();
    const Vec3 a = b[n - 4], from = b[n - 1] - a, to = end - a;
    b[n - 1] = end;
    const double lf = glm::length(from), lt = glm::length(to);
    if (lf < 1e-12 || lt < 1e-12) return b;
    const glm::dmat3 turn = turn_onto(from / lf, to / lt);
    for (std::size_t i = n - 3; i < n - 1; ++i) b[i] = a + (lt / lf) * (turn * (b[i] - a));
    return b;
}

}  // namespace

void ToolController::drag(EditorSession& session, const Camera& camera, const Viewport& viewport, double x, double y) {
    try {
        if (active_ == Active::point) {
            const Vec3 to = dragged_point_position(session, camera, viewport, x, y);
            MotionSpec next = session.curve();
            const std::vector<Vec3>& b = next.curve.bezier;
            if (!next.curve.is_handle && b.size() >= 4 && *point_ + 1 == b.size() && curve_start_.size() == b.size()) {
                next.curve.bezier = end_segment_moved(curve_start_, to);
                session.set_curve(next);
            } else {
                session.move_control_point(*point_, to);
            }
        } else if (active_ == Active::gizmo) {
            drag_gizmo(session, camera, viewport, x, y);
        } else if (active_ == Active::stroke) {
            const auto hit = session.pick_surface(camera.ray(x, y, viewport));
            if (hit) dab(session, *hit);
        }
    } catch (const std::exception& e) {
        message = e.what();
    }
}

void ToolController::release(EditorSession& session) {
    if (active_ == Active::point)
        session.end_curve_gesture("move control point " + std::to_string(*point_));
    else if (active_ == Active::gizmo)
        session.end_curve_gesture(is_ring(gizmo_part_) ? "rotate handle" : "move handle");
    else if (active_ == Active::stroke)
        session.end_region_gesture(tool_name(tool));
    active_ = Active::none;
    point_.reset();
    gizmo_part_ = GizmoPart::none;
    hint.clear();
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
