#include "desktop/app.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <glm/gtc/type_ptr.hpp>
#include <imgui.h>

#include "base/error.h"
#include "editor/gpu_live_deformation.h"
#include "gpu/capabilities.h"
#include "gpu/context.h"
#include "gpu/gl.h"

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

// Per frame the deformation may take about this long, so the UI stays responsive.
constexpr double kStepBudgetMs = 15.0;
// A changed session is autosaved at most this often.
constexpr double kAutosaveSeconds = 10.0;
constexpr const char* kRestoreTitle = "Restore autosave";

}  // namespace

App::App(const AppOptions& options) : options_(options), autosave_(editor::default_autosave_directory(), kAutosaveSeconds) {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) throw std::runtime_error("cannot initialise GLFW (no display? set DISPLAY or use xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    window_ = glfwCreateWindow(options.width, options.height, "vfsd", nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw std::runtime_error("cannot open a window with an OpenGL 3.3 core context");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(options.script.empty() ? 1 : 0);
    glfwSetWindowUserPointer(window_, this);
    glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
        if (count > 0) static_cast<App*>(glfwGetWindowUserPointer(w))->on_drop(paths[0]);
    });

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsLight();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    // The GPU path runs in this window's context when it can, else the CPU path.
    GlfwContext context(window_);
    std::string reason;
    editor::DeformationFactory gpu;
    if (options.backend == "cpu") {
        reason = "--backend cpu";
    } else {
        try {
            gpu::require_gpu_support(gpu::query_capabilities());
            gpu = editor::make_gpu_deformation;
        } catch (const std::exception& e) {
            reason = e.what();
        }
    }
    session_ = std::make_unique<editor::EditorSession>(gpu, reason);
    settings_.force_cpu = options.backend == "cpu";
    log(std::string("GL: ") + context.renderer() + (gpu ? " (GPU path)" : " (CPU path: " + reason + ")"));

    // The starting document: the mesh or scene asked for, else the default scene.
    const std::string first = !options.mesh.empty() ? options.mesh : options.scene;
    if (!first.empty()) open(first);
    if (session_->triangles().empty()) {
        try {
            session_->open_scene_file(VFSD_DEFAULT_SCENE);
        } catch (const std::exception&) {
            session_->open_mesh("builtin:box");
        }
        tools_.adapt_to(*session_);
        loaded();
    }
    autosave_.mark_saved(*session_);
    if (first.empty()) offer_restore();
    if (!options.script.empty()) script_ = std::make_unique<editor::ScriptRunner>(editor::load_script(options.script));
}

App::~App() {
    renderer_.reset();
    cpu_vertices_.reset();
    session_.reset();  // GPU objects die while the context lives
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
}

editor::Viewport App::viewport() const {
    int w = 1, h = 1;
    glfwGetFramebufferSize(window_, &w, &h);
    return {std::max(w, 1), std::max(h, 1)};
}

editor::CommandContext App::context() { return {*session_, tools_, camera_, settings_, viewport(), *this}; }

void App::command(const std::string& name, const nlohmann::json& args) {
    try {
        editor::CommandContext c = context();
        editor::run_command(name, args, c);
    } catch (const std::exception& e) {
        status_ = e.what();
    }
}

void App::log(const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); }

void App::loaded() {
    // Frame the mesh and the whole curve, as `vfsd render` does.
    camera_ = editor::Camera();
    camera_.frame(gpu::deformation_frame_points(session_->base_positions(), session_->s(), session_->motion()),
                  viewport().aspect());
}

void App::remember(const std::string& path) {
    recent_.erase(std::remove(recent_.begin(), recent_.end(), path), recent_.end());
    recent_.push_front(path);
    if (recent_.size() > 8) recent_.pop_back();
}

void App::open(const std::string& path) {
    // A failed load leaves the current document as it was and says why.
    try {
        session_->open(path);
        tools_.adapt_to(*session_);
        loaded();
        remember(path);
        load_error_.clear();
        status_ = "opened " + path;
    } catch (const std::exception& e) {
        load_error_ = e.what();
        log("open failed: " + load_error_);
    }
}

void App::on_drop(const std::string& path) { open(path); }

// ---- autosave ------------------------------------------------------------------

void App::offer_restore() {
    autosave_.offer_restore(*session_);
    if (const auto& offer = autosave_.offer())
        log("autosave: " + offer->mesh + " from " + offer->written_text() + " in " + autosave_.directory());
    else if (!autosave_.problem().empty())
        log(autosave_.problem());
}

void App::answer_restore(bool restore) {
    if (autosave_.answer(*session_, restore)) {
        tools_.adapt_to(*session_);
        loaded();
    }
    status_ = !restore ? "discarded the autosave" : autosave_.problem().empty() ? "restored the autosave" : "";
    if (!autosave_.problem().empty()) log(autosave_.problem());
}

void App::autosave_now() {
    if (autosave_.offer()) throw InputError("answer the offer to restore the autosave first");
    if (!autosave_.save(*session_)) throw IoError(session_->warnings().back());
}

void App::simulate_crash() {
    log("script: simulated crash (the autosave stays)");
    std::fflush(stderr);
    std::_Exit(3);
}

void App::draw_restore_offer() {
    const auto& offer = autosave_.offer();
    if (offer && !ImGui::IsPopupOpen(kRestoreTitle)) ImGui::OpenPopup(kRestoreTitle);
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::BeginPopupModal(kRestoreTitle, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    if (offer) {
        ImGui::Text("Restore the autosaved session from %s (%s)?", offer->written_text().c_str(), offer->mesh.c_str());
        ImGui::TextDisabled("%s", autosave_.directory().c_str());
        const bool restore = ImGui::Button("Restore");
        ImGui::SameLine();
        const bool discard = ImGui::Button("Discard");
        if (restore || discard) answer_restore(restore);
    }
    if (!autosave_.offer()) ImGui::CloseCurrentPopup();  // answered here or by a script
    ImGui::EndPopup();
}

void App::screenshot(const std::string& path, bool ui) { pending_screenshot_ = std::make_pair(path, ui); }

// ---- scripted orbits: pointer and frame times -------------------------------------

void App::point_at(double x, double y) { scripted_pointer_ = std::make_pair(x, y); }

void App::log_frame_times(int frames) {
    frames_to_log_ = frames;
    logged_frames_.clear();
}

void App::log_frame(const FrameTimes& t) {
    char line[160];
    std::snprintf(line, sizeof line, "frame %zu: app %.2f ms, GL calls %.2f ms, swap %.2f ms, whole %.2f ms",
                  logged_frames_.size() + 1, t.app_ms, t.draw_ms, t.swap_ms, t.app_ms + t.draw_ms + t.swap_ms);
    log(line);
    logged_frames_.push_back(t);
    if (--frames_to_log_ > 0) return;
    // The medians over the logged frames.
    const auto median_of = [&](double FrameTimes::*part) {
        std::vector<double> v;
        for (const FrameTimes& f : logged_frames_) v.push_back(f.*part);
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    std::vector<double> whole;
    for (const FrameTimes& f : logged_frames_) whole.push_back(f.app_ms + f.draw_ms + f.swap_ms);
    std::sort(whole.begin(), whole.end());
    std::snprintf(line, sizeof line, "frames: %zu, median app %.2f ms, GL calls %.2f ms, swap %.2f ms, whole %.2f ms",
                  logged_frames_.size(), median_of(&FrameTimes::app_ms), median_of(&FrameTimes::draw_ms),
                  median_of(&FrameTimes::swap_ms), whole[whole.size() / 2]);
    log(line);
}

void App::save_screenshot(const std::string& path) const {
    const editor::Viewport v = viewport();
    std::vector<std::uint8_t> pixels(std::size_t(v.width) * v.height * 4), flipped(pixels.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, v.width, v.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    const std::size_t row = std::size_t(v.width) * 4;
    for (int y = 0; y < v.height; ++y)
        std::copy_n(&pixels[std::size_t(v.height - 1 - y) * row], row, &flipped[std::size_t(y) * row]);
    for (std::size_t i = 3; i < flipped.size(); i += 4) flipped[i] = 255;
    gpu::write_png(path, v.width, v.height, flipped);
}

void App::handle_input() {
    ImGuiIO& io = ImGui::GetIO();
    const editor::Viewport v = viewport();
    int window_w = 1, window_h = 1;
    glfwGetWindowSize(window_, &window_w, &window_h);
    // Pointer in framebuffer pixels (they differ from window units on HiDPI screens).
    const double x = io.MousePos.x * v.width / std::max(window_w, 1), y = io.MousePos.y * v.height / std::max(window_h, 1);
    const double dx = x - last_x_, dy = y - last_y_;
    last_x_ = x, last_y_ = y;
    if (drag_ == Drag::none && !io.WantCaptureMouse) {
        if (io.MouseWheel != 0.0f) camera_.zoom(std::pow(0.85, io.MouseWheel), x, y, v);
        if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
            if (io.KeyShift) drag_ = Drag::pan;
            else if (tools_.press(*session_, camera_, v, x, y)) drag_ = Drag::tool;
            else drag_ = Drag::orbit;
        } else if (ImGui::IsMouseClicked(ImGuiMouseButton_Right) || ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
            drag_ = Drag::pan;
        }
        return;
    }
    const bool held = ImGui::IsMouseDown(ImGuiMouseButton_Left) || ImGui::IsMouseDown(ImGuiMouseButton_Right) ||
                      ImGui::IsMouseDown(ImGuiMouseButton_Middle);
    if (!held) {
        if (drag_ == Drag::tool) tools_.release(*session_);
        drag_ = Drag::none;
        return;
    }
    if (dx == 0.0 && dy == 0.0) return;
    switch (drag_) {
        case Drag::tool: tools_.drag(*session_, camera_, v, x, y); break;
        case Drag::orbit: camera_.orbit(dx, dy); break;
        case Drag::pan: camera_.pan(dx, dy, v); break;
        case Drag::none: break;
    }
}

void App::draw_scene() {
    const editor::Viewport v = viewport();
    // The renderer follows the mesh and the curve; the CPU path's positions are uploaded on change.
    if (!renderer_ || drawn_mesh_ != session_->mesh_revision()) {
        renderer_ = std::make_unique<gpu::Renderer>(session_->triangles(), session_->motion());
        drawn_mesh_ = session_->mesh_revision();
        drawn_curve_ = session_->curve_revision();
        drawn_revision_ = 0;
    }
    if (drawn_curve_ != session_->curve_revision()) {
        renderer_->set_motion(session_->motion());
        drawn_curve_ = session_->curve_revision();
    }
    const auto* on_gpu = dynamic_cast<const editor::GpuLiveDeformation*>(session_->deformation());
    if (!on_gpu && drawn_revision_ != session_->revision()) {
        cpu_vertices_ = gpu::make_vertex_texture(session_->positions(), session_->s());
        drawn_revision_ = session_->revision();
    }
    if (on_gpu) drawn_revision_ = 0;
    camera_.scene_radius = std::max(camera_.scene_radius, 0.5 * session_->diagonal());
    const glm::mat4 view(camera_.view()), projection(camera_.projection(v.aspect()));
    gpu::RenderOptions render;
    render.current_time = session_->time();
    render.target_time = session_->target_time();
    render.wireframe = settings_.wireframe;
    if (on_gpu) render.vertex_origin = on_gpu->vertex_origin();
    render.highlight = &session_->folded_triangles();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glEnable(GL_MULTISAMPLE);
    renderer_->draw(on_gpu ? on_gpu->vertex_texture() : *cpu_vertices_, glm::value_ptr(view),
                    glm::value_ptr(projection), 0.018 * session_->diagonal(), v.width, v.height, render);
}

void App::draw_overlay() {
    // Control points and polygon, the handle, loops, the brush: 2D over the scene.
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const editor::Viewport v = viewport();
    const float scale = float(ImGui::GetIO().DisplaySize.x / v.width);
    const auto screen = [&](const Vec3& p, bool& visible) {
        const glm::dvec3 s = camera_.project(p, v);
        visible = s.z <= 1.0;
        return ImVec2(float(s.x) * scale, float(s.y) * scale);
    };
    bool visible = false;
    const std::vector<Vec3> points = session_->control_points();
    const bool handle = session_->curve().curve.is_handle;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        if (!handle && i % 3 == 1) continue;  // polygon legs: 0-1 and 2-3 of each segment
        bool a = false, b = false;
        const ImVec2 p = screen(points[i], a), q = screen(points[i + 1], b);
        if (a && b) draw->AddLine(p, q, IM_COL32(90, 90, 110, 200), 1.5f);
    }
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const auto hovered = tools_.tool == editor::Tool::navigate
                             ? tools_.hovered_point(*session_, camera_, v, mouse.x / scale, mouse.y / scale)
                             : std::nullopt;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ImVec2 p = screen(points[i], visible);
        if (!visible) continue;
        const bool hot = hovered == i || tools_.dragged_point() == i;
        const bool knot = handle || i % 3 == 0;
        const ImU32 fill = hot ? IM_COL32(255, 200, 40, 255) : knot ? IM_COL32(30, 30, 30, 255) : IM_COL32(250, 250, 250, 255);
        draw->AddCircleFilled(p, hot ? 7.0f : 5.0f, fill);
        draw->AddCircle(p, hot ? 7.0f : 5.0f, IM_COL32(20, 20, 20, 255), 0, 1.5f);
    }
    draw_gizmo(draw, scale);
    // Loops in progress.
    for (const auto* loop : {&tools_.loop_in_progress()}) {
        for (std::size_t i = 0; i < loop->size(); ++i) {
            const ImVec2 p = screen(surface_position(session_->positions(), session_->triangles(), (*loop)[i]), visible);
            draw->AddCircleFilled(p, 3.5f, IM_COL32(250, 230, 60, 255));
        }
    }
    for (const SurfaceLoop& loop : tools_.loops())
        for (std::size_t i = 0; i < loop.size(); ++i) {
            bool a = false, b = false;
            const ImVec2 p = screen(surface_position(session_->positions(), session_->triangles(), loop[i]), a);
            const ImVec2 q = screen(surface_position(session_->positions(), session_->triangles(), loop[(i + 1) % loop.size()]), b);
            draw->AddLine(p, q, IM_COL32(250, 230, 60, 255), 2.0f);
        }
    // The brush outline under the pointer.
    const bool brush = tools_.tool == editor::Tool::paint_inner || tools_.tool == editor::Tool::paint_outer ||
                       tools_.tool == editor::Tool::erase || tools_.tool == editor::Tool::paint_s;
    if (brush && !ImGui::GetIO().WantCaptureMouse) {
        const auto hit = session_->pick_surface(camera_.ray(mouse.x / scale, mouse.y / scale, v));
        if (hit) {
            bool a = false, b = false;
            const ImVec2 c = screen(hit->position, a);
            const ImVec2 r = screen(hit->position + tools_.brush.radius * camera_.right(), b);
            draw->AddCircle(c, std::hypot(r.x - c.x, r.y - c.y), IM_COL32(255, 255, 255, 230), 48, 2.0f);
        }
    }
}

void App::draw_gizmo(ImDrawList* draw, float scale) {
    // Handle mode: the gizmo on the target pose, its hovered or dragged part highlighted.
    const editor::Viewport v = viewport();
    const auto gizmo = tools_.gizmo(*session_, camera_, v);
    if (!gizmo || !gizmo->visible()) return;
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const bool free = !ImGui::GetIO().WantCaptureMouse || tools_.active();
    const editor::GizmoPart hot =
        free ? tools_.highlighted_gizmo_part(*session_, camera_, v, mouse.x / scale, mouse.y / scale) : editor::GizmoPart::none;
    const editor::GizmoShapes shapes = gizmo->shapes(hot);
    const auto at = [&](glm::dvec2 p) { return ImVec2(float(p.x) * scale, float(p.y) * scale); };
    // Each stroke over a dark one, so it shows on the blue and red regions alike.
    const auto stroke = [&](const std::vector<glm::dvec2>& line, editor::Rgb c, bool bold, ImDrawFlags flags) {
        std::vector<ImVec2> points;
        for (const glm::dvec2& p : line) points.push_back(at(p));
        const float width = bold ? 4.0f : 2.5f;
        draw->AddPolyline(points.data(), int(points.size()), IM_COL32(20, 20, 20, 150), flags, width + 2.0f);
        draw->AddPolyline(points.data(), int(points.size()), IM_COL32(c.r, c.g, c.b, 255), flags, width);
    };
    for (const editor::GizmoRing& ring : shapes.rings) stroke(ring.points, ring.colour, ring.part == hot, ImDrawFlags_Closed);
    for (const editor::GizmoSegment& axis : shapes.axes) {
        stroke({axis.from, axis.to}, axis.colour, axis.part == hot, ImDrawFlags_None);
        draw->AddCircleFilled(at(axis.to), 5.0f, IM_COL32(axis.colour.r, axis.colour.g, axis.colour.b, 255));
        draw->AddCircle(at(axis.to), 5.0f, IM_COL32(20, 20, 20, 150), 0, 1.0f);
    }
    const float r = float(shapes.centre_radius) * scale;
    const editor::Rgb c = shapes.centre_colour;
    draw->AddCircleFilled(at(shapes.centre), r, IM_COL32(c.r, c.g, c.b, 255));
    draw->AddCircle(at(shapes.centre), r, IM_COL32(20, 20, 20, 255), 0, 1.5f);
}

int App::run() {
    using Clock = std::chrono::steady_clock;
    const auto elapsed_ms = [](Clock::time_point from, Clock::time_point to) {
        return std::chrono::duration<double, std::milli>(to - from).count();
    };
    while (!glfwWindowShouldClose(window_)) {
        const Clock::time_point start = Clock::now();
        glfwPollEvents();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        if (scripted_pointer_) {
            const float scale = float(ImGui::GetIO().DisplaySize.x / viewport().width);
            ImGui::GetIO().MousePos = ImVec2(float(scripted_pointer_->first) * scale, float(scripted_pointer_->second) * scale);
        }
        ImGui::NewFrame();

        handle_input();
        handle_shortcuts();
        if (script_ && !script_->done()) {
            script_->run_frame(context());
            if (script_->done()) {
                log(script_->failed() ? "script failed: " + script_->error() : "script: done");
                if (options_.exit_after_script && !pending_screenshot_) break;
            }
        }
        // Integrate toward the target within the frame's budget.
        const double ms = std::max(session_->stats().ms_per_step, 0.05);
        session_->update(std::clamp(int(kStepBudgetMs / ms), 1, 250));
        autosave_.maybe_save(*session_);

        draw_panels();
        draw_restore_offer();
        draw_overlay();
        ImGui::Render();
        const Clock::time_point drawing = Clock::now();
        draw_scene();
        const bool ui = !pending_screenshot_ || pending_screenshot_->second;
        if (ui && show_ui_) ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (pending_screenshot_) {
            try {
                save_screenshot(pending_screenshot_->first);
                status_ = "saved " + pending_screenshot_->first;
            } catch (const std::exception& e) {
                status_ = e.what();
                log(status_);
            }
            pending_screenshot_.reset();
            if (script_ && script_->done() && options_.exit_after_script) break;
        }
        const Clock::time_point swapping = Clock::now();
        glfwSwapBuffers(window_);
        if (frames_to_log_ > 0) log_frame({elapsed_ms(start, drawing), elapsed_ms(drawing, swapping), elapsed_ms(swapping, Clock::now())});
    }
    // A clean exit: the autosave goes, unless its offer was never answered.
    if (!autosave_.offer()) autosave_.clear();
    return script_ && script_->failed() ? 1 : 0;
}

}  // namespace vfsd::desktop
