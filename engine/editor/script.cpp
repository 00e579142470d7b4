#include "editor/script.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <glm/trigonometric.hpp>

#include "base/error.h"
#include "editor/picking.h"

namespace vfsd::editor {
namespace {

using nlohmann::json;

// A wait gives up after this many frames (the deformation stalled).
constexpr int kMaxWaitFrames = 200000;

glm::dvec2 two_numbers(const json& v, const std::string& what, const char* expected) {
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        throw InputError(what + ": expected " + expected);
    return {v[0].get<double>(), v[1].get<double>()};
}

glm::dvec2 pixel(const json& v, const std::string& what) { return two_numbers(v, what, "[x, y] in pixels"); }

std::vector<glm::dvec2> pixels(const json& v, const std::string& what) {
    if (!v.is_array() || v.empty()) throw InputError(what + ": expected a list of [x, y]");
    std::vector<glm::dvec2> out;
    for (const json& p : v) out.push_back(pixel(p, what));
    return out;
}

double number(const ScriptAction& a, const char* key) {
    if (!a.args.contains(key) || !a.args[key].is_number()) throw InputError(std::string(key) + ": expected a number");
    return a.args[key].get<double>();
}

std::string text(const ScriptAction& a, const char* key) {
    if (!a.args.contains(key) || !a.args[key].is_string()) throw InputError(std::string(key) + ": expected a string");
    return a.args[key].get<std::string>();
}

SurfacePoint surface_point_at_pixel(const EditorSession& s, const Camera& c, const Viewport& v, glm::dvec2 p) {
    const auto hit = s.pick_surface(c.ray(p.x, p.y, v));
    if (!hit) throw InputError("no surface under pixel (" + std::to_string(int(p.x)) + ", " + std::to_string(int(p.y)) + ")");
    return hit->point;
}

SurfaceLoop loop_at_pixels(const EditorSession& s, const Camera& c, const Viewport& v, const json& points,
                           const std::string& what) {
    SurfaceLoop loop;
    for (const glm::dvec2& p : pixels(points, what)) loop.push_back(surface_point_at_pixel(s, c, v, p));
    return loop;
}

Tool paint_tool(const std::string& name) {
    if (name == "inner") return Tool::paint_inner;
    if (name == "outer") return Tool::paint_outer;
    if (name == "erase") return Tool::erase;
    if (name == "s") return Tool::paint_s;
    throw InputError("tool: expected inner, outer, erase or s, not '" + name + "'");
}

// Any tool: the brushes by paint_tool's names, the others by tool_name's.
Tool any_tool(const std::string& name) {
    for (Tool t : kAllTools)
        if (name == tool_name(t)) return t;
    return paint_tool(name);
}

// One frame of an orbit: the camera turns by 1/frames of "degrees" (yaw, pitch);
// false until it has turned all the way. The first frame places the pointer and
// starts the host's frame log; the action ends on the frame after the last turn,
// so the host has logged every turning frame whole.
bool orbit_frame(const ScriptAction& a, int frame, Camera& camera, ScriptHost& host) {
    const int frames = static_cast<int>(number(a, "frames"));
    if (frames < 1) throw InputError("frames: expected at least 1");
    const glm::dvec2 degrees = two_numbers(a.args.value("degrees", json()), "degrees", "[yaw, pitch] in degrees");
    if (frame == 0) {
        if (a.args.contains("pointer")) {
            const glm::dvec2 p = pixel(a.args["pointer"], "pointer");
            host.point_at(p.x, p.y);
        }
        host.log_frame_times(frames);
    }
    if (frame >= frames) return true;
    const glm::dvec2 step = glm::radians(degrees) / (kOrbitRadiansPerPixel * frames);
    camera.orbit(-step.x, step.y);
    return false;
}

// The pointer's path for a gizmo drag from `grab`: to a pixel ("to"), by an offset
// ("by"), or (rings) round the gizmo's centre by "degrees", counter-clockwise on
// screen, in steps of at most 5 degrees.
std::vector<glm::dvec2> gizmo_path(const ScriptAction& a, glm::dvec2 grab, glm::dvec2 centre) {
    std::vector<glm::dvec2> path;
    if (a.args.contains("degrees")) {
        const double degrees = number(a, "degrees"), radius = glm::length(grab - centre);
        const double start = std::atan2(-(grab.y - centre.y), grab.x - centre.x);
        const int steps = std::max(1, int(std::ceil(std::abs(degrees) / 5.0)));
        for (int k = 1; k <= steps; ++k) {
            const double angle = start + glm::radians(degrees) * k / steps;
            path.push_back(centre + radius * glm::dvec2(std::cos(angle), -std::sin(angle)));
        }
        return path;
    }
    const glm::dvec2 to = a.args.contains("by") ? grab + pixel(a.args["by"], "by") : pixel(a.args.value("to", json()), "to");
    for (int k = 1; k <= 8; ++k) path.push_back(glm::mix(grab, to, k / 8.0));
    return path;
}

// Presses on the part's grab point as a pointer would, moves along the path, releases.
void drag_gizmo(const ScriptAction& a, EditorSession& session, ToolController& tools, const Camera& camera,
                const Viewport& viewport) {
    const GizmoPart part = parse_gizmo_part(text(a, "part"));
    const auto gizmo = tools.gizmo(session, camera, viewport);
    if (!gizmo) throw InputError("no handle: place one first (place-handle)");
    const auto grab = gizmo->grab_point(part);
    if (!grab) throw InputError(std::string(gizmo_part_name(part)) + " is not visible from this view");
    const Tool previous = tools.tool;
    tools.tool = Tool::navigate;
    tools.press(session, camera, viewport, grab->x, grab->y);
    const GizmoPart held = tools.highlighted_gizmo_part(session, camera, viewport, grab->x, grab->y);
    if (held == part)
        for (const glm::dvec2& p : gizmo_path(a, *grab, gizmo->centre())) tools.drag(session, camera, viewport, p.x, p.y);
    tools.release(session);
    tools.tool = previous;
    if (held != part) throw InputError(std::string("the press grabbed ") + gizmo_part_name(held));
    if (!tools.message.empty()) throw InputError(tools.message);
}

void place_handle_at(glm::dvec2 at, EditorSession& session, ToolController& tools, const Camera& camera,
                     const Viewport& viewport) {
    const Tool previous = tools.tool;
    tools.tool = Tool::handle;
    tools.press(session, camera, viewport, at.x, at.y);
    tools.release(session);
    const bool placed = tools.tool == Tool::navigate;  // the handle tool hands over to navigate
    tools.tool = previous;
    if (!placed) throw InputError(tools.message.empty() ? "no surface under the pixel" : tools.message);
    tools.message.clear();
}

}  // namespace

void ScriptHost::autosave_now() { throw InputError("this editor keeps no autosave"); }
void ScriptHost::answer_restore(bool) { throw InputError("this editor keeps no autosave"); }
void ScriptHost::simulate_crash() { throw InputError("this editor cannot simulate a crash"); }
void ScriptHost::point_at(double, double) {}
void ScriptHost::log_frame_times(int) {}

std::vector<ScriptAction> parse_script(const std::string& source_text, const std::string& source) {
    std::vector<ScriptAction> actions;
    auto add = [&](const json& j, const std::string& where) {
        if (!j.is_object() || !j.contains("action") || !j["action"].is_string())
            throw InputError(where + ": expected an object with \"action\"");
        actions.push_back({j["action"].get<std::string>(), j, where});
    };
    std::size_t first = source_text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && source_text[first] == '[') {
        json list;
        try {
            list = json::parse(source_text);
        } catch (const json::exception& e) {
            throw InputError(source + ": " + e.what());
        }
        for (std::size_t i = 0; i < list.size(); ++i) add(list[i], source + "[" + std::to_string(i) + "]");
        return actions;
    }
    std::istringstream in(source_text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::size_t start = line.find_first_not_of(" \t\r");
        if (start == std::string::npos || line[start] == '#' || line.compare(start, 2, "//") == 0) continue;
        const std::string where = source + ":" + std::to_string(number);
        try {
            add(json::parse(line), where);
        } catch (const json::exception& e) {
            throw InputError(where + ": " + e.what());
        }
    }
    return actions;
}

std::vector<ScriptAction> load_script(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open the script");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_script(text.str(), path);
}

bool ScriptRunner::run_frame(EditorSession& session, ToolController& tools, Camera& camera, const Viewport& viewport,
                             ScriptHost& host) {
    while (!done()) {
        const ScriptAction& a = actions_[next_];
        bool finished = false;
        try {
            finished = execute(a, session, tools, camera, viewport, host);
        } catch (const std::exception& e) {
            error_ = a.where + ": " + a.name + ": " + e.what();
            host.log("script: " + error_);
            return false;
        }
        if (!finished) {
            if (++waited_frames_ > kMaxWaitFrames) error_ = a.where + ": " + a.name + ": gave up waiting";
            return !done();
        }
        waited_frames_ = 0;
        ++next_;
        // A screenshot needs this frame rendered first.
        if (a.name == "screenshot") return !done();
    }
    return false;
}

bool ScriptRunner::execute(const ScriptAction& a, EditorSession& session, ToolController& tools, Camera& camera,
                           const Viewport& viewport, ScriptHost& host) {
    const std::string& n = a.name;
    if (waited_frames_ == 0) host.log("script: " + a.args.dump());
    if (n == "load") {
        session.open(text(a, "path"));
        tools.adapt_to(session);
        host.loaded();
    } else if (n == "pick") {
        if (a.args.contains("g_min")) tools.g_min = number(a, "g_min");
        if (a.args.contains("g_max")) tools.g_max = number(a, "g_max");
        std::uint32_t vertex = 0;
        if (a.args.contains("at")) {
            const glm::dvec2 p = pixel(a.args["at"], "at");
            const auto hit = session.pick_surface(camera.ray(p.x, p.y, viewport));
            if (!hit) throw InputError("no surface under the pixel");
            vertex = hit->nearest_vertex;
        } else if (a.args.contains("vertex")) {
            vertex = static_cast<std::uint32_t>(number(a, "vertex"));
        } else {
            SurfacePoint sp;
            sp.triangle = static_cast<std::uint32_t>(number(a, "triangle"));
            const json& b = a.args.at("barycentric");
            sp.barycentric = Vec3(b.at(0).get<double>(), b.at(1).get<double>(), b.at(2).get<double>());
            check_surface_point(sp, session.triangles().size(), "pick");
            const Triangle& t = session.triangles()[sp.triangle];
            const Vec3& w = sp.barycentric;
            vertex = t[w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2)];
        }
        session.pick_geodesic(vertex, tools.g_min, tools.g_max);
    } else if (n == "paint") {
        const Tool previous = tools.tool;
        tools.tool = paint_tool(text(a, "tool"));
        if (a.args.contains("radius")) tools.brush.radius = number(a, "radius");
        if (a.args.contains("target")) tools.brush.s_target = number(a, "target");
        if (a.args.contains("strength")) tools.brush.strength = number(a, "strength");
        const std::vector<glm::dvec2> points = pixels(a.args.value("points", json()), "points");
        if (!tools.press(session, camera, viewport, points[0].x, points[0].y))
            throw InputError("the stroke does not start on the surface");
        // Through every point, in steps of at most 4 pixels, as a pointer would move.
        for (std::size_t i = 1; i < points.size(); ++i) {
            const int steps = std::max(1, int(std::ceil(glm::length(points[i] - points[i - 1]) / 4.0)));
            for (int k = 1; k <= steps; ++k) {
                const glm::dvec2 p = glm::mix(points[i - 1], points[i], double(k) / steps);
                tools.drag(session, camera, viewport, p.x, p.y);
            }
        }
        tools.release(session);
        tools.tool = previous;
        if (!tools.message.empty()) throw InputError(tools.message);
    } else if (n == "loops") {
        session.set_region_from_loops(loop_at_pixels(session, camera, viewport, a.args.value("inner", json()), "inner"),
                                      loop_at_pixels(session, camera, viewport, a.args.value("outer", json()), "outer"),
                                      surface_point_at_pixel(session, camera, viewport, pixel(a.args.value("seed", json()), "seed")));
    } else if (n == "drag") {
        const int previous_axis = tools.axis;
        const std::string axis = a.args.value("axis", std::string());
        tools.axis = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
        const auto index = static_cast<std::size_t>(number(a, "index"));
        tools.press_control_point(session, index);
        const glm::dvec3 from3 = camera.project(session.control_points()[index], viewport);
        const glm::dvec2 from(from3.x, from3.y), to = pixel(a.args.value("to", json()), "to");
        for (int k = 1; k <= 8; ++k) {
            const glm::dvec2 p = glm::mix(from, to, k / 8.0);
            tools.drag(session, camera, viewport, p.x, p.y);
        }
        tools.release(session);
        tools.axis = previous_axis;
        if (!tools.message.empty()) throw InputError(tools.message);
    } else if (n == "place-handle") {
        place_handle_at(pixel(a.args.value("at", json()), "at"), session, tools, camera, viewport);
    } else if (n == "gizmo") {
        drag_gizmo(a, session, tools, camera, viewport);
    } else if (n == "add-segment") {
        session.add_segment();
    } else if (n == "remove-segment") {
        session.remove_segment();
    } else if (n == "twist") {
        CurveSettings c = session.curve();
        const json& alpha = a.args.at("alpha");
        c.twist_degrees[0] = alpha.at(0).get<double>();
        c.twist_degrees[1] = alpha.at(1).get<double>();
        session.set_curve(c);
    } else if (n == "inner-motion") {
        CurveSettings c = session.curve();
        const std::string mode = text(a, "mode");
        if (mode != "rotation" && mode != "translation") throw InputError("mode: expected rotation or translation");
        c.inner_motion = mode == "rotation" ? InnerMotionMode::Rotation : InnerMotionMode::Translation;
        session.set_curve(c);
    } else if (n == "set-time") {
        session.set_target_time(number(a, "t"));
    } else if (n == "wait-until-time") {
        const double t = number(a, "t");
        if (std::abs(session.time() - t) <= 1e-9) return true;
        if (!session.moving())  // stopped elsewhere: another target, or an error
            throw InputError("time stopped at " + std::to_string(session.time()) + " (target " +
                             std::to_string(session.target_time()) + ")");
        return false;
    } else if (n == "play") {
        session.play();
    } else if (n == "pause") {
        session.pause();
    } else if (n == "reset") {
        session.reset();
    } else if (n == "apply") {
        session.apply();
    } else if (n == "undo") {
        if (!session.undo()) throw InputError("nothing to undo");
    } else if (n == "redo") {
        if (!session.redo()) throw InputError("nothing to redo");
    } else if (n == "view") {
        const std::string name = text(a, "name");
        if (name == "frame") host.loaded();
        else if (name == "front") camera.set_view(StandardView::front);
        else if (name == "back") camera.set_view(StandardView::back);
        else if (name == "left") camera.set_view(StandardView::left);
        else if (name == "right") camera.set_view(StandardView::right);
        else if (name == "top") camera.set_view(StandardView::top);
        else if (name == "bottom") camera.set_view(StandardView::bottom);
        else if (name == "iso") camera.set_view(StandardView::iso);
        else throw InputError("name: unknown view '" + name + "'");
    } else if (n == "orbit") {
        return orbit_frame(a, waited_frames_, camera, host);
    } else if (n == "tool") {
        tools.tool = any_tool(text(a, "name"));
    } else if (n == "export") {
        session.export_mesh(text(a, "path"));
    } else if (n == "save-scene") {
        session.save_scene(text(a, "path"));
    } else if (n == "screenshot") {
        host.screenshot(text(a, "path"), a.args.value("ui", true));
    } else if (n == "wait-frames") {
        return waited_frames_ >= int(number(a, "n"));
    } else if (n == "autosave") {
        host.autosave_now();
    } else if (n == "restore-autosave") {
        const std::string answer = text(a, "answer");
        if (answer != "restore" && answer != "discard") throw InputError("answer: expected restore or discard");
        host.answer_restore(answer == "restore");
    } else if (n == "simulate-crash") {
        host.simulate_crash();
    } else if (n == "expect") {
        if (a.args.contains("time") && std::abs(session.time() - number(a, "time")) > 1e-9)
            throw InputError("time is " + std::to_string(session.time()));
        if (a.args.contains("undo_count") && session.history().undo_count() != std::size_t(number(a, "undo_count")))
            throw InputError("undo count is " + std::to_string(session.history().undo_count()));
        if (a.args.contains("warnings") && session.warnings().size() != std::size_t(number(a, "warnings")))
            throw InputError(std::to_string(session.warnings().size()) + " warnings");
    } else {
        throw InputError("unknown action");
    }
    return true;
}

}  // namespace vfsd::editor
