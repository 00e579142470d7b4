#pragma once
// Scripts: UI-level actions that drive an editor without a person (tests, CI,
// demos). A script is a JSON array of actions or one JSON object per line (blank
// lines and lines starting with # or // are skipped). Each action is an object
// with "action" and its arguments; screen coordinates are pixels of the viewport,
// origin top left. Each action is a command of the editor's table
// (editor/commands.h, docs/commands.md) with its arguments; the runner adds the
// waits: a command that waits (wait-until-time, wait-frames, orbit) is run again
// next frame, and a screenshot ends the frame so it can be rendered.
//
//   {"action": "paint", "tool": "inner", "radius": 0.1, "points": [[400, 300], [420, 310]]}
//   {"action": "set-time", "t": 1}
//   {"action": "wait-until-time", "t": 1}

#include <chrono>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/commands.h"

namespace vfsd::editor {

struct ScriptAction {
    std::string name;
    nlohmann::json args;
    std::string where;  // "script.jsonl:3" for messages
};

// Parses a script's text. Throws InputError naming the line (or array index).
std::vector<ScriptAction> parse_script(const std::string& text, const std::string& source);
std::vector<ScriptAction> load_script(const std::string& path);

class ScriptRunner {
public:
    explicit ScriptRunner(std::vector<ScriptAction> actions) : actions_(std::move(actions)) {}

    // Runs actions until one must wait for later frames (a screenshot, a time to be
    // reached). Call once per frame; returns false once the script has ended.
    // The context's `frame` is the runner's own. An action that waited logs, as it
    // ends, the frames it waited, the time from its first call to its last and
    // the longest time between two of its calls (a frame of the editor's, drawing
    // and input included), and, where the host counts them, the frames drawn
    // meanwhile: `wait-until-time` after an edit so times edit to final shape as
    // the user sees it.
    bool run_frame(CommandContext context);
    bool done() const { return next_ >= actions_.size() || failed(); }
    bool failed() const { return !error_.empty(); }
    const std::string& error() const { return error_; }

private:
    std::string waited_line(const std::string& name, double total_ms, long drawn) const;

    std::vector<ScriptAction> actions_;
    std::size_t next_ = 0;
    int waited_frames_ = 0;
    std::chrono::steady_clock::time_point began_, last_call_;  // of the action under way
    double longest_frame_ms_ = 0.0;
    long drawn_before_ = -1;  // the host's frames drawn when the action began
    std::string error_;
};

}  // namespace vfsd::editor
