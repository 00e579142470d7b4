#pragma once
// Scripts: UI-level actions that drive an editor without a person (tests, CI,
// demos). A script is a JSON array of actions or one JSON object per line (blank
// lines and lines starting with # or // are skipped). Each action is an object
// with "action" and its arguments; screen coordinates are pixels of the viewport,
// origin top left. docs/desktop.md lists them all:
//
//   {"action": "load", "path": "mesh.obj" | "scene.json"}
//   {"action": "pick", "at": [x, y]} | {"vertex": i} | {"triangle": i, "barycentric": [a, b, c]}
//                      optional "g_min", "g_max" (mesh units)
//   {"action": "paint", "tool": "inner"|"outer"|"erase"|"s", "radius": r, "points": [[x, y], ...],
//                      optional "target", "strength" (tool s)}
//   {"action": "loops", "inner": [[x, y], ...], "outer": [[x, y], ...], "seed": [x, y]}
//   {"action": "drag", "index": i, "to": [x, y], optional "axis": "x"|"y"|"z"}
//   {"action": "place-handle", "at": [x, y]}   (handle mode, the handle on the surface there)
//   {"action": "gizmo", "part": "centre"|"x"|"y"|"z"|"ring-x"|"ring-y"|"ring-z",
//                      "to": [x, y] | "by": [dx, dy] | "degrees": a (rings, counter-clockwise on screen)}
//   {"action": "add-segment"} {"action": "remove-segment"}
//   {"action": "twist", "alpha": [a0, a1]} (degrees)   {"action": "inner-motion", "mode": "rotation"|"translation"}
//   {"action": "set-time", "t": t}   {"action": "wait-until-time", "t": t}
//   {"action": "play"} {"action": "pause"} {"action": "reset"} {"action": "apply"}
//   {"action": "undo"} {"action": "redo"}
//   {"action": "view", "name": "front"|"back"|"left"|"right"|"top"|"bottom"|"iso"|"frame"}
//   {"action": "orbit", "degrees": [yaw, pitch], "frames": n, optional "pointer": [x, y]}
//                      (turns the camera over n frames as a pointer drag would, the
//                      hovering pointer at [x, y]; the editor logs each frame's times)
//   {"action": "tool", "name": "navigate"|"geodesic"|"inner"|"outer"|"erase"|"s"|"loops"|"handle"}
//   {"action": "export", "path": P} {"action": "save-scene", "path": P}
//   {"action": "screenshot", "path": P, optional "ui": false}
//   {"action": "wait-frames", "n": n}
//   {"action": "autosave"}   {"action": "restore-autosave", "answer": "restore"|"discard"}
//   {"action": "simulate-crash"}   (ends the editor at once: no clean exit, the autosave stays)
//   {"action": "expect", "time": t | "undo_count": n | "warnings": n}   (checks; fail the script)

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/camera.h"
#include "editor/session.h"
#include "editor/tools.h"

namespace vfsd::editor {

struct ScriptAction {
    std::string name;
    nlohmann::json args;
    std::string where;  // "script.jsonl:3" for messages
};

// Parses a script's text. Throws InputError naming the line (or array index).
std::vector<ScriptAction> parse_script(const std::string& text, const std::string& source);
std::vector<ScriptAction> load_script(const std::string& path);

// What only the application can do.
class ScriptHost {
public:
    virtual ~ScriptHost() = default;
    // Save the next rendered frame as PNG (with or without the panels).
    virtual void screenshot(const std::string& path, bool ui) = 0;
    // A loaded mesh or scene: the application frames it.
    virtual void loaded() = 0;
    virtual void log(const std::string& line) = 0;
    // The autosave (editor/autosave.h), in editors that keep one; the defaults
    // throw InputError. Write it now; answer the start-up offer to restore it; end
    // the process as a crash would, without the clean exit that clears it.
    virtual void autosave_now();
    virtual void answer_restore(bool restore);
    virtual void simulate_crash();
    // An orbit under way: the pointer hovers at viewport pixel (x, y) from the next
    // frame on, and the editor logs the times of the next `frames` frames. Editors
    // without a pointer or a frame clock ignore them.
    virtual void point_at(double x, double y);
    virtual void log_frame_times(int frames);
};

class ScriptRunner {
public:
    explicit ScriptRunner(std::vector<ScriptAction> actions) : actions_(std::move(actions)) {}

    // Runs actions until one must wait for later frames (a screenshot, a time to be
    // reached). Call once per frame; returns false once the script has ended.
    bool run_frame(EditorSession& session, ToolController& tools, Camera& camera, const Viewport& viewport,
                   ScriptHost& host);
    bool done() const { return next_ >= actions_.size() || failed(); }
    bool failed() const { return !error_.empty(); }
    const std::string& error() const { return error_; }

private:
    // Returns false when the action must be retried next frame.
    bool execute(const ScriptAction& a, EditorSession& session, ToolController& tools, Camera& camera,
                 const Viewport& viewport, ScriptHost& host);

    std::vector<ScriptAction> actions_;
    std::size_t next_ = 0;
    int waited_frames_ = 0;
    std::string error_;
};

}  // namespace vfsd::editor
