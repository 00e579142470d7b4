#pragma once
// The frame times an editor logs while a script orbits (the `orbit` command's
// "pointer"): each frame's parts and, after the last, their medians. The shell
// measures; this says what the lines are.

#include <string>
#include <vector>

namespace vfsd::editor {

struct FrameTimes {
    double app_ms = 0.0;   // input, script, deformation steps, panels, overlay (the hover pick)
    double draw_ms = 0.0;  // issuing the scene's and the panels' GL calls (the driver's vertex work included)
    double swap_ms = 0.0;  // the driver finishing the frame (buffer swap)
    double whole_ms() const { return app_ms + draw_ms + swap_ms; }
};

class FrameLog {
public:
    // Logs the next `frames` frames.
    void start(int frames);
    bool active() const { return left_ > 0; }
    // The frame's line, and after the last frame the medians' line too.
    std::vector<std::string> add(const FrameTimes& times);

private:
    int left_ = 0;
    std::vector<FrameTimes> frames_;
};

}  // namespace vfsd::editor
