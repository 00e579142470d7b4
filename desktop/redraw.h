#pragma once
// When the window draws, and when it may sleep until the next event. A frame that
// does not swap leaves the last image on the display, so the window draws only
// what changed:
// - while the deformation runs, the frames the editor's pacer draws (an edit's
//   run that holds its last result on show draws nothing new until its final
//   shape: its frames go to the steps), the frames after input (the camera, the
//   panels, the dragged curve), and one every kProgressMs for the panels' progress;
// - at rest, the frames after input (the event's and the next: ImGui settles hover
//   and click states in the frame after an event), the frame after a run ended,
//   every frame while a script runs, and one every kRestRedrawMs for what changed
//   without an event (the autosave's status line); between them the window
//   sleeps until an event or that redraw is due, instead of drawing at the
//   display's rate for nothing.
// Times are milliseconds on any steady clock, given by the caller.

#include <algorithm>
#include <limits>

namespace vfsd::desktop {

class WindowRedraw {
public:
    static constexpr int kAwakeFrames = 2;
    static constexpr double kProgressMs = 250.0;
    static constexpr double kRestRedrawMs = 1000.0;

    struct Frame {
        double now_ms = 0.0;
        bool working = false;     // the deformation runs or a region is computed (after the frame's steps)
        bool draw_due = true;     // the editor's pacer asks for a draw (Editor::draw_due)
        bool input = false;       // the window had an event since the last frame
        bool scripted = false;    // a script runs
        bool screenshot = false;  // a screenshot is pending: it needs this frame drawn
    };

    // Whether this frame draws (and swaps).
    bool draw(const Frame& f) {
        if (f.input) awake_ = kAwakeFrames;
        const bool awake = awake_ > 0;
        if (awake) --awake_;
        const double period = f.working ? kProgressMs : kRestRedrawMs;
        const bool draw = f.screenshot || awake || f.now_ms - drawn_at_ >= period ||
                          (f.working ? f.draw_due : was_working_ || f.scripted);
        was_working_ = f.working, scripted_ = f.scripted;
        if (draw) drawn_at_ = f.now_ms;
        return draw;
    }

    // How long the next frame may wait for an event before it starts, in seconds
    // (0: poll and go on): only at rest, with no frame after input left to draw.
    double wait_seconds(double now_ms) const {
        if (was_working_ || scripted_ || awake_ > 0) return 0.0;
        return std::max(0.0, drawn_at_ + kRestRedrawMs - now_ms) / 1000.0;
    }

private:
    int awake_ = kAwakeFrames;
    bool was_working_ = false, scripted_ = false;
    double drawn_at_ = -std::numeric_limits<double>::infinity();
};

}  // namespace vfsd::desktop
