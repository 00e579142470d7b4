#pragma once
// The live state of an editor: the mesh, how its region is defined (scene spec,
// painted labels or a painted field), the curve or handle with the motion
// settings, the deformation advancing toward a target time a bounded number of
// steps per frame, the edit history, and the numbers a user watches. Windows and
// browsers drive it through plain calls (editor/tools.h maps pointer events to
// them); it knows nothing of either.
//
// The session is always expressible as a scene file: current_scene() is what
// save_scene() writes, and `vfsd deform` of that file computes the same
// deformation (the same prepare_scene, the same steps), except where triangles
// fold: `vfsd deform` then refines the mesh there and runs again
// (scene/scene_run.h), which the session does not yet.

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/error.h"
#include "deform/deformation.h"
#include "deform/quality.h"
#include "editor/edit_history.h"
#include "editor/picking.h"
#include "io/mesh_file.h"
#include "region/boundary_cut.h"
#include "scene/prepared_scene.h"
#include "scene/scene_package.h"

namespace vfsd::editor {

// Makes a prepared scene's deformation from t = 0 on the GPU (gpu::start_gpu_deformation
// in an application with a GL context); throws (GpuUnavailable, InputError) when it cannot.
using DeformationFactory = std::function<Deformation(const PreparedScene&)>;

struct SessionStats {
    std::size_t vertices = 0, triangles = 0;
    std::string backend = "cpu";  // of the running deformation (or the one the next will use)
    std::string backend_reason;   // why not the GPU, when the CPU runs
    double ms_per_step = 0.0;
    double volume_error_percent = 0.0;  // live, against the base mesh (this edit)
    std::size_t flipped_triangles = 0;  // live, against the base mesh (this edit)
    double first_fold_time = -1.0;      // when folds were first counted in this deformation (−1: never)
    // Live against the mesh as opened, across applies (equal to the above until one).
    double volume_error_since_opened_percent = 0.0;
    std::size_t flipped_since_opened = 0;
    bool applied = false;  // the base mesh is an applied deformation (the two pairs may differ)
};

// The volume error and flipped triangles as both editors show them: since the
// mesh was opened, and after an apply the current edit's own figure too
// ("0.004 % since opened (this edit 0.001 %)", "3 since opened (this edit 1, from t = 0.42)").
std::string volume_stat_text(const SessionStats& stats);
std::string flipped_stat_text(const SessionStats& stats);

// A scene file whose mesh is neither where the scene says nor beside it; `file`
// is the mesh's file name, the one to open next (Editor::open completes the scene).
struct MissingMesh : InputError {
    MissingMesh(const std::string& message, std::string file_name) : InputError(message), file(std::move(file_name)) {}
    std::string file;
};

enum class BrushTool { paint_inner, paint_outer, erase, paint_s };

struct BrushSettings {
    BrushTool tool = BrushTool::paint_inner;
    double radius = 0.1;    // geodesic, in mesh units
    double s_target = 0.0;  // paint_s: the value s is pulled toward
    double strength = 0.5;  // paint_s: how far each dab pulls
};

class EditorSession {
public:
    // `gpu` makes the GPU deformation (empty: CPU only, `gpu_reason` says why).
    explicit EditorSession(DeformationFactory gpu = {}, std::string gpu_reason = "no GPU context");
    // Not copied or moved: a region computed in parts refers to the document's mesh.
    EditorSession(const EditorSession&) = delete;
    EditorSession& operator=(const EditorSession&) = delete;

    // Loading. Each either succeeds and replaces the document (clearing the
    // history) or throws and leaves everything as it was. A scene opens with its
    // target_time as the target (update() plays there); a mesh opens at rest.
    // A scene file's mesh is `mesh` when given, else the path it names, else the
    // file of that name beside the scene; neither throws MissingMesh.
    void open_scene_file(const std::string& path, const std::string& mesh = "");
    void open_scene(const Scene& scene);
    // A mesh file or builtin:NAME with a starting region (geodesic around the
    // highest vertex) and curve (from there up and sideways), ready to scrub.
    void open_mesh(const std::string& spec);
    // .json opens a scene, anything else a mesh; a mesh of the name missing_mesh()
    // says opens the scene that named it, with this mesh.
    void open(const std::string& path);
    // Several files at once (a drop, a choice of several): the first scene among
    // them opens with the one whose file name is its mesh's, else as open() would;
    // without a scene the first file opens. main_file() is the one that names it.
    void open(const std::vector<std::string>& paths);
    static const std::string& main_file(const std::vector<std::string>& paths);
    // The mesh file name a scene opened without its mesh asked for (MissingMesh);
    // empty when none, or after another file opened.
    const std::string& missing_mesh() const { return missing_.mesh; }

    // The session as a scene. save_scene writes it with what it needs
    // (scene/scene_package.h: the base mesh next to it as NAME.mesh.ply after an
    // apply), with target_time = the current target. A failed save throws IoError
    // and leaves the session and any existing file as they were.
    Scene current_scene() const;
    void save_scene(const std::string& path, InputMesh input = InputMesh::referenced) const;
    // The mesh at the current time in the input file's layout (.obj .ply .glb .off).
    void export_mesh(const std::string& path);

    // Region tools. Outside a gesture each call is one undo step; inside
    // begin_region_gesture / end_region_gesture all calls make one step (a stroke,
    // a slider drag).
    void begin_region_gesture();
    void end_region_gesture(const std::string& label);
    void pick_geodesic(std::uint32_t vertex, double g_min, double g_max);
    void set_geodesic_range(double g_min, double g_max);  // no-op unless the region is geodesic
    void brush(const SurfacePoint& centre, const BrushSettings& settings);
    // Inner = seed side of `inner`, outer = beyond `outer` (boundary_cut.h); throws InputError.
    void set_region_from_loops(const SurfaceLoop& inner, const SurfaceLoop& outer, const SurfacePoint& seed);
    // A clean painted region: nothing inner or outer, the band kept (or the default).
    void new_region();
    // The painted region's transition band in mesh units (>= 0): an inner region
    // painted alone blends over it, and where inner and outer meet the outer side
    // gives it up to the blend region. Turns a scene's or a field's region into
    // labels first.
    void set_region_band(double band);
    // The axis shown up ('z' or 'y'), stored in the scene; remembered for the
    // mesh's file type, so the next mesh of that type opens with it.
    void set_up_axis(char axis);
    char up_axis() const { return doc_.scene.up_axis; }
    double region_band() const;
    // The band a painted region starts with: kDefaultBandFraction of the diagonal.
    static constexpr double kDefaultBandFraction = 0.25;

    // Curve tools, with the same gesture rule. They edit the scene's motion: the
    // curve (or handle) and its settings.
    void begin_curve_gesture();
    void end_curve_gesture(const std::string& label);
    void set_curve(const MotionSpec& next);
    // The draggable points: Bézier control points, or (handle mode) from and to positions.
    std::vector<Vec3> control_points() const;
    void move_control_point(std::size_t index, const Vec3& position);
    void add_segment();
    void remove_segment();
    // Handle mode with the handle at `at` (normal along the surface normal there).
    void use_handle(const HandleFrame& from, const HandleFrame& to);

    // The region's s after an edit: at once (the default), or in parts: the edit
    // computes which vertices are inner, blend and outer (eq. 15 or 16), and
    // prepare_run() the blend's values, for about its budget a call, the view
    // showing the first values meanwhile. The editors ask for parts, so that a
    // pick or a stroke does not hold up a frame; scripts and tests need not.
    void set_regions_in_parts(bool in_parts) { regions_in_parts_ = in_parts; }
    bool region_pending() const { return region_build_.has_value(); }
    // Computes a pending region to the end now (a read of s that must be final).
    void finish_region() { compute_region(kToTheEnd); }

    // Time. The deformation integrates toward the target in update(); an edit of
    // the region or curve restarts it from t = 0 (the target stays).
    void set_target_time(double t);
    double target_time() const { return doc_.scene.target_time; }
    double time() const;
    bool moving() const { return time() != target_time(); }
    void play();   // target 1 (from 0 again when already there)
    void pause();  // target = current time
    void reset();  // back to t = 0 at once
    // Takes at most `max_steps` steps toward the target, on the CPU stopping
    // after the first that ends `budget_ms` or more after the call, and with
    // `stop_before_affine_test` before a later step that runs the fold repair's
    // affine test (Deformation::advance); returns how many.
    int update(int max_steps, double budget_ms = kToTheEnd, bool stop_before_affine_test = false);
    // Whether the next step runs the fold repair's affine test (Deformation::next_step_tests_affine).
    bool next_step_tests_affine() const { return deformation_ && deformation_->next_step_tests_affine(target_time()); }
    // Prepares what a run toward the target needs before its first step, one part
    // per call, so that an editor can give each a frame of its own: the region
    // an edit left to compute (for about `budget_ms`, while region_pending(),
    // whatever the target), the deformation (the region's parts, the mesh reordered, ...) when none is
    // ready, then what the first step needs (Deformation::prepare_first_step).
    // True when it did some (or failed to: the error is in warnings() and the run
    // stops, as update()'s); false once the run can step.
    bool prepare_run(double budget_ms = kToTheEnd);
    static constexpr double kToTheEnd = std::numeric_limits<double>::infinity();
    // A piece of the next step toward the target (Deformation::prepare_step),
    // which the next update() completes; none where none is left to prepare,
    // waiting where the GPU is still running the last piece.
    StepPiece prepare_step();
    // The longest time any of the current run's last eight steps took (its
    // pieces together), in milliseconds; 0 before a step.
    double longest_recent_step_ms() const;
    // Bakes the deformed mesh as the new base (one undo step) and sets the target
    // to 0. No-op at t = 0. While a run catches up to an edit or a time scrubbed
    // to (holding_result()), it first runs to the target, and bakes that. Its undo
    // restores the base and sets the target back to the time it was applied at
    // (update() plays there again); redo applies again.
    void apply();

    bool undo();
    bool redo();
    const EditHistory& history() const { return history_; }

    // What to draw and pick on.
    // At time(); base positions at t = 0. After an edit of the region or the
    // curve at a target time > 0, the shape the last run ended in until the new
    // run reaches the target (holding_result()): the editors show an edit's
    // result when it is computed, not the way to it; play, scrubbing and the
    // time slider show the way.
    const std::vector<Vec3>& positions() const;
    bool holding_result() const { return held_.has_value(); }
    const std::vector<Vec3>& base_positions() const { return doc_.file.mesh.positions; }
    const std::vector<Triangle>& triangles() const { return doc_.file.mesh.triangles; }
    const VertexRings& rings() const { return doc_.rings; }
    // s so far: while region_pending(), which vertices are inner, blend and outer
    // is final, and the blend's values are eq. (15)'s or (16)'s.
    const std::vector<double>& s() const;
    const RegionSource& region() const { return doc_.region; }
    const RegionPaint& paint() const { return doc_.paint; }
    // The curve (or handle) and its settings: the scene's motion, as set_curve takes it.
    const MotionSpec& curve() const { return doc_.scene.motion; }
    // The motion of the current curve (for drawing it); empty when it is invalid.
    const InnerMotion& motion() const { return motion_; }
    const std::string& mesh_name() const { return doc_.scene.mesh; }
    double diagonal() const { return diagonal_; }
    const Deformation* deformation() const { return deformation_ ? &*deformation_ : nullptr; }
    // The surface under a ray at positions(): the editors' one way to pick it
    // (a SurfacePicker following mesh_revision() and positions_revision()).
    std::optional<SurfaceHit> pick_surface(const Ray& ray) const;
    // Each edit tells changed() (private, below) what it changed; only it bumps these.
    // Bumped whenever positions() or s() change (the view re-uploads them), and
    // when the mesh is replaced (new triangles). Not by the curve alone
    // (curve_revision): a curve edit that keeps the last result on show uploads
    // nothing, so its frame's draw does not queue behind the GPU's steps.
    std::uint64_t revision() const { return revision_; }
    std::uint64_t mesh_revision() const { return mesh_revision_; }
    // Bumped whenever positions() may change: steps taken, back to the base
    // positions, new base positions (not when only s() changes).
    std::uint64_t positions_revision() const { return positions_revision_; }
    std::uint64_t curve_revision() const { return curve_revision_; }
    // Bumped whenever what save_scene() writes changes: the mesh or its base
    // positions, the region, the curve or the target time (not while time advances).
    std::uint64_t document_revision() const { return document_revision_; }

    const SessionStats& stats() const { return stats_; }
    // The triangles that face against their neighbours now (stats().flipped_triangles
    // of them), as indices into the mesh's triangles: what the editors highlight.
    const std::vector<std::uint32_t>& folded_triangles() const { return folded_; }
    // Mesh, region and curve warnings, the last runtime error and the autosave's problem.
    std::vector<std::string> warnings() const;
    // The autosave's last problem (editor/autosave.h); empty clears it.
    void set_autosave_warning(std::string text) { autosave_warning_ = std::move(text); }

    void set_force_cpu(bool cpu);
    const DeformationOptions& options() const { return doc_.scene.options; }

private:
    struct Document {
        MeshFile file;
        VertexRings rings;
        // The truth for the mesh name, the options, the target time and the motion.
        // Its region stays empty: `region` and `paint` define the region (painting
        // needs labels), and current_scene() fills it in from them (region_spec()).
        Scene scene;
        RegionSource region;
        RegionPaint paint;
        bool baked = false;  // base positions differ from the mesh file's
        std::vector<std::string> mesh_warnings;
    };

    // What an edit changed. changed() is the one place that turns it into the
    // revisions above (what invalidates what); each mutation calls it.
    enum Change : unsigned {
        mesh_replaced = 1u << 0,    // a new document: new triangles, and everything below
        base_moved = 1u << 1,       // new base positions (apply, and its undo)
        region_edited = 1u << 2,    // the region source or paint, hence s
        motion_edited = 1u << 3,    // the curve or handle, or its settings
        target_moved = 1u << 4,     // the target time
        positions_moved = 1u << 5,  // positions() moved: steps taken, or back to the base
        view_set = 1u << 6,         // how the scene is shown (its up axis)
        region_built = 1u << 7,     // s's final values, computed in parts after a region edit
    };
    void changed(unsigned what);

    void replace_document(Document doc);
    RegionSpec region_spec() const;
    void region_changed();
    // Moves the region being built into region_ once it is built (advancing it for
    // about `budget_ms` first); true when it did. compute_region also says so.
    bool take_built_region(double budget_ms);
    void compute_region(double budget_ms);
    void curve_changed();
    void refresh_curve_warnings();
    void set_region(const RegionSource& next, const RegionEdit& paint, const std::string& label);
    // The labels a painting starts from when the region on screen is not labels: none.
    RegionSource clean_labels(RegionEdit& paint) const;
    void follow_inner_region();
    void apply_edit(const Edit& edit, bool forward);
    void set_target(double t);
    void drop_deformation();
    void drop_held();
    void predict_backend();
    void restart_after_edit();
    void ensure_deformation();
    void run_step(const std::function<void()>& work);
    void update_stats();
    void reset_stats();
    void base_moved_stats();

    std::map<std::string, char> up_axis_by_type_;  // file extension -> up axis
    struct {
        std::string scene, mesh;  // the scene file, and its mesh's file name
    } missing_;
    DeformationFactory gpu_;
    std::string gpu_reason_;
    bool force_cpu_ = false;

    Document doc_;
    Region region_;  // s per vertex (sec. 6), for the document's region and base positions
    // The region an edit left to compute in parts (set_regions_in_parts); region_ is then the last one's.
    std::optional<RegionBuild> region_build_;
    bool regions_in_parts_ = false;
    std::vector<std::uint32_t> folded_;
    std::vector<std::string> region_warnings_, curve_warnings_;
    std::string runtime_error_, autosave_warning_;
    InnerMotion motion_;
    double diagonal_ = 1.0;
    double base_volume_ = 0.0;
    // The mesh as opened, for the stats since then (kept across applies).
    std::vector<Vec3> opened_positions_;
    double opened_volume_ = 0.0;
    // The fold count's parts that stay while the deformation runs (quality.h): the
    // triangles' edge neighbours, and which triangles already face against them at
    // the base and as opened.
    TriangleNeighbours neighbours_;
    std::vector<std::uint8_t> base_against_, opened_against_;
    struct {
        double volume_error_percent = 0.0;
        std::size_t flipped = 0;
    } base_since_opened_;

    EditHistory history_;
    bool region_gesture_ = false, curve_gesture_ = false;
    bool region_gesture_changed_ = false, curve_gesture_changed_ = false;
    RegionChange pending_region_;
    MotionSpec pending_curve_;

    std::optional<Deformation> deformation_;
    // The last CPU deformation's rest state: a curve edit's run starts from it
    // when the mesh, the region and the options are the same (deform/cpu_steps.h).
    std::shared_ptr<const CpuRest> rest_;
    std::optional<std::vector<Vec3>> held_;  // positions() while an edit's run catches up (restart_after_edit)
    bool held_for_rewind_ = false;           // or a run started again from rest catches up (set_target)
    SessionStats stats_;
    std::uint64_t revision_ = 1, mesh_revision_ = 1, curve_revision_ = 1, document_revision_ = 1;
    std::uint64_t positions_revision_ = 1;
    mutable SurfacePicker picker_;
};

// The current time as both editors show it: "0.420", or while an edit's run
// catches up with the last result on show, "updating 42 %" (of the way to the target).
std::string time_stat_text(const EditorSession& session);

}  // namespace vfsd::editor
