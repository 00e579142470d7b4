#pragma once
// The desktop editor's window: GLFW, Dear ImGui and the engine's renderer around
// the editor core (engine/editor). Everything a user can do goes through
// EditorSession and ToolController; this shell only turns events into their calls
// and draws panels.

#include <deque>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "editor/autosave.h"
#include "editor/camera.h"
#include "editor/commands.h"
#include "editor/script.h"
#include "editor/session.h"
#include "editor/tools.h"
#include "gpu/renderer.h"

struct GLFWwindow;
struct ImDrawList;

namespace vfsd::desktop {

struct AppOptions {
    std::string scene;   // --scene FILE
    std::string script;  // --script FILE
    std::string mesh;    // MESH
    std::string backend = "auto";  // --backend auto|cpu
    bool exit_after_script = false;
    int width = 1280, height = 800;
};

class App final : public editor::EditorHost {
public:
    explicit App(const AppOptions& options);
    ~App() override;
    // The main loop; returns the exit code (1 when the script failed).
    int run();

    // EditorHost
    void screenshot(const std::string& path, bool ui) override;
    void loaded() override;
    void log(const std::string& line) override;
    void autosave_now() override;
    void answer_restore(bool restore) override;
    void simulate_crash() override;
    void point_at(double x, double y) override;
    void log_frame_times(int frames) override;

    // Called by GLFW's callbacks.
    void on_drop(const std::string& path);

private:
    friend struct Panels;
    void open(const std::string& path);
    void handle_input();
    void handle_shortcuts();
    void draw_scene();
    void draw_overlay();
    void draw_gizmo(ImDrawList* draw, float scale);
    void draw_panels();
    void draw_restore_offer();
    void offer_restore();
    void save_screenshot(const std::string& path) const;
    editor::Viewport viewport() const;
    editor::CommandContext context();
    // Runs a command of the editor's table; a failure shows in the status line.
    void command(const std::string& name, const nlohmann::json& args = nlohmann::json::object());
    void remember(const std::string& path);

    AppOptions options_;
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<editor::EditorSession> session_;
    editor::ToolController tools_;
    editor::Camera camera_;
    editor::EditorSettings settings_;
    std::unique_ptr<gpu::Renderer> renderer_;
    std::optional<gpu::Texture> cpu_vertices_;
    std::uint64_t drawn_mesh_ = 0, drawn_curve_ = 0, drawn_revision_ = 0;
    std::unique_ptr<editor::ScriptRunner> script_;
    editor::Autosave autosave_;

    // Pointer state: a tool action or a camera drag (orbit / pan).
    enum class Drag { none, tool, orbit, pan } drag_ = Drag::none;
    double last_x_ = 0.0, last_y_ = 0.0;

    // Panels' state.
    bool show_help_ = false, show_ui_ = true;
    char path_field_[1024] = "";
    char output_field_[1024] = "vfsd-out";
    std::deque<std::string> recent_;
    std::string status_, load_error_;
    std::optional<std::pair<std::string, bool>> pending_screenshot_;

    // Scripted orbits: the pointer a script placed (viewport pixels), and the
    // frames still to log with the times of those logged so far.
    struct FrameTimes {
        double app_ms = 0.0;   // input, script, deformation steps, panels, overlay (the hover pick)
        double draw_ms = 0.0;  // issuing the scene's and the panels' GL calls (the driver's vertex work included)
        double swap_ms = 0.0;  // glfwSwapBuffers: the driver finishing the frame
    };
    void log_frame(const FrameTimes& times);
    std::optional<std::pair<double, double>> scripted_pointer_;
    int frames_to_log_ = 0;
    std::vector<FrameTimes> logged_frames_;
};

}  // namespace vfsd::desktop
