#include "deform/cpu_steps.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/error.h"
#include "base/parallel.h"
#include "deform/step_error.h"
#include "field/stream_gauge.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"
#include "mesh/vertex_order.h"

namespace vfsd {

CpuSteps::CpuSteps(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                   DeformationOptions options)
    : positions_(std::move(positions)),
      rings_(std::move(rings)),
      region_(std::move(region)),
      motion_(std::move(motion)),
      options_(options) {
    if (!region_.sphere_tool) {
        if (region_.s.size() != positions_.size())
            throw InputError("region: " + std::to_string(region_.s.size()) + " values of s for " +
                             std::to_string(positions_.size()) + " vertices");
        if (rings_.vertex_count() != positions_.size()) throw InputError("rings do not match the mesh");
    }
    if (!region_.sphere_tool) {
        frame_ = LocalFrame::of(positions_);
        input_order_ = positions_;
        for (Vec3& p : positions_) p = frame_.to_local(p);
        order_ = breadth_first_order(rings_);
        positions_ = gather_in_order(positions_, order_);
        rings_ = reorder_rings(rings_, order_);
        s_ = gather_in_order(region_.s, order_);
        parts_ = RegionParts::of(s_, rings_);
        gauge_samples_ = gauge_samples(s_, parts_.blend);
        size_ = centred_diameter(positions_);
    }
    normals_.assign(positions_.size(), Vec3(0.0));
    gradients_.assign(positions_.size(), Vec3(0.0));
    next_ = positions_;
    midpoints_ = positions_;
}

StepResult CpuSteps::step(double time, double h, int step, double max_error) {
    build_keepers();
    StepResult result;
    StepMotion motion = StepMotion::sample(motion_, time, h);
    for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) *m = frame_.to_local(*m);
    if (region_.sphere_tool) {
        next_ = positions_;
        deformation_step(motion, *region_.sphere_tool, next_);
        check_finite(next_, step, time);
    } else {
        // The gauge, like ∇r, is taken where the step's middle is, so that a step
        // back retraces the step; the midpoints are predicted with the last step's
        // ∇r and gauge fit, as sec. 5 with midpoint gradients does for ∇r alone.
        if (!options_.gradients_at_midpoint || !have_gradients_) estimate_at_start(time);
        if (options_.gradients_at_midpoint) {
            StepMotion half = StepMotion::sample(motion_, time, 0.5 * h);
            for (MotionSample* m : {&half.start, &half.middle, &half.end}) {
                *m = frame_.to_local(*m);
                if (options_.fit_stream_gauge) m->gauge = gauge_fit_->gauge_for(*m);
            }
            predict_midpoints(half, s_, parts_, gradients_, positions_, midpoints_);
            sample_gradients_.clear();
            for (const std::uint32_t v : gauge_samples_) sample_gradients_.push_back(gradients_[v]);
            const double span = std::abs(time + 0.5 * h - gradient_time_);
            estimate_surface_gradients(midpoints_);
            gradient_time_ = time + 0.5 * h;
            if (options_.fit_stream_gauge) gauge_fit_ = fit_stream_gauge(midpoints_);
            if (options_.fit_stream_gauge) motion.middle.gauge = gauge_fit_->gauge_for(motion.middle);
            if (std::isfinite(max_error)) {  // only the step control asks (its estimate costs ~0.1 ms)
                result.error = std::max(estimate_error(motion.middle, h, span), motion_error(motion, half, time, h));
                // Not taken: the next try predicts its midpoints with the ∇r and the
                // gauge found here, as a step does with its predecessor's.
                if (result.error > max_error) return {false, result.error};
            }
        }
        if (options_.fit_stream_gauge)
            for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) m->gauge = gauge_fit_->gauge_for(*m);
        deformation_step(motion, s_, parts_, gradients_, positions_, next_);
        check_finite(next_, step, time);
    }
    positions_.swap(next_);
    // The volume drift is undone after every step, while it is small and smooth
    // (restoring it every few steps folded thin features); it is then part of
    // the step's map, and a step back undoes it as well.
    if (!region_.sphere_tool) volume_restored_ += std::abs(volume_.restore(positions_, area_vectors_));
    // Then the fold repair, which sees what the keeper's move folded too (a
    // needle's corner pushed across its base). A repair moves vertices up to an
    // edge: the keeper's ∂V/∂x from the step's midpoint no longer describes
    // their rings, so it takes them where they are, before each of its Newton
    // steps; what those fold in turn is repaired again, up to kRepairCycles times.
    const bool affine_test = FoldRepair::affine_test_due(time, time + h);
    for (int cycle = 0; cycle < FoldRepair::kRepairCycles; ++cycle) {
        fold_repair_.repair(positions_, rings_, affine_test && cycle == 0, cycle == 0);
        if (!fold_repair_.acted() || !volume_.active()) break;
        for (int k = 0; k < VolumeKeeper::kStepsAfterRepair; ++k) {
            ring_area_vectors(positions_, rings_, parts_.blend, area_vectors_);
            volume_restored_ += std::abs(volume_.restore(positions_, area_vectors_));
        }
    }
    input_order_current_ = false;
    return result;
}

// RK4's error on the rigid motion over the step (rigid_step_error) within the
// mesh's size of c(t), relative to that size.
double CpuSteps::motion_error(const StepMotion& full, const StepMotion& first_half, double time, double h) const {
    StepMotion second_half = StepMotion::sample(motion_, time + 0.5 * h, 0.5 * h);
    for (MotionSample* m : {&second_half.start, &second_half.middle, &second_half.end}) *m = frame_.to_local(*m);
    return rigid_step_error(full, first_half, second_half, size_) / size_;
}

// The step's estimated error, relative to the mesh's size (centred_diameter): how far the step would
// move a vertex differently had ∇r been taken where the predictor's was (at
// gradient_time_ before this step, `span` from the step's middle), scaled to
// that difference over half the step. Like the error of taking ∇r at the
// step's start (sec. 5, first order), it grows as h²; the midpoint ∇r the
// step takes is second order and errs less (docs/method.md, "Error-controlled
// steps"). Taken at the gauge's samples, spread over the blend region: the
// GPU reads those back anyway, and estimates as this does.
double CpuSteps::estimate_error(const MotionSample& middle, double h, double span) const {
    return sampled_step_error(middle, h, span, gauge_samples_.size(),
                              [&](std::size_t j) {
                                  const std::uint32_t v = gauge_samples_[j];
                                  return StepErrorSample{midpoints_[v], s_[v], sample_gradients_[j], gradients_[v]};
                              }) /
           size_;
}

const std::vector<Vec3>& CpuSteps::positions() const {
    if (order_.empty()) return positions_;
    if (!input_order_current_) {
        // The outer region does not move: input_order_ keeps its input positions.
        for (const auto* part : {&parts_.inner, &parts_.blend})
            for (const std::uint32_t v : *part) input_order_[order_[v]] = frame_.to_world(positions_[v]);
        input_order_current_ = true;
    }
    return input_order_;
}

// One piece of the work per call (the keepers, then the estimates), so that
// each can have a frame of its own.
bool CpuSteps::prepare_first_step() {
    if (build_keepers()) return true;
    if (region_.sphere_tool || have_gradients_ || !options_.gradients_at_midpoint) return false;
    estimate_at_start(0.0);
    return true;
}

// The volume keeper and the fold repair take the rest positions: built before
// the first step, by it or by prepare_first_step (so that the editors' frame
// that prepares the deformation does not also pay for these). True if built now.
bool CpuSteps::build_keepers() {
    if (keepers_built_ || region_.sphere_tool) return false;
    keepers_built_ = true;
    if (options_.keep_volume) volume_ = VolumeKeeper(positions_, s_, rings_, parts_.blend);
    if (options_.repair_folds) fold_repair_ = FoldRepair(positions_, s_, rings_, order_);
    return options_.keep_volume || options_.repair_folds;
}

// ∇r and the gauge's fit at the step's start, `time`.
void CpuSteps::estimate_at_start(double time) {
    estimate_surface_gradients(positions_);
    gradient_time_ = time;
    if (options_.fit_stream_gauge) gauge_fit_ = fit_stream_gauge(positions_);
}

// The stream gauge's fit to the blend region at `at` with the current ∇r.
GaugeFit CpuSteps::fit_stream_gauge(const std::vector<Vec3>& at) const {
    std::vector<GaugeSample> samples;
    for (const std::uint32_t v : gauge_samples_) samples.push_back(gauge_sample(at[v], s_[v], gradients_[v]));
    return GaugeFit(std::move(samples));
}

FoldRepairStats CpuSteps::fold_repairs() const {
    FoldRepairStats stats = fold_repair_.stats();
    stats.max_shift /= frame_.scale;  // in the input's units
    return stats;
}

double CpuSteps::volume_restored_percent() const {
    return volume_.active() && volume_.rest_volume() != 0.0 ? 100.0 * volume_restored_ / std::abs(volume_.rest_volume())
                                                            : 0.0;
}

// Normal, gradient (eq. 6) and smoothing passes on the positions `at`.
void CpuSteps::estimate_surface_gradients(const std::vector<Vec3>& at) {
    estimate_normals(at, rings_, parts_.blend, normals_, area_vectors_);
    estimate_gradients(at, normals_, s_, rings_, parts_.blend, gradients_);
    smooth_gradients(normals_, parts_, options_.smoothing_steps, options_.smoothing_weight, options_.tangent_smoothing,
                     gradients_, smoothing_);
    have_gradients_ = true;
}

namespace {
template <class T>
std::size_t bytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}
}  // namespace

std::size_t CpuSteps::state_bytes() const {
    return bytes(positions_) + bytes(next_) + bytes(midpoints_) + bytes(normals_) + bytes(gradients_) +
           bytes(area_vectors_) + bytes(input_order_) + bytes(smoothing_.gradients) + bytes(smoothing_.next) +
           bytes(smoothing_.normals) + bytes(region_.s) + bytes(s_) + bytes(order_) + bytes(rings_.offsets) +
           bytes(rings_.neighbours) + bytes(rings_.wedge) + bytes(parts_.blend) + bytes(parts_.inner) +
           bytes(parts_.blend_ring_offsets) + bytes(parts_.blend_rings) + fold_repair_.bytes();
}

// Throws NumericalError at the first non-finite position among those the step moved.
void CpuSteps::check_finite(const std::vector<Vec3>& candidate, int step, double time) const {
    const auto check = [&](std::size_t v) {
        const Vec3& p = candidate[v];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) return;
        throw nonfinite_position(order_.empty() ? v : order_[v], step, time);
    };
    if (region_.sphere_tool) {
        for (std::size_t v = 0; v < candidate.size(); ++v) check(v);
        return;
    }
    for (const auto* part : {&parts_.inner, &parts_.blend}) {
        const auto non_finite = parallel_sum(part->size(), [&](std::size_t i) {
            const Vec3& p = candidate[(*part)[i]];
            return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? 0.0 : 1.0;
        });
        if (non_finite > 0.0)  // the first in order, named
            for (const std::uint32_t v : *part) check(v);
    }
}

}  // namespace vfsd
