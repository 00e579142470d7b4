// vfsd-web: the browser editor's shell. Like desktop/, a thin layer around the
// editor core (engine/editor): pointer events from the page go to the same
// ToolController and Camera, every control to the same EditorSession, and the
// engine's renderer draws into a WebGL2 canvas. The GPU path runs in that canvas's
// context when it renders to float textures (EXT_color_buffer_float); otherwise
// the CPU path runs and the stats say why.
//
// The page (web/vfsd-page.js) talks to this file through four C functions:
// vfsd_command (JSON in, JSON out: the editor's command table, editor/commands.h,
// and the page's queries: state, open, exports, projections),
// vfsd_pointer, vfsd_wheel and vfsd_array (positions or s for the tests). Each
// frame ends by handing the page the overlay (control points, loops, the brush)
// to draw on the 2D canvas above the WebGL one.
//
// The autosave (editor/autosave.h) lives in /autosave, an IDBFS folder the page
// loads from IndexedDB before the editor starts and writes back after each
// autosave, so a reloaded page offers to restore the session.

#include <emscripten.h>
#include <emscripten/html5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "editor/autosave.h"
#include "editor/camera.h"
#include "editor/gpu_live_deformation.h"
#include "editor/handle_gizmo.h"
#include "editor/picking.h"
#include "editor/script.h"
#include "editor/session.h"
#include "editor/session_view.h"
#include "editor/tools.h"
#include "gpu/capabilities.h"
#include "gpu/context.h"
#include "gpu/gl.h"
#include "gpu/renderer.h"
#include "scene/scene.h"

// The page's side (web/vfsd-page.js): start-up options, and one call per frame.
EM_JS(char*, vfsd_page_options, (), {
    const text = JSON.stringify(Module.vfsdOptions || {});
    const size = lengthBytesUTF8(text) + 1;
    const out = _malloc(size);
    stringToUTF8(text, out, size);
    return out;
});
EM_JS(void, vfsd_page_frame, (const char* overlay), {
    if (Module.vfsdFrame) Module.vfsdFrame(UTF8ToString(overlay));
});
EM_JS(void, vfsd_page_context, (int lost), {
    if (Module.vfsdContext) Module.vfsdContext(lost != 0);
});
// The autosave folder changed: the page writes it to IndexedDB.
EM_JS(void, vfsd_page_autosaved, (), {
    if (Module.vfsdAutosaved) Module.vfsdAutosaved();
});
// Mounts the autosave folder, loads it from IndexedDB, then starts the editor
// (vfsd_start); without IndexedDB the editor starts with an empty folder.
EM_JS(void, vfsd_page_load_autosave, (const char* folder), {
    const dir = UTF8ToString(folder);
    const start = () => Module.ccall('vfsd_start', null, [], []);
    try {
        FS.mkdir(dir);
        FS.mount(IDBFS, {}, dir);
        FS.syncfs(true, (err) => {
            if (err) console.warn('vfsd: the autosave could not be read from IndexedDB: ' + err);
            start();
        });
    } catch (e) {
        console.warn('vfsd: no autosave storage: ' + e);
        start();
    }
});

namespace vfsd::web {
namespace {

using nlohmann::json;

constexpr const char* kCanvas = "#vfsd-canvas";
constexpr const char* kDefaultScene = "/scenes/default.json";
constexpr const char* kFiles = "/files";  // uploaded meshes and scenes, exports
constexpr const char* kAutosave = "/autosave";  // IDBFS, kept in IndexedDB
// A changed session is autosaved at most this often.
constexpr double kAutosaveSeconds = 5.0;
// Per frame the deformation may take about this long, so the page stays responsive.
constexpr double kStepBudgetMs = 15.0;

class WebGlContext final : public gpu::Context {
public:
    explicit WebGlContext(EMSCRIPTEN_WEBGL_CONTEXT_HANDLE handle) : handle_(handle) {}
    void make_current() override { emscripten_webgl_make_context_current(handle_); }
    std::string kind() const override { return "webgl2"; }

private:
    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE handle_;
};

json points_json(const std::vector<Vec3>& points) {
    json out = json::array();
    for (const Vec3& p : points) out.push_back({p.x, p.y, p.z});
    return out;
}

std::string css_colour(editor::Rgb c) {
    return "rgb(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

// The handle gizmo's shapes in canvas pixels (editor/handle_gizmo.h).
json gizmo_json(const editor::GizmoShapes& shapes) {
    json out = {{"axes", json::array()},
                {"rings", json::array()},
                {"centre", {shapes.centre.x, shapes.centre.y, shapes.centre_radius}},
                {"centre_colour", css_colour(shapes.centre_colour)}};
    for (const editor::GizmoRing& ring : shapes.rings) {
        json points = json::array();
        for (const glm::dvec2& p : ring.points) points.push_back({p.x, p.y});
        out["rings"].push_back({{"points", points}, {"colour", css_colour(ring.colour)}});
    }
    for (const editor::GizmoSegment& axis : shapes.axes)
        out["axes"].push_back({{"from", {axis.from.x, axis.from.y}}, {"to", {axis.to.x, axis.to.y}},
                               {"colour", css_colour(axis.colour)}});
    return out;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

class App final : public editor::EditorHost {
public:
    explicit App(const json& options);

    void frame();
    json command(const json& c);
    void pointer(int kind, double x, double y, int button, bool shift);
    void wheel(double delta, double x, double y);
    // Positions (0) or s (1) of the current shape as doubles; returns the count.
    std::size_t array(int which);
    const std::vector<double>& array_data() const { return array_; }

    // EditorHost
    void screenshot(const std::string&, bool) override { log("script: screenshots are the page's (canvas)"); }
    void loaded() override;
    void log(const std::string& line) override { std::printf("%s\n", line.c_str()); }
    void autosave_now() override;
    void answer_restore(bool restore) override;

    void context_lost();
    void context_restored();

private:
    editor::Viewport viewport() const;
    void init_gl();
    void open(const std::string& path);
    void load_scene(json scene);
    editor::CommandContext context();
    json state() const;
    json autosave_state() const;
    json overlay() const;

    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE gl_ = 0;
    bool lost_ = false;
    bool allow_float_ = true;
    std::string backend_ = "auto";
    std::string gl_renderer_;
    editor::DeformationFactory gpu_;
    std::string gpu_reason_;

    std::unique_ptr<editor::EditorSession> session_;
    editor::ToolController tools_;
    editor::Camera camera_;
    editor::EditorSettings settings_;
    editor::SessionView view_;
    std::unique_ptr<editor::ScriptRunner> script_;
    editor::Autosave autosave_{kAutosave, kAutosaveSeconds};
    double ms_per_step_ = 0.0;  // wall time per step of the last update(), read-back included

    enum class Drag { none, tool, orbit, pan } drag_ = Drag::none;
    double mouse_x_ = -1.0, mouse_y_ = -1.0;
    std::string load_error_, status_;
    std::vector<double> array_;
};

App::App(const json& options) {
    allow_float_ = options.value("float", true);
    backend_ = options.value("backend", std::string("auto"));
    std::filesystem::create_directories(kFiles);
    init_gl();
    session_ = std::make_unique<editor::EditorSession>(gpu_, gpu_reason_);
    log("WebGL2: " + gl_renderer_ + (gpu_ ? " (GPU path)" : " (CPU path: " + gpu_reason_ + ")"));
    try {
        session_->open_scene_file(kDefaultScene);
    } catch (const std::exception& e) {
        log(std::string("default scene: ") + e.what());
        session_->open_mesh("builtin:box");
    }
    tools_.adapt_to(*session_);
    loaded();
    autosave_.mark_saved(*session_);
    autosave_.offer_restore(*session_);
}

void App::autosave_now() {
    if (autosave_.offer()) throw InputError("answer the offer to restore the autosave first");
    if (!autosave_.save(*session_)) throw IoError(session_->warnings().back());
    vfsd_page_autosaved();
}

void App::answer_restore(bool restore) {
    if (autosave_.answer(*session_, restore)) {
        tools_.adapt_to(*session_);
        loaded();
    }
    if (!restore) vfsd_page_autosaved();  // the cleared folder, to IndexedDB
    status_ = !restore ? "discarded the autosave" : autosave_.problem().empty() ? "restored the autosave" : "";
}

void App::init_gl() {
    EmscriptenWebGLContextAttributes attrs;
    emscripten_webgl_init_context_attributes(&attrs);
    attrs.majorVersion = 2;
    attrs.minorVersion = 0;
    attrs.alpha = false;
    attrs.antialias = true;
    attrs.preserveDrawingBuffer = true;  // the canvas can be read back (screenshots, tests)
    attrs.enableExtensionsByDefault = false;
    if (!gl_) gl_ = emscripten_webgl_create_context(kCanvas, &attrs);
    if (gl_ <= 0) throw std::runtime_error("this browser gives no WebGL2 context");
    emscripten_webgl_make_context_current(gl_);
    // Float render targets decide the backend; ?float=0 leaves the extension off
    // to show the CPU fallback.
    const bool float_targets = allow_float_ && emscripten_webgl_enable_extension(gl_, "EXT_color_buffer_float");
    gpu::Capabilities caps = gpu::query_capabilities();
    caps.float_render_targets = float_targets;
    gl_renderer_ = caps.renderer;
    gpu_ = {};
    gpu_reason_.clear();
    if (backend_ == "cpu") {
        gpu_reason_ = "CPU chosen (backend=cpu)";
        return;
    }
    try {
        gpu::require_gpu_support(caps);
        gpu_ = editor::make_gpu_deformation;
    } catch (const std::exception& e) {
        gpu_reason_ = e.what();
    }
}

editor::Viewport App::viewport() const {
    int w = 1, h = 1;
    emscripten_get_canvas_element_size(kCanvas, &w, &h);
    return {std::max(w, 1), std::max(h, 1)};
}

void App::loaded() {
    camera_ = editor::Camera();
    camera_.frame(gpu::deformation_frame_points(session_->base_positions(), session_->s(), session_->motion()),
                  viewport().aspect());
}

void App::open(const std::string& path) {
    // A failed load keeps the current document and says why.
    try {
        session_->open(path);
        tools_.adapt_to(*session_);
        loaded();
        load_error_.clear();
        status_ = "opened " + std::filesystem::path(path).filename().string();
    } catch (const std::exception& e) {
        load_error_ = std::filesystem::path(path).filename().string() + ": " + e.what();
        log("open failed: " + load_error_);
    }
}

void App::load_scene(json scene) {
    // Without "mesh" the scene applies to the current mesh.
    if (!scene.is_object()) throw InputError("scene: expected a JSON object");
    if (!scene.contains("mesh")) scene["mesh"] = session_->mesh_name();
    session_->open_scene(parse_scene(scene, kFiles, "scene"));
    tools_.adapt_to(*session_);
    loaded();
    load_error_.clear();
}

void App::pointer(int kind, double x, double y, int button, bool shift) {
    const editor::Viewport v = viewport();
    const double dx = x - mouse_x_, dy = y - mouse_y_;
    mouse_x_ = x, mouse_y_ = y;
    if (kind == 0) {  // press
        if (drag_ != Drag::none) return;
        if (button != 0 || shift) drag_ = Drag::pan;
        else if (tools_.press(*session_, camera_, v, x, y)) drag_ = Drag::tool;
        else drag_ = Drag::orbit;
    } else if (kind == 1) {  // move
        switch (drag_) {
            case Drag::tool: tools_.drag(*session_, camera_, v, x, y); break;
            case Drag::orbit: camera_.orbit(dx, dy); break;
            case Drag::pan: camera_.pan(dx, dy, v); break;
            case Drag::none: break;
        }
    } else if (kind == 2) {  // release
        if (drag_ == Drag::tool) tools_.release(*session_);
        drag_ = Drag::none;
    } else {  // left the canvas
        mouse_x_ = mouse_y_ = -1.0;
    }
}

void App::wheel(double delta, double x, double y) {
    camera_.zoom(std::pow(0.85, -delta / 100.0), x, y, viewport());
}

editor::CommandContext App::context() { return {*session_, tools_, camera_, settings_, viewport(), *this}; }

json App::state() const {
    const editor::EditorSession& s = *session_;
    const editor::SessionStats& st = s.stats();
    json stats = {{"vertices", st.vertices},
                  {"triangles", st.triangles},
                  {"time", s.time()},
                  {"backend", st.backend},
                  {"ms_per_step", ms_per_step_},
                  {"volume_error_percent", st.volume_error_percent},
                  {"flipped_triangles", st.flipped_triangles},
                  {"first_fold_time", st.first_fold_time}};
    const editor::CurveSettings& c = s.curve();
    return {{"stats", stats},
            {"backend_reason", st.backend_reason},
            {"renderer", gl_renderer_},
            {"target_time", s.target_time()},
            {"moving", s.moving()},
            {"tool", editor::tool_name(tools_.tool)},
            {"radius", tools_.brush.radius},
            {"s_target", tools_.brush.s_target},
            {"strength", tools_.brush.strength},
            {"g_min", tools_.g_min},
            {"g_max", tools_.g_max},
            {"axis", tools_.axis},
            {"diagonal", s.diagonal()},
            {"inner_motion", c.inner_motion == InnerMotionMode::Translation ? "translation" : "rotation"},
            {"alpha", {c.twist_degrees[0], c.twist_degrees[1]}},
            {"is_handle", c.curve.is_handle},
            {"control_points", points_json(s.control_points())},
            {"undo", s.history().undo_count()},
            {"redo", s.history().redo_count()},
            {"mesh", s.mesh_name()},
            {"warnings", s.warnings()},
            {"message", tools_.message},
            {"load_error", load_error_},
            {"status", status_},
            {"loops", {tools_.loops().size(), tools_.loop_in_progress().size()}},
            {"context_lost", lost_},
            {"force_cpu", settings_.force_cpu},
            {"wireframe", settings_.wireframe},
            {"autosave", autosave_state()},
            {"script", script_ ? json{{"done", script_->done()}, {"error", script_->error()}} : json()}};
}

json App::autosave_state() const {
    json offer;
    if (const auto& o = autosave_.offer())
        offer = {{"written", o->written_text()}, {"mesh", std::filesystem::path(o->mesh).filename().string()}};
    return {{"offer", offer}, {"behind", autosave_.behind(*session_)}};
}

json App::overlay() const {
    // What the page draws over the canvas, in canvas pixels.
    const editor::Viewport v = viewport();
    const auto px = [&](const Vec3& p) {
        const glm::dvec3 s = camera_.project(p, v);
        return s.z <= 1.0 ? json::array({s.x, s.y}) : json();
    };
    json out = {{"polygon", json::array()}, {"points", json::array()}, {"loops", json::array()},
                {"current", json::array()}, {"brush", nullptr}, {"gizmo", nullptr}};
    const std::vector<Vec3> points = session_->control_points();
    const bool handle = session_->curve().curve.is_handle;
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
        if (handle || i % 3 != 1) out["polygon"].push_back({px(points[i]), px(points[i + 1])});
    const bool navigating = tools_.tool == editor::Tool::navigate && mouse_x_ >= 0.0;
    const auto hovered = navigating ? tools_.hovered_point(*session_, camera_, v, mouse_x_, mouse_y_) : std::nullopt;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const bool hot = hovered == i || tools_.dragged_point() == i;
        out["points"].push_back({{"at", px(points[i])}, {"knot", handle || i % 3 == 0}, {"hot", hot}});
    }
    if (const auto gizmo = tools_.gizmo(*session_, camera_, v)) {
        const editor::GizmoPart hot = mouse_x_ >= 0.0 || tools_.active()
                                          ? tools_.highlighted_gizmo_part(*session_, camera_, v, mouse_x_, mouse_y_)
                                          : editor::GizmoPart::none;
        if (gizmo->visible()) out["gizmo"] = gizmo_json(gizmo->shapes(hot));
    }
    const auto& p = session_->positions();
    const auto& t = session_->triangles();
    for (const SurfaceLoop& loop : tools_.loops()) {
        json l = json::array();
        for (const SurfacePoint& q : loop) l.push_back(px(surface_position(p, t, q)));
        out["loops"].push_back(l);
    }
    for (const SurfacePoint& q : tools_.loop_in_progress()) out["current"].push_back(px(surface_position(p, t, q)));
    const bool brush = tools_.tool == editor::Tool::paint_inner || tools_.tool == editor::Tool::paint_outer ||
                       tools_.tool == editor::Tool::erase || tools_.tool == editor::Tool::paint_s;
    if (brush && mouse_x_ >= 0.0) {
        const auto hit = session_->pick_surface(camera_.ray(mouse_x_, mouse_y_, v));
        if (hit) {
            const glm::dvec3 c = camera_.project(hit->position, v);
            const glm::dvec3 r = camera_.project(hit->position + tools_.brush.radius * camera_.right(), v);
            out["brush"] = {c.x, c.y, std::hypot(r.x - c.x, r.y - c.y)};
        }
    }
    return out;
}

json App::command(const json& c) {
    const std::string cmd = c.value("cmd", std::string());
    if (cmd == "state") return state();
    if (cmd == "open") {
        open(c.value("path", std::string()));
        return {{"load_error", load_error_}};
    }
    if (cmd == "load-scene") {
        load_scene(c.value("scene", json()));
        return state();
    }
    if (cmd == "export-mesh") {
        const std::string format = c.value("format", std::string("ply"));
        if (format != "obj" && format != "ply" && format != "glb" && format != "off")
            throw InputError("export: format must be obj, ply, glb or off");
        const std::string stem = std::filesystem::path(session_->mesh_name()).stem().string();
        const std::string name = (stem.rfind("builtin:", 0) == 0 ? stem.substr(8) : stem) + "-deformed." + format;
        const std::string path = std::string(kFiles) + "/" + name;
        session_->export_mesh(path);
        return {{"path", path}, {"name", name}};
    }
    if (cmd == "export-scene") {
        // Written beside the uploaded meshes so the mesh path is the file's name;
        // after an apply the baked mesh comes along (NAME.mesh.ply).
        const std::string path = std::string(kFiles) + "/vfsd-scene.json";
        session_->save_scene(path);
        json out = {{"scene", json::parse(read_file(path))}, {"path", path}, {"files", json::array()}};
        const std::string mesh = out["scene"].value("mesh", std::string());
        if (mesh == "vfsd-scene.mesh.ply") out["files"].push_back(std::string(kFiles) + "/" + mesh);
        return out;
    }
    if (cmd == "project") {
        // Canvas pixels of points (tests aim the pointer with them), and the eye.
        json out = {{"pixels", json::array()}, {"eye", points_json({camera_.eye()})[0]}};
        for (const json& p : c.at("points")) {
            const glm::dvec3 q = camera_.project(Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()), viewport());
            out["pixels"].push_back({q.x, q.y});
        }
        return out;
    }
    if (cmd == "gizmo-parts") {
        // Canvas pixels of a point on each part of the handle gizmo (tests aim the
        // pointer with them); null outside handle mode.
        const auto gizmo = tools_.gizmo(*session_, camera_, viewport());
        if (!gizmo) return {{"parts", nullptr}};
        json parts = json::object();
        for (const editor::GizmoPart part : editor::kGizmoParts)
            if (const auto p = gizmo->grab_point(part)) parts[editor::gizmo_part_name(part)] = {p->x, p->y};
        return {{"parts", parts}, {"centre", {gizmo->centre().x, gizmo->centre().y}}};
    }
    if (cmd == "checksum") {
        // A cheap fingerprint of the current positions.
        double sum = 0.0;
        const auto& p = session_->positions();
        for (std::size_t i = 0; i < p.size(); ++i) sum += double(1 + i % 7) * (p[i].x + 2.0 * p[i].y + 3.0 * p[i].z);
        return {{"checksum", sum}};
    }
    if (cmd == "script") {
        script_ = std::make_unique<editor::ScriptRunner>(editor::parse_script(c.at("actions").dump(), "script"));
        return state();
    }
    if (cmd == "context") {
        // Test hook: what the page's context-loss handlers call.
        c.value("lost", false) ? context_lost() : context_restored();
        return state();
    }
    editor::CommandContext context = this->context();
    if (cmd == "key") {
        // The page's keys: the editor's key table; "handled" says whether one is bound.
        const bool handled = editor::run_key(c.value("key", ""), c.value("ctrl", false), c.value("shift", false), context);
        json out = state();
        out["handled"] = handled;
        return out;
    }
    // Everything else is a command of the editor's table (docs/commands.md).
    editor::run_command(cmd, c, context);
    return state();
}

std::size_t App::array(int which) {
    array_.clear();
    if (which == 0) {
        for (const Vec3& p : session_->positions()) array_.insert(array_.end(), {p.x, p.y, p.z});
    } else {
        array_ = session_->s();
    }
    return array_.size();
}

void App::frame() {
    if (lost_) return;
    try {
        if (script_ && !script_->done()) {
            script_->run_frame(context());
            if (script_->done()) log(script_->failed() ? "script failed: " + script_->error() : "script: done");
        }
        // Integrate toward the target within the frame's budget. The page times
        // update() itself: WebGL runs asynchronously, and update() ends with the
        // stats' read-back, so its wall time includes the GPU's work.
        const int budget = std::clamp(int(kStepBudgetMs / std::max(ms_per_step_, 0.05)), 1, 250);
        const double start = emscripten_get_now();
        const int taken = session_->update(budget);
        if (taken > 0) ms_per_step_ = (emscripten_get_now() - start) / taken;
        if (autosave_.maybe_save(*session_)) vfsd_page_autosaved();
        view_.wireframe = settings_.wireframe;
        view_.draw(*session_, camera_, viewport());
    } catch (const std::exception& e) {
        status_ = e.what();
        log(std::string("frame: ") + e.what());
    }
    vfsd_page_frame(overlay().dump().c_str());
}

void App::context_lost() {
    // Nothing on the GPU survives; the mesh, region and curve live on the CPU.
    lost_ = true;
    drag_ = Drag::none;
    vfsd_page_context(1);
}

void App::context_restored() {
    // New GL objects for everything; the deformation restarts from the CPU state
    // and integrates back to the target time.
    view_.reset();
    session_->set_force_cpu(!settings_.force_cpu);  // each switch drops the deformation
    session_->set_force_cpu(settings_.force_cpu);
    init_gl();
    lost_ = false;
    vfsd_page_context(0);
}

std::unique_ptr<App> app;
std::string reply;

}  // namespace
}  // namespace vfsd::web

using vfsd::web::app;
using vfsd::web::reply;

extern "C" {

// Runs one command (a JSON object); returns JSON, with "error" when it failed.
EMSCRIPTEN_KEEPALIVE const char* vfsd_command(const char* text) {
    try {
        if (!app) throw std::runtime_error("the editor is not running");
        reply = app->command(nlohmann::json::parse(text)).dump();
    } catch (const std::exception& e) {
        reply = nlohmann::json{{"error", e.what()}}.dump();
    }
    return reply.c_str();
}

// kind: 0 press, 1 move, 2 release, 3 leave; canvas pixels, origin top left.
EMSCRIPTEN_KEEPALIVE void vfsd_pointer(int kind, double x, double y, int button, int shift) {
    if (app) app->pointer(kind, x, y, button, shift != 0);
}

EMSCRIPTEN_KEEPALIVE void vfsd_wheel(double delta, double x, double y) {
    if (app) app->wheel(delta, x, y);
}

// Fills a buffer with the positions (which = 0, xyz per vertex) or s (1); returns
// its address (the count is vfsd_array_size()).
EMSCRIPTEN_KEEPALIVE const double* vfsd_array(int which) {
    if (!app) return nullptr;
    app->array(which);
    return app->array_data().data();
}

EMSCRIPTEN_KEEPALIVE int vfsd_array_size() { return app ? int(app->array_data().size()) : 0; }

// Starts the editor once the autosave folder is loaded (vfsd_page_load_autosave).
EMSCRIPTEN_KEEPALIVE void vfsd_start() {
    char* text = vfsd_page_options();
    const nlohmann::json options = nlohmann::json::parse(text, nullptr, false);
    std::free(text);
    try {
        app = std::make_unique<vfsd::web::App>(options.is_object() ? options : nlohmann::json::object());
    } catch (const std::exception& e) {
        EM_ASM({ if (Module.vfsdFailed) Module.vfsdFailed(UTF8ToString($0)); }, e.what());
        return;
    }
    emscripten_set_webglcontextlost_callback(
        "#vfsd-canvas", nullptr, true, [](int, const void*, void*) -> EM_BOOL {
            app->context_lost();
            return EM_TRUE;  // prevents the default, so the context can come back
        });
    emscripten_set_webglcontextrestored_callback(
        "#vfsd-canvas", nullptr, true, [](int, const void*, void*) -> EM_BOOL {
            app->context_restored();
            return EM_TRUE;
        });
    emscripten_set_main_loop([] { app->frame(); }, 0, false);
}

}  // extern "C"

int main() {
    vfsd_page_load_autosave(vfsd::web::kAutosave);
    return 0;
}
