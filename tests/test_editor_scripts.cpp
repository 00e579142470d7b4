// Scripted editor sessions run natively (no window): what a script exports is what
// `vfsd deform` computes for the scene it saves, and what the same edits made by
// plain session calls give. These sessions pin the editor's behaviour while its
// command layer changes: each export is compared with results computed here, never
// with numbers copied from a run.

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "view/camera.h"
#include "editor/script.h"
#include "editor/session.h"
#include "editor/tools.h"
#include "io/mesh_file.h"
#include "test_editor_support.h"
#include "test_io_support.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

// An editor without a window: it frames mesh and curve on load, as the Editor
// does, and keeps no autosave.
class HeadlessHost final : public EditorHost {
public:
    HeadlessHost(const EditorSession& session, Camera& camera, Viewport viewport)
        : session_(session), camera_(camera), viewport_(viewport) {}
    void screenshot(const std::string&, bool) override {}
    void loaded() override {
        camera_ = Camera();
        frame_session(camera_, session_, viewport_);
    }
    void log(const std::string& line) override { lines.push_back(line); }
    long frames_drawn() const override { return drawn; }
    std::vector<std::string> lines;
    long drawn = -1;  // the frames "drawn", where the test counts them

private:
    const EditorSession& session_;
    Camera& camera_;
    Viewport viewport_;
};

// Runs a script to its end as an editor's frames would, a few steps per frame.
void run_script(const std::string& text, EditorSession& session) {
    ToolController tools;
    Camera camera;
    EditorSettings settings;
    const Viewport viewport{1280, 800};
    HeadlessHost host(session, camera, viewport);
    ScriptRunner runner(parse_script(text, "session"));
    while (runner.run_frame({session, tools, camera, settings, viewport, host})) session.update(7);
    INFO(runner.error());
    REQUIRE(!runner.failed());
}

// The frames, total and longest frame a waiting action logged ("NAME waited N
// frames, T ms (longest frame L ms)"), from the last such line; false if none.
bool waited(const std::vector<std::string>& lines, const std::string& name, int& frames, double& total_ms,
            double& longest_ms) {
    const std::string prefix = "script: " + name + " waited %d frames, %lf ms (longest frame %lf ms)";
    for (auto line = lines.rbegin(); line != lines.rend(); ++line)
        if (std::sscanf(line->c_str(), prefix.c_str(), &frames, &total_ms, &longest_ms) == 3) return true;
    return false;
}

using test::deform_scene_file;
using test::run_to_target;

// Largest distance between two vertex lists of the same length, as a fraction of `diagonal`.
double largest_gap(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double diagonal) {
    REQUIRE(a.size() == b.size());
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
    return worst / diagonal;
}

std::string path_in(const test::ScratchDir& dir, const std::string& name) { return dir.file(name); }

// The export (written in float precision) matches `vfsd deform` of the saved scene.
void check_export_matches_saved_scene(const test::ScratchDir& dir, const EditorSession& session) {
    const std::vector<Vec3> exported = load_mesh(path_in(dir, "out.ply")).positions;
    CHECK(largest_gap(exported, session.positions(), session.diagonal()) < 1e-6);
    CHECK(deform_scene_file(path_in(dir, "out.json")) == session.positions());
}

std::string ending(const test::ScratchDir& dir) {
    return "{\"action\": \"export\", \"path\": \"" + path_in(dir, "out.ply") + "\"}\n"
           "{\"action\": \"save-scene\", \"path\": \"" + path_in(dir, "out.json") + "\"}\n";
}

}  // namespace

TEST_CASE("Scripted sessions: a geodesic pick, translation, apply, undo and redo", "[editor][script]") {
    test::ScratchDir dir;
    EditorSession scripted;
    run_script("{\"action\": \"load\", \"path\": \"builtin:bar\"}\n"
               "{\"action\": \"pick\", \"vertex\": 5, \"g_min\": 0.1, \"g_max\": 0.5}\n"
               "{\"action\": \"inner-motion\", \"mode\": \"translation\"}\n"
               "{\"action\": \"set-time\", \"t\": 1}\n"
               "{\"action\": \"wait-until-time\", \"t\": 1}\n"
               "{\"action\": \"apply\"}\n"
               "{\"action\": \"twist\", \"alpha\": [0, 35]}\n"
               "{\"action\": \"set-time\", \"t\": 0.5}\n"
               "{\"action\": \"wait-until-time\", \"t\": 0.5}\n"
               "{\"action\": \"undo\"}\n"
               "{\"action\": \"redo\"}\n"
               "{\"action\": \"wait-until-time\", \"t\": 0.5}\n"
               "{\"action\": \"expect\", \"undo_count\": 4}\n" + ending(dir),
               scripted);
    check_export_matches_saved_scene(dir, scripted);

    // The same edits as plain session calls.
    EditorSession direct;
    direct.open_mesh("builtin:bar");
    direct.pick_geodesic(5, 0.1, 0.5);
    MotionSpec curve = direct.curve();
    curve.inner_motion = InnerMotionMode::Translation;
    direct.set_curve(curve);
    direct.set_target_time(1.0);
    run_to_target(direct);
    direct.apply();
    curve = direct.curve();
    curve.twist_degrees[0] = 0.0;
    curve.twist_degrees[1] = 35.0;
    direct.set_curve(curve);
    direct.set_target_time(0.5);
    direct.undo();
    direct.redo();
    run_to_target(direct);
    CHECK(direct.positions() == scripted.positions());
}

TEST_CASE("Scripted sessions: a painted region, a dragged control point and a twist", "[editor][script]") {
    test::ScratchDir dir;
    EditorSession session;
    run_script("{\"action\": \"load\", \"path\": \"" VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json\"}\n"
               "{\"action\": \"view\", \"name\": \"front\"}\n"
               "{\"action\": \"paint\", \"tool\": \"inner\", \"radius\": 0.15, \"points\": [[542, 592], [562, 602]]}\n"
               "{\"action\": \"paint\", \"tool\": \"s\", \"radius\": 0.3, \"target\": 0.3, \"strength\": 0.6, "
               "\"points\": [[533, 583]]}\n"
               "{\"action\": \"drag\", \"index\": 3, \"to\": [640, 502]}\n"
               "{\"action\": \"drag\", \"index\": 2, \"to\": [589, 527], \"axis\": \"z\"}\n"
               "{\"action\": \"twist\", \"alpha\": [10, -30]}\n"
               "{\"action\": \"set-time\", \"t\": 0.6}\n"
               "{\"action\": \"wait-until-time\", \"t\": 0.6}\n"
               "{\"action\": \"expect\", \"time\": 0.6}\n" + ending(dir),
               session);
    CHECK(session.history().undo_count() == 5);
    check_export_matches_saved_scene(dir, session);
}

TEST_CASE("Scripted sessions: a handle placed and turned by its gizmo", "[editor][script]") {
    test::ScratchDir dir;
    EditorSession session;
    run_script("{\"action\": \"load\", \"path\": \"builtin:bar\"}\n"
               "{\"action\": \"view\", \"name\": \"iso\"}\n"
               "{\"action\": \"tool\", \"name\": \"navigate\"}\n"
               "{\"action\": \"place-handle\", \"at\": [640, 400]}\n"
               "{\"action\": \"gizmo\", \"part\": \"ring-y\", \"degrees\": 30}\n"
               "{\"action\": \"gizmo\", \"part\": \"centre\", \"by\": [60, -20]}\n"
               "{\"action\": \"set-time\", \"t\": 1}\n"
               "{\"action\": \"wait-until-time\", \"t\": 1}\n" + ending(dir),
               session);
    CHECK(session.curve().curve.is_handle);
    check_export_matches_saved_scene(dir, session);
}

TEST_CASE("Scripted sessions: a loaded scene plays to its target_time; undo of apply plays back to the applied pose",
          "[editor][script][apply]") {
    test::ScratchDir dir;
    EditorSession saved;
    saved.open_mesh("builtin:bar");
    saved.pick_geodesic(5, 0.1, 0.5);
    saved.set_target_time(0.7);
    saved.save_scene(path_in(dir, "bar-0.7.json"));

    EditorSession scripted;
    run_script("{\"action\": \"load\", \"path\": \"" + path_in(dir, "bar-0.7.json") + "\"}\n"
               "{\"action\": \"wait-until-time\", \"t\": 0.7}\n"
               "{\"action\": \"expect\", \"time\": 0.7}\n"
               "{\"action\": \"apply\"}\n"
               "{\"action\": \"expect\", \"time\": 0, \"undo_count\": 1}\n"
               "{\"action\": \"undo\"}\n"
               "{\"action\": \"wait-until-time\", \"t\": 0.7}\n"
               "{\"action\": \"expect\", \"time\": 0.7, \"undo_count\": 0}\n"
               "{\"action\": \"redo\"}\n"
               "{\"action\": \"expect\", \"time\": 0, \"undo_count\": 1}\n",
               scripted);
    // The redone apply baked the pose at t = 0.7, as the saved scene deforms it.
    CHECK(scripted.target_time() == 0.0);
    CHECK(scripted.base_positions() == deform_scene_file(path_in(dir, "bar-0.7.json")));
}

TEST_CASE("Scripted sessions: a wait logs the frames it waited, its time, its longest frame and the frames drawn", "[editor][script]") {
    EditorSession session;
    ToolController tools;
    Camera camera;
    EditorSettings settings;
    const Viewport viewport{1280, 800};
    HeadlessHost host(session, camera, viewport);
    ScriptRunner runner(parse_script("{\"action\": \"load\", \"path\": \"" VFSD_SOURCE_DIR
                                     "/assets/scenes/fig04-box-bend.json\"}\n"
                                     "{\"action\": \"set-time\", \"t\": 0}\n"
                                     "{\"action\": \"wait-until-time\", \"t\": 0}\n"
                                     "{\"action\": \"set-time\", \"t\": 1}\n"
                                     "{\"action\": \"wait-until-time\", \"t\": 1}\n",
                                     "session"));
    // Each frame takes at most 7 steps: the run to t = 1 waits several frames.
    // The host "draws" every other frame.
    int frames = 0;
    host.drawn = 0;
    while (runner.run_frame({session, tools, camera, settings, viewport, host})) {
        session.update(7);
        if (frames % 2 == 0) ++host.drawn;
        ++frames;
    }
    INFO(runner.error());
    REQUIRE(!runner.failed());
    REQUIRE(session.time() == 1.0);
    int waited_frames = 0;
    double total_ms = -1.0, longest_ms = -1.0;
    REQUIRE(waited(host.lines, "wait-until-time", waited_frames, total_ms, longest_ms));
    // The wait began in the frame that set the target and ended in the last one.
    CHECK(waited_frames == frames);
    CHECK(waited_frames * 7 >= 250);
    // The total is the sum of the frames, each at most the longest; the line
    // rounds both to 0.1 ms, each by up to 0.05.
    CHECK(longest_ms >= 0.0);
    CHECK(longest_ms <= total_ms);
    CHECK(total_ms <= waited_frames * (longest_ms + 0.05) + 0.05);
    // The frames drawn while it waited, as the host counts them.
    int drawn = -1;
    for (const std::string& line : host.lines)
        if (line.rfind("script: wait-until-time waited", 0) == 0) {
            const std::size_t at = line.find(", drew ");
            REQUIRE(at != std::string::npos);
            drawn = std::atoi(line.c_str() + at + 7);
        }
    CHECK(drawn == (waited_frames + 1) / 2);
    // An action that did not wait logs no such line.
    int none = 0;
    double ignored = 0.0;
    CHECK(!waited(host.lines, "set-time", none, ignored, ignored));
}
