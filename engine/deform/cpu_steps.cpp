#include "deform/cpu_steps.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/error.h"
#include "base/parallel.h"
#include "deform/step_error.h"
#include "field/stream_gauge.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"
#include "mesh/vertex_order.h"

namespace vfsd {
namespace {

// A hash of the rings' vertex lists (FNV-1a), to tell meshes apart cheaply.
std::uint64_t hash_rings(const VertexRings& rings) {
    std::uint64_t hash = 1469598103934665603ull;
    const auto add = [&](std::uint32_t x) { hash = (hash ^ x) * 1099511628211ull; };
    for (const std::uint32_t x : rings.offsets) add(x);
    for (const std::uint32_t x : rings.neighbours) add(x);
    return hash;
}

}  // namespace

// The steps of two deformations are the same from the same rest state when these agree.
bool CpuRest::fits(const std::vector<Vec3>& positions, const VertexRings& input_rings, const Region& region,
                   const DeformationOptions& other) const {
    const DeformationOptions& o = options;
    if (region.sphere_tool || region.s.size() != positions.size() || positions != input_positions) return false;
    if (o.smoothing_steps != other.smoothing_steps || o.smoothing_weight != other.smoothing_weight ||
        o.gradients_at_midpoint != other.gradients_at_midpoint || o.fit_stream_gauge != other.fit_stream_gauge ||
        o.tangent_smoothing != other.tangent_smoothing || o.keep_volume != other.keep_volume ||
        o.repair_folds != other.repair_folds)
        return false;
    for (std::size_t i = 0; i < order.size(); ++i)
        if (s[i] != region.s[order[i]]) return false;
    return hash_rings(input_rings) == rings_hash;
}

CpuSteps::CpuSteps(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                   DeformationOptions options)
    : region_(std::move(region)), motion_(std::move(motion)), options_(options) {
    if (region_.sphere_tool) {
        positions_ = std::move(positions);
    } else {
        if (region_.s.size() != positions.size())
            throw InputError("region: " + std::to_string(region_.s.size()) + " values of s for " +
                             std::to_string(positions.size()) + " vertices");
        if (rings.vertex_count() != positions.size()) throw InputError("rings do not match the mesh");
        auto rest = std::make_shared<CpuRest>();
        rest->rings_hash = hash_rings(rings);
        rest->options = options;
        rest->frame = LocalFrame::of(positions);
        rest->input_positions = std::move(positions);
        rest->order = breadth_first_order(rings);
        rest->positions = gather_in_order(rest->input_positions, rest->order);
        for (Vec3& p : rest->positions) p = rest->frame.to_local(p);
        rest->rings = reorder_rings(rings, rest->order);
        rest->s = gather_in_order(region_.s, rest->order);
        rest->parts = RegionParts::of(rest->s, rest->rings);
        rest->gauge_samples = gauge_samples(rest->s, rest->parts.blend);
        for (const std::uint32_t v : rest->gauge_samples)
            rest->gauge_in_blend.push_back(static_cast<std::uint32_t>(
                std::lower_bound(rest->parts.blend.begin(), rest->parts.blend.end(), v) - rest->parts.blend.begin()));
        rest->size = centred_diameter(rest->positions);
        region_.s.clear();
        building_ = rest;
        rest_ = std::move(rest);
    }
    start_from_rest();
}

CpuSteps::CpuSteps(std::shared_ptr<const CpuRest> rest, InnerMotion motion, DeformationOptions options)
    : rest_(std::move(rest)), motion_(std::move(motion)), options_(options) {
    if (!rest_ || !rest_->keepers_built) throw std::invalid_argument("CpuSteps: a rest state not yet built");
    start_from_rest();
}

// The work arrays at t = 0, from rest_ and as far as it is built.
void CpuSteps::start_from_rest() {
    if (rest_) {
        frame_ = rest_->frame;
        positions_ = rest_->positions;
        input_order_ = rest_->input_positions;
    }
    normals_.assign(positions_.size(), Vec3(0.0));
    gradients_.assign(rest_ ? rest_->parts.blend.size() : 0, Float4{});
    next_ = positions_;
    midpoints_ = positions_;
    if (!rest_) return;
    if (rest_->keepers_built) fold_repair_ = rest_->fold_repair;
    if (rest_->estimated) {
        const std::vector<std::uint32_t>& blend = rest_->parts.blend;
        for (std::size_t i = 0; i < blend.size(); ++i) normals_[blend[i]] = rest_->normals[i];
        gradients_ = rest_->gradients;
        area_vectors_ = rest_->area_vectors;
        gauge_fit_ = rest_->gauge_fit;
        have_gradients_ = true;
        gradient_time_ = 0.0;
        estimate_keeper_velocity(positions_, sample_at(0.0));  // the motion's own
    }
}

// As a deformation from the rest state starts (the constructor above), once
// the first step has built it (with midpoint gradients, estimated ∇r at rest);
// the sphere tool, whose region moves with the positions, has none.
bool CpuSteps::restarts() const {
    return rest_ && !region_.sphere_tool && (rest_->estimated || !options_.gradients_at_midpoint);
}

void CpuSteps::restart() {
    prepared_.reset();
    input_order_current_ = false;
    start_from_rest();
}

// A copy of every member: the rest state shared, the work arrays copied (the
// outer positions in next_ and midpoints_ with them), the scratch that no step
// reads before it writes (the fold repair's sums, the smoothing's) left out.
std::unique_ptr<StepBackend> CpuSteps::snapshot() const {
    auto copy = std::make_unique<CpuSteps>(*this);
    copy->release_scratch();
    copy->smoothing_ = SmoothingScratch();
    return copy;
}

void CpuSteps::restore(const StepBackend& snapshot) {
    *this = dynamic_cast<const CpuSteps&>(snapshot);  // the arrays keep their capacity
}

std::shared_ptr<const CpuRest> CpuSteps::cpu_rest() const {
    if (!rest_ || !rest_->keepers_built || (options_.gradients_at_midpoint && !rest_->estimated)) return nullptr;
    return rest_;
}

StepResult CpuSteps::step(double time, double h, int step, double max_error) {
    build_keepers();
    StepResult result;
    std::optional<PreparedTry> piece;
    if (prepared_for(time, h, max_error)) piece = prepared_;
    prepared_.reset();
    if (!region_.sphere_tool) {
        result = piece ? piece->estimate : estimate_try(time, h, max_error);
        if (!result.taken) return result;
    }
    if (!(piece && piece->moved)) move(time, h, step);
    if (region_.sphere_tool) {  // the sphere tool has neither a volume keeper nor a fold repair
        positions_.swap(next_);
        input_order_current_ = false;
        return result;
    }
    const FoldTest test = piece && piece->tested ? piece->test : settle_move(time, h, max_error, false);
    if (test.verdict == FoldTest::land) return {false, result.error, false, test.land_at};
    positions_.swap(next_);
    input_order_current_ = false;
    if (test.verdict == FoldTest::repair) repair_folds(time, h, max_error, test.measured, result);
    return result;
}

// What follows the move in next_, before the step is taken: what the step left
// of the volume drift undone after it, while it is small (restoring it every few
// steps folded thin features; it is then part of the step's map, and a step back
// undoes it as well), and at the fold repair's times the test the repair acts
// on, which sees what the keeper's move folded too (a needle's corner pushed
// across its base). An error-controlled step that passed the repair's time and
// folded is tried again to end there (land): nothing moves. One that did not
// fold needs no repair (clean). With `test_all`, a step that ends where the
// repair acts is tested too, and needs it only where a triangle is short of the
// lift's target (repair() then does nothing else: the same bits), and the
// repair's lift starts from that test's measures; without, it is left to
// repair()'s own test.
CpuSteps::FoldTest CpuSteps::settle_move(double time, double h, double max_error, bool test_all) {
    FoldTest test;
    rest_->volume.restore(next_, area_vectors_, area_norm_);
    if (!FoldRepair::repair_due(time, time + h)) return test;
    const bool affine_test = FoldRepair::affine_test_due(time, time + h);
    test.land_at = std::isfinite(max_error) ? FoldRepair::repair_time_within(time, time + h) : -1.0;
    if (test.land_at > 0.0) {
        const bool affine_at_land = FoldRepair::affine_test_due(time, test.land_at);
        // A step that passes the affine test's time only after the landing's is
        // tested by the neighbour test for the landing, then by both for the
        // repair: the neighbour test's measures are kept for the second, which
        // adds the affine test's alone.
        const bool affine_after = affine_test && !affine_at_land;
        if (fold_repair_.count_folds(next_, rest_->rings, affine_at_land, affine_after) > 0) {
            test.verdict = FoldTest::land;
            return test;
        }
        if (!affine_after) return test;  // tested as the repair would: nothing folded
        test.measured = fold_repair_.count_folds_with_affine(next_, rest_->rings) > 0;
        if (test.measured) test.verdict = FoldTest::repair;
        return test;
    }
    test.verdict = FoldTest::repair;
    if (!test_all) return test;
    test.measured = fold_repair_.count_folds(next_, rest_->rings, affine_test, true) > 0;
    if (!test.measured) test.verdict = FoldTest::clean;
    return test;
}

// The fold repair after a step that passed its time (`measured`: its test's
// measures kept, settle_move). A repair moves vertices up
// to an edge: the keeper's ∂V/∂x from the step's midpoint no longer describes
// their rings, so it takes them where they are, before each of its Newton steps;
// what those fold in turn is repaired again, up to kRepairCycles times.
void CpuSteps::repair_folds(double time, double h, double max_error, bool measured, StepResult& result) {
    const bool affine_test = FoldRepair::affine_test_due(time, time + h);
    for (int cycle = 0; cycle < FoldRepair::kRepairCycles; ++cycle) {
        fold_repair_.repair(positions_, rest_->rings, affine_test && cycle == 0, cycle == 0, measured && cycle == 0);
        if (cycle == 0 && fold_repair_.acted() && std::isfinite(max_error))
            result.land_at = FoldRepair::next_repair_time(time + h);
        if (!fold_repair_.acted() || !rest_->volume.active()) break;
        rest_->volume.restore_after_repair(positions_, rest_->rings, area_vectors_, area_norm_);
    }
}

// The step's RK4 move from positions_ into next_, with the ∇r and gauge estimate_try found.
void CpuSteps::move(double time, double h, int step) {
    StepMotion motion = StepMotion::sample(motion_, time, h);
    for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) *m = frame_.to_local(*m);
    if (region_.sphere_tool) {
        next_ = positions_;
        deformation_step(motion, *region_.sphere_tool, next_);
        check_finite(next_, step, time);
    } else {
        if (options_.fit_stream_gauge)
            for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) m->gauge = gauge_fit_->gauge_for(*m);
        if (deformation_step(motion, rest_->parts, gradients_, positions_, next_, keeper_velocity()) > 0)
            check_finite(next_, step, time);
    }
}

// The first piece of a step: ∇r and the gauge where the step's middle is, and the
// step's estimated error (with a finite `max_error`); not taken when that is over it.
StepResult CpuSteps::estimate_try(double time, double h, double max_error) {
    // The gauge, like ∇r, is taken where the step's middle is, so that a step
    // back retraces the step; the midpoints are predicted with the last step's
    // ∇r and gauge fit, as sec. 5 with midpoint gradients does for ∇r alone.
    if (!options_.gradients_at_midpoint || !have_gradients_) estimate_at_start(time);
    if (!options_.gradients_at_midpoint) return {};
    StepMotion motion = StepMotion::sample(motion_, time, h), half = StepMotion::sample(motion_, time, 0.5 * h);
    for (MotionSample* m : {&motion.start, &motion.middle, &motion.end}) *m = frame_.to_local(*m);
    for (MotionSample* m : {&half.start, &half.middle, &half.end}) {
        *m = frame_.to_local(*m);
        if (options_.fit_stream_gauge) m->gauge = gauge_fit_->gauge_for(*m);
    }
    predict_midpoints(half, rest_->parts, gradients_, positions_, midpoints_, keeper_velocity());
    sample_gradients_.clear();
    for (std::size_t j = 0; j < rest_->gauge_samples.size(); ++j) sample_gradients_.push_back(gradient_at_sample(j));
    const double span = std::abs(time + 0.5 * h - gradient_time_);
    estimate_surface_gradients(midpoints_);
    gradient_time_ = time + 0.5 * h;
    if (options_.fit_stream_gauge) gauge_fit_ = fit_stream_gauge(midpoints_);
    if (options_.fit_stream_gauge) motion.middle.gauge = gauge_fit_->gauge_for(motion.middle);
    estimate_keeper_velocity(midpoints_, motion.middle);
    if (!std::isfinite(max_error)) return {};  // only the step control asks (its estimate costs ~0.1 ms)
    const double error = std::max(estimate_error(motion.middle, h, span), motion_error(motion, half, time, h));
    // Not taken: the next try predicts its midpoints with the ∇r and the gauge
    // found here, as a step does with its predecessor's.
    return {!(error > max_error), error};
}

// step()'s pieces ahead of it, one a call, so that a caller can give each a
// frame of its own: the estimates (estimate_try), then the move (into next_),
// and where the step passes a fold repair's time, the volume keeper's move and
// the fold test (settle_move, in next_; a try that lands on the repair's time
// ends there): with the move where the neighbour test alone is due (a few ms on
// 163k vertices), in a piece of its own where the affine test is too (tens of
// ms). The step() from `time` by `h` then does the rest. A prepared try that no
// step() takes leaves ∇r and the gauge where a rejected one would, and the
// positions as they were.
std::optional<StepResult> CpuSteps::prepare_step(double time, double h, int step, double max_error) {
    if (region_.sphere_tool || !rest_) return std::nullopt;
    build_keepers();
    if (!prepared_for(time, h, max_error)) {
        prepared_ = PreparedTry{time, h, max_error, estimate_try(time, h, max_error), false, false, {}};
        const StepResult estimate = prepared_->estimate;
        if (!estimate.taken) prepared_.reset();  // over: no step() follows
        return estimate;
    }
    const bool test_due = fold_repair_.active() && FoldRepair::repair_due(time, time + h);
    if (!prepared_->moved) {
        move(time, h, step);
        prepared_->moved = true;
        if (!test_due || FoldRepair::affine_test_due(time, time + h)) return prepared_->estimate;
    } else if (prepared_->tested || !test_due) {
        return std::nullopt;
    }
    prepared_->test = settle_move(time, h, max_error, true);
    prepared_->tested = true;
    if (prepared_->test.verdict != FoldTest::land) return prepared_->estimate;
    const StepResult landing{false, prepared_->estimate.error, false, prepared_->test.land_at};
    prepared_.reset();  // tried again to end on the repair's time: no step() follows
    return landing;
}

bool CpuSteps::prepared_for(double time, double h, double max_error) const {
    return prepared_ && prepared_->time == time && prepared_->h == h && prepared_->max_error == max_error;
}

// RK4's error on the rigid motion over the step (rigid_step_error) within the
// mesh's size of c(t), relative to that size.
double CpuSteps::motion_error(const StepMotion& full, const StepMotion& first_half, double time, double h) const {
    StepMotion second_half = StepMotion::sample(motion_, time + 0.5 * h, 0.5 * h);
    for (MotionSample* m : {&second_half.start, &second_half.middle, &second_half.end}) *m = frame_.to_local(*m);
    return rigid_step_error(full, first_half, second_half, rest_->size) / rest_->size;
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
    return sampled_step_error(
               middle, h, span, rest_->gauge_samples.size(),
               [&](std::size_t j) {
                   const std::uint32_t v = rest_->gauge_samples[j];
                   return StepErrorSample{midpoints_[v], rest_->s[v], sample_gradients_[j], gradient_at_sample(j)};
               }) /
           rest_->size;
}

const std::vector<Vec3>& CpuSteps::positions() const {
    if (!rest_) return positions_;
    if (!input_order_current_) {
        // The outer region does not move: input_order_ keeps its input positions.
        for (const auto* part : {&rest_->parts.inner, &rest_->parts.blend})
            for (const std::uint32_t v : *part) input_order_[rest_->order[v]] = frame_.to_world(positions_[v]);
        input_order_current_ = true;
    }
    return input_order_;
}

// One piece of the work per call (the keepers' parts, then the estimates), so
// that each can have a frame of its own.
bool CpuSteps::prepare_first_step() {
    if (build_keeper_part()) return true;
    if (region_.sphere_tool || have_gradients_ || !options_.gradients_at_midpoint) return false;
    estimate_at_start(0.0);
    return true;
}

// The volume keeper and the fold repair take the rest positions: built before
// the first step, by it or part by part by prepare_first_step (so that the
// editors' frame that prepares the deformation does not also pay for these,
// and no frame pays for all of them), into the rest state: the volume keeper
// with the fold repair's first part, then each of the fold repair's further
// parts. True if it built one.
bool CpuSteps::build_keeper_part() {
    if (!rest_ || rest_->keepers_built) return false;
    CpuRest& rest = *building_;
    if (!rest.keepers_begun) {
        rest.keepers_begun = true;
        if (options_.keep_volume) rest.volume = VolumeKeeper(rest.positions, rest.s, rest.rings, rest.parts.blend);
        if (options_.repair_folds)
            rest.fold_repair = FoldRepair(rest.positions, rest.s, rest.rings, rest.order, FoldRepair::InParts{});
    } else {
        rest.fold_repair.build_part(rest.rings);
    }
    if (rest.fold_repair.built()) {
        rest.keepers_built = true;
        fold_repair_ = rest.fold_repair;
    }
    return options_.keep_volume || options_.repair_folds;
}

// ∇r and the gauge's fit at the step's start, `time`; the first, at rest, is
// kept in the rest state (with midpoint gradients, later steps do not estimate
// at their start).
void CpuSteps::estimate_at_start(double time) {
    estimate_surface_gradients(positions_);
    gradient_time_ = time;
    if (options_.fit_stream_gauge) gauge_fit_ = fit_stream_gauge(positions_);
    estimate_keeper_velocity(positions_, sample_at(time));
    if (!building_ || building_->estimated || !options_.gradients_at_midpoint) return;
    CpuRest& rest = *building_;
    rest.estimated = true;
    rest.normals.reserve(rest.parts.blend.size());
    for (const std::uint32_t v : rest.parts.blend)
        rest.normals.push_back(normals_[v]);  // the passes write the blend region's only
    rest.gradients = gradients_;
    rest.area_vectors = area_vectors_;
    rest.gauge_fit = gauge_fit_;
}

// The stream gauge's fit to the blend region at `at` with the current ∇r.
GaugeFit CpuSteps::fit_stream_gauge(const std::vector<Vec3>& at) const {
    std::vector<GaugeSample> samples;
    for (std::size_t j = 0; j < rest_->gauge_samples.size(); ++j) {
        const std::uint32_t v = rest_->gauge_samples[j];
        samples.push_back(gauge_sample(at[v], rest_->s[v], gradient_at_sample(j)));
    }
    return GaugeFit(std::move(samples));
}

// The motion at `time` in the local frame, with the gauge fitted last.
MotionSample CpuSteps::sample_at(double time) const {
    MotionSample sample = frame_.to_local(motion_.at(time));
    if (options_.fit_stream_gauge) sample.gauge = gauge_fit_->gauge_for(sample);
    return sample;
}

// The volume keeper's velocity (deform/volume_keeper.h) with the field at `at`
// for `sample` and the ∇r, gauge and area vectors just estimated there.
void CpuSteps::estimate_keeper_velocity(const std::vector<Vec3>& at, const MotionSample& sample) {
    const VolumeKeeper& keeper = rest_->volume;
    keeper_lambda_ = 0.0;
    area_norm_ = 0.0;
    if (!keeper.active()) return;
    const double flux = blend_flux(sample, rest_->parts, gradients_, at, area_vectors_);
    area_norm_ = keeper.area_norm(area_vectors_);
    keeper_lambda_ = keeper.lambda(keeper.rate(at, flux, sample), area_norm_);
}

// The keeper's velocity for the passes: with the area vectors of the last normal
// pass (or of the fold repair's last move). None where λ is 0, as where a sum
// was not finite: a non-finite area vector is then not spread.
KeeperVelocity CpuSteps::keeper_velocity() const {
    return keeper_lambda_ != 0.0 ? KeeperVelocity{keeper_lambda_, &area_vectors_} : KeeperVelocity{};
}

// ∇r at the gauge's sample j.
Vec3 CpuSteps::gradient_at_sample(std::size_t j) const {
    const Float4& g = gradients_[rest_->gauge_in_blend[j]];
    return Vec3(g[0], g[1], g[2]);
}

FoldRepairStats CpuSteps::fold_repairs() const {
    FoldRepairStats stats = fold_repair_.stats();
    stats.max_shift /= frame_.scale;  // in the input's units
    return stats;
}

// Normal, gradient (eq. 6) and smoothing passes on the positions `at`.
void CpuSteps::estimate_surface_gradients(const std::vector<Vec3>& at) {
    estimate_normals(at, rest_->rings, rest_->parts.blend, normals_, area_vectors_);
    estimate_gradients(at, normals_, rest_->s, rest_->rings, rest_->parts.blend, gradients_);
    smooth_gradients(normals_, rest_->parts, options_.smoothing_steps, options_.smoothing_weight,
                     options_.tangent_smoothing, gradients_, smoothing_);
    have_gradients_ = true;
}

namespace {
template <class T>
std::size_t capacity_bytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}
}  // namespace

std::size_t CpuRest::bytes() const {
    return capacity_bytes(input_positions) + capacity_bytes(order) + capacity_bytes(rings.offsets) +
           capacity_bytes(rings.neighbours) + capacity_bytes(rings.wedge) + capacity_bytes(s) +
           capacity_bytes(positions) + capacity_bytes(parts.blend) + capacity_bytes(parts.inner) +
           capacity_bytes(parts.blend_ring_offsets) + capacity_bytes(parts.blend_rings) +
           capacity_bytes(parts.one_minus_b) + capacity_bytes(parts.b_slope) + capacity_bytes(gauge_samples) +
           capacity_bytes(gauge_in_blend) + fold_repair.bytes() + capacity_bytes(normals) + capacity_bytes(gradients) +
           capacity_bytes(area_vectors);
}

std::size_t CpuSteps::state_bytes() const {
    return capacity_bytes(positions_) + capacity_bytes(next_) + capacity_bytes(midpoints_) + capacity_bytes(normals_) +
           capacity_bytes(gradients_) + capacity_bytes(area_vectors_) + capacity_bytes(input_order_) +
           capacity_bytes(smoothing_.next) + capacity_bytes(smoothing_.normals) + fold_repair_.bytes(false) +
           (rest_ ? rest_->bytes() : 0);
}

std::size_t CpuSteps::snapshot_bytes() const {
    return state_bytes() - (rest_ ? rest_->bytes() : 0) - capacity_bytes(smoothing_.next) -
           capacity_bytes(smoothing_.normals);
}

// Throws NumericalError at the first non-finite position among those the step
// moved (the step counted some: deformation_step).
void CpuSteps::check_finite(const std::vector<Vec3>& candidate, int step, double time) const {
    const auto check = [&](std::size_t v) {
        const Vec3& p = candidate[v];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) return;
        throw nonfinite_position(rest_ ? rest_->order[v] : v, step, time);
    };
    if (region_.sphere_tool) {
        for (std::size_t v = 0; v < candidate.size(); ++v) check(v);
        return;
    }
    for (const auto* part : {&rest_->parts.inner, &rest_->parts.blend})  // the first in order, named
        for (const std::uint32_t v : *part) check(v);
}

}  // namespace vfsd
