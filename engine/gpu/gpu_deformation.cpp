#include "gpu/gpu_deformation.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "base/error.h"
#include "deform/step_error.h"
#include "deform/volume_keeper.h"
#include "field/stream_gauge.h"
#include "gpu/gl.h"
#include "gpu/gpu_error.h"
#include "gpu/gpu_passes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_order.h"

namespace vfsd::gpu {
namespace {

const std::vector<double>& checked_s(const Region& region, std::size_t vertex_count) {
    if (region.sphere_tool)
        throw GpuUnavailable(
            "the GPU path takes a surface field s; the implicit sphere tool runs on the CPU "
            "(--backend cpu)");
    if (region.s.size() != vertex_count)
        throw InputError("region: " + std::to_string(region.s.size()) + " values of s for " +
                         std::to_string(vertex_count) + " vertices");
    return region.s;
}

// The GPU's textures hold positions relative to the mesh's centre in float; the
// field's terms grow like |x − c|³, so a mesh much smaller or larger than a unit
// would underflow or lose its digits there. The CPU works in a local frame of
// any size (deform/local_frame.h) and runs those.
const std::vector<Vec3>& checked_size(const std::vector<Vec3>& positions) {
    constexpr double kSmallest = 1e-6, kLargest = 1e6;
    const double diagonal = bounding_box(positions).diagonal();
    if (!positions.empty() && !(diagonal >= kSmallest && diagonal <= kLargest)) {
        char message[200];
        std::snprintf(message, sizeof message,
                      "coordinates too %s for the GPU's float textures: the mesh is %.3g units across, the GPU "
                      "takes %g to %g; the CPU runs it (--backend cpu)",
                      diagonal < kSmallest ? "small" : "large", diagonal, kSmallest, kLargest);
        throw GpuUnavailable(message);
    }
    return positions;
}

// What a deformation sets up at rest for its mesh, region and options: the
// passes' textures and programs, and what the CPU's default scheme adds to sec. 5,
// in the CPU's work order (mesh/vertex_order.h) where the order matters (the
// gauge's samples, the fold repair's rounds), with the fold repair at rest.
struct GpuRest {
    GpuRest(const std::vector<Vec3>& positions, const VertexRings& rings, const Region& region,
            const DeformationOptions& options)
        : positions(positions),
          s(region.s),
          input_rings(rings),
          options(options),
          passes(checked_size(positions), checked_s(region, positions.size()), rings) {}

    // Whether a deformation of this mesh can take the passes (their textures
    // and programs), and whether it can take the rest of the set-up too (the
    // same region and options).
    bool fits_mesh(const std::vector<Vec3>& p, const VertexRings& r) const {
        return p == positions && r.offsets == input_rings.offsets && r.neighbours == input_rings.neighbours &&
               r.wedge == input_rings.wedge;
    }
    bool fits_scheme(const Region& region, const DeformationOptions& o) const {
        return region.s == s && o.fit_stream_gauge == options.fit_stream_gauge &&
               o.keep_volume == options.keep_volume && o.repair_folds == options.repair_folds;
    }
    // The passes kept for a deformation of the same mesh with this region and
    // these options, the set-up beyond them done again.
    void restart(const Region& region, const DeformationOptions& o) {
        s = checked_s(region, positions.size());
        options = o;
        passes.set_region(s);
        parts_done = 0;
        order.clear(), s_in_order.clear(), sample_s.clear();
        rings = {};
        fold_repair = {};
        keep_volume = false;
    }
    // The passes' positions back at rest and ∇r zero: where a deformation that
    // takes the kept passes starts.
    void back_to_rest() {
        passes.set_positions(positions);
        passes.set_gradients(std::vector<Vec3>(positions.size(), Vec3(0.0)));
    }

    std::vector<Vec3> positions;
    std::vector<double> s;
    VertexRings input_rings;
    DeformationOptions options;
    GpuPasses passes;
    int parts_done = 0;  // of the set-up beyond the passes (GpuSteps::set_up_part)
    // order, s_in_order and rings in the CPU's work order.
    std::vector<std::uint32_t> order;
    std::vector<double> s_in_order, sample_s;
    VertexRings rings;
    FoldRepair fold_repair;
    bool keep_volume = false;
};

}  // namespace

struct GpuRestShelf::Kept {
    std::unique_ptr<GpuRest> rest;
};

GpuRestShelf::GpuRestShelf() : kept_(std::make_unique<Kept>()) {}
GpuRestShelf::~GpuRestShelf() = default;
void GpuRestShelf::clear() { kept_->rest.reset(); }

namespace {

// The step of CpuSteps::step, pass for pass. With the paper's steps alone it
// reads nothing back; the stream gauge's fit reads its samples back (two texels
// each) once per step and fits on the CPU, and the fold test reads one texel per
// step the repair is due after (every 1/20 in time); the positions are read
// back, for the CPU's repair, only after such a step that folded or one the
// repair's affine test is due after (every 1/5 in time).
class GpuSteps final : public StepBackend {
public:
    // With a shelf, the set-up a deformation of the same mesh, region and options
    // left there is taken (the passes' positions set back to rest), and this
    // one's is left there when it ends.
    GpuSteps(const std::vector<Vec3>& positions, const VertexRings& rings, const Region& region, InnerMotion motion,
             DeformationOptions options, std::shared_ptr<GpuRestShelf> shelf)
        : motion_(std::move(motion)), options_(options), shelf_(std::move(shelf)) {
        std::unique_ptr<GpuRest>* kept = shelf_ ? &shelf_->kept().rest : nullptr;
        if (kept && *kept && !region.sphere_tool && (*kept)->fits_mesh(positions, rings)) {
            rest_ = std::move(*kept);
            if (!rest_->fits_scheme(region, options)) rest_->restart(region, options);  // a region edit
            rest_->back_to_rest();  // fits_mesh: its positions are these
        } else {
            rest_ = std::make_unique<GpuRest>(positions, rings, region, options);
        }
        if (set_up_done()) fold_repair_ = rest_->fold_repair;
        size_ = centred_diameter(positions);
    }
    ~GpuSteps() override {
        if (!shelf_) return;
        try_.reset();
        shelf_->kept().rest = std::move(rest_);
    }
    GpuSteps(const GpuSteps&) = delete;
    GpuSteps& operator=(const GpuSteps&) = delete;

    // The default scheme's set-up, a part a call (set_up_part); the first step
    // does what is left.
    bool prepare_first_step() override { return set_up_part(); }

    const char* name() const override { return "gpu"; }
    bool asynchronous() const override { return true; }
    void finish() const override { glFinish(); }
    std::optional<DeviceVertices> device_vertices() const override {
        return DeviceVertices{&passes().vertex_texture(), passes().vertex_origin()};
    }
    FoldRepairStats fold_repairs() const override { return fold_repair_.stats(); }
    void release_scratch() override { fold_repair_.release_scratch(); }

    // Back to where the constructor leaves a deformation that takes a kept
    // set-up (the same steps as a fresh one's, bit for bit): the rest positions,
    // ∇r zero, and this run's state dropped.
    bool restarts() const override { return set_up_done(); }
    void restart() override {
        if (try_ && try_->stage == Stage::move_issued) passes().discard_step();
        try_.reset();
        rest_->back_to_rest();
        have_gradients_ = false;
        gradient_time_ = 0.0;
        positions_valid_ = false;
        sample_positions_.clear();
        sample_gradients_.clear();
        gauge_fit_.reset();
        fold_repair_ = rest_->fold_repair;
        folds_tested_ = false;
    }

    // With the stream gauge's fit, whose samples it reads back anyway, the step
    // estimates its error as the CPU's does (CpuSteps::estimate_error).
    bool estimates_error() const override { return options_.fit_stream_gauge && options_.gradients_at_midpoint; }
    std::vector<double> motion_joins() const override { return motion_.joins(); }

    StepResult step(double time, double h, int, double max_error) override {
        while (set_up_part()) {
        }
        Try& t = try_for(time, h, max_error);
        while (t.stage != Stage::move_issued) {
            run_stage(t);
            if (!t.result.taken) return std::exchange(try_, std::nullopt)->result;
        }
        StepResult result = t.result;
        try_.reset();
        // CpuSteps::step's order: the keeper (in the staged step), then, at the
        // repair's times, the landing of a controlled step that passed one and
        // folded, or the repair and the keeper's Newton steps where it left the
        // rings, again while the repair acts.
        bool due = FoldRepair::repair_due(time, time + h);
        const bool affine_test = due && FoldRepair::affine_test_due(time, time + h);
        const double land_at = due && std::isfinite(max_error) ? FoldRepair::repair_time_within(time, time + h) : -1.0;
        if (land_at > 0.0) {
            const bool affine_at_land = FoldRepair::affine_test_due(time, land_at);
            if (staged_folds(affine_at_land) > 0) {
                passes().discard_step();
                folds_tested_ = false;
                return {false, result.error, false, land_at};
            }
            if (affine_at_land || !affine_test) due = false;  // tested as the repair would: nothing folded
        }
        passes().commit_step();
        positions_valid_ = false;
        if (!due) {
            folds_tested_ = false;
            return result;
        }
        for (int cycle = 0; cycle < FoldRepair::kRepairCycles; ++cycle) {
            const bool repaired = repair_folds(affine_test && cycle == 0, cycle == 0);
            if (cycle == 0 && repaired && std::isfinite(max_error))
                result.land_at = FoldRepair::next_repair_time(time + h);
            if (!repaired || !rest_->keep_volume) break;
            for (int k = 0; k < VolumeKeeper::kStepsAfterRepair; ++k) {
                if (k > 0) passes().estimate_normals(At::positions);  // the area vectors where the last step left them
                passes().keep_volume();
            }
            positions_valid_ = false;
        }
        return result;
    }

    // The step's pieces, a stage each (run_stage), each ending with the passes it
    // issued and a fence; a piece whose fence the GPU has not passed yet waits
    // for nothing and does nothing. So the caller's thread never waits for the
    // GPU within a piece: on a software renderer (a page on SwiftShader) its
    // passes take tens of milliseconds a step.
    std::optional<StepResult> prepare_step(double time, double h, int, double max_error) override {
        if (set_up_part()) return StepResult{};
        Try& t = try_for(time, h, max_error);
        if (!t.fence.signaled()) {
            StepResult waiting = t.result;
            waiting.waiting = true;
            return waiting;
        }
        if (t.stage == Stage::move_issued) return std::nullopt;  // step() ends it
        run_stage(t);
        if (!t.result.taken) return std::exchange(try_, std::nullopt)->result;
        return t.result;
    }

    const std::vector<Vec3>& positions() const override {
        if (!positions_valid_) positions_ = passes().read_positions();
        positions_valid_ = true;
        return positions_;
    }

private:
    // The set-up beyond the passes (GpuRest), a part per call, so that an editor
    // can give each a frame of its own (on the page each is CPU work in wasm:
    // 8-26 ms at 41k vertices, the fold repair's whole before it took parts);
    // false once all are done. The keeper's rest volume
    // is measured on the rest positions: no step runs before the last part.
    static constexpr int kSetUpParts = 3;
    bool set_up_done() const {
        return rest_->parts_done == kSetUpParts ||
               !(options_.fit_stream_gauge || options_.keep_volume || options_.repair_folds);
    }
    bool set_up_part() {
        if (set_up_done()) return false;
        GpuRest& r = *rest_;
        switch (r.parts_done++) {
            case 0:
                r.order = breadth_first_order(r.input_rings);
                r.s_in_order = gather_in_order(r.s, r.order);
                if (options_.fit_stream_gauge) {
                    std::vector<std::uint32_t> samples = gauge_samples(r.s_in_order, blend_vertices(r.s_in_order));
                    for (std::uint32_t& v : samples) v = r.order[v];
                    r.passes.set_gauge_samples(samples);
                    for (const std::uint32_t v : samples) r.sample_s.push_back(r.s[v]);
                }
                return true;
            case 1:  // the fold repair, a part per call (FoldRepair::InParts)
                if (!options_.repair_folds) return set_up_part();
                if (r.fold_repair.built()) {  // none begun yet: restart() leaves the empty one, which is built
                    r.rings = reorder_rings(r.input_rings, r.order);
                    r.fold_repair = FoldRepair(gather_in_order(r.positions, r.order), r.s_in_order, r.rings, r.order,
                                               FoldRepair::InParts{});
                } else {
                    r.fold_repair.build_part(r.rings);
                }
                if (r.fold_repair.built())
                    r.passes.set_fold_checks(r.fold_repair.checks(), r.order);
                else
                    --r.parts_done;  // this part again
                return true;
            default:
                r.keep_volume = options_.keep_volume && VolumeKeeper::applies_to(r.input_rings);
                if (r.keep_volume) r.passes.measure_rest_volume(bounding_box(r.positions).centre());
                fold_repair_ = r.fold_repair;
                return true;
        }
    }

    // A try of the step from `time` by `h` (CpuSteps::step's work, in stages):
    // ∇r at the start where needed (and the gauge's samples gathered there),
    // then fitted; the midpoints predicted and ∇r there; then fitted, the error
    // estimated, and the move staged (the deformation pass, the volume keeper
    // and the fold test). step() commits it and repairs.
    enum class Stage { begin, start_issued, estimate_issued, move_issued };
    struct Try {
        double time = 0.0, h = 0.0, max_error = 0.0;
        Stage stage = Stage::begin;
        Fence fence;  // after the stage's passes
        StepResult result;
        std::vector<Vec3> predicted_gradients;  // at the gauge's samples, those the midpoints were predicted with
        double span = 0.0;                      // the time from those to the step's middle
    };

    // The try of this step, begun now or earlier (prepare_step). One of another
    // step, begun and not taken, is dropped with its staged move; the ∇r it
    // estimated stays, as a rejected try's does, and so the gauge's fit to it
    // is read (else the next try would predict with a gauge of other ∇r, or,
    // at the first step, with none).
    Try& try_for(double time, double h, double max_error) {
        if (try_ && try_->time == time && try_->h == h && try_->max_error == max_error) return *try_;
        if (try_ && try_->stage == Stage::move_issued) passes().discard_step();
        if (try_ && (try_->stage == Stage::start_issued || try_->stage == Stage::estimate_issued)) {
            fit_gauge();
            issue_keeper_rate(try_->stage == Stage::start_issued ? At::positions : At::midpoints);
        }
        try_.emplace();
        try_->time = time, try_->h = h, try_->max_error = max_error;
        return *try_;
    }

    // The try's next stage: reads back what the last one gathered (waiting for
    // the GPU when its fence has not passed) and issues the next passes.
    void run_stage(Try& t) {
        const bool midpoint = options_.gradients_at_midpoint;
        switch (t.stage) {
            case Stage::begin:
                if (!midpoint || !have_gradients_) {
                    issue_surface_gradients(At::positions);
                    gradient_time_ = t.time;
                    t.stage = Stage::start_issued;
                } else {
                    issue_prediction(t);
                }
                break;
            case Stage::start_issued:
                fit_gauge();
                issue_keeper_rate(At::positions);
                if (midpoint)
                    issue_prediction(t);
                else
                    issue_move(t);
                break;
            case Stage::estimate_issued:
                fit_gauge();
                issue_keeper_rate(At::midpoints);
                t.result = estimate_error(t);
                if (!t.result.taken) return;
                issue_move(t);
                break;
            case Stage::move_issued: return;
        }
        t.fence = Fence::issue();
    }

    // The midpoints predicted over half the step with the current ∇r and gauge,
    // and ∇r there.
    void issue_prediction(Try& t) {
        StepMotion half = StepMotion::sample(motion_, t.time, 0.5 * t.h);
        if (options_.fit_stream_gauge)
            for (MotionSample* m : {&half.start, &half.middle, &half.end}) m->gauge = gauge_fit_->gauge_for(*m);
        passes().predict_midpoints(half);
        t.predicted_gradients = sample_gradients_;
        t.span = std::abs(t.time + 0.5 * t.h - gradient_time_);
        issue_surface_gradients(At::midpoints);
        gradient_time_ = t.time + 0.5 * t.h;
        t.stage = Stage::estimate_issued;
    }

    // The step's estimated error (CpuSteps::estimate_error and motion_error), with
    // the gauge just fitted at its middle; not taken when over the try's bound.
    StepResult estimate_error(const Try& t) const {
        if (!estimates_error() || !std::isfinite(t.max_error)) return {};
        StepMotion motion = StepMotion::sample(motion_, t.time, t.h);
        motion.middle.gauge = gauge_fit_->gauge_for(motion.middle);
        double error = sampled_step_error(motion.middle, t.h, t.span, sample_positions_.size(),
                                          [&](std::size_t j) {
                                              return StepErrorSample{sample_positions_[j], rest_->sample_s[j],
                                                                     t.predicted_gradients[j], sample_gradients_[j]};
                                          }) /
                       size_;
        const StepMotion half = StepMotion::sample(motion_, t.time, 0.5 * t.h);
        const StepMotion second_half = StepMotion::sample(motion_, t.time + 0.5 * t.h, 0.5 * t.h);
        error = std::max(error, rigid_step_error(motion, half, second_half, size_) / size_);
        return {!(error > t.max_error), error};
    }

    // The deformation pass and the volume keeper, staged, and the fold test on
    // their result where step() will ask for its count.
    void issue_move(Try& t) {
        StepMotion motion = StepMotion::sample(motion_, t.time, t.h);
        if (options_.fit_stream_gauge)
            for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) m->gauge = gauge_fit_->gauge_for(*m);
        passes().stage_step(motion, rest_->keep_volume);
        folds_tested_ = fold_repair_.active() && FoldRepair::repair_due(t.time, t.time + t.h) &&
                        !FoldRepair::affine_test_due(t.time, t.time + t.h);
        if (folds_tested_) passes().test_folds();
        t.stage = Stage::move_issued;
    }

    // Normal, gradient (eq. 6) and smoothing passes on the positions or
    // midpoints, and the gauge's samples gathered there for fit_gauge().
    void issue_surface_gradients(At at) {
        passes().estimate_normals(at);
        passes().estimate_gradients(at);
        passes().smooth_gradients(options_.smoothing_steps, options_.smoothing_weight, options_.tangent_smoothing);
        have_gradients_ = true;
        if (options_.fit_stream_gauge) passes().gather_gauge_samples(at);
    }

    // The keeper's velocity where ∇r was just estimated (CpuSteps::estimate_keeper_velocity).
    void issue_keeper_rate(At at) {
        if (!rest_->keep_volume) return;
        MotionSample sample = motion_.at(gradient_time_);
        if (options_.fit_stream_gauge) sample.gauge = gauge_fit_->gauge_for(sample);
        passes().keeper_rate(at, sample);
    }

    // The gauge's fit to the samples gathered last (CpuSteps::fit_stream_gauge).
    void fit_gauge() {
        if (!options_.fit_stream_gauge) return;
        passes().read_gathered_samples(sample_positions_, sample_gradients_);
        std::vector<GaugeSample> samples;
        for (std::size_t j = 0; j < sample_positions_.size(); ++j)
            samples.push_back(gauge_sample(sample_positions_[j], rest_->sample_s[j], sample_gradients_[j]));
        gauge_fit_ = GaugeFit(std::move(samples));
    }

    // The folds in the staged step's positions: the fold pass's count (the one
    // issue_move staged, or a test now), and with `affine_test` the CPU's tests
    // on the positions read back (FoldRepair::count_folds).
    std::size_t staged_folds(bool affine_test) {
        if (!fold_repair_.active()) return 0;
        if (!affine_test) return folds_tested_ ? passes().read_fold_count() : passes().count_folds();
        const std::vector<Vec3> staged = gather_in_order(passes().read_staged_positions(), rest_->order);
        return fold_repair_.count_folds(staged, rest_->rings, true);
    }

    // FoldRepair::repair on the CPU after a step the fold pass found folds in, or
    // one the affine test is due after (it runs on the CPU, on the positions read
    // back); the repaired positions go back up, with their rings' area vectors
    // for the keeper. Returns whether it repaired.
    bool repair_folds(bool affine_test, bool new_step) {
        if (!fold_repair_.active()) return false;
        // The count of the fold test issue_move staged, or of a test now.
        const bool tested = std::exchange(folds_tested_, false);
        if (!affine_test && (tested ? passes().read_fold_count() : passes().count_folds()) == 0) return false;
        std::vector<Vec3> work = gather_in_order(positions(), rest_->order);
        fold_repair_.repair(work, rest_->rings, affine_test, new_step);
        if (!fold_repair_.acted()) return false;
        for (std::size_t i = 0; i < rest_->order.size(); ++i) positions_[rest_->order[i]] = work[i];
        passes().set_positions(positions_);
        passes().estimate_normals(At::positions);
        return true;
    }

    GpuPasses& passes() const { return rest_->passes; }

    InnerMotion motion_;
    DeformationOptions options_;
    std::shared_ptr<GpuRestShelf> shelf_;
    std::unique_ptr<GpuRest> rest_;
    bool have_gradients_ = false;
    double gradient_time_ = 0.0;  // the time the gradient texture was estimated for
    double size_ = 0.0;           // centred_diameter at rest
    mutable std::vector<Vec3> positions_;
    mutable bool positions_valid_ = false;
    // The default scheme's state in this run.
    std::vector<Vec3> sample_positions_, sample_gradients_;
    std::optional<GaugeFit> gauge_fit_;
    FoldRepair fold_repair_;
    bool folds_tested_ = false;  // the staged step's fold test has been issued and not read
    std::optional<Try> try_;
};

}  // namespace

Deformation make_gpu_deformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region,
                                 InnerMotion motion, DeformationOptions options, std::shared_ptr<GpuRestShelf> shelf) {
    check_options(options);
    return Deformation(
        std::make_unique<GpuSteps>(positions, rings, region, std::move(motion), options, std::move(shelf)), options);
}

Deformation start_gpu_deformation(const PreparedScene& scene, std::shared_ptr<GpuRestShelf> shelf) {
    return make_gpu_deformation(scene.file.mesh.positions, scene.rings, scene.region, scene.motion, scene.scene.options,
                                std::move(shelf));
}

}  // namespace vfsd::gpu
