// The browser page's curve edit without the browser: the 41k sphere (or the mesh
// given) opened through the page's own commands (editor/page_api.h), a geodesic
// region and the starting curve run to t = 1, then the curve's end dragged
// sideways by a tenth of the diagonal and back, `edits` times; each edit timed
// from the drag command to the frame that reached t = 1, the Editor's frames
// run back to back (the page yields to the browser between them). One thread.
// Built natively and, in the wasm preset, as WebAssembly for node, whose V8 is
// Chromium's: the two printed side by side give the page's engine and editor
// against native with no renderer on the machine (docs/web.md, "The page's
// SIMD"). scripts/bench-page builds and runs both.
//
//   page_edit [MESH] [EDITS]     default builtin:sphere:6, 5

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/parallel.h"
#include "editor/editor.h"
#include "editor/page_api.h"

namespace {

using json = nlohmann::json;
using namespace vfsd;
using namespace vfsd::editor;

class QuietShell final : public Shell {
public:
    Viewport viewport() const override { return {1200, 800}; }  // the page tests' window
    void log(const std::string&) override {}
    void screenshot(const std::string&, bool) override {}
};

double now_ms() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int run(const std::string& mesh, int edits) {
    set_parallel_thread_limit(1);
    QuietShell shell;
    EditorOptions options;
    options.autosave_directory = (std::filesystem::temp_directory_path() / "vfsd-page-edit").string();
    Editor editor(shell, {}, "not timed here", options);
    const PageInfo page{std::filesystem::temp_directory_path().string(), "none", false};
    const auto send = [&](const json& command) { return page_command(editor, command, page); };
    const auto run_frames = [&] {
        int frames = 0;
        while (editor.busy()) editor.advance(), ++frames;
        return frames;
    };

    // As web/tests/harness.mjs's openRunToEnd: the region about the curve's start.
    const std::string error = send({{"cmd", "open"}, {"path", mesh}})["load_error"];
    if (!error.empty()) throw InputError(error);
    const json opened = send({{"cmd", "state"}});
    json points = opened["control_points"];
    const double diagonal = opened["diagonal"];
    const json region = {
        {"kind", "geodesic"}, {"seed", points[0]}, {"g_min", 0.1 * diagonal}, {"g_max", 0.45 * diagonal}};
    send({{"cmd", "load-scene"}, {"scene", {{"region", region}, {"curve", {{"bezier", points}}}, {"target_time", 1}}}});
    send({{"cmd", "set-time"}, {"t", 1}});
    run_frames();

    std::vector<double> ms;
    int frames = 0, steps = 0;
    const int last = static_cast<int>(points.size()) - 1;
    for (int k = 0; k < edits; ++k) {
        json to = points[last];
        to[1] = to[1].get<double>() + (k % 2 ? -0.1 : 0.1) * diagonal;  // out and back, as latency.mjs
        const json pixel = send({{"cmd", "project"}, {"points", json::array({to})}})["pixels"][0];
        const double start = now_ms();
        send({{"cmd", "drag"}, {"index", last}, {"to", pixel}});
        frames = run_frames();
        ms.push_back(now_ms() - start);
        const json state = send({{"cmd", "state"}});
        if (state["stats"]["time"] != 1.0) throw std::runtime_error("the edit's run stopped short of t = 1");
        steps = static_cast<int>(editor.session().deformation()->step_milliseconds().size());
        points = state["control_points"];
    }
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    std::printf(
        "%s: curve edit through the page's commands, %s, one thread: median %.1f ms of %d (%.1f-%.1f), "
        "%d steps in %d frames\n",
#ifdef __EMSCRIPTEN__
        mesh.c_str(), "WebAssembly",
#else
        mesh.c_str(), "native",
#endif
        sorted[sorted.size() / 2], edits, sorted.front(), sorted.back(), steps, frames);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const int edits = argc > 2 ? std::stoi(argv[2]) : 5;
        if (edits < 1) throw std::invalid_argument("EDITS: expected at least 1");
        return run(argc > 1 ? argv[1] : "builtin:sphere:6", edits);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "page_edit: %s\n", e.what());
        return 1;
    }
}
