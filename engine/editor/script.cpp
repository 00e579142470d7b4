#include "editor/script.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "base/error.h"

namespace vfsd::editor {
namespace {

using nlohmann::json;

// A wait gives up after this many frames (the deformation stalled).
constexpr int kMaxWaitFrames = 200000;

}  // namespace

std::string ScriptRunner::waited_line(const std::string& name, double total_ms, long drawn) const {
    char line[200];
    const int length = std::snprintf(line, sizeof line, "script: %s waited %d frames, %.1f ms (longest frame %.1f ms)",
                                     name.c_str(), waited_frames_, total_ms, longest_frame_ms_);
    if (drawn >= 0 && drawn_before_ >= 0 && length > 0 && std::size_t(length) < sizeof line)
        std::snprintf(line + length, sizeof line - length, ", drew %ld", drawn - drawn_before_);
    return line;
}

std::vector<ScriptAction> parse_script(const std::string& source_text, const std::string& source) {
    std::vector<ScriptAction> actions;
    auto add = [&](const json& j, const std::string& where) {
        if (!j.is_object() || !j.contains("action") || !j["action"].is_string())
            throw InputError(where + ": expected an object with \"action\"");
        actions.push_back({j["action"].get<std::string>(), j, where});
    };
    std::size_t first = source_text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && source_text[first] == '[') {
        json list;
        try {
            list = json::parse(source_text);
        } catch (const json::exception& e) {
            throw InputError(source + ": " + e.what());
        }
        for (std::size_t i = 0; i < list.size(); ++i) add(list[i], source + "[" + std::to_string(i) + "]");
        return actions;
    }
    std::istringstream in(source_text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::size_t start = line.find_first_not_of(" \t\r");
        if (start == std::string::npos || line[start] == '#' || line.compare(start, 2, "//") == 0) continue;
        const std::string where = source + ":" + std::to_string(number);
        try {
            add(json::parse(line), where);
        } catch (const json::exception& e) {
            throw InputError(where + ": " + e.what());
        }
    }
    return actions;
}

std::vector<ScriptAction> load_script(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open the script");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_script(text.str(), path);
}

bool ScriptRunner::run_frame(CommandContext context) {
    using Clock = std::chrono::steady_clock;
    const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
    const Clock::time_point now = Clock::now();
    if (waited_frames_ > 0) longest_frame_ms_ = std::max(longest_frame_ms_, ms(now - last_call_));
    last_call_ = now;
    while (!done()) {
        const ScriptAction& a = actions_[next_];
        if (waited_frames_ == 0) {
            context.host.log("script: " + a.args.dump());
            began_ = now;
            longest_frame_ms_ = 0.0;
            drawn_before_ = context.host.frames_drawn();
        }
        context.frame = waited_frames_;
        bool finished = false;
        try {
            finished = run_command(a.name, a.args, context);
        } catch (const std::exception& e) {
            error_ = a.where + ": " + a.name + ": " + e.what();
            context.host.log("script: " + error_);
            return false;
        }
        if (!finished) {
            if (++waited_frames_ > kMaxWaitFrames) error_ = a.where + ": " + a.name + ": gave up waiting";
            return !done();
        }
        if (waited_frames_ > 0) context.host.log(waited_line(a.name, ms(now - began_), context.host.frames_drawn()));
        waited_frames_ = 0;
        ++next_;
        // A screenshot needs this frame rendered first.
        if (a.name == "screenshot") return !done();
    }
    return false;
}

}  // namespace vfsd::editor
