#include "editor/session.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "base/error.h"
#include "base/heap.h"
#include "curve/curve_on_region.h"
#include "deform/cpu_steps.h"
#include "deform/quality.h"
#include "mesh/geometry.h"
#include "mesh/validation.h"
#include "region/selectors.h"

namespace vfsd::editor {
namespace {

// Live quality numbers need the positions (a GPU read-back): every step below
// this many vertices, otherwise only when the deformation reaches its target.
constexpr std::size_t kLiveStatsVertexLimit = 300000;

Selector vertex_selector(const std::vector<std::uint8_t>& labels, RegionLabel label) {
    Selector sel;
    sel.kind = SelectorKind::vertices;
    for (std::size_t v = 0; v < labels.size(); ++v)
        if (labels[v] == static_cast<std::uint8_t>(label)) sel.vertices.push_back(static_cast<std::uint32_t>(v));
    return sel;
}

// The edit that sets channel values to `next` (only the vertices that change).
RegionEdit diff_edit(RegionChannel channel, const std::vector<double>& current, const std::vector<double>& next) {
    RegionEdit edit;
    edit.channel = channel;
    for (std::size_t v = 0; v < current.size(); ++v)
        if (current[v] != next[v]) {
            edit.vertices.push_back(static_cast<std::uint32_t>(v));
            edit.old_values.push_back(current[v]);
            edit.new_values.push_back(next[v]);
        }
    return edit;
}

std::vector<double> labels_as_values(const RegionPaint& paint) {
    return std::vector<double>(paint.labels.begin(), paint.labels.end());
}

// Folds `next` into `total` (either may be empty).
void accumulate(RegionEdit& total, const RegionEdit& next) {
    if (next.vertices.empty()) return;
    if (total.vertices.empty()) {
        total = next;
        return;
    }
    merge_edit(total, next);
}

std::vector<std::string> mesh_warnings(const MeshFile& file) {
    const TriangleMesh& mesh = file.mesh;
    std::vector<std::string> out;
    if (std::string turned = turned_triangles_warning(file); !turned.empty()) out.push_back(std::move(turned));
    const ValidationReport report = validate_mesh(mesh);
    if (!report.is_manifold)
        for (const std::string& r : report.reasons) out.push_back("mesh: not a 2-manifold: " + r);
    if (!report.is_closed)
        out.push_back("mesh: has boundary edges; the volume error is measured against the origin");
    return out;
}

bool is_scene_file(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".json" || ext == ".JSON";
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// |volume - reference| in percent of |reference| (0 without a reference volume).
double volume_error_percent(double volume, double reference) {
    return reference != 0.0 ? 100.0 * std::abs(volume - reference) / std::abs(reference) : 0.0;
}

// A scene file's mesh (scene.h resolved it against the scene's folder): there, else
// the file of that name beside the scene (a scene and its mesh moved or uploaded
// together); neither throws MissingMesh naming the file.
std::string find_scene_mesh(const std::string& mesh, const std::string& scene_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (mesh.rfind("builtin:", 0) == 0 || fs::exists(mesh, ec)) return mesh;
    const std::string name = file_name(mesh);
    const fs::path beside = fs::path(scene_path).parent_path() / name;
    if (fs::exists(beside, ec)) return beside.string();
    throw MissingMesh("its mesh " + name + " is not at " + mesh + " nor beside the scene: choose " + name, name);
}

// The file type a mesh spec names: its extension in lower case, or "builtin".
std::string file_type(const std::string& spec) {
    if (spec.rfind("builtin:", 0) == 0) return "builtin";
    std::string ext = std::filesystem::path(spec).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

std::string volume_stat_text(const SessionStats& st) {
    char text[96];
    if (st.applied)
        std::snprintf(text, sizeof text, "%.3f %% since opened (this edit %.3f %%)", st.volume_error_since_opened_percent,
                      st.volume_error_percent);
    else
        std::snprintf(text, sizeof text, "%.3f %% since opened", st.volume_error_since_opened_percent);
    return text;
}

std::string time_stat_text(const EditorSession& session) {
    char text[32];
    if (session.holding_result())
        std::snprintf(text, sizeof text, "updating %.0f %%",
                      100.0 * session.time() / std::max(session.target_time(), 1e-9));
    else
        std::snprintf(text, sizeof text, "%.3f", session.time());
    return text;
}

std::string flipped_stat_text(const SessionStats& st) {
    std::string text = std::to_string(st.flipped_since_opened) + " since opened";
    std::string edit = st.applied ? "this edit " + std::to_string(st.flipped_triangles) : "";
    if (st.flipped_triangles > 0 && st.first_fold_time >= 0.0) {
        char from[32];
        std::snprintf(from, sizeof from, "from t = %.2f", st.first_fold_time);
        edit += (edit.empty() ? "" : ", ") + std::string(from);
    }
    return edit.empty() ? text : text + " (" + edit + ")";
}

EditorSession::EditorSession(DeformationFactory gpu, std::string gpu_reason)
    : gpu_(std::move(gpu)), gpu_reason_(std::move(gpu_reason)) {
    predict_backend();
}

// The backend the next deformation will use, and why not the GPU, until one runs.
void EditorSession::predict_backend() {
    const bool gpu = gpu_ && !force_cpu_;
    stats_.backend = gpu ? "gpu" : "cpu";
    stats_.backend_reason = gpu ? "" : !gpu_ ? gpu_reason_ : "CPU chosen";
}

// ---- loading and saving --------------------------------------------------

void EditorSession::open_scene_file(const std::string& path, const std::string& mesh) {
    Scene scene = load_scene(path);
    scene.mesh = mesh.empty() ? find_scene_mesh(scene.mesh, path) : mesh;
    open_scene(scene);
}

void EditorSession::open_scene(const Scene& scene) {
    Document doc;
    doc.file = load_mesh_file(scene.mesh);
    doc.scene = scene;
    doc.region.kind = RegionSource::Kind::spec;
    doc.region.spec = std::move(doc.scene.region);
    doc.scene.region = {};
    replace_document(std::move(doc));
}

void EditorSession::open_mesh(const std::string& spec) {
    Document doc;
    doc.file = load_mesh_file(spec);
    const auto& p = doc.file.mesh.positions;
    if (p.empty()) throw InputError(spec + ": the mesh has no vertices");
    doc.scene.mesh = spec;
    doc.scene.target_time = 0.0;  // a mesh opens at rest
    if (const auto known = up_axis_by_type_.find(file_type(spec)); known != up_axis_by_type_.end())
        doc.scene.up_axis = known->second;
    // A region around the highest vertex and a curve that lifts it and bends it over.
    const double d = bounding_box(p).diagonal();
    const auto top = static_cast<std::size_t>(
        std::max_element(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) { return a.z < b.z; }) - p.begin());
    doc.region.spec.kind = RegionSpec::Kind::geodesic;
    doc.region.spec.seed = p[top];
    doc.region.spec.g_min = 0.1 * d;
    doc.region.spec.g_max = 0.45 * d;
    doc.scene.options.smoothing_steps = 40;  // as the paper-figure scenes: smoother blends
    doc.scene.options.tolerance = kSceneTolerance;  // error-controlled steps, as a scene file without "steps"
    const Vec3 c0 = p[top];
    doc.scene.motion.curve.bezier = {c0, c0 + d * Vec3(0.0, 0.0, 0.12), c0 + d * Vec3(0.08, 0.0, 0.22),
                                     c0 + d * Vec3(0.25, 0.0, 0.25)};
    replace_document(std::move(doc));
}

void EditorSession::open(const std::string& path) {
    if (is_scene_file(path)) {
        try {
            open_scene_file(path);
        } catch (const MissingMesh& e) {
            missing_ = {path, e.file};
            throw;
        }
    } else if (!missing_.mesh.empty() && file_name(path) == missing_.mesh) {
        open_scene_file(missing_.scene, path);
    } else {
        open_mesh(path);
    }
    missing_ = {};
}

const std::string& EditorSession::main_file(const std::vector<std::string>& paths) {
    if (paths.empty()) throw InputError("open: no file given");
    const auto scene = std::find_if(paths.begin(), paths.end(), is_scene_file);
    return scene != paths.end() ? *scene : paths.front();
}

void EditorSession::open(const std::vector<std::string>& paths) {
    const std::string& main = main_file(paths);
    if (is_scene_file(main)) {
        const std::string mesh = file_name(load_scene(main).mesh);
        for (const std::string& path : paths)
            if (!is_scene_file(path) && file_name(path) == mesh) {
                open_scene_file(main, path);
                missing_ = {};
                return;
            }
    }
    open(main);
}

void EditorSession::replace_document(Document doc) {
    // Everything that can throw happens before the current document is replaced:
    // the new region's first part (eq. 15 or 16) runs on the new document with
    // the old one kept aside, and a failure puts the old one back.
    doc.rings = build_vertex_rings(doc.file.mesh);
    doc.paint = make_region_paint(doc.file.mesh.vertex_count());
    doc.mesh_warnings = mesh_warnings(doc.file);
    InnerMotion motion = build_motion(doc.scene.motion);
    compute_region(kToTheEnd);  // no region left to compute refers to the document set aside
    std::swap(doc_, doc);
    try {
        region_build_.emplace(doc_.region.spec, doc_.file.mesh.positions, doc_.rings);
    } catch (...) {
        std::swap(doc_, doc);
        throw;
    }
    region_warnings_.clear();
    if (!regions_in_parts_) take_built_region(kToTheEnd);
    motion_ = std::move(motion);
    history_.clear();
    region_gesture_ = curve_gesture_ = false;
    diagonal_ = bounding_box(doc_.file.mesh.positions).diagonal();
    if (!(diagonal_ > 0.0)) diagonal_ = 1.0;
    opened_positions_ = doc_.file.mesh.positions;
    opened_volume_ = signed_volume(opened_positions_, doc_.file.mesh.triangles);
    neighbours_ = triangle_neighbours(doc_.file.mesh.triangles);
    opened_against_ = facing_against_neighbours(opened_positions_, doc_.file.mesh.triangles, neighbours_);
    base_moved_stats();
    stats_.vertices = doc_.file.mesh.vertex_count();
    stats_.triangles = doc_.file.mesh.triangle_count();
    drop_held();
    drop_deformation();
    rest_.reset();  // of another mesh: freed now, not when the next run starts
    changed(mesh_replaced);
    refresh_curve_warnings();
    // The picker's hierarchy now, with the rest of the opening, rather than in
    // the first pick (a drag or a stroke; 22 ms at 82k triangles).
    picker_.follow(positions(), triangles(), mesh_revision_, positions_revision_);
    // The old document, and what its runs freed and the heap kept (base/heap.h),
    // go back to the system: the new mesh may be far smaller.
    doc = Document();
    return_freed_memory();
}

// The revisions' promises (session.h), kept in one place.
void EditorSession::changed(unsigned what) {
    if (what & mesh_replaced) what |= base_moved | region_edited | motion_edited | target_moved;
    if (what & base_moved) what |= positions_moved;
    if (what & mesh_replaced) ++mesh_revision_;
    if (what & motion_edited) ++curve_revision_;
    if (what & positions_moved) ++positions_revision_;
    // What the view uploads: positions() and s() (the curve has its own revision).
    if (what & (positions_moved | region_edited | region_built)) ++revision_;
    // What save_scene() writes; time advancing toward the target is not a change.
    if (what & (base_moved | region_edited | motion_edited | target_moved | view_set)) ++document_revision_;
}

Scene EditorSession::current_scene() const {
    Scene scene = doc_.scene;
    scene.region = region_spec();
    return scene;
}

void EditorSession::save_scene(const std::string& path, InputMesh input) const {
    write_scene_package(path, current_scene(), input, doc_.baked ? &doc_.file.mesh : nullptr);
}

void EditorSession::export_mesh(const std::string& path) {
    compute_region(kToTheEnd);
    TriangleMesh result = doc_.file.mesh;
    result.positions = positions();
    result.scalar = region_.s;
    write_mesh_file(path, doc_.baked ? result : to_file_layout(doc_.file, result));
}

// ---- region ----------------------------------------------------------------

RegionSpec EditorSession::region_spec() const {
    switch (doc_.region.kind) {
        case RegionSource::Kind::spec: return doc_.region.spec;
        case RegionSource::Kind::labels: {
            RegionSpec spec;
            spec.kind = RegionSpec::Kind::painted;
            spec.band = doc_.region.band;
            const Selector inner = vertex_selector(doc_.paint.labels, RegionLabel::inner);
            const Selector outer = vertex_selector(doc_.paint.labels, RegionLabel::outer);
            if (!inner.vertices.empty()) spec.inner.push_back(inner);
            if (!outer.vertices.empty()) spec.outer.push_back(outer);
            return spec;
        }
        case RegionSource::Kind::field: {
            RegionSpec spec;
            spec.kind = RegionSpec::Kind::field;
            spec.s = doc_.paint.s;
            return spec;
        }
    }
    return doc_.region.spec;
}

// Eq. (15) or (16) at once (it throws for a region that cannot be built); the
// harmonic blend then too, or in parts when the editor asked for them
// (compute_region, from prepare_run).
void EditorSession::region_changed() {
    region_build_.emplace(region_spec(), doc_.file.mesh.positions, doc_.rings);
    if (!regions_in_parts_) take_built_region(kToTheEnd);
    restart_after_edit();
    changed(region_edited);
    refresh_curve_warnings();
}

bool EditorSession::take_built_region(double budget_ms) {
    if (!region_build_ || !region_build_->advance(budget_ms)) return false;
    std::vector<std::string> warnings;
    region_ = region_build_->take(warnings);
    region_build_.reset();
    region_warnings_ = std::move(warnings);
    return true;
}

void EditorSession::compute_region(double budget_ms) {
    if (!take_built_region(budget_ms)) return;
    changed(region_built);
    refresh_curve_warnings();
}

const std::vector<double>& EditorSession::s() const { return region_build_ ? region_build_->s() : region_.s; }

void EditorSession::set_region(const RegionSource& next, const RegionEdit& paint, const std::string& label) {
    const RegionSource before = doc_.region;
    const MotionSpec motion_before = doc_.scene.motion;
    const std::vector<double> s_before = s();
    doc_.region = next;
    ::vfsd::apply_edit(doc_.paint, paint);
    try {
        region_changed();
    } catch (...) {
        ::vfsd::revert_edit(doc_.paint, paint);
        doc_.region = before;
        region_changed();
        throw;
    }
    const auto inner = [](const std::vector<double>& s) {
        std::vector<bool> in(s.size());
        for (std::size_t v = 0; v < s.size(); ++v) in[v] = s[v] <= 0.0;
        return in;
    };
    if (inner(s()) != inner(s_before)) follow_inner_region();
    if (region_gesture_) {
        accumulate(pending_region_.paint, paint);
        region_gesture_changed_ = true;
    } else {
        history_.push({label, RegionChange{before, doc_.region, paint, motion_before, doc_.scene.motion}});
    }
}

// Sec. 3 wants c(0) in the inner region: a new inner region carries the curve
// along, its start at the region's centroid, leaving along its axis, its shape
// kept (curve/curve_on_region.h). A handle stays where the user put it.
void EditorSession::follow_inner_region() {
    if (doc_.scene.motion.curve.is_handle) return;
    std::vector<Vec3> normals;
    vertex_normals(doc_.file.mesh.positions, doc_.rings, normals);
    MotionSpec next = doc_.scene.motion;
    next.curve.bezier = curve_on_region(next.curve.bezier, doc_.file.mesh.positions, normals, s());
    if (next == doc_.scene.motion) return;
    doc_.scene.motion = next;
    curve_changed();
}

void EditorSession::begin_region_gesture() {
    region_gesture_ = true;
    region_gesture_changed_ = false;
    pending_region_ = RegionChange();
    pending_region_.before = doc_.region;
    pending_region_.motion_before = doc_.scene.motion;
}

void EditorSession::end_region_gesture(const std::string& label) {
    if (!region_gesture_) return;
    region_gesture_ = false;
    if (!region_gesture_changed_) return;
    pending_region_.after = doc_.region;
    pending_region_.motion_after = doc_.scene.motion;
    history_.push({label, std::move(pending_region_)});
}

RegionSource EditorSession::clean_labels(RegionEdit& paint) const {
    RegionSource labels;
    labels.kind = RegionSource::Kind::labels;
    labels.band = region_band();
    paint = diff_edit(RegionChannel::labels, labels_as_values(doc_.paint), std::vector<double>(s().size(), 0.0));
    return labels;
}

double EditorSession::region_band() const {
    return doc_.region.kind == RegionSource::Kind::labels ? doc_.region.band : kDefaultBandFraction * diagonal_;
}

void EditorSession::set_up_axis(char axis) {
    if (axis != 'z' && axis != 'y') throw InputError(std::string("up axis: expected z or y, got ") + axis);
    up_axis_by_type_[file_type(doc_.scene.mesh)] = axis;
    if (axis == doc_.scene.up_axis) return;
    doc_.scene.up_axis = axis;
    changed(view_set);
}

void EditorSession::new_region() {
    RegionEdit paint;
    const RegionSource next = clean_labels(paint);
    set_region(next, paint, "new region");
}

void EditorSession::set_region_band(double band) {
    if (!(band >= 0.0) || !std::isfinite(band)) throw InputError("region band: expected a distance >= 0");
    RegionEdit paint;
    RegionSource next = doc_.region.kind == RegionSource::Kind::labels ? doc_.region : clean_labels(paint);
    if (next.kind == doc_.region.kind && next.band == band) return;
    next.band = band;
    set_region(next, paint, "transition band");
}

void EditorSession::pick_geodesic(std::uint32_t vertex, double g_min, double g_max) {
    if (vertex >= doc_.file.mesh.vertex_count()) throw InputError("geodesic pick: vertex out of range");
    RegionSource next;
    next.spec.kind = RegionSpec::Kind::geodesic;
    next.spec.seed = doc_.file.mesh.positions[vertex];
    next.spec.g_min = g_min;
    next.spec.g_max = g_max;
    set_region(next, {}, "geodesic region");
}

void EditorSession::set_geodesic_range(double g_min, double g_max) {
    if (doc_.region.kind != RegionSource::Kind::spec || doc_.region.spec.kind != RegionSpec::Kind::geodesic) return;
    RegionSource next = doc_.region;
    next.spec.g_min = g_min;
    next.spec.g_max = g_max;
    set_region(next, {}, "geodesic range");
}

void EditorSession::brush(const SurfacePoint& centre, const BrushSettings& b) {
    RegionEdit total;
    RegionSource next = doc_.region;
    RegionPaint paint = doc_.paint;
    // Painting s starts from the field on screen; painting labels starts clean, so
    // no label the user did not paint hides in the region (only the band is kept).
    if (b.tool == BrushTool::paint_s && next.kind != RegionSource::Kind::field) {
        compute_region(kToTheEnd);
        total = diff_edit(RegionChannel::s, paint.s, region_.s);
        next.kind = RegionSource::Kind::field;
    } else if (b.tool != BrushTool::paint_s && next.kind != RegionSource::Kind::labels) {
        next = clean_labels(total);
    }
    ::vfsd::apply_edit(paint, total);
    const auto& mesh = doc_.file.mesh;
    RegionEdit dab;
    if (b.tool == BrushTool::paint_s) {
        dab = field_brush(paint, mesh.positions, mesh.triangles, doc_.rings, centre, b.radius, b.s_target, b.strength);
    } else {
        const LabelBrush mode = b.tool == BrushTool::paint_inner   ? LabelBrush::paint_inner
                                : b.tool == BrushTool::paint_outer ? LabelBrush::paint_outer
                                                                   : LabelBrush::erase;
        dab = label_brush(paint, mesh.positions, mesh.triangles, doc_.rings, centre, b.radius, mode);
    }
    accumulate(total, dab);
    next.spec = RegionSpec{};
    static const char* names[] = {"paint inner", "paint outer", "erase", "paint s"};
    set_region(next, total, names[int(b.tool)]);
}

void EditorSession::set_region_from_loops(const SurfaceLoop& inner, const SurfaceLoop& outer,
                                          const SurfacePoint& seed) {
    const auto& mesh = doc_.file.mesh;
    const LoopRegions regions = regions_from_loops(mesh.positions, mesh.triangles, doc_.rings, inner, outer, seed);
    std::vector<double> labels(mesh.vertex_count(), 0.0);
    for (std::size_t v = 0; v < labels.size(); ++v)
        labels[v] = regions.inner[v] ? double(RegionLabel::inner) : regions.outer[v] ? double(RegionLabel::outer) : 0.0;
    RegionSource next;
    next.kind = RegionSource::Kind::labels;
    set_region(next, diff_edit(RegionChannel::labels, labels_as_values(doc_.paint), labels), "region from loops");
}

// ---- curve -----------------------------------------------------------------

void EditorSession::curve_changed() {
    motion_ = build_motion(doc_.scene.motion);
    restart_after_edit();
    changed(motion_edited);
    refresh_curve_warnings();
}

void EditorSession::set_curve(const MotionSpec& next) {
    if (next == doc_.scene.motion) return;
    build_motion(next);  // throws InputError for an invalid curve, before any change
    const MotionSpec before = doc_.scene.motion;
    doc_.scene.motion = next;
    curve_changed();
    if (curve_gesture_) curve_gesture_changed_ = true;
    else history_.push({"edit curve", CurveChange{before, doc_.scene.motion}});
}

void EditorSession::begin_curve_gesture() {
    curve_gesture_ = true;
    curve_gesture_changed_ = false;
    pending_curve_ = doc_.scene.motion;
}

void EditorSession::end_curve_gesture(const std::string& label) {
    if (!curve_gesture_) return;
    curve_gesture_ = false;
    if (curve_gesture_changed_ && pending_curve_ != doc_.scene.motion)
        history_.push({label, CurveChange{pending_curve_, doc_.scene.motion}});
}

std::vector<Vec3> EditorSession::control_points() const {
    const CurveSpec& c = doc_.scene.motion.curve;
    if (c.is_handle) return {c.from.position, c.to.position};
    return c.bezier;
}

void EditorSession::move_control_point(std::size_t index, const Vec3& position) {
    MotionSpec next = doc_.scene.motion;
    if (next.curve.is_handle) {
        if (index == 0) next.curve.from.position = position;
        else if (index == 1) next.curve.to.position = position;
        else throw InputError("handle mode has two points (0: from, 1: to)");
    } else {
        if (index >= next.curve.bezier.size())
            throw InputError("control point " + std::to_string(index) + " does not exist (the curve has " +
                             std::to_string(next.curve.bezier.size()) + ")");
        next.curve.bezier[index] = position;
    }
    set_curve(next);
}

void EditorSession::add_segment() {
    MotionSpec next = doc_.scene.motion;
    auto& b = next.curve.bezier;
    if (next.curve.is_handle || b.size() < 4) return;
    // Continue along the last tangent, so the join is C1.
    Vec3 d = b.back() - b[b.size() - 2];
    if (glm::length(d) == 0.0) d = Vec3(0.0, 0.0, 0.05 * diagonal_);
    const Vec3 last = b.back();
    for (int k = 1; k <= 3; ++k) b.push_back(last + double(k) * d);
    set_curve(next);
}

void EditorSession::remove_segment() {
    MotionSpec next = doc_.scene.motion;
    if (next.curve.is_handle || next.curve.bezier.size() < 7) return;
    next.curve.bezier.resize(next.curve.bezier.size() - 3);
    set_curve(next);
}

void EditorSession::use_handle(const HandleFrame& from, const HandleFrame& to) {
    MotionSpec next = doc_.scene.motion;
    next.curve.is_handle = true;
    next.curve.from = from;
    next.curve.to = to;
    set_curve(next);
}

void EditorSession::refresh_curve_warnings() {
    curve_warnings_.clear();
    if (motion_.is_fixed_rotation() || s().empty()) return;
    if (motion_.curve().polygon_length() == 0.0) {
        curve_warnings_.push_back("curve: all control points coincide, so nothing moves");
        return;
    }
    const std::uint32_t v = nearest_vertex(doc_.file.mesh.positions, motion_.curve().at(0.0).position);
    if (s()[v] > 0.0)
        curve_warnings_.push_back("curve: c(0) does not start in the inner region (s = " + std::to_string(s()[v]) +
                                  " at the nearest vertex)");
}

// ---- time --------------------------------------------------------------------

double EditorSession::time() const { return deformation_ ? deformation_->time() : 0.0; }

void EditorSession::set_target_time(double t) { set_target(std::clamp(t, 0.0, 1.0)); }

void EditorSession::set_target(double t) {
    if (held_ && !held_for_rewind_) {  // a new target: show the way there, with its stats
        drop_held();
        changed(positions_moved);
        if (deformation_)
            update_stats();
        else
            reset_stats();
    }
    if (t == doc_.scene.target_time) return;
    doc_.scene.target_time = t;
    // Back across a step the fold repair acted after, the deformation starts
    // again from rest and steps forward to t (Deformation::advance): the shape
    // on show stays until it gets there.
    if (deformation_ && !held_ && deformation_->rewinds_to(t)) {
        held_ = deformation_->positions();
        held_for_rewind_ = true;
    }
    changed(target_moved);
}

void EditorSession::play() {
    if (time() >= 1.0) reset();
    set_target(1.0);
}

void EditorSession::pause() { set_target(time()); }

void EditorSession::reset() {
    drop_deformation();
    set_target(0.0);
}

void EditorSession::set_force_cpu(bool cpu) {
    if (cpu == force_cpu_) return;
    force_cpu_ = cpu;
    drop_deformation();
}

// An edit of the region or the curve: the run starts again from t = 0 and,
// until it is back at the target, positions() keeps the shape the last run
// ended in (or, after edits in quick succession, the last one that ended).
void EditorSession::restart_after_edit() {
    if (deformation_ && !held_ && time() > 0.0 && !moving()) held_ = deformation_->positions();
    held_for_rewind_ = false;  // what is held is now the edit's
    drop_deformation();
}

// The shape on show while a run catches up goes: positions() is the run's again.
void EditorSession::drop_held() {
    held_.reset();
    held_for_rewind_ = false;
}

void EditorSession::drop_deformation() {
    // The next deformation starts afresh: the last one's error goes with it.
    runtime_error_.clear();
    const bool deformed = static_cast<bool>(deformation_);
    if (deformed)
        if (auto rest = deformation_->cpu_rest()) rest_ = std::move(rest);
    deformation_.reset();
    stats_.ms_per_step = 0.0;
    predict_backend();
    // Unless the last result stays on show (positions() and its stats do not
    // change, and a pick need not refit: every event of a curve drag restarts the
    // run), back to the base positions.
    if (held_) return;
    if (deformed) changed(positions_moved);
    reset_stats();
}

// The stats of the base positions, where the deformation starts.
void EditorSession::reset_stats() {
    stats_.volume_error_percent = 0.0;
    stats_.flipped_triangles = 0;
    folded_.clear();
    stats_.first_fold_time = -1.0;
    stats_.volume_error_since_opened_percent = base_since_opened_.volume_error_percent;
    stats_.flipped_since_opened = base_since_opened_.flipped;
}

// New base positions (opened, applied, or that undone): what the applies so far
// did to the mesh as opened, the since-opened stats at rest.
void EditorSession::base_moved_stats() {
    const auto& mesh = doc_.file.mesh;
    base_volume_ = signed_volume(mesh.positions, mesh.triangles);
    stats_.applied = doc_.baked;
    base_since_opened_.volume_error_percent = volume_error_percent(base_volume_, opened_volume_);
    base_against_ = facing_against_neighbours(mesh.positions, mesh.triangles, neighbours_);
    base_since_opened_.flipped = doc_.baked ? newly_facing_against(opened_against_, base_against_).size() : 0;
}

void EditorSession::ensure_deformation() {
    if (deformation_) return;
    compute_region(kToTheEnd);
    PreparedScene prepared = prepare_scene(current_scene(), doc_.file, doc_.rings, region_);
    std::string reason = force_cpu_ ? "CPU chosen" : gpu_reason_;
    if (gpu_ && !force_cpu_) {
        try {
            deformation_ = gpu_(prepared);
        } catch (const std::exception& e) {
            reason = e.what();
        }
    }
    if (!deformation_) {
        // A curve edit keeps the mesh, the region and the options: what the last
        // run built at rest is the same (the steps are, bit for bit).
        const DeformationOptions& options = prepared.scene.options;
        if (rest_ && rest_->fits(doc_.file.mesh.positions, doc_.rings, region_, options))
            deformation_.emplace(rest_, std::move(prepared.motion), options);
        else
            deformation_ = std::move(prepared).start_deformation();
    }
    rest_.reset();  // the deformation holds it, or it no longer fits
    stats_.backend = deformation_->backend_name();
    stats_.backend_reason = stats_.backend == "gpu" ? "" : reason;
}

int EditorSession::update(int max_steps, double budget_ms, bool stop_before_affine_test) {
    if (time() == target_time()) return 0;
    int taken = 0;
    run_step([&] {
        ensure_deformation();
        const double before = time();
        const bool held = held_.has_value();
        taken = deformation_->advance(target_time(), max_steps, budget_ms, stop_before_affine_test);
        if (!moving()) drop_held();  // the edit's (or the way back's) result is ready
        // Back to t = 0 from rest takes no step, but the positions changed.
        if (taken > 0 || time() != before || held != held_.has_value()) {
            changed(positions_moved);
            update_stats();
        }
    });
    return taken;
}

bool EditorSession::prepare_run(double budget_ms) {
    if (region_build_) {
        run_step([&] { compute_region(budget_ms); });
        return true;
    }
    if (time() == target_time()) return false;
    bool prepared = true;
    run_step([&] {
        if (!deformation_)
            ensure_deformation();
        else
            prepared = deformation_->prepare_first_step();
    });
    return prepared;
}

StepPiece EditorSession::prepare_step() {
    if (!deformation_ || time() == target_time()) return StepPiece::none;
    StepPiece piece = StepPiece::none;
    run_step([&] { piece = deformation_->prepare_step(target_time()); });
    return piece;
}

double EditorSession::longest_recent_step_ms() const {
    if (!deformation_) return 0.0;
    const std::vector<double>& ms = deformation_->step_milliseconds();
    const std::size_t recent = std::min<std::size_t>(ms.size(), 8);
    return ms.empty() ? 0.0 : *std::max_element(ms.end() - recent, ms.end());
}

// A failure on the way to the target stops the run where it is and says why.
void EditorSession::run_step(const std::function<void()>& work) {
    try {
        work();
    } catch (const std::exception& e) {
        runtime_error_ = std::string("deformation stopped: ") + e.what();
        set_target(time());
    }
}

void EditorSession::update_stats() {
    stats_.ms_per_step = deformation_->ms_per_step();
    // The stats are those of positions(): of the result on show while it is held.
    if (held_ || (doc_.file.mesh.vertex_count() > kLiveStatsVertexLimit && moving())) return;
    const auto& now = deformation_->positions();
    const auto& mesh = doc_.file.mesh;
    const double volume = signed_volume(now, mesh.triangles);
    stats_.volume_error_percent = volume_error_percent(volume, base_volume_);
    const std::vector<std::uint8_t> against = facing_against_neighbours(now, mesh.triangles, neighbours_);
    folded_ = newly_facing_against(base_against_, against);
    stats_.flipped_triangles = folded_.size();
    stats_.volume_error_since_opened_percent = volume_error_percent(volume, opened_volume_);
    stats_.flipped_since_opened = doc_.baked ? newly_facing_against(opened_against_, against).size() : folded_.size();
    if (stats_.flipped_triangles > 0 && stats_.first_fold_time < 0.0) stats_.first_fold_time = time();
}

const std::vector<Vec3>& EditorSession::positions() const {
    if (held_) return *held_;
    return deformation_ ? deformation_->positions() : doc_.file.mesh.positions;
}

std::optional<SurfaceHit> EditorSession::pick_surface(const Ray& ray) const {
    return picker_.pick(ray, positions(), triangles(), mesh_revision_, positions_revision_);
}

std::vector<std::string> EditorSession::warnings() const {
    std::vector<std::string> out = doc_.mesh_warnings;
    out.insert(out.end(), region_warnings_.begin(), region_warnings_.end());
    out.insert(out.end(), curve_warnings_.begin(), curve_warnings_.end());
    if (!runtime_error_.empty()) out.push_back(runtime_error_);
    if (!autosave_warning_.empty()) out.push_back(autosave_warning_);
    return out;
}

// ---- apply, undo, redo ------------------------------------------------------------

void EditorSession::apply() {
    // While a run catches up (holding_result()), what it catches up to is baked:
    // the edit's result, or the time scrubbed to, not the way there.
    if (held_) update(std::numeric_limits<int>::max());
    if (!deformation_ || time() == 0.0) return;
    drop_held();  // what is baked is the deformation at time() (a failed run's last good shape)
    BakeChange bake;
    bake.before = doc_.file.mesh.positions;
    bake.after = positions();
    bake.region_before = doc_.region;
    bake.region_after.kind = RegionSource::Kind::spec;
    bake.region_after.spec.kind = RegionSpec::Kind::field;
    bake.region_after.spec.s = region_.s;
    bake.motion_before = doc_.scene.motion;
    bake.motion_after = doc_.scene.motion;
    bake.baked_before = doc_.baked;
    bake.time = time();
    // The next deformation starts where this one ended: a straight curve along the
    // end tangent (handle mode: the handle at its target, moved along its normal).
    const double length = std::max(0.25 * motion_.curve().polygon_length(), 0.05 * diagonal_);
    if (bake.motion_after.curve.is_handle) {
        HandleFrame& from = bake.motion_after.curve.from;
        from = bake.motion_after.curve.to;
        bake.motion_after.curve.to.position = from.position + length * from.normal;
    } else {
        const CurvePoint end = motion_.curve().at(1.0);
        const double speed = glm::length(end.d1);
        const Vec3 tangent = speed > 0.0 ? end.d1 / speed : Vec3(0.0, 0.0, 1.0);
        auto& b = bake.motion_after.curve.bezier;
        b.clear();
        for (int k = 0; k <= 3; ++k) b.push_back(end.position + (length * k / 3.0) * tangent);
    }
    bake.motion_after.twist_degrees[0] = bake.motion_after.twist_degrees[1] = 0.0;
    apply_edit(bake, true);
    history_.push({"apply deformation", std::move(bake)});
}

void EditorSession::apply_edit(const Edit& edit, bool forward) {
    if (const auto* r = std::get_if<RegionChange>(&edit)) {
        if (forward) ::vfsd::apply_edit(doc_.paint, r->paint);
        else ::vfsd::revert_edit(doc_.paint, r->paint);
        doc_.region = forward ? r->after : r->before;
        region_changed();
        doc_.scene.motion = forward ? r->motion_after : r->motion_before;
        curve_changed();
    } else if (const auto* c = std::get_if<CurveChange>(&edit)) {
        doc_.scene.motion = forward ? c->after : c->before;
        curve_changed();
    } else if (const auto* b = std::get_if<BakeChange>(&edit)) {
        doc_.file.mesh.positions = forward ? b->after : b->before;
        doc_.baked = forward ? true : b->baked_before;
        doc_.region = forward ? b->region_after : b->region_before;
        doc_.scene.motion = forward ? b->motion_after : b->motion_before;
        drop_held();  // new base positions: nothing of the last run stays on show
        drop_deformation();
        rest_.reset();
        diagonal_ = bounding_box(doc_.file.mesh.positions).diagonal();
        base_moved_stats();
        changed(base_moved);
        region_changed();
        curve_changed();
        set_target(forward ? 0.0 : b->time);
    }
}

bool EditorSession::undo() {
    end_region_gesture("");
    end_curve_gesture("");
    const HistoryEntry* entry = history_.undo();
    if (!entry) return false;
    apply_edit(entry->edit, false);
    return true;
}

bool EditorSession::redo() {
    const HistoryEntry* entry = history_.redo();
    if (!entry) return false;
    apply_edit(entry->edit, true);
    return true;
}

}  // namespace vfsd::editor
