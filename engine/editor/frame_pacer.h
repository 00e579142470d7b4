#pragma once
// How a frame splits between integrating and drawing while the deformation runs.
// A draw that fits in a 60 Hz frame is made every frame, after step_budget_ms of
// steps. On a software renderer (the page in SwiftShader, the window in llvmpipe)
// a draw of a large mesh costs more than several steps; where the shell keeps its
// last image (the page's canvas, the window's displayed buffer), the pacer then
// draws only once the steps since the last draw took about three draws' time,
// and fills each frame up to that length with steps, so drawing takes about a
// quarter of the run and no frame is much longer than max_frame_ms. A draw's cost
// is what the frame after it waited, or, where the shell can tell (the page, by a
// GL fence), how long the renderer took to finish it; while the renderer is still
// busy with the last draw no costly draw is added.
// Times are milliseconds on any steady clock, given by the caller.

namespace vfsd::editor {

class FramePacer {
public:
    FramePacer(double step_budget_ms, double max_frame_ms)
        : step_budget_ms_(step_budget_ms), max_frame_ms_(max_frame_ms) {}

    struct Plan {
        bool draw = true;           // draw this frame
        double integrate_ms = 0.0;  // integrate for about this long first
    };
    // The frame starting at `now`: whether the deformation runs, whether the shell
    // keeps its last image when it does not draw, whether the renderer has not
    // finished the last draw yet (the shell's fence).
    Plan plan(double now, bool running, bool keeps_image, bool renderer_busy = false);
    // The frame's steps ended at `now`; `drew`: the frame draws next.
    void integrated(double now, bool drew);
    // The renderer finished a draw `ms` after it was issued.
    void renderer_finished(double ms);
    // A drawn frame's cost: the larger of the wait after it and the renderer's time
    // (each smoothed; 0 before the first).
    double draw_ms() const;
    // Drawing costs more than a 60 Hz frame: frames that do not draw are worth having.
    bool draws_costly() const;

private:
    double step_budget_ms_, max_frame_ms_;
    double draw_ms_ = 0.0, renderer_ms_ = 0.0;
    double integrated_at_ = 0.0;  // when the last frame's steps ended
    bool last_drew_ = false;
    bool last_running_ = false;
    double last_draw_ = 0.0;  // when the last drawn frame's steps ended
};

}  // namespace vfsd::editor
