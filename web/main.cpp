// vfsd-web: the browser editor's shell. Like desktop/, an adapter around the
// editor (engine/editor/editor.h): pointer events from the page go to the
// Editor's pointer calls, every control to its command table, and the engine's
// renderer draws into a WebGL2 canvas. The GPU path runs in that canvas's
// context when it renders to float textures (EXT_color_buffer_float); otherwise
// the CPU path runs and the stats say why.
//
// The page (web/vfsd-page.js) talks to this file through four C functions:
// vfsd_command (JSON in, JSON out: the editor's command table, editor/commands.h,
// and the page's queries: state, open, exports, projections),
// vfsd_pointer, vfsd_wheel and vfsd_array (positions or s for the tests). Each
// frame ends by handing the page the Editor's overlay (control points, loops, the
// brush, the gizmo) to draw on the 2D canvas above the WebGL one.
//
// Frames are drawn only while something changes: the deformation moves, a script
// runs, or a command, the pointer, the wheel or the page (vfsd_wake) asked for
// one. Otherwise the main loop pauses, and an autosave still due wakes it once.
//
// The autosave (editor/autosave.h) lives in /autosave, an IDBFS folder the page
// loads from IndexedDB before the editor starts and writes back after each
// autosave, so a reloaded page offers to restore the session.

#include <emscripten.h>
#include <emscripten/eventloop.h>
#include <emscripten/html5.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "editor/editor.h"
#include "gpu/gpu_deformation.h"
#include "editor/page_api.h"
#include "editor/session_view.h"
#include "gpu/capabilities.h"
#include "gpu/context.h"

// The page's side (web/vfsd-page.js): start-up options, and one call per frame.
EM_JS(char*, vfsd_page_options, (), {
    const text = JSON.stringify(Module.vfsdOptions || {});
    const size = lengthBytesUTF8(text) + 1;
    const out = _malloc(size);
    stringToUTF8(text, out, size);
    return out;
});
// The renderer's name, from a context of a canvas of its own (lost again at once):
// it decides the view canvas's own context attributes, so must come first.
EM_JS(char*, vfsd_page_probe_renderer, (), {
    let name = "";
    try {
        const gl = document.createElement('canvas').getContext('webgl2');
        if (gl) {
            const info = gl.getExtension('WEBGL_debug_renderer_info');
            name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER) || "");
            const lose = gl.getExtension('WEBGL_lose_context');
            if (lose) lose.loseContext();
        }
    } catch (e) {
        name = "";
    }
    const size = lengthBytesUTF8(name) + 1;
    const out = _malloc(size);
    stringToUTF8(name, out, size);
    return out;
});
// The editor could not start: the page says why.
EM_JS(void, vfsd_page_failed, (const char* message), {
    if (Module.vfsdFailed) Module.vfsdFailed(UTF8ToString(message));
});
// Returns whether the page wants another frame (it waits on one).
EM_JS(int, vfsd_page_frame, (const char* overlay), {
    return Module.vfsdFrame && Module.vfsdFrame(UTF8ToString(overlay)) ? 1 : 0;
});
// A frame that did not draw while the deformation runs: the page's panel shows the progress.
EM_JS(void, vfsd_page_progress, (), {
    if (Module.vfsdProgress) Module.vfsdProgress();
});
// A frame's steps reached the target time: when, on the page's clock (performance.now()).
EM_JS(void, vfsd_page_reached_target, (double now), {
    if (Module.vfsdReachedTarget) Module.vfsdReachedTarget(now);
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
// While draws are skipped, the page's panel (time, progress) is refreshed this often.
constexpr double kProgressMs = 100.0;

// The renderer's real name (WEBGL_debug_renderer_info), else WebGL's masked one.
std::string webgl_renderer(EMSCRIPTEN_WEBGL_CONTEXT_HANDLE gl, const std::string& masked) {
    constexpr GLenum kUnmaskedRenderer = 0x9246;  // UNMASKED_RENDERER_WEBGL
    if (!emscripten_webgl_enable_extension(gl, "WEBGL_debug_renderer_info")) return masked;
    char* text = emscripten_webgl_get_parameter_utf8(kUnmaskedRenderer);
    std::string name = text ? text : "";
    std::free(text);
    return name.empty() ? masked : name;
}

class WebGlContext final : public gpu::Context {
public:
    explicit WebGlContext(EMSCRIPTEN_WEBGL_CONTEXT_HANDLE handle) : handle_(handle) {}
    void make_current() override { emscripten_webgl_make_context_current(handle_); }
    std::string kind() const override { return "webgl2"; }

private:
    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE handle_;
};

class App final : public editor::Shell {
public:
    explicit App(const json& options);

    void frame();
    // Something may look different: draw the next frame (resumes a paused loop).
    void wake();
    // Only the overlay may look different: hand the page the next frame's overlay
    // without drawing the canvas.
    void wake_overlay();
    json command(const json& c);
    void pointer(int kind, double x, double y, int button, bool shift);
    void wheel(double delta, double x, double y) {
        wake();
        editor_->wheel(-delta / 100.0, x, y);
    }
    // Positions (0) or s (1) of the current shape as doubles; returns the count.
    std::size_t array(int which);
    const std::vector<double>& array_data() const { return array_; }

    // editor::Shell
    Viewport viewport() const override;
    void log(const std::string& line) override { std::printf("%s\n", line.c_str()); }
    void screenshot(const std::string&, bool) override { log("script: screenshots are the page's (canvas)"); }
    void autosaved() override { vfsd_page_autosaved(); }
    bool keeps_image() const override { return true; }  // the canvas: preserveDrawingBuffer
    bool renderer_busy() const override { return fence_ != nullptr; }
    long frames_drawn() const override { return frames_drawn_; }

    void context_lost();
    void context_restored();

private:
    void init_gl();
    std::string url_choice(const json& options, const char* name, const std::vector<std::string>& allowed);
    editor::PageInfo page() const { return {kFiles, gl_renderer_, lost_, multisampled_, frames_drawn_}; }
    void pause();
    void resume();
    // Wakes the loop as it goes out of scope (an event's or a command's handler
    // that threw too): after the edit, so that resume() sees a run it started.
    struct WakeAfter {
        App& app;
        bool wake = true;
        bool overlay_only = false;  // set once the handler knows the canvas's image did not change
        ~WakeAfter() {
            if (wake) overlay_only ? app.wake_overlay() : app.wake();
        }
    };
    enum class Timing { animation_frames, timeout, immediate };
    void set_timing(Timing timing);  // how the main loop calls the next frame
    void autosave_due();
    void fence_draw(bool timed);
    void poll_fence();

    bool dirty_ = true;    // draw the next frame
    bool overlay_due_ = false;  // hand the page the next frame's overlay, even without a draw
    long frames_drawn_ = 0;
    GLsync fence_ = nullptr;  // set after each draw, until the GPU finished it
    double fenced_at_ = 0.0;
    bool fence_timed_ = false;                  // the draw came while the deformation ran: its time goes to the pacer
    Timing timing_ = Timing::animation_frames;  // how the main loop's next frame is called
    double panel_at_ = 0.0;  // when the page's panel last showed the state (emscripten_get_now)
    bool waiting_ = false;  // the page waits for a drawn frame (its frame call said so)
    bool paused_ = false;  // the main loop waits for wake()
    bool autosave_timer_ = false;

    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE gl_ = 0;
    bool lost_ = false;
    bool allow_float_ = true;
    std::string antialias_ = "auto";  // ?antialias=on|off: multisample the view or not (gpu::multisample_view)
    bool multisampled_ = false;
    std::string backend_ = "auto";
    std::string gl_renderer_;
    editor::DeformationFactory gpu_;
    // A curve edit's GPU deformation takes the last one's set-up (textures,
    // programs, the fold test's checks) from here.
    std::shared_ptr<gpu::GpuRestShelf> gpu_shelf_ = std::make_shared<gpu::GpuRestShelf>();
    std::string gpu_reason_;

    std::unique_ptr<editor::Editor> editor_;
    editor::SessionView view_;
    std::vector<double> array_;
};

// The value of URL option `name` if it is one of `allowed` (the first is the
// default); another is reported in the page's log, and the default taken.
std::string App::url_choice(const json& options, const char* name, const std::vector<std::string>& allowed) {
    const std::string value = options.value(name, allowed.front());
    if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    log("?" + std::string(name) + "=" + value + ": expected one of " + list + "; " + allowed.front() + " taken");
    return allowed.front();
}

App::App(const json& options) {
    allow_float_ = options.value("float", true);
    antialias_ = url_choice(options, "antialias", {"auto", "on", "off"});
    backend_ = url_choice(options, "backend", {"auto", "cpu", "gpu"});
    std::filesystem::create_directories(kFiles);
    init_gl();
    editor::EditorOptions editor_options;
    editor_options.autosave_directory = kAutosave;
    editor_options.autosave_seconds = kAutosaveSeconds;
    editor_ = std::make_unique<editor::Editor>(*this, gpu_, gpu_reason_, editor_options);
    log("WebGL2: " + gl_renderer_ + (gpu_ ? " (GPU path)" : " (CPU path: " + gpu_reason_ + ")") +
        (multisampled_ ? ", multisampled" : ", not multisampled"));
    editor_->open_default(kDefaultScene, true);
}

void App::init_gl() {
    EmscriptenWebGLContextAttributes attrs;
    emscripten_webgl_init_context_attributes(&attrs);
    attrs.majorVersion = 2;
    attrs.minorVersion = 0;
    attrs.alpha = false;
    if (!gl_) {
        char* probe = vfsd_page_probe_renderer();
        attrs.antialias = multisampled_ = gpu::multisample_view(probe, antialias_);
        std::free(probe);
    }
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
    gl_renderer_ = webgl_renderer(gl_, caps.renderer);
    caps.renderer = gl_renderer_;
    // ?backend=gpu runs the GPU passes even on a software renderer.
    gpu_reason_ = gpu::cpu_path_reason(caps, backend_);
    gpu_ = gpu_reason_.empty() ? editor::DeformationFactory([shelf = gpu_shelf_](const PreparedScene& p) {
        return gpu::start_gpu_deformation(p, shelf);
    })
                               : editor::DeformationFactory();
}

Viewport App::viewport() const {
    int w = 1, h = 1;
    emscripten_get_canvas_element_size(kCanvas, &w, &h);
    return {std::max(w, 1), std::max(h, 1)};
}

// kind: 0 press, 1 move, 2 release, 3 leave; another button or Shift pans.
// The loop is woken after the event, as after a command: a release that started
// a run is then started by a timeout, not the next animation frame.
// A move that changed neither the camera nor what the canvas shows (the session's
// revision: positions, s) changes only the overlay: the hover highlight, the brush,
// a dragged point. The canvas then keeps its image; on a software renderer a draw
// of a large mesh takes 50-150 ms, and during an edit's run it would take the
// renderer from the steps.
void App::pointer(int kind, double x, double y, int button, bool shift) {
    WakeAfter wake_after{*this};  // the hover highlight and the brush follow the pointer
    const std::uint64_t revision = editor_->session().revision();
    const glm::dmat4 view = editor_->camera().view();
    if (kind == 0) editor_->press(x, y, button != 0 || shift);
    else if (kind == 1) editor_->move(x, y);
    else if (kind == 2) editor_->release();
    else editor_->leave();
    wake_after.overlay_only = kind == 1 && editor_->session().revision() == revision && editor_->camera().view() == view;
}

// The page's commands (editor/page_api.h), and the context-loss handlers' test hook.
// Every command but the read-only queries may change what is drawn: the loop is
// woken after the command (one that failed too), so that resume() sees the run
// an edit started and starts it by a timeout, not the next animation frame (up
// to a display frame later).
json App::command(const json& c) {
    const std::string cmd = c.value("cmd", std::string());
    if (cmd == "context") {
        wake();
        c.value("lost", false) ? context_lost() : context_restored();
        return editor::page_state(*editor_, page());
    }
    const WakeAfter wake_after{*this, !editor::page_query(cmd)};
    return editor::page_command(*editor_, c, page());
}

std::size_t App::array(int which) {
    editor::EditorSession& s = editor_->session();
    array_.clear();
    if (which == 1) {
        s.finish_region();  // the API's s is final, not eq. (15)'s or (16)'s meanwhile
        array_ = s.s();
    } else
        for (const Vec3& p : s.positions()) array_.insert(array_.end(), {p.x, p.y, p.z});
    return array_.size();
}

void App::wake() {
    dirty_ = true;
    resume();
}

void App::wake_overlay() {
    overlay_due_ = true;
    resume();
}

void App::resume() {
    if (!paused_) return;
    paused_ = false;
    // An edit that starts a run while draws are costly starts it by a timeout:
    // the next animation frame waits for the renderer, on a software renderer
    // 130-160 ms after a drag (the page's run's draws are skipped anyway).
    if (editor_->busy() && editor_->draws_costly()) set_timing(Timing::timeout);
    emscripten_resume_main_loop();
}

// Nothing to draw until wake(); a due autosave wakes the loop once its interval passed.
void App::pause() {
    paused_ = true;
    // A draw still unfinished now would be timed across the pause: it is not a
    // draw's cost. Its fence stays: the next frame's GL work waits for it.
    fence_timed_ = false;
    emscripten_pause_main_loop();
    const editor::Autosave& autosave = editor_->autosave();
    if (autosave_timer_ || autosave.offer() || !autosave.behind(editor_->session())) return;
    autosave_timer_ = true;
    emscripten_set_timeout([](void* self) { static_cast<App*>(self)->autosave_due(); }, 1000.0 * kAutosaveSeconds,
                           this);
}

// One frame without drawing: advance() writes the autosave.
void App::autosave_due() {
    autosave_timer_ = false;
    resume();
}

void App::frame() {
    if (lost_) return pause();  // context_restored() wakes it
    poll_fence();
    bool draw = dirty_;
    // A draw waits for the last one: on a software renderer a draw takes 50-150 ms
    // of the GPU process, and GL calls made meanwhile (a second draw, the GPU
    // deformation's set-up) wait for it on the main thread. What changed is drawn
    // once the renderer is free (dirty_ stays).
    try {
        // While the deformation runs the pacer decides (a costly draw is skipped in
        // some frames); otherwise a frame draws when something changed or the page
        // waits for a frame.
        const bool busy = editor_->busy();
        const bool moving = editor_->session().moving();
        editor_->advance();
        if (moving && !editor_->session().moving()) vfsd_page_reached_target(emscripten_get_now());
        draw = (draw || (busy ? editor_->draw_due() : waiting_)) && !fence_;
        if (draw) {
            view_.wireframe = editor_->settings().wireframe;
            view_.draw(editor_->session(), editor_->camera(), viewport());
            ++frames_drawn_;
            fence_draw(editor_->busy());
        }
    } catch (const std::exception& e) {
        editor_->set_status(e.what());
        log(std::string("frame: ") + e.what());
    }
    const double now = emscripten_get_now();
    bool shown = draw || overlay_due_;  // this frame changed what the page shows
    if (draw || overlay_due_) {
        if (draw) dirty_ = false;  // a command the page runs in its frame sets it again
        overlay_due_ = false;
        waiting_ = vfsd_page_frame(editor::overlay_json(editor_->overlay(editor_->pointer())).dump().c_str());
        panel_at_ = now;
    } else if (editor_->busy() && now - panel_at_ >= kProgressMs) {
        vfsd_page_progress();  // the pacer skips costly draws; the panel still follows the run
        panel_at_ = now;
        shown = true;
    }
    // While costly draws are skipped, a frame that only integrates is followed at
    // once (setImmediate: no 4 ms timeout clamp) and one that changed what the page
    // shows by a timeout, which gives the browser a chance to render it; frames
    // queued back to back by setImmediate alone left it none until the run ended.
    // One that ended waiting for the GPU's passes (steps in pieces) is followed by
    // a timeout too: polling its fence back to back would keep a core from them.
    const Timing timing = !(editor_->busy() && editor_->draws_costly()) ? Timing::animation_frames
                          : shown || editor_->waiting_on_gpu()          ? Timing::timeout
                                                                        : Timing::immediate;
    set_timing(timing);
    if (!dirty_ && !waiting_ && !editor_->busy()) pause();
}

void App::set_timing(Timing timing) {
    if (timing == timing_) return;
    if (timing == Timing::immediate)
        emscripten_set_main_loop_timing(EM_TIMING_SETIMMEDIATE, 0);
    else if (timing == Timing::timeout)
        emscripten_set_main_loop_timing(EM_TIMING_SETTIMEOUT, 0);
    else
        emscripten_set_main_loop_timing(EM_TIMING_RAF, 1);
    timing_ = timing;
}

// WebGL runs the draw in the GPU process; a fence tells when it is done, without
// waiting (glGetError or a read-back would wait), and that time is the draw's cost.
void App::fence_draw(bool timed) {
    if (fence_) return;
    fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    fenced_at_ = emscripten_get_now();
    fence_timed_ = timed;
}

void App::poll_fence() {
    if (!fence_) return;
    GLint status = GL_UNSIGNALED;
    glGetSynciv(fence_, GL_SYNC_STATUS, 1, nullptr, &status);
    const double ms = emscripten_get_now() - fenced_at_;
    if (status != GL_SIGNALED && ms < 1000.0) return;
    if (fence_timed_) editor_->renderer_finished(ms);
    glDeleteSync(fence_);
    fence_ = nullptr;
}

void App::context_lost() {
    // Nothing on the GPU survives; the mesh, region and curve live on the CPU.
    lost_ = true;
    editor_->release();
    gpu_shelf_->clear();  // its GL objects went with the context
    vfsd_page_context(1);
}

void App::context_restored() {
    // New GL objects for everything; the deformation restarts from the CPU state
    // and integrates back to the target time.
    view_.reset();
    fence_ = nullptr;  // it went with the lost context
    editor_->restart_deformation();
    gpu_shelf_->clear();
    init_gl();
    lost_ = false;
    vfsd_page_context(0);
    wake();
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

// The page asks for a frame: the canvas was resized, or it waits on a frame.
EMSCRIPTEN_KEEPALIVE void vfsd_wake() {
    if (app) app->wake();
}

// Starts the editor once the autosave folder is loaded (vfsd_page_load_autosave).
EMSCRIPTEN_KEEPALIVE void vfsd_start() {
    char* text = vfsd_page_options();
    const nlohmann::json options = nlohmann::json::parse(text, nullptr, false);
    std::free(text);
    try {
        app = std::make_unique<vfsd::web::App>(options.is_object() ? options : nlohmann::json::object());
    } catch (const std::exception& e) {
        vfsd_page_failed(e.what());
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
