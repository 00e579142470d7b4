#include "editor/editor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "base/error.h"

namespace vfsd::editor {
namespace {

bool is_brush(Tool tool) {
    return tool == Tool::paint_inner || tool == Tool::paint_outer || tool == Tool::erase || tool == Tool::paint_s;
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// Why `path` did not open, led by its file name: a reader's message names the
// whole path first ("/a/b/m.obj: cannot open: ..."), which the name replaces;
// another's ("its mesh box.ply is missing") gets the name in front.
std::string load_error_text(const std::string& path, const std::string& why) {
    if (!path.empty() && why.rfind(path + ": ", 0) == 0) return file_name(path) + why.substr(path.size());
    return file_name(path) + ": " + why;
}

// Commands that change only the view, the tool or its settings: they leave a due apply waiting.
bool leaves_document(const std::string& command) {
    for (const char* c : {"tool", "brush", "brush-size", "view", "orbit", "wireframe", "screenshot", "wait-frames"})
        if (command == c) return true;
    return false;
}

}  // namespace

Editor::Editor(Shell& shell, DeformationFactory gpu, const std::string& gpu_reason, const EditorOptions& options)
    : shell_(shell),
      options_(options),
      session_(std::make_unique<EditorSession>(std::move(gpu), gpu_reason)),
      autosave_(options.autosave_directory, options.autosave_seconds),
      pacer_(options.step_budget_ms, options.max_frame_ms) {
    settings_.force_cpu = options.force_cpu;
    session_->set_regions_in_parts(true);  // a pick or a stroke does not hold up its frame
}

CommandContext Editor::context() { return {*session_, tools_, camera_, settings_, shell_.viewport(), *this}; }

// ---- documents ----------------------------------------------------------------------

bool Editor::open(const std::string& path) { return open(std::vector<std::string>{path}); }

bool Editor::open(const std::vector<std::string>& paths) {
    settle_apply();
    // A failed load keeps the current document and says why.
    std::string path = paths.empty() ? "" : paths.front();
    try {
        path = EditorSession::main_file(paths);
        session_->open(paths);
        tools_.adapt_to(*session_);
        loaded();
        load_error_.clear();
        status_ = "opened " + file_name(path);
        return true;
    } catch (const std::exception& e) {
        load_error_ = load_error_text(path, e.what());
        log("open failed: " + load_error_);
        return false;
    }
}

void Editor::open_default(const std::string& scene_path, bool offer_autosave) {
    settle_apply();
    if (session_->triangles().empty()) {
        try {
            session_->open_scene_file(scene_path);
            session_->set_target_time(0.0);  // the start-up document waits for Play
        } catch (const std::exception& e) {
            log(std::string("default scene: ") + e.what());
            session_->open_mesh("builtin:box");
        }
        tools_.adapt_to(*session_);
        loaded();
    }
    autosave_.mark_saved(*session_);
    if (!offer_autosave) return;
    autosave_.offer_restore(*session_);
    if (const auto& offer = autosave_.offer())
        log("autosave: " + offer->mesh + " from " + offer->written_text() + " in " + autosave_.directory());
    else if (!autosave_.problem().empty())
        log(autosave_.problem());
}

void Editor::open_scene(const Scene& scene) {
    settle_apply();
    session_->open_scene(scene);
    tools_.adapt_to(*session_);
    loaded();
    load_error_.clear();
}

void Editor::loaded() {
    camera_ = Camera();
    camera_.up_axis = up_axis_named(std::string(1, session_->up_axis()));
    frame_session(camera_, *session_, shell_.viewport());
}

// ---- commands and scripts -------------------------------------------------------------

void Editor::command(const std::string& name, const nlohmann::json& args) {
    if (name == "apply" && session_->holding_result()) {
        validate_arguments(find_command(name), args);
        apply_due_ = true;
        status_ = "applying when the run reaches its target";
        return;
    }
    if (!leaves_document(name)) settle_apply();
    CommandContext c = context();
    run_command(name, args, c);
}

bool Editor::key(const std::string& key, bool ctrl, bool shift) {
    const KeyBinding* k = find_key(key, ctrl, shift);
    if (k) command(k->command, nlohmann::json::parse(k->args));
    return k != nullptr;
}

void Editor::run_script(std::vector<ScriptAction> actions) {
    settle_apply();
    script_ = std::make_unique<ScriptRunner>(std::move(actions));
}

void Editor::settle_apply() {
    if (!apply_due_) return;
    apply_due_ = false;
    session_->apply();  // the rest of the run, if any, then the bake
    status_ = "applied";
}

// ---- the autosave -----------------------------------------------------------------------

void Editor::autosave_now() {
    if (autosave_.offer()) throw InputError("answer the offer to restore the autosave first");
    if (!autosave_.save(*session_)) throw IoError(session_->warnings().back());
    shell_.autosaved();
}

void Editor::answer_restore(bool restore) {
    settle_apply();
    if (autosave_.answer(*session_, restore)) {
        tools_.adapt_to(*session_);
        loaded();
    }
    if (!restore) shell_.autosaved();  // the cleared folder
    status_ = !restore ? "discarded the autosave" : autosave_.problem().empty() ? "restored the autosave" : "";
    if (!autosave_.problem().empty()) log(autosave_.problem());
}

void Editor::clean_exit() {
    if (!autosave_.offer()) autosave_.clear();
}

// ---- the pointer --------------------------------------------------------------------------

void Editor::press(double x, double y, bool pan) {
    if (drag_ != Drag::none) return;
    // A press a tool takes acts on the applied document: a due apply is baked
    // first. One that turns or moves the view leaves it to the frames.
    if (!pan && apply_due_ && tools_.takes_press(*session_, camera_, shell_.viewport(), x, y)) settle_apply();
    last_ = {x, y};
    pointer_ = last_;
    if (pan) drag_ = Drag::pan;
    else if (tools_.press(*session_, camera_, shell_.viewport(), x, y)) drag_ = Drag::tool;
    else drag_ = Drag::orbit;
}

void Editor::move(double x, double y) {
    const glm::dvec2 d = glm::dvec2(x, y) - last_;
    last_ = {x, y};
    pointer_ = last_;
    switch (drag_) {
        case Drag::tool: tools_.drag(*session_, camera_, shell_.viewport(), x, y); break;
        case Drag::orbit: camera_.orbit(d.x, d.y); break;
        case Drag::pan: camera_.pan(d.x, d.y, shell_.viewport()); break;
        case Drag::none: break;
    }
}

void Editor::release() {
    if (drag_ == Drag::tool) tools_.release(*session_);
    drag_ = Drag::none;
}

void Editor::leave() { pointer_.reset(); }

void Editor::wheel(double notches, double x, double y) {
    camera_.zoom(std::pow(0.85, notches), x, y, shell_.viewport());
}

// ---- each frame ------------------------------------------------------------------------------

void Editor::advance() {
    if (script_ && !script_->done()) {
        settle_apply();
        script_->run_frame(context());
        if (script_->done()) log(script_->failed() ? "script failed: " + script_->error() : "script: done");
    }
    const auto now = [] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
    };
    const bool working = session_->moving() || session_->region_pending();
    const FramePacer::Plan plan = pacer_.plan(now(), working, shell_.keeps_image(), shell_.renderer_busy());
    integrate_for(plan.integrate_ms);
    // The run reached its target (or stopped short of it: a failed step).
    if (apply_due_ && !(session_->holding_result() && session_->moving())) settle_apply();
    // While an edit's run keeps the last result on show, or its region's s is
    // computed, the image does not change: a shell that keeps its image (the
    // page, the window) has nothing new to draw until the run ends or the region
    // is built, unless it changed something itself (the camera, the dragged
    // curve). Its draws would take the renderer from the GPU's steps.
    const bool same_image = shell_.keeps_image() && (session_->holding_result() || session_->region_pending());
    // The last step is always drawn, and a region's final s.
    draw_due_ = (plan.draw && !same_image) || !(session_->moving() || session_->region_pending());
    pacer_.integrated(now(), draw_due_);
    if (autosave_.maybe_save(*session_)) shell_.autosaved();
}

// Integrates toward the target for about `budget_ms`. The region an edit left to
// compute takes the frames' budgets first; a new deformation is prepared part by
// part (EditorSession::prepare_run), and a frame whose parts so far took under
// half its budget goes on to the next part, where the recent parts at its place
// (PieceTimes) fit in what is left, or, once none is left, to the steps (where
// steps run whole): a frame is at most one part longer than half the budget,
// and that only where the part took longer than the ones before it at its
// place; a quick preparation costs no frame of its own. A run starts with
// one step, which no earlier rate predicts (the first also estimates ∇r at the
// start); the rest of the frame is filled at the rate measured so far, so no
// frame takes much longer than the budget plus one step. Steps are the same
// whatever their grouping. update() ends with the stats' read-back, so the GPU's
// work is in the time.
void Editor::integrate_for(double budget_ms) {
    waiting_on_gpu_ = false;
    // The GPU's set-up and steps check for errors and read back, and in WebGL
    // each waits for the renderer's last draw (on SwiftShader 50-150 ms): while
    // the shell says that draw is unfinished, the frame leaves the GPU alone. A
    // region the last edit left to compute is the CPU's work and goes on.
    if (session_->moving() && !session_->region_pending() && shell_.renderer_busy() &&
        session_->stats().backend == "gpu") {
        waiting_on_gpu_ = true;
        return;
    }
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); };
    for (;;) {
        const bool region_part = session_->region_pending();  // budgeted by its own work
        const double part_from = elapsed();
        if (!session_->prepare_run(budget_ms - part_from)) break;
        moving_ = false;
        step_so_far_ms_ = 0.0;
        piece_place_ = 0;
        if (!region_part) part_times_.record({part_place_++, false}, elapsed() - part_from);
        const double next_part = session_->region_pending() ? 0.0 : part_times_.expected({part_place_, false});
        if (2.0 * elapsed() >= budget_ms || elapsed() + next_part > budget_ms ||
            longest_step_ms_ > options_.split_step_ms)
            return;
    }
    part_place_ = 0;  // prepared: the next preparation's parts count from its first
    // Where the longest of the last steps (in this run or the one before) took
    // over split_step_ms, steps run in pieces. The GPU's whole steps wait for the
    // GPU at their read-backs (on a software renderer, a page on SwiftShader, 90
    // ms a step) and its pieces do not; but each piece that finds the GPU at work
    // ends its frame, so a GPU that runs a step in a millisecond or two keeps
    // whole steps, and a step in pieces is timed from its first piece to its end.
    if (longest_step_ms_ > options_.split_step_ms) return integrate_in_pieces(budget_ms);
    // A step through a time of the affine test, two to three times as long as
    // the others, could take a frame past 50 ms where they take over
    // split_affine_step_ms: it runs in pieces.
    const bool split_affine = longest_step_ms_ > options_.split_affine_step_ms;
    if (split_affine && session_->next_step_tests_affine()) return integrate_in_pieces(budget_ms - elapsed());
    const double steps_from = elapsed();  // the steps' rate leaves the preparation out
    const auto steps_left = [&](double ms) { return int((budget_ms - ms) / std::max(ms_per_step_, 0.01)); };
    int chunk = moving_ ? std::clamp(steps_left(steps_from), 1, 250) : 1, taken = 0;
    while (chunk > 0) {
        // A chunk that would start with the step through the affine test's time
        // runs it whole (a call takes at least one step): the frame goes on with
        // that step's pieces below instead.
        if (taken > 0 && split_affine && session_->next_step_tests_affine()) break;
        // The CPU also stops after the step that spends the budget: tries found
        // over the tolerance and slower steps than the rate said (the machine
        // busy) add at most one step to the frame.
        const int done = session_->update(chunk, budget_ms - elapsed(), split_affine);
        taken += done;
        if (taken > 0) ms_per_step_ = (elapsed() - steps_from) / taken;
        if (done > 0) longest_step_ms_ = session_->longest_recent_step_ms();
        if (done < chunk) break;  // at the target, stopped, before the affine test, or the budget spent
        chunk = std::min(steps_left(elapsed()), 250 - taken);
    }
    moving_ = taken > 0;
    // Stopped before a step through the affine test's time: the frame goes on
    // with that step's pieces while its budget lasts.
    if (split_affine && elapsed() < budget_ms && session_->moving() && session_->next_step_tests_affine()) {
        const bool stepped = taken > 0;
        integrate_in_pieces(budget_ms - elapsed(), stepped);
        moving_ = moving_ || stepped;
    }
}

// Long steps in pieces (Deformation::prepare_step: ∇r and the gauge at the
// step's middle, then the move, then at a fold repair's time the volume keeper
// and the fold test; the step itself ends it with the volume keeper or the
// repair), as many in a frame as leave room for the next piece within the
// budget, planned by the recent pieces of its kind (PieceTimes). A frame that
// has done nothing yet takes at least one, so no frame takes much longer than
// the budget plus one piece; where `after_steps`, the frame's whole steps came
// first and count as its progress. The steps are the same as whole ones. On the
// GPU a piece issues passes; the frame ends where the GPU has not finished the last.
void Editor::integrate_in_pieces(double budget_ms, bool after_steps) {
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) {
        return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
    };
    const Clock::time_point start = Clock::now();
    bool worked = false;
    for (;;) {
        const PieceTimes::Kind kind{piece_place_, session_->next_step_tests_affine()};
        if ((worked || after_steps) && since(start) + piece_times_.expected(kind) > budget_ms) break;
        const Clock::time_point piece_start = Clock::now();
        const StepPiece piece = session_->prepare_step();
        if (piece == StepPiece::waiting) {  // the GPU runs the last piece's passes: the frame ends
            waiting_on_gpu_ = worked = true;
            break;
        }
        const bool prepared = piece == StepPiece::done || piece == StepPiece::retried;
        const int done = prepared ? 0 : session_->update(1);
        if (!prepared && done == 0) break;  // at the target, or stopped
        worked = true;
        const double piece_ms = since(piece_start);
        piece_times_.record(kind, piece_ms);
        step_so_far_ms_ += piece_ms;
        piece_place_ = piece == StepPiece::retried ? 0 : piece_place_ + 1;  // a try again starts with its first piece
        if (done > 0) {
            ms_per_step_ = step_so_far_ms_;
            step_so_far_ms_ = 0.0;
            piece_place_ = 0;
            longest_step_ms_ = session_->longest_recent_step_ms();
            if (longest_step_ms_ <= options_.split_step_ms) break;  // whole steps again from the next frame
        }
        if (!session_->moving()) break;
    }
    moving_ = worked;
}

void Editor::restart_deformation() {
    session_->set_force_cpu(!settings_.force_cpu);  // each switch drops the deformation
    session_->set_force_cpu(settings_.force_cpu);
}

Overlay Editor::overlay(std::optional<glm::dvec2> pointer) const {
    const Viewport v = shell_.viewport();
    Overlay out;
    const auto on_screen = [&](const Vec3& p) -> std::optional<glm::dvec2> {
        const glm::dvec3 s = camera_.project(p, v);
        if (s.z > 1.0) return std::nullopt;
        return glm::dvec2(s.x, s.y);
    };
    // The control polygon: legs 0-1 and 2-3 of each segment (a handle: its one line).
    const std::vector<Vec3> points = session_->control_points();
    const bool handle = session_->curve().curve.is_handle;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const auto a = on_screen(points[i]), b = on_screen(points[i + 1]);
        if ((handle || i % 3 != 1) && a && b) out.polygon.emplace_back(*a, *b);
    }
    const bool navigating = tools_.tool == Tool::navigate && pointer;
    const auto hovered = navigating ? tools_.hovered_point(*session_, camera_, v, pointer->x, pointer->y) : std::nullopt;
    for (std::size_t i = 0; i < points.size(); ++i)
        if (const auto at = on_screen(points[i]))
            out.points.push_back({*at, handle || i % 3 == 0, hovered == i || tools_.dragged_point() == i});
    // The handle's gizmo, its hovered or dragged part highlighted.
    if (const auto gizmo = tools_.gizmo(*session_, camera_, v); gizmo && gizmo->visible()) {
        const glm::dvec2 at = pointer.value_or(glm::dvec2(-1.0));
        const GizmoPart hot = pointer || tools_.active() ? tools_.highlighted_gizmo_part(*session_, camera_, v, at.x, at.y)
                                                         : GizmoPart::none;
        out.gizmo = gizmo->shapes(hot);
        out.gizmo_hot = hot;
    }
    // Boundary loops, closed and in progress.
    const auto surface = [&](const SurfacePoint& q) {
        return on_screen(surface_position(session_->positions(), session_->triangles(), q));
    };
    for (const SurfaceLoop& loop : tools_.loops()) {
        std::vector<glm::dvec2> line;
        for (const SurfacePoint& q : loop)
            if (const auto p = surface(q)) line.push_back(*p);
        out.loops.push_back(line);
    }
    for (const SurfacePoint& q : tools_.loop_in_progress())
        if (const auto p = surface(q)) out.loop_in_progress.push_back(*p);
    // The brush's outline on the surface under the pointer.
    if (is_brush(tools_.tool) && pointer) {
        if (const auto hit = session_->pick_surface(camera_.ray(pointer->x, pointer->y, v))) {
            const glm::dvec3 c = camera_.project(hit->position, v);
            const glm::dvec3 r = camera_.project(hit->position + tools_.brush.radius * camera_.right(), v);
            out.brush = glm::dvec3(c.x, c.y, std::hypot(r.x - c.x, r.y - c.y));
        }
    }
    return out;
}

}  // namespace vfsd::editor
