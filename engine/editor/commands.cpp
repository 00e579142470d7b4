#include "editor/commands.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include <glm/trigonometric.hpp>

#include "base/error.h"
#include "editor/picking.h"
#include "scene/framing.h"

namespace vfsd::editor {
namespace {

using nlohmann::json;

// ---- argument checks --------------------------------------------------------------

bool is_pair(const json& v) { return v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number(); }

bool is_triple(const json& v) {
    return v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number();
}

bool is_pair_list(const json& v) {
    return v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), [](const json& p) { return is_pair(p); });
}

bool is_one_of(const std::string& value, const char* choices) {
    std::istringstream list(choices);
    std::string choice;
    while (std::getline(list, choice, '|'))
        if (choice == value) return true;
    return false;
}

const char* expected(ArgType type) {
    switch (type) {
        case ArgType::number: return "a number";
        case ArgType::integer: return "a whole number";
        case ArgType::boolean: return "true or false";
        case ArgType::text: return "a string";
        case ArgType::pixel: return "[x, y] in pixels";
        case ArgType::pixels: return "a list of [x, y]";
        case ArgType::pair: return "[a, b]";
        case ArgType::triple: return "[a, b, c]";
    }
    return "?";
}

bool fits(const json& v, ArgType type) {
    switch (type) {
        case ArgType::number: return v.is_number();
        case ArgType::integer: return v.is_number() && v.get<double>() == std::floor(v.get<double>());
        case ArgType::boolean: return v.is_boolean();
        case ArgType::text: return v.is_string();
        case ArgType::pixel:
        case ArgType::pair: return is_pair(v);
        case ArgType::pixels: return is_pair_list(v);
        case ArgType::triple: return is_triple(v);
    }
    return false;
}

void check_argument(const ArgSpec& spec, const json& v) {
    if (!fits(v, spec.type)) throw InputError(std::string(spec.name) + ": expected " + expected(spec.type));
    if (spec.choices && !is_one_of(v.get<std::string>(), spec.choices))
        throw InputError(std::string(spec.name) + ": expected " + spec.choices + ", not '" + v.get<std::string>() + "'");
}

// ---- the pointer, as scripts move it -------------------------------------------------

SurfacePoint surface_point_at_pixel(const CommandContext& c, glm::dvec2 p) {
    const auto hit = c.session.pick_surface(c.camera.ray(p.x, p.y, c.viewport));
    if (!hit) throw InputError("no surface under pixel (" + std::to_string(int(p.x)) + ", " + std::to_string(int(p.y)) + ")");
    return hit->point;
}

SurfaceLoop loop_at_pixels(const CommandContext& c, const std::vector<glm::dvec2>& points) {
    SurfaceLoop loop;
    for (const glm::dvec2& p : points) loop.push_back(surface_point_at_pixel(c, p));
    return loop;
}

Tool paint_tool(const std::string& name) {
    if (name == "inner") return Tool::paint_inner;
    if (name == "outer") return Tool::paint_outer;
    if (name == "erase") return Tool::erase;
    return Tool::paint_s;
}

// Any tool: by tool_name's names, or the brushes by paint's short names.
Tool any_tool(const std::string& name) {
    for (Tool t : kAllTools)
        if (name == tool_name(t)) return t;
    if (!is_one_of(name, "inner|outer|erase|s")) throw InputError("name: unknown tool '" + name + "'");
    return paint_tool(name);
}

// `steps` evenly spaced points from `from` (excluded) to `to`.
std::vector<glm::dvec2> straight_path(glm::dvec2 from, glm::dvec2 to, int steps) {
    std::vector<glm::dvec2> path;
    for (int k = 1; k <= steps; ++k) path.push_back(glm::mix(from, to, double(k) / steps));
    return path;
}

// Moves the pressed pointer through `path`, releases it, and fails with the tools' message.
void drag_and_release(CommandContext& c, const std::vector<glm::dvec2>& path) {
    for (const glm::dvec2& p : path) c.tools.drag(c.session, c.camera, c.viewport, p.x, p.y);
    c.tools.release(c.session);
}

void check_tool_message(const CommandContext& c) {
    if (!c.tools.message.empty()) throw InputError(c.tools.message);
}

int axis_index(const std::string& name) { return name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1; }

// The pointer's path for a gizmo drag from `grab`: to a pixel ("to"), by an offset
// ("by"), or (rings) round the gizmo's centre by "degrees", counter-clockwise on
// screen, in steps of at most 5 degrees.
std::vector<glm::dvec2> gizmo_path(const CommandArgs& a, glm::dvec2 grab, glm::dvec2 centre) {
    std::vector<glm::dvec2> path;
    if (a.has("degrees")) {
        const double degrees = a.number("degrees"), radius = glm::length(grab - centre);
        const double start = std::atan2(-(grab.y - centre.y), grab.x - centre.x);
        const int steps = std::max(1, int(std::ceil(std::abs(degrees) / 5.0)));
        for (int k = 1; k <= steps; ++k) {
            const double angle = start + glm::radians(degrees) * k / steps;
            path.push_back(centre + radius * glm::dvec2(std::cos(angle), -std::sin(angle)));
        }
        return path;
    }
    if (!a.has("by") && !a.has("to")) throw InputError("to: expected [x, y] in pixels");
    return straight_path(grab, a.has("by") ? grab + a.pair("by") : a.pair("to"), 8);
}

// ---- the commands ---------------------------------------------------------------------

bool load(const CommandArgs& a, CommandContext& c) {
    c.session.open(a.text("path"));
    c.tools.adapt_to(c.session);
    c.host.loaded();
    return true;
}

std::uint32_t vertex_of(const SurfacePoint& sp, const EditorSession& session) {
    check_surface_point(sp, session.triangles().size(), "pick");
    const Triangle& t = session.triangles()[sp.triangle];
    const Vec3& w = sp.barycentric;
    return t[w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2)];
}

bool pick(const CommandArgs& a, CommandContext& c) {
    c.tools.g_min = a.number_or("g_min", c.tools.g_min);
    c.tools.g_max = a.number_or("g_max", c.tools.g_max);
    std::uint32_t vertex = 0;
    if (a.has("at")) {
        const glm::dvec2 p = a.pair("at");
        const auto hit = c.session.pick_surface(c.camera.ray(p.x, p.y, c.viewport));
        if (!hit) throw InputError("no surface under the pixel");
        vertex = hit->nearest_vertex;
    } else if (a.has("vertex")) {
        vertex = static_cast<std::uint32_t>(a.integer("vertex"));
    } else {
        SurfacePoint sp;
        sp.triangle = static_cast<std::uint32_t>(a.integer("triangle"));
        sp.barycentric = a.triple("barycentric");
        vertex = vertex_of(sp, c.session);
    }
    c.session.pick_geodesic(vertex, c.tools.g_min, c.tools.g_max);
    return true;
}

bool brush(const CommandArgs& a, CommandContext& c) {
    BrushSettings& b = c.tools.brush;
    b.radius = a.number_or("radius", b.radius);
    b.s_target = a.number_or("target", b.s_target);
    b.strength = a.number_or("strength", b.strength);
    return true;
}

bool paint(const CommandArgs& a, CommandContext& c) {
    brush(a, c);
    const std::vector<glm::dvec2> points = a.pixels("points");
    const Tool previous = c.tools.tool;
    c.tools.tool = paint_tool(a.text("tool"));
    if (!c.tools.press(c.session, c.camera, c.viewport, points[0].x, points[0].y))
        throw InputError("the stroke does not start on the surface");
    // Through every point, in steps of at most 4 pixels, as a pointer would move.
    std::vector<glm::dvec2> path;
    for (std::size_t i = 1; i < points.size(); ++i) {
        const int steps = std::max(1, int(std::ceil(glm::length(points[i] - points[i - 1]) / 4.0)));
        for (const glm::dvec2& p : straight_path(points[i - 1], points[i], steps)) path.push_back(p);
    }
    drag_and_release(c, path);
    c.tools.tool = previous;
    check_tool_message(c);
    return true;
}

bool loops(const CommandArgs& a, CommandContext& c) {
    c.session.set_region_from_loops(loop_at_pixels(c, a.pixels("inner")), loop_at_pixels(c, a.pixels("outer")),
                                    surface_point_at_pixel(c, a.pair("seed")));
    return true;
}

bool drag(const CommandArgs& a, CommandContext& c) {
    const int previous_axis = c.tools.axis;
    c.tools.axis = a.has("axis") ? axis_index(a.text("axis")) : -1;
    const auto index = static_cast<std::size_t>(a.integer("index"));
    if (index >= c.session.control_points().size()) throw InputError("index: no control point " + std::to_string(index));
    c.tools.press_control_point(c.session, index);
    const glm::dvec3 from3 = c.camera.project(c.session.control_points()[index], c.viewport);
    drag_and_release(c, straight_path(glm::dvec2(from3.x, from3.y), a.pair("to"), 8));
    c.tools.axis = previous_axis;
    check_tool_message(c);
    return true;
}

bool place_handle(const CommandArgs& a, CommandContext& c) {
    const glm::dvec2 at = a.pair("at");
    const Tool previous = c.tools.tool;
    c.tools.tool = Tool::handle;
    c.tools.press(c.session, c.camera, c.viewport, at.x, at.y);
    c.tools.release(c.session);
    const bool placed = c.tools.tool == Tool::navigate;  // the handle tool hands over to navigate
    c.tools.tool = previous;
    if (!placed) throw InputError(c.tools.message.empty() ? "no surface under the pixel" : c.tools.message);
    c.tools.message.clear();
    return true;
}

// Presses on the part's grab point as a pointer would, moves along the path, releases.
bool gizmo(const CommandArgs& a, CommandContext& c) {
    const GizmoPart part = parse_gizmo_part(a.text("part"));
    const auto shown = c.tools.gizmo(c.session, c.camera, c.viewport);
    if (!shown) throw InputError("no handle: place one first (place-handle)");
    const auto grab = shown->grab_point(part);
    if (!grab) throw InputError(std::string(gizmo_part_name(part)) + " is not visible from this view");
    const std::vector<glm::dvec2> path = gizmo_path(a, *grab, shown->centre());
    const Tool previous = c.tools.tool;
    c.tools.tool = Tool::navigate;
    c.tools.press(c.session, c.camera, c.viewport, grab->x, grab->y);
    const GizmoPart held = c.tools.highlighted_gizmo_part(c.session, c.camera, c.viewport, grab->x, grab->y);
    drag_and_release(c, held == part ? path : std::vector<glm::dvec2>());
    c.tools.tool = previous;
    if (held != part) throw InputError(std::string("the press grabbed ") + gizmo_part_name(held));
    check_tool_message(c);
    return true;
}

// A curve setting changed: one undo step, or part of the slider drag under way.
void change_curve(const CommandArgs& a, CommandContext& c, const MotionSpec& curve) {
    if (a.boolean_or("gesture", false) && !c.settings.curve_gesture) {
        c.settings.curve_gesture = true;
        c.session.begin_curve_gesture();
    }
    c.session.set_curve(curve);
}

bool twist(const CommandArgs& a, CommandContext& c) {
    MotionSpec curve = c.session.curve();
    const glm::dvec2 alpha = a.pair("alpha");
    curve.twist_degrees[0] = alpha[0];
    curve.twist_degrees[1] = alpha[1];
    change_curve(a, c, curve);
    return true;
}

bool inner_motion(const CommandArgs& a, CommandContext& c) {
    MotionSpec curve = c.session.curve();
    curve.inner_motion = a.text("mode") == "rotation" ? InnerMotionMode::Rotation : InnerMotionMode::Translation;
    change_curve(a, c, curve);
    return true;
}

// The geodesic region's thresholds (eq. 15), kept apart by a hair of the diagonal.
bool g_range(const CommandArgs& a, CommandContext& c) {
    const double d = c.session.diagonal();
    const double lo = a.number_or("g_min", c.tools.g_min), hi = a.number_or("g_max", c.tools.g_max);
    c.tools.g_min = std::min(lo, hi - 1e-4 * d);
    c.tools.g_max = std::max(hi, lo + 1e-4 * d);
    if (a.boolean_or("gesture", false) && !c.settings.region_gesture) {
        c.settings.region_gesture = true;
        c.session.begin_region_gesture();
    }
    c.session.set_geodesic_range(c.tools.g_min, c.tools.g_max);
    return true;
}

bool region_band(const CommandArgs& a, CommandContext& c) {
    if (a.boolean_or("gesture", false) && !c.settings.region_gesture) {
        c.settings.region_gesture = true;
        c.session.begin_region_gesture();
    }
    c.session.set_region_band(a.number("band"));
    return true;
}

// The scene's up axis; the view turns to keep its direction about the new axis, framed.
bool up_axis(const CommandArgs& a, CommandContext& c) {
    const std::string axis = a.text("axis");
    c.camera.up_axis = up_axis_named(axis);
    c.session.set_up_axis(axis[0]);
    frame_session(c.camera, c.session, c.viewport);
    return true;
}

bool end_gesture(const CommandArgs&, CommandContext& c) {
    if (c.settings.region_gesture) c.session.end_region_gesture("region slider");
    if (c.settings.curve_gesture) c.session.end_curve_gesture("curve settings");
    c.settings.region_gesture = c.settings.curve_gesture = false;
    return true;
}

bool brush_size(const CommandArgs& a, CommandContext& c) {
    c.tools.brush.radius *= std::pow(1.2, double(a.integer("step")));
    return true;
}

bool axis(const CommandArgs& a, CommandContext& c) {
    c.tools.axis = axis_index(a.text("name"));
    return true;
}

bool toggle_axis(const CommandArgs& a, CommandContext& c) {
    const int axis = axis_index(a.text("name"));
    c.tools.axis = c.tools.axis == axis ? -1 : axis;
    return true;
}

bool set_time(const CommandArgs& a, CommandContext& c) {
    c.session.set_target_time(a.number("t"));
    return true;
}

bool wait_until_time(const CommandArgs& a, CommandContext& c) {
    const double t = a.number("t");
    if (std::abs(c.session.time() - t) <= 1e-9) return true;
    if (!c.session.moving())  // stopped elsewhere: another target, or an error
        throw InputError("time stopped at " + std::to_string(c.session.time()) + " (target " +
                         std::to_string(c.session.target_time()) + ")");
    return false;
}

bool play_pause(const CommandArgs&, CommandContext& c) {
    c.session.moving() ? c.session.pause() : c.session.play();
    return true;
}

bool view(const CommandArgs& a, CommandContext& c) {
    const std::string name = a.text("name");
    if (name != "frame") c.camera.set_view(standard_view_named(name));
    frame_session(c.camera, c.session, c.viewport);
    return true;
}

// One frame of an orbit: the camera turns by 1/frames of "degrees" (yaw, pitch);
// false until it has turned all the way. The first frame places the pointer and
// starts the host's frame log; the command ends on the frame after the last turn,
// so the host has logged every turning frame whole.
bool orbit(const CommandArgs& a, CommandContext& c) {
    const int frames = int(a.integer("frames"));
    if (frames < 1) throw InputError("frames: expected at least 1");
    if (c.frame == 0) {
        if (a.has("pointer")) {
            const glm::dvec2 p = a.pair("pointer");
            c.host.point_at(p.x, p.y);
        }
        c.host.log_frame_times(frames);
    }
    if (c.frame >= frames) return true;
    const glm::dvec2 step = glm::radians(a.pair("degrees")) / (kOrbitRadiansPerPixel * frames);
    c.camera.orbit(-step.x, step.y);
    return false;
}

bool wireframe(const CommandArgs& a, CommandContext& c) {
    c.settings.wireframe = a.boolean_or("on", !c.settings.wireframe);
    return true;
}

bool force_cpu(const CommandArgs& a, CommandContext& c) {
    c.settings.force_cpu = a.boolean_or("on", true);
    c.session.set_force_cpu(c.settings.force_cpu);
    return true;
}

bool restore_autosave(const CommandArgs& a, CommandContext& c) {
    c.host.answer_restore(a.text("answer") == "restore");
    return true;
}

bool expect(const CommandArgs& a, CommandContext& c) {
    const EditorSession& s = c.session;
    if (a.has("time") && std::abs(s.time() - a.number("time")) > 1e-9)
        throw InputError("time is " + std::to_string(s.time()));
    if (a.has("undo_count") && s.history().undo_count() != std::size_t(a.integer("undo_count")))
        throw InputError("undo count is " + std::to_string(s.history().undo_count()));
    if (a.has("warnings") && s.warnings().size() != std::size_t(a.integer("warnings")))
        throw InputError(std::to_string(s.warnings().size()) + " warnings");
    return true;
}

// A command that calls one session or tool function.
#define VFSD_CALL(body) [](const CommandArgs&, CommandContext& c) { body; return true; }

constexpr const char* kToolNames = "navigate|geodesic|paint inner|paint outer|erase|paint s|loops|handle|inner|outer|s";
constexpr const char* kGizmoPartNames = "centre|x|y|z|ring-x|ring-y|ring-z";

using T = ArgType;

const std::vector<Command> kCommands = {
    // ---- files
    {"load", "open a mesh or a scene (.json)", {{"path", T::text, true, "file or builtin:NAME"}}, load},
    {"export", "write the current shape (.obj .ply .glb .off)", {{"path", T::text, true, "output file"}},
     [](const CommandArgs& a, CommandContext& c) { c.session.export_mesh(a.text("path")); return true; }},
    {"save-scene", "write the session as a scene file `vfsd deform` reproduces", {{"path", T::text, true, "output file"}},
     [](const CommandArgs& a, CommandContext& c) { c.session.save_scene(a.text("path")); return true; }},
    {"screenshot", "save the next frame as PNG", {{"path", T::text, true, "output file"}, {"ui", T::boolean, false, "with the panels (default true)"}},
     [](const CommandArgs& a, CommandContext& c) { c.host.screenshot(a.text("path"), a.boolean_or("ui", true)); return true; }},
    // ---- region
    {"pick", "geodesic region around a vertex (eq. 15)",
     {{"at", T::pixel, false, "the vertex nearest the surface under the pixel"}, {"vertex", T::integer, false, "or a vertex index"},
      {"triangle", T::integer, false, "or a surface point: triangle"}, {"barycentric", T::triple, false, "and its barycentric coordinates"},
      {"g_min", T::number, false, "mesh units"}, {"g_max", T::number, false, "mesh units"}}, pick},
    {"g-range", "the geodesic region's g_min and g_max", {{"g_min", T::number, false, "mesh units"}, {"g_max", T::number, false, "mesh units"},
     {"gesture", T::boolean, false, "part of a slider drag (one undo step until end-gesture)"}}, g_range},
    {"paint", "a brush stroke through the points",
     {{"tool", T::text, true, "brush", "inner|outer|erase|s"}, {"points", T::pixels, true, "the stroke"},
      {"radius", T::number, false, "mesh units"}, {"target", T::number, false, "tool s: the value s is pulled toward"},
      {"strength", T::number, false, "tool s: how far each dab pulls"}}, paint},
    {"loops", "region between two boundary loops, the seed side moving",
     {{"inner", T::pixels, true, "inner loop"}, {"outer", T::pixels, true, "outer loop"}, {"seed", T::pixel, true, "on the part that moves"}}, loops},
    {"new-region", "a clean painted region: nothing inner or outer yet", {}, VFSD_CALL(c.session.new_region())},
    {"region-band", "the painted region's transition band: an inner region alone blends over it",
     {{"band", T::number, true, "mesh units"}, {"gesture", T::boolean, false, "part of a slider drag"}}, region_band},
    {"close-loop", "close the loop in progress (loops tool)", {}, VFSD_CALL(c.tools.close_loop())},
    {"clear-loops", "drop the loops drawn so far", {}, VFSD_CALL(c.tools.clear_loops())},
    // ---- curve and handle
    {"drag", "drag a control point to a pixel",
     {{"index", T::integer, true, "control point"}, {"to", T::pixel, true, "where"}, {"axis", T::text, false, "along one axis", "x|y|z"}}, drag},
    {"add-segment", "append a Bezier segment to the curve", {}, VFSD_CALL(c.session.add_segment())},
    {"remove-segment", "drop the curve's last segment", {}, VFSD_CALL(c.session.remove_segment())},
    {"place-handle", "a handle (sec. 6.2) on the surface under the pixel", {{"at", T::pixel, true, "where"}}, place_handle},
    {"gizmo", "drag a part of the handle's gizmo",
     {{"part", T::text, true, "which", kGizmoPartNames}, {"to", T::pixel, false, "to a pixel"}, {"by", T::pixel, false, "or by an offset"},
      {"degrees", T::number, false, "or (rings) by an angle, counter-clockwise on screen"}}, gizmo},
    {"twist", "twist angles at the curve's ends (eq. 14)",
     {{"alpha", T::pair, true, "[alpha0, alpha1] in degrees"}, {"gesture", T::boolean, false, "part of a slider drag"}}, twist},
    {"inner-motion", "how the inner region follows the curve",
     {{"mode", T::text, true, "mode", "rotation|translation"}, {"gesture", T::boolean, false, "part of a slider drag"}}, inner_motion},
    {"end-gesture", "end a slider drag: its changes become one undo step", {}, end_gesture},
    {"axis", "constrain control point drags", {{"name", T::text, true, "axis", "free|x|y|z"}}, axis},
    {"toggle-axis", "constrain drags to an axis, or free them again", {{"name", T::text, true, "axis", "x|y|z"}}, toggle_axis},
    // ---- tools
    {"tool", "choose the pointer's tool", {{"name", T::text, true, "tool", kToolNames}},
     [](const CommandArgs& a, CommandContext& c) { c.tools.tool = any_tool(a.text("name")); return true; }},
    {"brush", "brush settings", {{"radius", T::number, false, "mesh units"}, {"target", T::number, false, "tool s: the value s is pulled toward"},
     {"strength", T::number, false, "tool s: how far each dab pulls"}}, brush},
    {"brush-size", "brush radius times 1.2^step", {{"step", T::integer, true, "+1 larger, -1 smaller"}}, brush_size},
    // ---- time
    {"set-time", "the target time the deformation runs to", {{"t", T::number, true, "0 to 1"}}, set_time},
    {"wait-until-time", "wait until the deformation reaches t", {{"t", T::number, true, "0 to 1"}}, wait_until_time},
    {"play", "run to t = 1 (from 0 again when there)", {}, VFSD_CALL(c.session.play())},
    {"pause", "stop at the current time", {}, VFSD_CALL(c.session.pause())},
    {"play-pause", "play, or pause while moving", {}, play_pause},
    {"reset", "back to t = 0", {}, VFSD_CALL(c.session.reset())},
    {"apply", "bake the deformed mesh as the base of the next deformation", {}, VFSD_CALL(c.session.apply())},
    {"undo", "undo the last edit", {},
     [](const CommandArgs&, CommandContext& c) { if (!c.session.undo()) throw InputError("nothing to undo"); return true; }},
    {"redo", "redo the last undone edit", {},
     [](const CommandArgs&, CommandContext& c) { if (!c.session.redo()) throw InputError("nothing to redo"); return true; }},
    // ---- view
    {"view", "a standard view, or frame all: each frames mesh and curve; frame keeps the direction", {{"name", T::text, true, "view", "front|back|left|right|top|bottom|iso|frame"}}, view},
    {"up-axis", "the axis shown up (stored in the scene, remembered for the file type)",
     {{"axis", T::text, true, "axis", "z|y"}}, up_axis},
    {"orbit", "turn the camera over frames as a pointer drag would",
     {{"degrees", T::pair, true, "[yaw, pitch]"}, {"frames", T::integer, true, "how many"},
      {"pointer", T::pixel, false, "the hovering pointer; the editor logs each frame's times"}}, orbit},
    {"wireframe", "draw the triangles' edges", {{"on", T::boolean, false, "without it: toggle"}}, wireframe},
    {"force-cpu", "run the deformation on the CPU", {{"on", T::boolean, false, "default true"}}, force_cpu},
    // ---- the editor
    {"wait-frames", "wait n frames", {{"n", T::integer, true, "frames"}},
     [](const CommandArgs& a, CommandContext& c) { return c.frame >= a.integer("n"); }},
    {"autosave", "write the autosave now", {}, VFSD_CALL(c.host.autosave_now())},
    {"restore-autosave", "answer the offer to restore the autosave", {{"answer", T::text, true, "answer", "restore|discard"}}, restore_autosave},
    {"simulate-crash", "end at once, without the clean exit that clears the autosave", {}, VFSD_CALL(c.host.simulate_crash())},
    {"expect", "check the editor's state; fails the script otherwise",
     {{"time", T::number, false, "current time"}, {"undo_count", T::integer, false, "undo steps"}, {"warnings", T::integer, false, "warnings shown"}}, expect},
};

#undef VFSD_CALL

const std::vector<KeyBinding> kKeys = {
    {"n", "tool", R"({"name": "navigate"})", "navigate: drag control points or the handle's gizmo; elsewhere drag to orbit"},
    {"g", "tool", R"({"name": "geodesic"})", "geodesic region: click a vertex"},
    {"i", "tool", R"({"name": "paint inner"})", "paint the inner region (moves fully)"},
    {"o", "tool", R"({"name": "paint outer"})", "paint the outer region (stays)"},
    {"e", "tool", R"({"name": "erase"})", "erase painted labels"},
    {"s", "tool", R"({"name": "paint s"})", "paint s directly"},
    {"l", "tool", R"({"name": "loops"})", "draw boundary loops (Enter closes a loop)"},
    {"h", "tool", R"({"name": "handle"})", "handle: click the surface to place a handle, then drag its gizmo"},
    {"[", "brush-size", R"({"step": -1})", "brush radius smaller"},
    {"]", "brush-size", R"({"step": 1})", "brush radius larger"},
    {"x", "toggle-axis", R"({"name": "x"})", "constrain control point drags to x (again: free)"},
    {"y", "toggle-axis", R"({"name": "y"})", "constrain control point drags to y (again: free)"},
    {"z", "toggle-axis", R"({"name": "z"})", "constrain control point drags to z (again: free)"},
    {"enter", "close-loop", "{}", "close the loop in progress"},
    {"space", "play-pause", "{}", "play / pause"},
    {"r", "reset", "{}", "reset to t = 0"},
    {"a", "apply", "{}", "apply: bake the deformed mesh"},
    {"ctrl+z", "undo", "{}", "undo"},
    {"ctrl+shift+z", "redo", "{}", "redo"},
    {"ctrl+y", "redo", "{}", "redo"},
    {"f", "view", R"({"name": "frame"})", "frame all"},
    {"1", "view", R"({"name": "front"})", "front view"},
    {"3", "view", R"({"name": "right"})", "right view"},
    {"7", "view", R"({"name": "top"})", "top view"},
    {"0", "view", R"({"name": "iso"})", "3/4 view"},
    {"ctrl+1", "view", R"({"name": "back"})", "back view"},
    {"ctrl+3", "view", R"({"name": "left"})", "left view"},
    {"ctrl+7", "view", R"({"name": "bottom"})", "bottom view"},
    {"w", "wireframe", "{}", "wireframe"},
};

std::string type_text(const ArgSpec& spec) {
    if (spec.choices) return std::string("`") + spec.choices + "`";
    switch (spec.type) {
        case ArgType::number: return "number";
        case ArgType::integer: return "integer";
        case ArgType::boolean: return "bool";
        case ArgType::text: return "string";
        case ArgType::pixel: return "[x, y]";
        case ArgType::pixels: return "[[x, y], ...]";
        case ArgType::pair: return "[a, b]";
        case ArgType::triple: return "[a, b, c]";
    }
    return "?";
}

}  // namespace

// ---- CommandArgs -----------------------------------------------------------------------

double CommandArgs::number(const char* name) const {
    if (!has(name) || !args_[name].is_number()) throw InputError(std::string(name) + ": expected a number");
    return args_[name].get<double>();
}

long long CommandArgs::integer(const char* name) const { return static_cast<long long>(number(name)); }

bool CommandArgs::boolean_or(const char* name, bool fallback) const {
    if (!has(name)) return fallback;
    if (!args_[name].is_boolean()) throw InputError(std::string(name) + ": expected true or false");
    return args_[name].get<bool>();
}

std::string CommandArgs::text(const char* name) const {
    if (!has(name) || !args_[name].is_string()) throw InputError(std::string(name) + ": expected a string");
    return args_[name].get<std::string>();
}

glm::dvec2 CommandArgs::pair(const char* name) const {
    if (!has(name) || !is_pair(args_[name])) throw InputError(std::string(name) + ": expected [x, y]");
    return {args_[name][0].get<double>(), args_[name][1].get<double>()};
}

glm::dvec3 CommandArgs::triple(const char* name) const {
    if (!has(name) || !is_triple(args_[name])) throw InputError(std::string(name) + ": expected [a, b, c]");
    const nlohmann::json& v = args_[name];
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

std::vector<glm::dvec2> CommandArgs::pixels(const char* name) const {
    if (!has(name) || !is_pair_list(args_[name])) throw InputError(std::string(name) + ": expected a list of [x, y]");
    std::vector<glm::dvec2> out;
    for (const nlohmann::json& p : args_[name]) out.emplace_back(p[0].get<double>(), p[1].get<double>());
    return out;
}

// ---- the table -------------------------------------------------------------------------

void EditorHost::autosave_now() { throw InputError("this editor keeps no autosave"); }
void EditorHost::answer_restore(bool) { throw InputError("this editor keeps no autosave"); }
void EditorHost::simulate_crash() { throw InputError("this editor cannot simulate a crash"); }
void EditorHost::point_at(double, double) {}
void EditorHost::log_frame_times(int) {}
long EditorHost::frames_drawn() const { return -1; }

const std::vector<Command>& command_table() { return kCommands; }

const Command& find_command(const std::string& name) {
    for (const Command& c : kCommands)
        if (name == c.name) return c;
    throw InputError("unknown command '" + name + "'");
}

void validate_arguments(const Command& command, const json& args) {
    if (!args.is_object()) throw InputError("expected an object of arguments");
    for (const auto& item : args.items()) {
        const std::string& name = item.key();
        if (name == "action" || name == "cmd") continue;
        const auto spec = std::find_if(command.args.begin(), command.args.end(),
                                       [&](const ArgSpec& s) { return name == s.name; });
        if (spec == command.args.end()) throw InputError("unknown argument '" + name + "'");
        check_argument(*spec, item.value());
    }
    for (const ArgSpec& spec : command.args)
        if (spec.required && !args.contains(spec.name)) throw InputError(std::string(spec.name) + ": missing");
}

bool run_command(const std::string& name, const json& args, CommandContext& context) {
    const Command& command = find_command(name);
    validate_arguments(command, args);
    return command.run(CommandArgs(args), context);
}

// ---- keys ------------------------------------------------------------------------------

const std::vector<KeyBinding>& key_bindings() { return kKeys; }

std::string key_name(const std::string& key, bool ctrl, bool shift) {
    std::string name = key == " " ? "space" : key;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (ctrl) name = (shift ? "ctrl+shift+" : "ctrl+") + name;
    return name;
}

const KeyBinding* find_key(const std::string& key, bool ctrl, bool shift) {
    const std::string name = key_name(key, ctrl, shift);
    for (const KeyBinding& k : kKeys)
        if (name == k.key) return &k;
    return nullptr;
}

bool run_key(const std::string& key, bool ctrl, bool shift, CommandContext& context) {
    const KeyBinding* k = find_key(key, ctrl, shift);
    if (k) run_command(k->command, json::parse(k->args), context);
    return k != nullptr;
}

// ---- docs ------------------------------------------------------------------------------

std::string commands_markdown() {
    std::ostringstream out;
    out << "| command | arguments | what it does |\n|---|---|---|\n";
    for (const Command& c : kCommands) {
        out << "| `" << c.name << "` | ";
        for (std::size_t i = 0; i < c.args.size(); ++i) {
            const ArgSpec& a = c.args[i];
            out << (i ? "<br>" : "") << "`" << a.name << "`" << (a.required ? "" : "?") << ": " << type_text(a) << ", "
                << a.help;
        }
        out << " | " << c.summary << " |\n";
    }
    out << "\n| key | command | what it does |\n|---|---|---|\n";
    for (const KeyBinding& k : kKeys) {
        const std::string args = k.args == std::string("{}") ? "" : std::string(" `") + k.args + "`";
        out << "| `" << k.key << "` | `" << k.command << "`" << args << " | " << k.help << " |\n";
    }
    return out.str();
}

void frame_session(Camera& camera, const EditorSession& session, const Viewport& viewport) {
    camera.frame(deformation_frame_points(session.base_positions(), session.s(), session.motion()),
                 viewport.aspect());
}

}  // namespace vfsd::editor
