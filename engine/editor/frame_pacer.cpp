#include "editor/frame_pacer.h"

#include <algorithm>

namespace vfsd::editor {

namespace {
constexpr double kCheapDrawMs = 20.0;      // fits in a 60 Hz frame, with its wait for the display
constexpr double kLongestDrawMs = 1000.0;  // beyond: a pause, not a draw
constexpr double kStepsPerDraw = 3.0;      // time on steps per time drawing, when a draw is costly
}  // namespace

FramePacer::Plan FramePacer::plan(double now, bool running, bool keeps_image) {
    // The time from the last frame's steps to this frame is its draw (and the wait
    // for the display), while frames follow each other (not after the loop paused).
    if (last_drew_ && last_running_ && running) {
        const double sample = std::clamp(now - integrated_at_, 0.0, kLongestDrawMs);
        draw_ms_ = draw_ms_ == 0.0 ? sample : 0.7 * draw_ms_ + 0.3 * sample;
    }
    last_running_ = running;
    if (!running || !keeps_image || !draws_costly()) return {true, step_budget_ms_};
    const double frame = std::clamp(kStepsPerDraw * draw_ms_, step_budget_ms_, max_frame_ms_);
    const bool draw = now - last_draw_ >= (kStepsPerDraw + 1.0) * draw_ms_;  // that draw, then the steps
    return {draw, draw ? std::max(frame - draw_ms_, 0.0) : frame};
}

bool FramePacer::draws_costly() const { return draw_ms_ >= kCheapDrawMs; }

void FramePacer::integrated(double now, bool drew) {
    integrated_at_ = now;
    last_drew_ = drew;
    if (drew) last_draw_ = now;
}

}  // namespace vfsd::editor
