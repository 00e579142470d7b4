#include "editor/page_api.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.h"
#include "scene/scene.h"

namespace vfsd::editor {
namespace {

using nlohmann::json;

json pixel(glm::dvec2 p) { return {p.x, p.y}; }

json points_json(const std::vector<Vec3>& points) {
    json out = json::array();
    for (const Vec3& p : points) out.push_back({p.x, p.y, p.z});
    return out;
}

std::string css_colour(Rgb c) {
    return "rgb(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The handle gizmo's shapes in canvas pixels (editor/handle_gizmo.h).
json gizmo_json(const GizmoShapes& shapes) {
    json out = {{"axes", json::array()},
                {"rings", json::array()},
                {"centre", {shapes.centre.x, shapes.centre.y, shapes.centre_radius}},
                {"centre_colour", css_colour(shapes.centre_colour)}};
    for (const GizmoRing& ring : shapes.rings) {
        json points = json::array();
        for (const glm::dvec2& p : ring.points) points.push_back(pixel(p));
        out["rings"].push_back({{"points", points}, {"colour", css_colour(ring.colour)}});
    }
    for (const GizmoSegment& axis : shapes.axes)
        out["axes"].push_back({{"from", pixel(axis.from)}, {"to", pixel(axis.to)}, {"colour", css_colour(axis.colour)}});
    return out;
}

json stats_json(const Editor& editor) {
    const EditorSession& s = editor.session();
    const SessionStats& st = s.stats();
    return {{"vertices", st.vertices},
            {"triangles", st.triangles},
            {"time", s.time()},
            {"backend", st.backend},
            {"ms_per_step", st.ms_per_step},  // the median step, as the desktop shows it
            {"volume_error_percent", st.volume_error_percent},
            {"flipped_triangles", st.flipped_triangles},
            {"first_fold_time", st.first_fold_time},
            {"volume_error_since_opened_percent", st.volume_error_since_opened_percent},
            {"flipped_since_opened", st.flipped_since_opened},
            {"applied", st.applied},
            {"volume_text", volume_stat_text(st)},
            {"flipped_text", flipped_stat_text(st)}};
}

json autosave_json(const Editor& editor) {
    json offer;
    if (const auto& o = editor.autosave().offer())
        offer = {{"written", o->written_text()}, {"mesh", std::filesystem::path(o->mesh).filename().string()}};
    return {{"offer", offer}, {"behind", editor.autosave().behind(editor.session())}};
}

// ---- the page's queries ----------------------------------------------------------------

json load_scene(Editor& editor, json scene, const PageInfo& page) {
    // Without "mesh" the scene applies to the current mesh.
    if (!scene.is_object()) throw InputError("scene: expected a JSON object");
    if (!scene.contains("mesh")) scene["mesh"] = editor.session().mesh_name();
    editor.open_scene(parse_scene(scene, page.files, "scene"));
    return page_state(editor, page);
}

json export_mesh(Editor& editor, const std::string& format, const PageInfo& page) {
    if (format != "obj" && format != "ply" && format != "glb" && format != "off")
        throw InputError("export: format must be obj, ply, glb or off");
    const std::string stem = std::filesystem::path(editor.session().mesh_name()).stem().string();
    const std::string name = (stem.rfind("builtin:", 0) == 0 ? stem.substr(8) : stem) + "-deformed." + format;
    const std::string path = page.files + "/" + name;
    editor.command("export", {{"path", path}});
    return {{"path", path}, {"name", name}};
}

json export_scene(Editor& editor, const PageInfo& page) {
    // Written beside the uploaded meshes so the mesh path is the file's name;
    // after an apply the baked mesh comes along (NAME.mesh.ply).
    const std::string path = page.files + "/vfsd-scene.json";
    editor.command("save-scene", {{"path", path}});
    json out = {{"scene", json::parse(read_file(path))}, {"path", path}, {"files", json::array()}};
    const std::string mesh = out["scene"].value("mesh", std::string());
    if (mesh == "vfsd-scene.mesh.ply") out["files"].push_back(page.files + "/" + mesh);
    return out;
}

// Canvas pixels of points (tests aim the pointer with them), and the eye.
json project(const Editor& editor, const json& points) {
    const Camera& camera = editor.camera();
    json out = {{"pixels", json::array()}, {"eye", points_json({camera.eye()})[0]}};
    for (const json& p : points) {
        const glm::dvec3 q = camera.project(Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()), editor.viewport());
        out["pixels"].push_back({q.x, q.y});
    }
    return out;
}

// Canvas pixels of a point on each part of the handle gizmo (tests aim the
// pointer with them); null outside handle mode.
json gizmo_parts(const Editor& editor) {
    const auto gizmo = editor.tools().gizmo(editor.session(), editor.camera(), editor.viewport());
    if (!gizmo) return {{"parts", nullptr}};
    json parts = json::object();
    for (const GizmoPart part : kGizmoParts)
        if (const auto p = gizmo->grab_point(part)) parts[gizmo_part_name(part)] = pixel(*p);
    return {{"parts", parts}, {"centre", pixel(gizmo->centre())}};
}

// A cheap fingerprint of positions.
double checksum(const std::vector<Vec3>& p) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += double(1 + i % 7) * (p[i].x + 2.0 * p[i].y + 3.0 * p[i].z);
    return sum;
}

}  // namespace

json page_state(const Editor& editor, const PageInfo& page) {
    const EditorSession& s = editor.session();
    const ToolController& tools = editor.tools();
    const ScriptRunner* script = editor.script();
    const MotionSpec& c = s.curve();
    return {{"stats", stats_json(editor)},
            {"backend_reason", s.stats().backend_reason},
            {"renderer", page.renderer},
            {"multisampled", page.multisampled},
            {"canvas_draws", page.canvas_draws},
            {"target_time", s.target_time()},
            {"moving", s.moving()},
            {"holding", s.holding_result()},         // the last result on show while an edit's run catches up
            {"apply_due", editor.apply_due()},       // an apply waits for that run to reach its target
            {"region_pending", s.region_pending()},  // an edit's s still computed in parts
            {"time_text", time_stat_text(s)},
            {"tool", tool_name(tools.tool)},
            {"radius", tools.brush.radius},
            {"s_target", tools.brush.s_target},
            {"strength", tools.brush.strength},
            {"g_min", tools.g_min},
            {"g_max", tools.g_max},
            {"band", s.region_band()},
            {"up", std::string(1, s.up_axis())},
            {"axis", tools.axis},
            {"diagonal", s.diagonal()},
            {"inner_motion", c.inner_motion == InnerMotionMode::Translation ? "translation" : "rotation"},
            {"alpha", {c.twist_degrees[0], c.twist_degrees[1]}},
            {"is_handle", c.curve.is_handle},
            {"control_points", points_json(s.control_points())},
            {"undo", s.history().undo_count()},
            {"redo", s.history().redo_count()},
            {"mesh", s.mesh_name()},
            {"warnings", s.warnings()},
            {"message", tools.message},
            {"hint", tools.hint},
            {"load_error", editor.load_error()},
            {"missing_mesh", s.missing_mesh()},
            {"status", editor.status()},
            {"loops", {tools.loops().size(), tools.loop_in_progress().size()}},
            {"context_lost", page.context_lost},
            {"force_cpu", editor.settings().force_cpu},
            {"wireframe", editor.settings().wireframe},
            {"autosave", autosave_json(editor)},
            {"script", script ? json{{"done", script->done()}, {"error", script->error()}} : json()}};
}

json overlay_json(const Overlay& o) {
    json out = {{"polygon", json::array()}, {"points", json::array()}, {"loops", json::array()},
                {"current", json::array()}, {"brush", nullptr}, {"gizmo", nullptr}};
    for (const auto& [a, b] : o.polygon) out["polygon"].push_back({pixel(a), pixel(b)});
    for (const OverlayPoint& p : o.points) out["points"].push_back({{"at", pixel(p.at)}, {"knot", p.knot}, {"hot", p.hot}});
    if (o.gizmo) out["gizmo"] = gizmo_json(*o.gizmo);
    for (const auto& loop : o.loops) {
        json l = json::array();
        for (const glm::dvec2& p : loop) l.push_back(pixel(p));
        out["loops"].push_back(l);
    }
    for (const glm::dvec2& p : o.loop_in_progress) out["current"].push_back(pixel(p));
    if (o.brush) out["brush"] = {o.brush->x, o.brush->y, o.brush->z};
    return out;
}

bool page_query(const std::string& cmd) {
    return cmd == "state" || cmd == "project" || cmd == "gizmo-parts" || cmd == "checksum";
}

json page_command(Editor& editor, const json& c, const PageInfo& page) {
    const std::string cmd = c.value("cmd", std::string());
    if (cmd == "state") return page_state(editor, page);
    if (cmd == "open") {
        // One path, or several at once (a scene and its mesh); a failure keeps the document and says why.
        if (c.contains("paths")) editor.open(c.at("paths").get<std::vector<std::string>>());
        else editor.open(c.value("path", std::string()));
        return {{"load_error", editor.load_error()}};
    }
    if (cmd == "load-scene") return load_scene(editor, c.value("scene", json()), page);
    if (cmd == "export-mesh") return export_mesh(editor, c.value("format", std::string("ply")), page);
    if (cmd == "export-scene") return export_scene(editor, page);
    if (cmd == "project") return project(editor, c.at("points"));
    if (cmd == "gizmo-parts") return gizmo_parts(editor);
    if (cmd == "checksum") return {{"checksum", checksum(editor.session().positions())}};
    json state = json::object();
    if (cmd == "script") {
        editor.run_script(parse_script(c.at("actions").dump(), "script"));
    } else if (cmd == "key") {
        // The editor's key table; "handled" says whether a command is bound to the key.
        const bool handled = editor.key(c.value("key", ""), c.value("ctrl", false), c.value("shift", false));
        state["handled"] = handled;
    } else {
        editor.command(cmd, c);
    }
    state.update(page_state(editor, page));
    return state;
}

}  // namespace vfsd::editor
