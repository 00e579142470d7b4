#pragma once
// The editor's command vocabulary: every named thing a user, a script, the page or
// a key can do, each with typed, validated arguments and one function over the
// session, tools and camera. Scripts ({"action": NAME, ...}, editor/script.h), the
// page's window.vfsd.command ({"cmd": NAME, ...}), both shells' controls and the
// key table (key_bindings(), run_key) dispatch through it by name.
// docs/commands.md lists it (commands_markdown(); a test checks the two agree).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "view/camera.h"
#include "editor/session.h"
#include "editor/tools.h"

namespace vfsd::editor {

// What only the application can do.
class EditorHost {
public:
    virtual ~EditorHost() = default;
    // Save the next rendered frame as PNG (with or without the panels).
    virtual void screenshot(const std::string& path, bool ui) = 0;
    // A loaded mesh or scene: the application turns to its default view and frames it.
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
    // The frames the editor has drawn so far; -1 where it does not count them.
    virtual long frames_drawn() const;
};

// Editor state the commands change beside the session, tools and camera.
struct EditorSettings {
    bool wireframe = false;
    bool force_cpu = false;
    // A slider drag under way: its changes become one undo step at end-gesture.
    bool region_gesture = false, curve_gesture = false;
};

// What a command acts on. `frame` counts the frames the command has already waited.
struct CommandContext {
    EditorSession& session;
    ToolController& tools;
    Camera& camera;
    EditorSettings& settings;
    Viewport viewport;
    EditorHost& host;
    int frame = 0;
};

enum class ArgType {
    number,   // any number
    integer,  // a whole number
    boolean,
    text,     // a string, one of `choices` when given ("a|b|c")
    pixel,    // [x, y], viewport pixels from the top left
    pixels,   // [[x, y], ...], at least one
    pair,     // [a, b]
    triple,   // [a, b, c]
};

struct ArgSpec {
    const char* name;
    ArgType type;
    bool required;
    const char* help;
    const char* choices = nullptr;
};

// A command's arguments, validated against its ArgSpecs before it runs.
class CommandArgs {
public:
    explicit CommandArgs(const nlohmann::json& args) : args_(args) {}
    bool has(const char* name) const { return args_.contains(name); }
    double number(const char* name) const;
    double number_or(const char* name, double fallback) const { return has(name) ? number(name) : fallback; }
    long long integer(const char* name) const;
    bool boolean_or(const char* name, bool fallback) const;
    std::string text(const char* name) const;
    glm::dvec2 pair(const char* name) const;
    glm::dvec3 triple(const char* name) const;
    std::vector<glm::dvec2> pixels(const char* name) const;
    const nlohmann::json& raw() const { return args_; }

private:
    const nlohmann::json& args_;
};

struct Command {
    const char* name;
    const char* summary;
    std::vector<ArgSpec> args;
    // Returns false while the command waits for later frames (it is called again).
    bool (*run)(const CommandArgs& args, CommandContext& context);
};

// Frames the mesh and the whole curve (as `vfsd render` does), keeping the view's
// direction: "frame all", and every standard view.
void frame_session(Camera& camera, const EditorSession& session, const Viewport& viewport);

const std::vector<Command>& command_table();
// Throws InputError for an unknown name.
const Command& find_command(const std::string& name);
// Names known, types right, required ones present; "action" and "cmd" (the
// dispatch keys of scripts and the page) are skipped. Throws InputError.
void validate_arguments(const Command& command, const nlohmann::json& args);
// Validates and runs; false while the command waits for later frames.
bool run_command(const std::string& name, const nlohmann::json& args, CommandContext& context);

// A key and the command it runs. Keys are named as key_name() writes them.
struct KeyBinding {
    const char* key;
    const char* command;
    const char* args;  // JSON object
    const char* help;
};
const std::vector<KeyBinding>& key_bindings();
// "z", "ctrl+z", "ctrl+shift+z", "space", "enter", "[", "1": the key's character
// (or name) in lower case; Shift counts only together with Ctrl.
std::string key_name(const std::string& key, bool ctrl, bool shift);
// The binding of the key; null when none is.
const KeyBinding* find_key(const std::string& key, bool ctrl, bool shift);
// Runs the command bound to the key; false when none is.
bool run_key(const std::string& key, bool ctrl, bool shift, CommandContext& context);

// The table and the key bindings as Markdown (docs/commands.md).
std::string commands_markdown();

}  // namespace vfsd::editor
