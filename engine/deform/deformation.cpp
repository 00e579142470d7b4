#include "deform/deformation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "deform/cpu_steps.h"

namespace vfsd {

void check_options(const DeformationOptions& options) {
    if (options.steps < 1) throw InputError("steps must be at least 1");
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

NumericalError nonfinite_position(std::size_t vertex, int step, double time) {
    return NumericalError("integration step " + std::to_string(step) + " (t = " + std::to_string(time) +
                          ") made vertex " + std::to_string(vertex) + " non-finite; the mesh before that step is kept");
}

Deformation::Deformation(std::unique_ptr<StepBackend> backend, DeformationOptions options)
    : backend_(std::move(backend)), options_(options) {
    check_options(options_);
}

Deformation::Deformation(std::vector<Vec3> positions, VertexRings rings, Region region, InnerMotion motion,
                         DeformationOptions options)
    : Deformation(std::make_unique<CpuSteps>(std::move(positions), std::move(rings), std::move(region),
                                             std::move(motion), options),
                  options) {}

int Deformation::advance(double target, int max_steps) {
    target = std::clamp(target, 0.0, 1.0);
    using Clock = std::chrono::steady_clock;
    const auto milliseconds = [](Clock::time_point since) {
        return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
    };
    const auto start = Clock::now();
    int taken = 0;
    while (taken < max_steps && time_ != target) {
        const double next = next_time_on_grid(time_, target, options_.steps);
        const auto step_start = Clock::now();
        backend_->step(time_, next - time_, steps_taken_ + 1);
        time_ = next;
        ++steps_taken_;
        ++taken;
        if (!backend_->asynchronous()) step_ms_.push_back(milliseconds(step_start));
    }
    if (taken > 0 && backend_->asynchronous()) {
        backend_->finish();
        step_ms_.insert(step_ms_.end(), taken, milliseconds(start) / taken);
        checked_ = false;
    }
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
