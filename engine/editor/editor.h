#pragma once
// One editor, whatever shows it: the session, tools, camera and view settings,
// the autosave, the script runner, the per-frame step budget, the pointer's
// press / drag / release rules, and the overlay to paint, as data. The shells
// (desktop/: GLFW + Dear ImGui; web/: a page around a WebGL2 canvas) only adapt:
// they open the window, turn its events into the calls below, paint the scene
// (editor/session_view.h) and the Overlay, and draw their panels, whose controls
// run the command table (editor/commands.h).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "editor/autosave.h"
#include "editor/commands.h"
#include "editor/frame_pacer.h"
#include "editor/handle_gizmo.h"
#include "editor/piece_times.h"
#include "editor/script.h"
#include "editor/session.h"
#include "editor/tools.h"
#include "view/camera.h"

namespace vfsd::editor {

// What only the window or page can do (the rest of EditorHost the editor does itself).
class Shell {
public:
    virtual ~Shell() = default;
    virtual Viewport viewport() const = 0;
    virtual void log(const std::string& line) = 0;
    // Save the next rendered frame as PNG (with or without the panels).
    virtual void screenshot(const std::string& path, bool ui) = 0;
    // The autosave folder was written (the page copies it to IndexedDB).
    virtual void autosaved() {}
    // As EditorHost's: end as a crash would; place the hovering pointer; log frame times.
    virtual void simulate_crash() { throw InputError("this editor cannot simulate a crash"); }
    virtual void point_at(double, double) {}
    virtual void log_frame_times(int) {}
    // The view keeps its last image through a frame that does not draw (the page's
    // canvas; the window, which then does not swap its buffers).
    virtual bool keeps_image() const { return false; }
    // As EditorHost's: the frames drawn so far (-1: not counted).
    virtual long frames_drawn() const { return -1; }
    // The renderer has not finished the last draw yet (the page's GL fence; it then
    // reports the draw's time through Editor::renderer_finished).
    virtual bool renderer_busy() const { return false; }
};

// What the shells paint over the scene, in viewport pixels; only points in front
// of the camera.
struct OverlayPoint {
    glm::dvec2 at;
    bool knot = false;  // a curve's knot (dark) or a Bezier handle point (light); handles: both knots
    bool hot = false;   // under the pointer or dragged
};
struct Overlay {
    std::vector<std::pair<glm::dvec2, glm::dvec2>> polygon;  // the control polygon's legs (0-1 and 2-3 of each segment)
    std::vector<OverlayPoint> points;
    std::optional<GizmoShapes> gizmo;            // handle mode: the target's gizmo
    GizmoPart gizmo_hot = GizmoPart::none;       // its part under the pointer or dragged
    std::vector<std::vector<glm::dvec2>> loops;  // closed boundary loops
    std::vector<glm::dvec2> loop_in_progress;
    std::optional<glm::dvec3> brush;  // centre x, y and radius in pixels, under the pointer
};

struct EditorOptions {
    std::string autosave_directory;
    double autosave_seconds = 10.0;
    // Per frame the deformation may take about this long, so the shell stays responsive;
    // where drawing is costly and skipped in some frames (FramePacer), up to max_frame_ms
    // (with one step after it, a frame's task stays under 50 ms in the page).
    double step_budget_ms = 15.0;
    double max_frame_ms = 30.0;
    // Where the longest of the last steps took longer than this, steps run in
    // pieces (Deformation::prepare_step), a frame ending within about its budget
    // and one piece; otherwise a frame's steps end within about max_frame_ms +
    // split_step_ms. The longest, not the mean: one step in a few takes longer
    // (the fold repair's affine test, every fifth of the run).
    double split_step_ms = 20.0;
    // Where it took over this (and not over split_step_ms), the step through a
    // time of the affine test, which takes two to three times as long as the
    // others, runs in pieces (on the 163k sphere in the page, 40-60 ms whole).
    double split_affine_step_ms = 7.0;
    bool force_cpu = false;  // the "force CPU" setting at start
};

class Editor final : public EditorHost {
public:
    // `gpu` makes the GPU deformation (empty: CPU only, `gpu_reason` says why).
    Editor(Shell& shell, DeformationFactory gpu, const std::string& gpu_reason, const EditorOptions& options);

    EditorSession& session() { return *session_; }
    const EditorSession& session() const { return *session_; }
    const ToolController& tools() const { return tools_; }
    Camera& camera() { return camera_; }
    const Camera& camera() const { return camera_; }
    Viewport viewport() const { return shell_.viewport(); }
    const EditorSettings& settings() const { return settings_; }
    const Autosave& autosave() const { return autosave_; }
    const ScriptRunner* script() const { return script_.get(); }
    // The last open's error ("" after a success) and a line for the status bar.
    const std::string& load_error() const { return load_error_; }
    void dismiss_load_error() { load_error_.clear(); }
    const std::string& status() const { return status_; }
    void set_status(std::string text) { status_ = std::move(text); }

    // Opens a mesh or scene file, or several files at once (a scene and its mesh:
    // EditorSession::open); a failure keeps the document and sets load_error()
    // (a scene whose mesh is missing: "choose NAME", and the next open of NAME completes it).
    bool open(const std::string& path);
    bool open(const std::vector<std::string>& paths);
    // The default scene (at rest, not played to its target), else the built-in box;
    // at start-up (offers the autosave).
    void open_default(const std::string& scene_path, bool offer_autosave);
    void open_scene(const Scene& scene);
    // Runs a command of the table (editor/commands.h); throws InputError. An
    // apply while the run catches up to an edit (EditorSession::holding_result)
    // waits for it: the frames go on with the run's steps, and the frame that
    // reaches the target bakes (apply_due()). EditorSession::apply would run the
    // rest of the run in this call, in the page one task as long as the run.
    // Anything else that may change the document (other commands than the view's
    // and the tool's, a press but a pan, an open, a script) first bakes a due apply.
    void command(const std::string& name, const nlohmann::json& args = nlohmann::json::object());
    bool apply_due() const { return apply_due_; }
    // Runs the command bound to the key; false when none is.
    bool key(const std::string& key, bool ctrl, bool shift);
    void run_script(std::vector<ScriptAction> actions);

    // The pointer, in viewport pixels. A press with `pan` (another button, or
    // Shift) pans; otherwise the tool takes it, and when it declines the drag
    // orbits. move() drags or, between presses, only hovers.
    void press(double x, double y, bool pan);
    void move(double x, double y);
    void release();
    void leave();
    // The wheel, in notches (positive zooms in toward the pointer).
    void wheel(double notches, double x, double y);
    bool dragging() const { return drag_ != Drag::none; }
    // Where the pointer hovers (none after leave()).
    std::optional<glm::dvec2> pointer() const { return pointer_; }

    // The frame's work before drawing: the script's actions, the deformation's
    // steps toward the target within the step budget, the autosave.
    void advance();
    // Whether the frame just advanced should draw: always, unless the deformation
    // runs, drawing is costly and the shell keeps its image (FramePacer).
    bool draw_due() const { return draw_due_; }
    // Drawing costs more than a 60 Hz frame (the page then runs its loop on timeouts while the deformation runs).
    bool draws_costly() const { return pacer_.draws_costly(); }
    void renderer_finished(double ms) { pacer_.renderer_finished(ms); }
    // What to paint over the scene; `pointer` hovers over the view (none: over a panel or outside).
    Overlay overlay(std::optional<glm::dvec2> pointer) const;
    // Frames must follow each other: the deformation moves, a region is computed
    // (EditorSession::region_pending) or a script runs.
    bool busy() const { return session_->moving() || session_->region_pending() || (script_ && !script_->done()); }
    // Whether the last frame ended waiting for the GPU to finish a step's passes
    // (steps in pieces): a shell may let the next frame come a little later.
    bool waiting_on_gpu() const { return waiting_on_gpu_; }
    // The context's loss (web): the deformation restarts from the CPU state.
    void restart_deformation();

    // A clean exit: the autosave goes, unless its offer was never answered.
    void clean_exit();

    // EditorHost
    void screenshot(const std::string& path, bool ui) override { shell_.screenshot(path, ui); }
    void loaded() override;
    void log(const std::string& line) override { shell_.log(line); }
    void autosave_now() override;
    void answer_restore(bool restore) override;
    void simulate_crash() override { shell_.simulate_crash(); }
    void point_at(double x, double y) override { shell_.point_at(x, y); }
    void log_frame_times(int frames) override { shell_.log_frame_times(frames); }
    long frames_drawn() const override { return shell_.frames_drawn(); }

private:
    CommandContext context();
    // A due apply, now: before anything else changes the document.
    void settle_apply();
    void integrate_for(double budget_ms);
    void integrate_in_pieces(double budget_ms, bool after_steps = false);

    Shell& shell_;
    EditorOptions options_;
    std::unique_ptr<EditorSession> session_;
    ToolController tools_;
    Camera camera_;
    EditorSettings settings_;
    Autosave autosave_;
    std::unique_ptr<ScriptRunner> script_;
    double ms_per_step_ = 0.0;  // the integration's time per step, measured over frames
    bool moving_ = false;       // the last frame integrated
    bool waiting_on_gpu_ = false;   // the last frame's pieces ended waiting for the GPU
    double longest_step_ms_ = 0.0;  // the longest of the last steps (EditorSession::longest_recent_step_ms)
    // Steps in pieces: the recent pieces' times by kind, the time of the step under
    // way so far and the place of its next piece.
    PieceTimes piece_times_;
    double step_so_far_ms_ = 0.0;
    int piece_place_ = 0;
    // A run's preparation (EditorSession::prepare_run): its parts' times by their
    // place after the region's, and the place of the next.
    PieceTimes part_times_;
    int part_place_ = 0;
    FramePacer pacer_;
    bool draw_due_ = true;
    bool apply_due_ = false;  // an apply waits for the run to reach its target
    std::string load_error_, status_;

    enum class Drag { none, tool, orbit, pan } drag_ = Drag::none;
    glm::dvec2 last_{0.0};
    std::optional<glm::dvec2> pointer_;
};

}  // namespace vfsd::editor
