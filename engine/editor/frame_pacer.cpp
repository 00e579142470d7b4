#include "editor/frame_pacer.h"

#include <algorithm>

namespace vfsd::editor {

namespace {
constexpr double kCheapDrawMs = 20.0;      // fits in a 60 Hz frame, with its wait for the display
constexpr double kLongestDrawMs = 1000.0;  // beyond: a pause, not a draw
constexpr double kStepsPerDraw = 3.0;      // time on steps per time drawing, when a draw is costly
double smoothed(double average, double sample) { return average == 0.0 ? sample : 0.7 * average + 0.3 * sample; }
}  // namespace

FramePacer::Plan FramePacer::plan(double now, bool running, bool keeps_image, bool renderer_busy) {
    // The time from the last frame's steps to this frame is its draw (and the wait
    // for the display), while frames follow each other (not after the loop paused).
    if (last_drew_ && last_running_ && running) {
        const double sample = std::clamp(now - integrated_at_, 0.0, kLongestDrawMs);
        draw_ms_ = smoothed(draw_ms_, sample);
    }
    last_running_ = running;
    if (!running || !keeps_image || !draws_costly()) return {true, step_budget_ms_};
    const double cost = draw_ms();
    const double frame = std::clamp(kStepsPerDraw * cost, step_budget_ms_, max_frame_ms_);
    const bool draw = !renderer_busy && now - last_draw_ >= (kStepsPerDraw + 1.0) * cost;  // that draw, then the steps
    return {draw, draw ? std::max(frame - draw_ms_, 0.0) : frame};
}

void FramePacer::renderer_finished(double ms) {
    renderer_ms_ = smoothed(renderer_ms_, std::clamp(ms, 0.0, kLongestDrawMs));
}

double FramePacer::draw_ms() const { return std::max(draw_ms_, renderer_ms_); }

bool FramePacer::draws_costly() const { return draw_ms() >= kCheapDrawMs; }

void FramePacer::integrated(double now, bool drew) {
    integrated_at_ = now;
    last_drew_ = drew;
    if (drew) last_draw_ = now;
}

}  // namespace vfsd::editor
