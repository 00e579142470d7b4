#include "deform/deformation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "deform/cpu_steps.h"
#include "deform/fold_repair.h"

namespace vfsd {

void check_options(const DeformationOptions& options) {
    if (options.steps < 1) throw InputError("steps must be at least 1");
    if (!(options.tolerance >= 0.0 && options.tolerance <= 0.1))
        throw InputError("tolerance must be 0 (fixed steps) to 0.1 of the mesh's size");
    if (options.smoothing_steps < 0) throw InputError("smoothing_steps must not be negative");
    if (options.fold_refinements < 0 || options.fold_refinements > kMaxFoldRefinements)
        throw InputError("fold_refinement must be 0 to " + std::to_string(kMaxFoldRefinements));
}

DeformationOptions paper_steps(DeformationOptions options) {
    options.fit_stream_gauge = options.keep_volume = options.repair_folds = false;
    options.fold_refinements = 0;
    return options;
}

double next_time_on_grid(double time, double target, int steps) {
    const double n = steps;
    const double k = time * n;
    const double next = target > time ? (std::floor(k + 1e-9) + 1.0) / n : (std::ceil(k - 1e-9) - 1.0) / n;
    return (target > time) == (next > target) ? target : next;
}

double grid_time_at_or_after(double time, int steps) {
    const double n = steps;
    return std::ceil(time * n - 1e-9) / n;
}

double StepControl::next_length(double h, double error, double tolerance) {
    const double factor =
        error > 0.0 ? std::clamp(kSafety * std::sqrt(tolerance / error), kMostShrink, kMostGrowth) : kMostGrowth;
    return std::clamp(std::abs(h) * factor, kShortestStep, kLongestStep);
}

double StepControl::retry_length(double h, double error, double tolerance) {
    const double factor = error > 0.0 ? std::clamp(kSafety * std::sqrt(tolerance / error), kMostShrinkRetry, 0.5) : 0.5;
    return std::max(std::abs(h) * factor, kShortestStep);
}

double StepControl::foreseen_length(double h, double length, double last, double coefficient, double apart,
                                    double tolerance) {
    if (!(coefficient > last && last > 0.0 && apart > 0.0)) return length;
    const double rate = std::log(coefficient / last) / apart;  // per unit time
    const double ahead = coefficient * std::exp(rate * 0.5 * (std::abs(h) + length));
    const double foreseen = kSafety * std::sqrt(tolerance / ahead);
    const double shortest = std::min(length, std::max(kMostShrink * std::abs(h), kShortestStep));
    return std::max(std::min(length, foreseen), shortest);
}

NumericalError nonfinite_position(std::size_t vertex, int step, double time) {
    return NumericalError("integration step " + std::to_string(step) + " (t = " + std::to_string(time) +
                          ") made vertex " + std::to_string(vertex) + " non-finite; the mesh before that step is kept");
}

Deformation::Deformation(std::unique_ptr<StepBackend> backend, DeformationOptions options)
    : backend_(std::move(backend)), options_(options) {
    check_options(options_);
    controlled_ = options_.tolerance > 0.0 && backend_->estimates_error();
    joins_ = backend_->motion_joins();
}

Deformation::Deformation(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                         DeformationOptions options)
    : Deformation(std::make_unique<CpuSteps>(std::move(positions), std::move(rings), std::move(region),
                                             std::move(motion), options),
                  options) {}

Deformation::Deformation(std::shared_ptr<const CpuRest> rest, InnerMotion motion, DeformationOptions options)
    : Deformation(std::make_unique<CpuSteps>(std::move(rest), std::move(motion), options), options) {}

// The time the next step ends at, on the way to `target`; `controlled`: the
// step extends the schedule and its error decides whether it is taken.
double Deformation::next_time(double target, bool& controlled) const {
    controlled = false;
    if (!controlled_) {  // the grid k / steps, each step ending on a join it would cross
        const double next = next_time_on_grid(time_, target, options_.steps);
        const double low = std::min(time_, next), high = std::max(time_, next);
        const auto join = std::upper_bound(joins_.begin(), joins_.end(), low);
        if (join == joins_.end() || *join >= high) return next;
        return next > time_ ? *join : *(std::lower_bound(joins_.begin(), joins_.end(), high) - 1);
    }
    if (target < time_) {  // back, along the times reached
        const auto before = std::lower_bound(grid_.begin(), grid_.end(), time_) - 1;
        return std::max(*before, target);
    }
    const auto after = std::upper_bound(grid_.begin(), grid_.end(), time_);
    if (after != grid_.end()) return std::min(*after, target);
    controlled = true;  // forward from the last time reached: a new step
    const auto join = std::upper_bound(joins_.begin(), joins_.end(), time_ + StepControl::kShortestStep);
    // The next time a step must end on: a join, the target or t = 1, or the
    // repair's time a try passed and folded.
    double landing = std::min(join != joins_.end() ? *join : 1.0, target);
    if (forced_landing_ > time_) landing = std::min(landing, forced_landing_);
    // Within a fifth of a step of it, the step reaches it rather than leave a
    // sliver (a step from 0.35 of 0.05 ends at 0.39999999999999997, and one of
    // 5.6e-17 would follow to reach 0.4).
    const double stretched = std::min(1.2 * next_length_, StepControl::kLongestStep);
    const double next = time_ + stretched >= landing ? landing : time_ + next_length_;
    return std::min(next, target);
}

// The bound on the error of the step ending at `next`: the tolerance for a
// controlled step longer than the shortest, none (infinite) otherwise.
double Deformation::max_error(double next, bool controlled) const {
    const bool shortest = next - time_ <= StepControl::kShortestStep;
    return controlled && !shortest ? options_.tolerance : std::numeric_limits<double>::infinity();
}

// A step back cannot undo the fold repair: back across a step it acted after
// (scrubbing back, on a scene that folded, had ended 3e-2 of the size from the
// way out's shape, and 8e-2 from rest at t = 0), the backend starts again from
// rest and the steps forward along the times reached repeat the way out. Back
// to t = 0 too, for the rest positions bit for bit. Where the backend cannot
// start again, it steps back.
bool Deformation::rewinds_to(double target) const {
    target = std::clamp(target, 0.0, 1.0);
    if (target == time_ || (target > time_ && !stepped_back_) || !backend_->restarts()) return false;
    if (target == 0.0) return true;
    // A repair between the two times: after it on the way out, a step back
    // cannot undo it; before it, the repair would act on positions a step back
    // left a little off the way out's, and can tip to another shape.
    const double low = std::min(target, time_), high = std::max(target, time_);
    const auto after_low = std::upper_bound(repaired_.begin(), repaired_.end(), low);
    return after_low != repaired_.end() && *after_low <= high;
}

// From the latest checkpoint at or before the target, or from rest (and to
// t = 0 always: the rest positions bit for bit).
void Deformation::rewind(double target) {
    if (!rewinds_to(target)) return;
    const Checkpoint* from = nullptr;
    for (const Checkpoint& c : checkpoints_)
        if (target > 0.0 && c.time <= target) from = &c;
    if (from) {
        backend_->restore(*from->state);
        time_ = from->time;
        steps_taken_ = from->steps_taken;
        repeat_ = from->repeat;
    } else {
        backend_->restart();
        time_ = 0.0;
        steps_taken_ = 0;
        repeat_ = tries_.empty() ? std::string::npos : 0;
    }
    stepped_back_ = false;
    on_way_out_ = true;
    rewound_ = true;
}

// After a step of the way out from `from` to `to`, a checkpoint where the step
// reached or passed a fifth of unit time that has none yet: once a way back has
// started again from rest, at every fifth; before, where the repair has acted
// (so that a way back across it would start from rest), at the last fifth short
// of the run's `target` alone, from which the first way back from there, the
// most common, starts instead (one copy a run: on the raised claw about 1 ms).
void Deformation::keep_checkpoint(double from, double to, double target) {
    if (!on_way_out_ || !(to > from)) return;
    const int fifth = static_cast<int>(std::floor(to * kCheckpointsPerUnit + 1e-9));
    if (fifth >= kCheckpointsPerUnit || fifth <= static_cast<int>(std::floor(from * kCheckpointsPerUnit + 1e-9)))
        return;
    const int last_fifth = static_cast<int>(std::ceil(target * kCheckpointsPerUnit - 1e-9)) - 1;
    if (!rewound_ && (repaired_.empty() || fifth != last_fifth)) return;
    const auto at = std::lower_bound(checkpoints_.begin(), checkpoints_.end(), to,
                                     [](const Checkpoint& c, double t) { return c.time < t; });
    const auto same_fifth = [&](const Checkpoint& c) {
        return static_cast<int>(std::floor(c.time * kCheckpointsPerUnit + 1e-9)) == fifth;
    };
    if ((at != checkpoints_.end() && same_fifth(*at)) || (at != checkpoints_.begin() && same_fifth(*(at - 1)))) return;
    if (checkpoint_bytes_ + backend_->snapshot_bytes() > kCheckpointBytes) return;
    std::unique_ptr<StepBackend> state = backend_->snapshot();
    if (!state) return;
    checkpoint_bytes_ += state->snapshot_bytes();
    const std::size_t repeat = repeat_ != std::string::npos ? repeat_ : controlled_ ? tries_.size() : repeat_;
    checkpoints_.insert(at, Checkpoint{to, steps_taken_, repeat, std::move(state)});
}

Deformation::NextStep Deformation::next_step(double target) const {
    if (repeat_ < tries_.size() && target > time_) {
        const StepTry& t = tries_[repeat_];
        const double end = t.time + t.length;
        // A try the way out did not take is repeated past the target too: it
        // moves nothing, and leaves its ∇r to the step that follows it.
        if (t.time == time_ && (end <= target || !t.taken)) {
            const bool shortest = t.length <= StepControl::kShortestStep;
            return {end, shortest ? std::numeric_limits<double>::infinity() : options_.tolerance, false, true};
        }
    }
    NextStep n;
    n.end = next_time(target, n.controlled);
    n.max_error = max_error(n.end, n.controlled);
    return n;
}

StepPiece Deformation::prepare_step(double target) {
    target = std::clamp(target, 0.0, 1.0);
    // Starting again from rest shows other positions: advance() does it.
    if (time_ == target || rewinds_to(target)) return StepPiece::none;
    const auto start = std::chrono::steady_clock::now();
    const NextStep n = next_step(target);
    if (!n.repeated) repeat_ = std::string::npos;  // off the way out: its tries no longer follow
    const std::optional<StepResult> piece = backend_->prepare_step(time_, n.end - time_, steps_taken_ + 1, n.max_error);
    if (!piece) return StepPiece::none;
    if (!first_piece_) first_piece_ = start;
    if (piece->waiting) return StepPiece::waiting;
    if (!piece->taken) {  // as advance() notes a try over the tolerance
        if (n.repeated)
            ++repeat_;
        else
            note_step(n.end, n.controlled, *piece);
    }
    prepared_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return piece->taken ? StepPiece::done : StepPiece::retried;
}

// Keeps the step's estimate, and for a controlled step the time reached and the
// next step's length.
void Deformation::note_step(double next, bool controlled, const StepResult& result) {
    const double h = next - time_;
    if (result.error >= 0.0 && h > 0.0 && result.taken) {
        errors_.largest = std::max(errors_.largest, result.error);
        errors_.sum += result.error;
        ++errors_.estimated_steps;
    }
    if (!controlled) return;
    tries_.push_back({time_, h, result.error, result.taken});
    if (result.land_at > time_) forced_landing_ = result.land_at;
    if (!result.taken && result.land_at > time_) return;  // not rejected: tried again to the repair's time
    if (!result.taken) {
        ++errors_.rejected;
        next_length_ = StepControl::retry_length(h, std::max(result.error, 0.0), options_.tolerance);
        just_rejected_ = true;
        return;
    }
    const double length = StepControl::next_length(h, std::max(result.error, 0.0), options_.tolerance);
    grid_.push_back(next);
    // A step cut short by a join or the target says little about a longer one;
    // the step after a rejected one does not grow (it would be rejected again).
    const bool cut_short = h < next_length_ * (1.0 - 1e-9);
    next_length_ = cut_short ? std::max(next_length_ * std::min(1.0, length / h), length) : length;
    if (just_rejected_) next_length_ = std::min(next_length_, h);
    // Two taken steps in a row whose estimates' coefficient grew: the next is
    // as long as the coefficient foreseen at its middle allows.
    const double coefficient = result.error > 0.0 ? result.error / (h * h) : -1.0, middle = time_ + 0.5 * h;
    if (!just_rejected_ && last_coefficient_ > 0.0)
        next_length_ = StepControl::foreseen_length(h, next_length_, last_coefficient_, coefficient,
                                                    middle - last_middle_, options_.tolerance);
    last_coefficient_ = coefficient, last_middle_ = middle;
    just_rejected_ = false;
}

bool Deformation::next_step_tests_affine(double target) const {
    target = std::clamp(target, 0.0, 1.0);
    if (time_ == target || !options_.repair_folds) return false;
    return FoldRepair::affine_test_due(time_, next_step(target).end);
}

int Deformation::advance(double target, int max_steps, double budget_ms, bool stop_before_affine_test) {
    target = std::clamp(target, 0.0, 1.0);
    rewind(target);
    using Clock = std::chrono::steady_clock;
    const auto milliseconds = [](Clock::time_point since) {
        return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
    };
    const auto start = Clock::now();
    auto step_start = start;
    int taken = 0;
    while (taken < max_steps && time_ != target) {
        if (taken > 0 && stop_before_affine_test && next_step_tests_affine(target)) break;
        const NextStep n = next_step(target);
        const double next = n.end;
        const std::size_t repairs = backend_->fold_repairs().steps_repaired;
        const StepResult result = backend_->step(time_, next - time_, steps_taken_ + 1, n.max_error);
        if (n.repeated) {
            ++repeat_;
        } else {
            repeat_ = std::string::npos;  // off the way out: its tries no longer follow
            note_step(next, n.controlled, result);
        }
        if (!result.taken) continue;  // tried again shorter; its time counts to the step taken
        if (next < time_) stepped_back_ = true;
        const bool way_out_step = next > time_ && (controlled_ ? n.repeated || n.controlled
                                                               : next == grid_time_at_or_after(next, options_.steps));
        on_way_out_ = on_way_out_ && way_out_step;
        if (next > time_ && backend_->fold_repairs().steps_repaired != repairs) {
            const auto at = std::lower_bound(repaired_.begin(), repaired_.end(), next);
            if (at == repaired_.end() || *at != next) repaired_.insert(at, next);
        }
        const double from = time_;
        time_ = next;
        ++steps_taken_;
        ++taken;
        keep_checkpoint(from, next, target);
        if (!backend_->asynchronous()) step_ms_.push_back(milliseconds(step_start) + prepared_ms_);
        prepared_ms_ = 0.0;
        step_start = Clock::now();
        if (!backend_->asynchronous() && milliseconds(start) >= budget_ms) break;
    }
    if (taken > 0 && backend_->asynchronous()) {
        backend_->finish();
        const auto since = std::min(start, first_piece_.value_or(start));
        step_ms_.insert(step_ms_.end(), taken, milliseconds(since) / taken);
        checked_ = false;
    }
    if (taken > 0) first_piece_.reset();
    if (time_ == target) backend_->release_scratch();
    return taken;
}

const std::vector<Vec3>& Deformation::positions() const {
    const std::vector<Vec3>& positions = backend_->positions();
    if (checked_) return positions;
    // An asynchronous backend cannot stop mid-advance: the first non-finite
    // position is found here, after the fact.
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const Vec3& p = positions[v];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
            throw NumericalError(std::string("the ") + backend_->name() + " integration made vertex " +
                                 std::to_string(v) + " non-finite by t = " + std::to_string(time_));
    }
    checked_ = true;
    return positions;
}

double Deformation::ms_per_step() const {
    if (step_ms_.empty()) return 0.0;
    std::vector<double> ms = step_ms_;
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    return ms[ms.size() / 2];
}

}  // namespace vfsd
