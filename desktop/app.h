#pragma once
// The desktop editor's window: GLFW, Dear ImGui and the engine's renderer around
// the editor (engine/editor/editor.h). The shell turns the window's events into
// the editor's calls, paints the scene and the editor's overlay, and draws panels
// whose controls run the editor's commands; every editor rule lives in the editor.

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/editor.h"
#include "editor/frame_log.h"
#include "editor/session_view.h"
#include "desktop/redraw.h"

struct GLFWwindow;
struct ImDrawList;

namespace vfsd::desktop {

struct AppOptions {
    std::string scene;   // --scene FILE
    std::string script;  // --script FILE
    std::string mesh;    // MESH
    std::string backend = "auto";  // --backend auto|cpu
    std::string antialias = "auto";  // --antialias auto|on|off: multisample the view (gpu::multisample_view)
    bool exit_after_script = false;
    int width = 1280, height = 800;
};

class App final : public editor::Shell {
public:
    explicit App(const AppOptions& options);
    ~App() override;
    // The main loop; returns the exit code (1 when the script failed).
    int run();

    // editor::Shell
    Viewport viewport() const override;
    void log(const std::string& line) override;
    void screenshot(const std::string& path, bool ui) override;
    void simulate_crash() override;
    void point_at(double x, double y) override;
    void log_frame_times(int frames) override;
    bool keeps_image() const override { return true; }  // a frame that does not swap leaves it on the display
    long frames_drawn() const override { return frames_drawn_; }

    // Called by GLFW's callbacks.
    void on_drop(const std::vector<std::string>& paths);
    void on_event() { input_ = true; }
    void on_cursor_moved() { moved_ = true; }

private:
    void open(const std::string& path);
    // Runs a command of the editor's table; a failure shows in the status line (false).
    bool command(const std::string& name, const nlohmann::json& args = nlohmann::json::object());
    void handle_input();
    void handle_shortcuts();
    void draw_overlay();
    void draw_panels();
    void draw_file_panel();
    void draw_tools_panel();
    void draw_curve_panel();
    void draw_time_bar();
    void draw_stats_line();
    void draw_options();
    void draw_load_error();
    void draw_help();
    void draw_restore_offer();
    void save_screenshot(const std::string& path) const;
    void remember(const std::string& path);
    // The pointer in framebuffer pixels (they differ from window units on HiDPI screens).
    glm::dvec2 pointer() const;
    bool script_over() const;

    AppOptions options_;
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<editor::Editor> editor_;
    editor::SessionView view_;

    // Panels' state.
    bool show_help_ = false, show_ui_ = true;
    char path_field_[1024] = "";
    char output_field_[1024] = "vfsd-out";
    std::deque<std::string> recent_;
    std::optional<std::pair<std::string, bool>> pending_screenshot_;

    // Scripted orbits: the pointer a script placed (viewport pixels), and the
    // frames' times to log.
    std::optional<std::pair<double, double>> scripted_pointer_;
    editor::FrameLog frame_log_;

    // Which frames draw (redraw.h); an event since the last frame; frames drawn.
    // A cursor move alone draws where it changes what is shown: over the panels, with
    // a button held, with a brush, or where the hovered point or gizmo part changed.
    struct Hover {
        bool panels = false, brush = false;
        int point = -1, gizmo = 0;
        bool operator==(const Hover& o) const {
            return panels == o.panels && brush == o.brush && point == o.point && gizmo == o.gizmo;
        }
    };
    bool cursor_shows(const Hover& now) const;
    WindowRedraw redraw_;
    bool input_ = true, moved_ = false;
    Hover hover_, drawn_hover_;
    long frames_drawn_ = 0;
};

}  // namespace vfsd::desktop
