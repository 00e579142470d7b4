#include "desktop/app.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "gpu/gpu_deformation.h"
#include "gpu/capabilities.h"
#include "gpu/context.h"
#include "gpu/gl.h"
#include "io/png.h"

namespace vfsd::desktop {
namespace {

// The window's context as the GPU path sees it.
class GlfwContext final : public gpu::Context {
public:
    explicit GlfwContext(GLFWwindow* window) : window_(window) {}
    void make_current() override { glfwMakeContextCurrent(window_); }
    std::string kind() const override { return "glfw"; }

private:
    GLFWwindow* window_;
};

GLFWwindow* open_window(const AppOptions& options) {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) throw std::runtime_error("cannot initialise GLFW (no display? set DISPLAY or use xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    const auto create = [&](int samples) {
        glfwWindowHint(GLFW_SAMPLES, samples);
        GLFWwindow* window = glfwCreateWindow(options.width, options.height, "vfsd", nullptr, nullptr);
        if (!window) {
            glfwTerminate();
            throw std::runtime_error("cannot open a window with an OpenGL 3.3 core context");
        }
        glfwMakeContextCurrent(window);
        return window;
    };
    // Multisampled unless the renderer, known once a context exists, rasterises
    // in software (gpu::multisample_view): then the window is opened again without.
    GLFWwindow* window = create(4);
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (!gpu::multisample_view(renderer ? renderer : "", options.antialias)) {
        glfwDestroyWindow(window);
        window = create(0);
    }
    glfwSwapInterval(options.script.empty() ? 1 : 0);
    return window;
}

// An event for the window's frames to draw (redraw.h).
void wake(GLFWwindow* window) { static_cast<App*>(glfwGetWindowUserPointer(window))->on_event(); }

}  // namespace

App::App(const AppOptions& options) : options_(options), window_(open_window(options)) {
    glfwSetWindowUserPointer(window_, this);
    glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
        App* app = static_cast<App*>(glfwGetWindowUserPointer(w));
        app->on_event();
        if (count > 0) app->on_drop(std::vector<std::string>(paths, paths + count));
    });
    // Any event wakes the window's frames (redraw.h). Set before ImGui's backend,
    // which calls the callbacks it finds (ImGui 1.86 polls the cursor, so its
    // callback is the window's alone).
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double, double) {
        static_cast<App*>(glfwGetWindowUserPointer(w))->on_cursor_moved();
    });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int, int, int) { wake(w); });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double) { wake(w); });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int, int, int, int) { wake(w); });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned int) { wake(w); });
    glfwSetCursorEnterCallback(window_, [](GLFWwindow* w, int) { wake(w); });
    glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int) { wake(w); });
    glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { wake(w); });
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { wake(w); });
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsLight();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    // The GPU path runs in this window's context when it can, else the CPU path.
    GlfwContext context(window_);
    const std::string reason = gpu::cpu_path_reason(gpu::query_capabilities(), options.backend);
    // A curve edit's GPU deformation takes the last one's set-up from the shelf.
    const auto shelf = std::make_shared<gpu::GpuRestShelf>();
    const editor::DeformationFactory gpu = reason.empty() ? editor::DeformationFactory([shelf](const PreparedScene& p) {
        return gpu::start_gpu_deformation(p, shelf);
    })
                                                          : editor::DeformationFactory();
    editor::EditorOptions editor_options;
    editor_options.autosave_directory = editor::default_autosave_directory();
    editor_options.force_cpu = options.backend == "cpu";
    editor_ = std::make_unique<editor::Editor>(*this, gpu, reason, editor_options);
    GLint samples = 0;
    glGetIntegerv(GL_SAMPLES, &samples);
    log(std::string("GL: ") + context.renderer() + (gpu ? " (GPU path)" : " (CPU path: " + reason + ")") +
        (samples > 1 ? ", multisampled" : ", not multisampled"));

    // The starting document: the mesh or scene asked for, else the default scene.
    const std::string first = !options.mesh.empty() ? options.mesh : options.scene;
    if (!first.empty()) open(first);
    editor_->open_default(VFSD_DEFAULT_SCENE, first.empty());
    if (!options.script.empty()) editor_->run_script(editor::load_script(options.script));
}

App::~App() {
    view_.reset();
    editor_.reset();  // GPU objects die while the context lives
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
}

// The framebuffer's size in pixels (on HiDPI screens larger than the window's).
Viewport App::viewport() const {
    int size[2] = {1, 1};
    glfwGetFramebufferSize(window_, &size[0], &size[1]);
    return {std::max(size[0], 1), std::max(size[1], 1)};
}

void App::log(const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); }

bool App::command(const std::string& name, const nlohmann::json& args) {
    try {
        editor_->command(name, args);
        return true;
    } catch (const std::exception& e) {
        editor_->set_status(e.what());
        return false;
    }
}

void App::remember(const std::string& path) {
    recent_.erase(std::remove(recent_.begin(), recent_.end(), path), recent_.end());
    recent_.push_front(path);
    if (recent_.size() > 8) recent_.pop_back();
}

void App::open(const std::string& path) {
    if (editor_->open(path)) remember(path);
}

// Several files dropped together open together: a scene with the mesh it names.
void App::on_drop(const std::vector<std::string>& paths) {
    if (editor_->open(paths)) remember(editor::EditorSession::main_file(paths));
}

void App::simulate_crash() {
    log("script: simulated crash (the autosave stays)");
    std::fflush(stderr);
    std::_Exit(3);
}

void App::screenshot(const std::string& path, bool ui) { pending_screenshot_ = std::make_pair(path, ui); }

// ---- scripted orbits: pointer and frame times -------------------------------------

void App::point_at(double x, double y) { scripted_pointer_ = std::make_pair(x, y); }

void App::log_frame_times(int frames) { frame_log_.start(frames); }

void App::save_screenshot(const std::string& path) const {
    const Viewport v = viewport();
    std::vector<std::uint8_t> pixels(std::size_t(v.width) * v.height * 4), flipped(pixels.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, v.width, v.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    const std::size_t row = std::size_t(v.width) * 4;
    for (int y = 0; y < v.height; ++y)
        std::copy_n(&pixels[std::size_t(v.height - 1 - y) * row], row, &flipped[std::size_t(y) * row]);
    for (std::size_t i = 3; i < flipped.size(); i += 4) flipped[i] = 255;
    write_png(path, v.width, v.height, flipped);
}

// ---- input -------------------------------------------------------------------------

glm::dvec2 App::pointer() const {
    const ImGuiIO& io = ImGui::GetIO();
    const Viewport v = viewport();
    int window_w = 1, window_h = 1;
    glfwGetWindowSize(window_, &window_w, &window_h);
    return {io.MousePos.x * v.width / std::max(window_w, 1), io.MousePos.y * v.height / std::max(window_h, 1)};
}

void App::handle_input() {
    ImGuiIO& io = ImGui::GetIO();
    const glm::dvec2 p = pointer();
    if (!editor_->dragging() && !io.WantCaptureMouse) {
        if (io.MouseWheel != 0.0f) editor_->wheel(io.MouseWheel, p.x, p.y);
        if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) editor_->press(p.x, p.y, io.KeyShift);
        else if (ImGui::IsMouseClicked(ImGuiMouseButton_Right) || ImGui::IsMouseClicked(ImGuiMouseButton_Middle))
            editor_->press(p.x, p.y, true);
        else editor_->move(p.x, p.y);
        return;
    }
    const bool held = ImGui::IsMouseDown(ImGuiMouseButton_Left) || ImGui::IsMouseDown(ImGuiMouseButton_Right) ||
                      ImGui::IsMouseDown(ImGuiMouseButton_Middle);
    if (!held) editor_->release();
    else if (p != editor_->pointer().value_or(p + 1.0)) editor_->move(p.x, p.y);
}

// A cursor move changes what is shown over the panels (their hover), with a button
// held (a drag), with a brush (its outline follows), or where the hovered curve
// point or gizmo part differs from the last drawn frame's.
bool App::cursor_shows(const Hover& now) const {
    const bool held = ImGui::IsMouseDown(ImGuiMouseButton_Left) || ImGui::IsMouseDown(ImGuiMouseButton_Right) ||
                      ImGui::IsMouseDown(ImGuiMouseButton_Middle);
    return now.panels || now.brush || held || !(now == drawn_hover_);
}

// ---- the overlay: what the editor hands over, in ImGui's background list ----------------

namespace {

ImU32 colour(editor::Rgb c, int alpha = 255) { return IM_COL32(c.r, c.g, c.b, alpha); }

// Each stroke over a dark one, so it shows on the blue and red regions alike.
void stroke(ImDrawList* draw, const std::vector<ImVec2>& points, editor::Rgb c, bool bold, ImDrawFlags flags) {
    const float width = bold ? 4.0f : 2.5f;
    draw->AddPolyline(points.data(), int(points.size()), IM_COL32(20, 20, 20, 150), flags, width + 2.0f);
    draw->AddPolyline(points.data(), int(points.size()), colour(c), flags, width);
}

void draw_gizmo(ImDrawList* draw, const editor::GizmoShapes& shapes, editor::GizmoPart hot, float scale) {
    const auto at = [&](glm::dvec2 p) { return ImVec2(float(p.x) * scale, float(p.y) * scale); };
    const auto line = [&](const std::vector<glm::dvec2>& points) {
        std::vector<ImVec2> out;
        for (const glm::dvec2& p : points) out.push_back(at(p));
        return out;
    };
    for (const editor::GizmoRing& ring : shapes.rings)
        stroke(draw, line(ring.points), ring.colour, ring.part == hot, ImDrawFlags_Closed);
    for (const editor::GizmoSegment& axis : shapes.axes) {
        stroke(draw, line({axis.from, axis.to}), axis.colour, axis.part == hot, ImDrawFlags_None);
        draw->AddCircleFilled(at(axis.to), 5.0f, colour(axis.colour));
        draw->AddCircle(at(axis.to), 5.0f, IM_COL32(20, 20, 20, 150), 0, 1.0f);
    }
    const float r = float(shapes.centre_radius) * scale;
    draw->AddCircleFilled(at(shapes.centre), r, colour(shapes.centre_colour));
    draw->AddCircle(at(shapes.centre), r, IM_COL32(20, 20, 20, 255), 0, 1.5f);
}

}  // namespace

void App::draw_overlay() {
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const float scale = float(ImGui::GetIO().DisplaySize.x / viewport().width);
    const auto at = [&](glm::dvec2 p) { return ImVec2(float(p.x) * scale, float(p.y) * scale); };
    const bool free = !ImGui::GetIO().WantCaptureMouse;
    const editor::Overlay o = editor_->overlay(free ? std::optional<glm::dvec2>(pointer()) : std::nullopt);
    hover_ = Hover{!free, o.brush.has_value(), -1, int(o.gizmo_hot)};
    for (std::size_t i = 0; i < o.points.size(); ++i)
        if (o.points[i].hot) hover_.point = int(i);
    for (const auto& [a, b] : o.polygon) draw->AddLine(at(a), at(b), IM_COL32(90, 90, 110, 200), 1.5f);
    for (const editor::OverlayPoint& p : o.points) {
        const ImU32 fill = p.hot ? IM_COL32(255, 200, 40, 255) : p.knot ? IM_COL32(30, 30, 30, 255) : IM_COL32(250, 250, 250, 255);
        draw->AddCircleFilled(at(p.at), p.hot ? 7.0f : 5.0f, fill);
        draw->AddCircle(at(p.at), p.hot ? 7.0f : 5.0f, IM_COL32(20, 20, 20, 255), 0, 1.5f);
    }
    if (o.gizmo) draw_gizmo(draw, *o.gizmo, o.gizmo_hot, scale);
    for (const glm::dvec2& p : o.loop_in_progress) draw->AddCircleFilled(at(p), 3.5f, IM_COL32(250, 230, 60, 255));
    for (const auto& loop : o.loops) {
        std::vector<ImVec2> points;
        for (const glm::dvec2& p : loop) points.push_back(at(p));
        draw->AddPolyline(points.data(), int(points.size()), IM_COL32(250, 230, 60, 255), ImDrawFlags_Closed, 2.0f);
    }
    if (o.brush) draw->AddCircle(at(*o.brush), float(o.brush->z) * scale, IM_COL32(255, 255, 255, 230), 48, 2.0f);
}

// ---- the main loop ------------------------------------------------------------------

bool App::script_over() const {
    const editor::ScriptRunner* script = editor_->script();
    return options_.exit_after_script && script && script->done();
}

int App::run() {
    using Clock = std::chrono::steady_clock;
    const auto elapsed_ms = [](Clock::time_point from, Clock::time_point to) {
        return std::chrono::duration<double, std::milli>(to - from).count();
    };
    const Clock::time_point opened = Clock::now();
    while (!glfwWindowShouldClose(window_) && !(script_over() && !pending_screenshot_)) {
        // At rest with nothing to draw, the window sleeps until an event (redraw.h).
        const double wait = redraw_.wait_seconds(elapsed_ms(opened, Clock::now()));
        if (wait > 0.0)
            glfwWaitEventsTimeout(wait);
        else
            glfwPollEvents();
        const Clock::time_point start = Clock::now();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        if (scripted_pointer_) {
            const float scale = float(ImGui::GetIO().DisplaySize.x / viewport().width);
            ImGui::GetIO().MousePos = ImVec2(float(scripted_pointer_->first) * scale, float(scripted_pointer_->second) * scale);
        }
        ImGui::NewFrame();
        handle_input();
        handle_shortcuts();
        editor_->advance();
        draw_panels();
        draw_restore_offer();
        draw_overlay();
        ImGui::Render();
        const Clock::time_point drawing = Clock::now();
        const editor::EditorSession& session = editor_->session();
        const editor::ScriptRunner* script = editor_->script();
        WindowRedraw::Frame frame;
        frame.now_ms = elapsed_ms(opened, drawing);
        frame.working = session.moving() || session.region_pending();
        frame.draw_due = editor_->draw_due();
        frame.input = std::exchange(input_, false) || (std::exchange(moved_, false) && cursor_shows(hover_));
        frame.scripted = script && !script->done();
        frame.screenshot = pending_screenshot_.has_value();
        if (!redraw_.draw(frame)) {
            if (frame_log_.active())
                for (const std::string& line : frame_log_.add({elapsed_ms(start, drawing), 0.0, 0.0})) log(line);
            continue;
        }
        ++frames_drawn_;
        drawn_hover_ = hover_;
        glEnable(GL_MULTISAMPLE);
        view_.wireframe = editor_->settings().wireframe;
        view_.draw(editor_->session(), editor_->camera(), viewport());
        const bool ui = !pending_screenshot_ || pending_screenshot_->second;
        if (ui && show_ui_) ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (pending_screenshot_) {
            try {
                save_screenshot(pending_screenshot_->first);
                editor_->set_status("saved " + pending_screenshot_->first);
            } catch (const std::exception& e) {
                editor_->set_status(e.what());
                log(e.what());
            }
            pending_screenshot_.reset();
            if (script_over()) break;
        }
        const Clock::time_point swapping = Clock::now();
        glfwSwapBuffers(window_);
        if (frame_log_.active())
            for (const std::string& line : frame_log_.add({elapsed_ms(start, drawing), elapsed_ms(drawing, swapping),
                                                           elapsed_ms(swapping, Clock::now())}))
                log(line);
    }
    editor_->clean_exit();
    return editor_->script() && editor_->script()->failed() ? 1 : 0;
}

}  // namespace vfsd::desktop
