#include "gpu/gpu_deformation.h"

#include <cmath>
#include <cstdio>
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

// The step of CpuSteps::step, pass for pass. With the paper's steps alone it
// reads nothing back; the stream gauge's fit reads its samples back (two texels
// each) once per step and fits on the CPU, and the fold test reads one texel per
// step; the positions are read back, for the CPU's repair, only after a step
// that folded or one the repair's affine test is due after (every 1/5 in time).
class GpuSteps final : public StepBackend {
public:
    GpuSteps(const std::vector<Vec3>& positions, const VertexRings& rings, const Region& region, InnerMotion motion,
             DeformationOptions options)
        : motion_(std::move(motion)),
          options_(options),
          passes_(checked_size(positions), checked_s(region, positions.size()), rings) {
        if (options_.fit_stream_gauge || options_.keep_volume || options_.repair_folds)
            set_up_ = SetUp{positions, region.s, rings};
        size_ = centred_diameter(positions);
    }

    // The default scheme's set-up, a part a call (set_up_part); the first step
    // does what is left.
    bool prepare_first_step() override { return set_up_part(); }

    const char* name() const override { return "gpu"; }
    bool asynchronous() const override { return true; }
    void finish() const override { glFinish(); }
    std::optional<DeviceVertices> device_vertices() const override {
        return DeviceVertices{&passes_.vertex_texture(), passes_.vertex_origin()};
    }
    FoldRepairStats fold_repairs() const override { return fold_repair_.stats(); }

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
        const StepResult result = t.result;
        try_.reset();
        passes_.commit_step();
        positions_valid_ = false;
        // CpuSteps::step's order: the keeper (in the staged step), then the
        // repair and the keeper's Newton steps where it left the rings, again
        // while the repair acts.
        const bool affine_test = FoldRepair::affine_test_due(time, time + h);
        for (int cycle = 0; cycle < FoldRepair::kRepairCycles; ++cycle) {
            if (!repair_folds(affine_test && cycle == 0, cycle == 0) || !keep_volume_) break;
            for (int k = 0; k < VolumeKeeper::kStepsAfterRepair; ++k) {
                if (k > 0) passes_.estimate_normals(At::positions);  // the area vectors where the last step left them
                passes_.keep_volume();
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
        if (!positions_valid_) positions_ = passes_.read_positions();
        positions_valid_ = true;
        return positions_;
    }

private:
    // What the CPU's default scheme adds to sec. 5, in the CPU's work order
    // (mesh/vertex_order.h) where the order matters: the gauge's samples and the
    // fold repair's rounds. A part per call, so that an editor can give each a
    // frame of its own (on the page each is CPU work in wasm: 8-26 ms at 41k
    // vertices); false once all are done. The keeper's rest volume is measured
    // on the rest positions: no step runs before the last part.
    struct SetUp {
        std::vector<Vec3> positions;
        std::vector<double> s;
        VertexRings rings;
        int part = 0;
    };
    bool set_up_part() {
        if (!set_up_) return false;
        SetUp& up = *set_up_;
        switch (up.part++) {
            case 0:
                order_ = breadth_first_order(up.rings);
                s_ = gather_in_order(up.s, order_);
                if (options_.fit_stream_gauge) {
                    std::vector<std::uint32_t> samples = gauge_samples(s_, blend_vertices(s_));
                    for (std::uint32_t& v : samples) v = order_[v];
                    passes_.set_gauge_samples(samples);
                    for (const std::uint32_t v : samples) sample_s_.push_back(up.s[v]);
                }
                return true;
            case 1:
                if (!options_.repair_folds) return set_up_part();
                rings_ = reorder_rings(up.rings, order_);
                fold_repair_ = FoldRepair(gather_in_order(up.positions, order_), s_, rings_, order_);
                passes_.set_fold_checks(fold_repair_.checks(), order_);
                return true;
            default:
                keep_volume_ = options_.keep_volume && VolumeKeeper::applies_to(up.rings);
                if (keep_volume_) passes_.measure_rest_volume(bounding_box(up.positions).centre());
                set_up_.reset();
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

    // The try of this step, begun now or earlier (prepare_step); one of another
    // step, begun and not taken, is dropped with its staged move.
    Try& try_for(double time, double h, double max_error) {
        if (try_ && try_->time == time && try_->h == h && try_->max_error == max_error) return *try_;
        if (try_ && try_->stage == Stage::move_issued) passes_.discard_step();
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
                if (midpoint)
                    issue_prediction(t);
                else
                    issue_move(t);
                break;
            case Stage::estimate_issued:
                fit_gauge();
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
        passes_.predict_midpoints(half);
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
                                              return StepErrorSample{sample_positions_[j], sample_s_[j],
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
        passes_.stage_step(motion, keep_volume_);
        folds_tested_ = fold_repair_.active() && !FoldRepair::affine_test_due(t.time, t.time + t.h);
        if (folds_tested_) passes_.test_folds();
        t.stage = Stage::move_issued;
    }

    // Normal, gradient (eq. 6) and smoothing passes on the positions or
    // midpoints, and the gauge's samples gathered there for fit_gauge().
    void issue_surface_gradients(At at) {
        passes_.estimate_normals(at);
        passes_.estimate_gradients(at);
        passes_.smooth_gradients(options_.smoothing_steps, options_.smoothing_weight, options_.tangent_smoothing);
        have_gradients_ = true;
        if (options_.fit_stream_gauge) passes_.gather_gauge_samples(at);
    }

    // The gauge's fit to the samples gathered last (CpuSteps::fit_stream_gauge).
    void fit_gauge() {
        if (!options_.fit_stream_gauge) return;
        passes_.read_gathered_samples(sample_positions_, sample_gradients_);
        std::vector<GaugeSample> samples;
        for (std::size_t j = 0; j < sample_positions_.size(); ++j)
            samples.push_back(gauge_sample(sample_positions_[j], sample_s_[j], sample_gradients_[j]));
        gauge_fit_ = GaugeFit(std::move(samples));
    }

    // FoldRepair::repair on the CPU after a step the fold pass found folds in, or
    // one the affine test is due after (it runs on the CPU, on the positions read
    // back); the repaired positions go back up, with their rings' area vectors
    // for the keeper. Returns whether it repaired.
    bool repair_folds(bool affine_test, bool new_step) {
        if (!fold_repair_.active()) return false;
        // The count of the fold test issue_move staged, or of a test now.
        const bool tested = std::exchange(folds_tested_, false);
        if (!affine_test && (tested ? passes_.read_fold_count() : passes_.count_folds()) == 0) return false;
        std::vector<Vec3> work = gather_in_order(positions(), order_);
        fold_repair_.repair(work, rings_, affine_test, new_step);
        if (!fold_repair_.acted()) return false;
        for (std::size_t i = 0; i < order_.size(); ++i) positions_[order_[i]] = work[i];
        passes_.set_positions(positions_);
        passes_.estimate_normals(At::positions);
        return true;
    }

    InnerMotion motion_;
    DeformationOptions options_;
    GpuPasses passes_;
    bool have_gradients_ = false;
    double gradient_time_ = 0.0;  // the time the gradient texture was estimated for
    double size_ = 0.0;           // centred_diameter at rest
    mutable std::vector<Vec3> positions_;
    mutable bool positions_valid_ = false;
    // The default scheme's state; order_, s_ and rings_ in the CPU's work order.
    std::vector<std::uint32_t> order_;
    std::vector<double> s_, sample_s_;
    VertexRings rings_;
    std::vector<Vec3> sample_positions_, sample_gradients_;
    std::optional<GaugeFit> gauge_fit_;
    FoldRepair fold_repair_;
    bool keep_volume_ = false;
    bool folds_tested_ = false;  // the staged step's fold test has been issued and not read
    std::optional<SetUp> set_up_;  // the set-up's parts still to do
    std::optional<Try> try_;
};

}  // namespace

Deformation make_gpu_deformation(const std::vector<Vec3>& positions, const VertexRings& rings, Region region,
                                 InnerMotion motion, DeformationOptions options) {
    check_options(options);
    return Deformation(std::make_unique<GpuSteps>(positions, rings, region, std::move(motion), options), options);
}

Deformation start_gpu_deformation(const PreparedScene& scene) {
    return make_gpu_deformation(scene.file.mesh.positions, scene.rings, scene.region, scene.motion,
                                scene.scene.options);
}

}  // namespace vfsd::gpu
