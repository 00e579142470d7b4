// The editor's command table: arguments are validated by type, the page's command
// strings (web/vfsd-page.js) and every key binding run natively, the page's API
// answers through the Editor without a browser, and docs/commands.md lists the
// table as it is.

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "base/error.h"
#include "editor/commands.h"
#include "editor/editor.h"
#include "editor/page_api.h"
#include "test_editor_support.h"
#include "test_io_support.h"

using namespace vfsd;
using namespace vfsd::editor;
using nlohmann::json;
using vfsd::test::run_to_target;

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

class QuietHost final : public EditorHost {
public:
    void screenshot(const std::string&, bool) override {}
    void loaded() override { ++loads; }
    void log(const std::string&) override {}
    void answer_restore(bool restore) override { answers.push_back(restore); }
    int loads = 0;
    std::vector<bool> answers;
};

// The table's context on the bar, with one undo and one redo step to take.
struct TableEditor {
    EditorSession session;
    ToolController tools;
    Camera camera;
    EditorSettings settings;
    QuietHost host;

    TableEditor() {
        session.open_mesh("builtin:bar");
        tools.adapt_to(session);
        camera.frame(session.base_positions(), 1.5);
        run("add-segment");
        run("remove-segment");
        run("undo");
    }
    CommandContext context() { return {session, tools, camera, settings, Viewport{900, 600}, host}; }
    bool run(const std::string& name, const json& args = json::object()) {
        CommandContext c = context();
        return run_command(name, args, c);
    }
};

// The page's command objects written as plain literals ({ cmd: 'view', name: 'front' }),
// as JSON.
std::vector<json> page_literals(const std::string& page) {
    std::vector<json> out;
    const std::regex literal(R"(\{ cmd: '[a-z-]+'(, \w+: '[^']*')* \})");
    const std::regex key(R"((\w+): '([^']*)')");
    for (auto m = std::sregex_iterator(page.begin(), page.end(), literal); m != std::sregex_iterator(); ++m) {
        const std::string text = m->str();
        json object = json::object();
        for (auto k = std::sregex_iterator(text.begin(), text.end(), key); k != std::sregex_iterator(); ++k)
            object[(*k)[1].str()] = (*k)[2].str();
        out.push_back(object);
    }
    return out;
}

std::set<std::string> matches(const std::string& text, const std::string& pattern) {
    std::set<std::string> out;
    const std::regex re(pattern);
    for (auto m = std::sregex_iterator(text.begin(), text.end(), re); m != std::sregex_iterator(); ++m)
        out.insert((*m)[1].str());
    return out;
}

}  // namespace

TEST_CASE("Commands: arguments are checked against the table", "[editor][commands]") {
    TableEditor e;
    CHECK_THROWS_WITH(e.run("set-time"), Catch::Contains("t: missing"));
    CHECK_THROWS_WITH(e.run("set-time", {{"t", "1"}}), Catch::Contains("t: expected a number"));
    CHECK_THROWS_WITH(e.run("set-time", {{"t", 1}, {"when", 2}}), Catch::Contains("unknown argument 'when'"));
    CHECK_THROWS_WITH(e.run("view", {{"name", "sideways"}}), Catch::Contains("front|back"));
    CHECK_THROWS_WITH(e.run("drag", {{"index", 1.5}, {"to", {1, 2}}}), Catch::Contains("whole number"));
    CHECK_THROWS_WITH(e.run("paint", {{"tool", "inner"}, {"points", json::array()}}), Catch::Contains("list of [x, y]"));
    CHECK_THROWS_WITH(e.run("fly"), Catch::Contains("unknown command 'fly'"));
    // The dispatch keys of scripts and the page are not arguments.
    CHECK(e.run("set-time", {{"action", "set-time"}, {"t", 0.5}}));
    CHECK(e.run("set-time", {{"cmd", "set-time"}, {"t", 0.25}}));
    CHECK(e.session.target_time() == 0.25);
}

TEST_CASE("Commands: the page's command strings run natively", "[editor][commands][web]") {
    const std::string page = read_text(VFSD_SOURCE_DIR "/web/vfsd-page.js");
    // The page's own queries: page_api.cpp's, and the shell's context hook.
    const std::string shell = read_text(VFSD_SOURCE_DIR "/engine/editor/page_api.cpp") +
                              read_text(VFSD_SOURCE_DIR "/web/main.cpp");

    SECTION("every command the page sends is the table's or one of the page's queries") {
        const std::set<std::string> queries = matches(shell, R"re(cmd == "([a-z-]+)")re");
        const std::set<std::string> sent = matches(page, R"(cmd: '([a-z-]+)')");
        REQUIRE(sent.size() > 10);
        for (const std::string& name : sent) {
            INFO(name);
            const bool in_table = std::any_of(command_table().begin(), command_table().end(),
                                              [&](const Command& c) { return name == c.name; });
            CHECK(in_table != (queries.count(name) == 1));  // one or the other, never both
        }
    }
    SECTION("each literal command runs in an editor") {
        const std::set<std::string> queries = matches(shell, R"re(cmd == "([a-z-]+)")re");
        const std::vector<json> literals = page_literals(page);
        REQUIRE(literals.size() > 10);
        for (const json& c : literals) {
            const std::string name = c["cmd"];
            if (queries.count(name)) continue;  // a query of the page's own (state, checksum, ...)
            INFO(c.dump());
            TableEditor e;
            CHECK_NOTHROW(e.run(name, c));
        }
    }
    SECTION("the sliders' strings and their gestures") {
        TableEditor e;
        const std::size_t before = e.session.history().undo_count();
        e.run("g-range", json::parse(R"({"cmd": "g-range", "gesture": true, "g_min": 0.2})"));
        e.run("g-range", json::parse(R"({"cmd": "g-range", "gesture": true, "g_max": 0.7})"));
        e.run("end-gesture", json::parse(R"({"cmd": "end-gesture"})"));
        CHECK(e.tools.g_min == 0.2);
        CHECK(e.tools.g_max == 0.7);
        e.run("twist", json::parse(R"({"cmd": "twist", "gesture": true, "alpha": [0, 20]})"));
        e.run("twist", json::parse(R"({"cmd": "twist", "gesture": true, "alpha": [0, 40]})"));
        e.run("end-gesture", json::parse(R"({"cmd": "end-gesture"})"));
        CHECK(e.session.curve().twist_degrees[1] == 40.0);
        CHECK(e.session.history().undo_count() <= before + 2);  // one step per drag at most
        e.run("brush", json::parse(R"({"cmd": "brush", "radius": 0.3})"));
        CHECK(e.tools.brush.radius == 0.3);
        e.run("axis", json::parse(R"({"cmd": "axis", "name": "y"})"));
        CHECK(e.tools.axis == 1);
        e.run("set-time", json::parse(R"({"cmd": "set-time", "t": 0.5})"));
        CHECK(e.session.target_time() == 0.5);
        e.run("wireframe", json::parse(R"({"cmd": "wireframe", "on": true})"));
        CHECK(e.settings.wireframe);
    }
}

TEST_CASE("Commands: every key binding runs its command", "[editor][commands][keys]") {
    for (const KeyBinding& k : key_bindings()) {
        INFO(k.key);
        CHECK(key_name(k.key, false, false) == k.key);  // names are key_name's own
        TableEditor e;
        const std::string key = std::string(k.key);
        const bool ctrl = key.rfind("ctrl+", 0) == 0, shift = key.rfind("ctrl+shift+", 0) == 0;
        const std::string bare = key.substr(shift ? 11 : ctrl ? 5 : 0);
        CommandContext c = e.context();
        CHECK(run_key(bare == "space" ? " " : bare, ctrl, shift, c));
    }
    TableEditor e;
    CommandContext c = e.context();
    const double radius = e.tools.brush.radius;
    run_key("]", false, false, c);
    CHECK(e.tools.brush.radius == Approx(1.2 * radius));
    run_key("X", false, true, c);  // Shift alone does not change a key
    CHECK(e.tools.axis == 0);
    run_key("x", false, false, c);
    CHECK(e.tools.axis == -1);
    run_key("Z", true, true, c);  // ctrl+shift+z: redo
    CHECK(e.session.history().redo_count() == 0);
    CHECK_FALSE(run_key("q", false, false, c));
}

TEST_CASE("Commands: frame all keeps the view's direction, and every standard view frames mesh and curve",
          "[editor][commands][camera]") {
    TableEditor e;
    const Viewport viewport = e.context().viewport;
    const auto everything_in_view = [&] {
        // Every vertex and the curve's ends project inside the image.
        std::vector<Vec3> points = e.session.base_positions();
        points.push_back(e.session.motion().curve().at(0.0).position);
        points.push_back(e.session.motion().curve().at(1.0).position);
        for (const Vec3& p : points) {
            const glm::dvec3 pixel = e.camera.project(p, viewport);
            if (!(pixel.x >= 0 && pixel.x <= viewport.width && pixel.y >= 0 && pixel.y <= viewport.height)) return false;
        }
        return true;
    };
    // Wander off: orbit, pan far away, zoom in hard.
    e.camera.orbit(123.0, -31.0);
    e.camera.pan(5000.0, -3000.0, viewport);
    e.camera.zoom(0.01, 10.0, 10.0, viewport);
    REQUIRE(!everything_in_view());
    const Vec3 forward = e.camera.forward();
    REQUIRE(e.run("view", {{"name", "frame"}}));
    CHECK(glm::length(e.camera.forward() - forward) < 1e-12);  // the direction kept
    CHECK(everything_in_view());
    const int loads = e.host.loads;
    for (const char* side : {"front", "back", "left", "right", "top", "bottom", "iso"}) {
        INFO(side);
        e.camera.pan(5000.0, -3000.0, viewport);
        e.camera.zoom(0.01, 10.0, 10.0, viewport);
        REQUIRE(e.run("view", {{"name", side}}));
        CHECK(everything_in_view());
        Camera turned;
        turned.set_view(standard_view_named(side));
        CHECK(glm::length(e.camera.forward() - turned.forward()) < 1e-12);
    }
    CHECK(e.host.loads == loads);  // framing is not loading
}

TEST_CASE("Commands: only the page's read-only queries leave the view as it was", "[editor][commands][web]") {
    for (const char* query : {"state", "project", "gizmo-parts", "checksum"}) CHECK(page_query(query));
    for (const Command& command : command_table()) {
        INFO(command.name);
        CHECK(!page_query(command.name));
    }
    for (const char* changes : {"open", "load-scene", "script", "key", "context"}) CHECK(!page_query(changes));
}

TEST_CASE("Commands: docs/commands.md lists the table", "[editor][commands][docs]") {
    const std::string docs = read_text(VFSD_SOURCE_DIR "/docs/commands.md");
    const std::string begin = "<!-- table: begin -->\n", end = "<!-- table: end -->";
    const std::size_t from = docs.find(begin), to = docs.find(end);
    REQUIRE(from != std::string::npos);
    REQUIRE(to != std::string::npos);
    const std::string listed = docs.substr(from + begin.size(), to - from - begin.size());
    if (listed != commands_markdown()) {
        std::ofstream(VFSD_SOURCE_DIR "/build/commands.md.expected") << commands_markdown();
        FAIL("docs/commands.md differs from the table; the table's text is in build/commands.md.expected");
    }
}

namespace {

// A window of fixed size without a GPU: the Editor as the page's shell holds it.
class TestShell final : public Shell {
public:
    Viewport viewport() const override { return {900, 600}; }
    void log(const std::string&) override {}
    void screenshot(const std::string&, bool) override {}
};

// The Editor in that window on fig. 4's scene, its autosave in `dir`.
struct ShellEditor {
    TestShell shell;
    Editor editor;
    explicit ShellEditor(const test::ScratchDir& dir) : editor(shell, {}, "no GPU in this test", options(dir)) {
        editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
    }
    static EditorOptions options(const test::ScratchDir& dir) {
        EditorOptions o;
        o.autosave_directory = dir.file("autosave");
        return o;
    }
};

}  // namespace

TEST_CASE("Commands: the page's API answers natively through the Editor", "[editor][commands][web]") {
    test::ScratchDir dir;
    ShellEditor shell_editor(dir);
    Editor& editor = shell_editor.editor;
    const PageInfo page{dir.path().string(), "test", false};
    const auto send = [&](const std::string& text) { return page_command(editor, json::parse(text), page); };

    const json state = send(R"({"cmd": "state"})");
    CHECK(state["stats"]["vertices"].get<int>() > 0);
    CHECK(state["tool"] == "navigate");
    CHECK(send(R"({"cmd": "tool", "name": "paint inner"})")["tool"] == "paint inner");
    CHECK(send(R"({"cmd": "key", "key": "g", "ctrl": false, "shift": false})")["tool"] == "geodesic");
    CHECK(send(R"({"cmd": "key", "key": "q", "ctrl": false, "shift": false})")["handled"] == false);
    CHECK_THROWS_WITH(send(R"({"cmd": "brush", "radius": "wide"})"), Catch::Contains("radius: expected a number"));
    CHECK(send(R"({"cmd": "open", "path": "no-such-file.obj"})")["load_error"] != "");
    // A missing file is named once, by its name, whatever folder it was looked for in.
    const json open_missing = {{"cmd", "open"}, {"path", dir.file("folder/model.obj")}};
    const std::string missing = page_command(editor, open_missing, page)["load_error"];
    CHECK(missing.rfind("model.obj: cannot open", 0) == 0);
    CHECK(missing.find("folder") == std::string::npos);

    // Time runs in frames, as the page's runTo waits for them.
    send(R"({"cmd": "set-time", "t": 0.5})");
    while (editor.session().moving()) editor.advance();
    const double moved = send(R"({"cmd": "checksum"})")["checksum"];
    const json exported = send(R"({"cmd": "export-mesh", "format": "obj"})");
    CHECK(std::filesystem::exists(exported["path"].get<std::string>()));
    const json scene = send(R"({"cmd": "export-scene"})")["scene"];
    CHECK(scene["target_time"] == 0.5);
    send(R"({"cmd": "key", "key": "r"})");  // reset
    CHECK(send(R"({"cmd": "checksum"})")["checksum"] != moved);

    // The pointer's aim: a mesh point's pixel, and the gizmo's parts once a handle is placed.
    const Vec3 centre = editor.camera().target;
    const json pixels = send(R"({"cmd": "project", "points": [[)" + std::to_string(centre.x) + ", " +
                             std::to_string(centre.y) + ", " + std::to_string(centre.z) + "]]}")["pixels"];
    CHECK(pixels[0][0].get<double>() == Approx(450.0).margin(1.0));  // the view's centre
    CHECK(pixels[0][1].get<double>() == Approx(300.0).margin(1.0));
    CHECK(send(R"({"cmd": "gizmo-parts"})")["parts"].is_null());
    send(R"({"cmd": "place-handle", "at": [450, 300]})");
    CHECK(send(R"({"cmd": "gizmo-parts"})")["parts"].contains("ring-z"));

    // The overlay the page paints: the handle's two points and its gizmo.
    const json overlay = overlay_json(editor.overlay(std::nullopt));
    CHECK(overlay["points"].size() == 2);
    CHECK(overlay["gizmo"].is_object());
}

TEST_CASE("Commands: the up axis turns the view, is saved in the scene and remembered for the file type",
          "[editor][commands][camera]") {
    test::ScratchDir dir;
    ShellEditor shell_editor(dir);
    Editor& editor = shell_editor.editor;
    CHECK(editor.session().up_axis() == 'z');
    CHECK(glm::length(editor.camera().world_up() - Vec3(0, 0, 1)) < 1e-12);

    editor.command("up-axis", {{"axis", "y"}});
    CHECK(editor.session().up_axis() == 'y');
    CHECK(glm::length(editor.camera().world_up() - Vec3(0, 1, 0)) < 1e-12);
    editor.session().save_scene(dir.file("y-up.json"));
    CHECK(load_scene(dir.file("y-up.json")).up_axis == 'y');

    // The next mesh of the same type opens Y-up; a scene opens as it says.
    REQUIRE(editor.open("builtin:bar"));
    CHECK(editor.session().up_axis() == 'y');
    CHECK(glm::length(editor.camera().world_up() - Vec3(0, 1, 0)) < 1e-12);
    REQUIRE(editor.open(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json"));
    CHECK(editor.session().up_axis() == 'z');
    CHECK(glm::length(editor.camera().world_up() - Vec3(0, 0, 1)) < 1e-12);
    CHECK_THROWS_AS(editor.command("up-axis", {{"axis", "x"}}), InputError);
}

TEST_CASE("Commands: the start-up scene waits at rest, an opened scene plays to its target, a scene and its mesh open together",
          "[editor][commands][open]") {
    test::ScratchDir dir;
    ShellEditor shell_editor(dir);
    Editor& editor = shell_editor.editor;
    const PageInfo page{dir.path().string(), "test", false};
    const auto send = [&](const json& command) { return page_command(editor, command, page); };
    CHECK(editor.session().target_time() == 0.0);
    for (int frames = 0; editor.busy() && frames < 1000; ++frames) editor.advance();  // the region's parts
    CHECK_FALSE(editor.busy());
    CHECK(editor.session().time() == 0.0);

    // fig. 4's scene with target_time 0.3, its mesh a file the scene names by a path that is not there.
    std::filesystem::create_directories(dir.file("elsewhere"));
    write_mesh_file(dir.file("elsewhere/box.ply"), load_mesh_file("builtin:box").mesh);
    json scene = scene_to_json(load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json"));
    scene["mesh"] = "meshes/box.ply";
    scene["target_time"] = 0.3;
    test::write_bytes(dir.file("box-scene.json"), scene.dump());

    const json failed = send({{"cmd", "open"}, {"path", dir.file("box-scene.json")}});
    CHECK(failed["load_error"].get<std::string>().find("box-scene.json: its mesh box.ply") == 0);
    CHECK(failed["load_error"].get<std::string>().find("choose box.ply") != std::string::npos);
    CHECK(send({{"cmd", "state"}})["missing_mesh"] == "box.ply");
    CHECK(editor.session().mesh_name() == "builtin:box");

    // The mesh chosen next completes the scene, which plays to its target.
    CHECK(send({{"cmd", "open"}, {"path", dir.file("elsewhere/box.ply")}})["load_error"] == "");
    json state = send({{"cmd", "state"}});
    CHECK(state["mesh"] == dir.file("elsewhere/box.ply"));
    CHECK(state["missing_mesh"] == "");
    CHECK(state["target_time"] == 0.3);
    CHECK(editor.busy());
    while (editor.busy()) editor.advance();
    CHECK(editor.session().time() == 0.3);

    // Both at once: paired by the mesh's file name.
    REQUIRE(editor.open("builtin:bar"));
    CHECK(send({{"cmd", "open"}, {"paths", {dir.file("elsewhere/box.ply"), dir.file("box-scene.json")}}})["load_error"] == "");
    state = send({{"cmd", "state"}});
    CHECK(state["mesh"] == dir.file("elsewhere/box.ply"));
    CHECK(state["target_time"] == 0.3);
    CHECK(editor.status() == "opened box-scene.json");
    CHECK(state["stats"]["volume_text"].get<std::string>().find("since opened") != std::string::npos);
}

TEST_CASE("Frames: steps longer than the split limit run in pieces over frames, the same steps", "[editor][frames]") {
    // With no limit every step after the first (which no rate predicts) runs in
    // pieces: its estimates, its move, then the rest; without, none does. A
    // budget of 0 gives each frame one step or one piece; a frame's budget fits
    // several pieces of this small scene.
    struct Run {
        std::vector<Vec3> positions;
        int frames = 0, frames_without_time = 0;
    };
    const auto run = [](double split_step_ms, double budget_ms, double split_affine_step_ms = 1e9) {
        test::ScratchDir dir;
        TestShell shell;
        EditorOptions options = ShellEditor::options(dir);
        options.split_step_ms = split_step_ms;
        options.split_affine_step_ms = split_affine_step_ms;
        options.step_budget_ms = options.max_frame_ms = budget_ms;
        Editor editor(shell, {}, "no GPU in this test", options);
        editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
        editor.session().set_target_time(1.0);
        Run r;
        while (editor.session().moving()) {
            const double before = editor.session().time();
            editor.advance();
            ++r.frames;
            if (editor.session().time() == before) ++r.frames_without_time;
        }
        CHECK(editor.session().time() == 1.0);
        r.positions = editor.session().positions();
        return r;
    };
    const Run whole = run(1e9, 0.0), split = run(0.0, 0.0), packed = run(0.0, 1e3);
    CHECK(split.positions == whole.positions);
    CHECK(packed.positions == whole.positions);
    INFO("frames: whole steps " << whole.frames << " (" << whole.frames_without_time << " without a step), split "
                                << split.frames << " (" << split.frames_without_time << "), packed " << packed.frames);
    // One step or piece a frame: whole, every frame past the run's preparation
    // takes a step; split, every step but the first has two frames that only
    // prepared its pieces (a try over the tolerance one more).
    const int steps = whole.frames - whole.frames_without_time;
    CHECK(steps > 3);
    CHECK(split.frames - split.frames_without_time == steps);
    CHECK(split.frames_without_time >= whole.frames_without_time + 2 * (steps - 1));
    CHECK(split.frames_without_time <= whole.frames_without_time + 3 * (steps - 1));
    // A budget that fits many pieces packs them into few frames.
    CHECK(packed.frames < whole.frames);
    // With only the affine test's steps split (the scene's 250 fixed steps pass
    // its times at t = 0.2, 0.4, 0.6, 0.8 and 1), those five steps run in
    // pieces, each with three frames that only prepare (its estimates, its move,
    // its fold test), and the others whole.
    const Run affine = run(1e9, 0.0, 0.0);
    CHECK(affine.positions == whole.positions);
    CHECK(affine.frames - affine.frames_without_time == steps);
    CHECK(affine.frames_without_time == whole.frames_without_time + 3 * 5);
}

TEST_CASE(
    "Frames: a frame's whole steps stop before the affine test's step, which runs in pieces, whatever the "
    "chunk they fell in",
    "[editor][frames]") {
    // With only that step split and a budget that fits the whole run, each frame
    // that steps ends right after a step through a time of the affine test (the
    // pieces end the frame once that step is done). The frame after a stop two
    // steps before such a time takes one step first (a run's first chunk), so
    // its second chunk would start with that step: it too ends at the test's
    // time, not at the next one. The steps are those of a run that does not stop.
    const auto editor_on_box = [](test::ScratchDir& dir, TestShell& shell) {
        EditorOptions options = ShellEditor::options(dir);
        options.split_step_ms = 1e9;
        options.split_affine_step_ms = 0.0;
        options.step_budget_ms = options.max_frame_ms = 1e5;
        auto editor = std::make_unique<Editor>(shell, DeformationFactory{}, "no GPU in this test", options);
        editor->open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
        return editor;
    };
    const auto run_to = [](Editor& editor, double target) {
        editor.session().set_target_time(target);
        std::vector<double> ends;  // the times the frames that stepped ended at
        for (int frames = 0; editor.session().moving() && frames < 10000; ++frames) {
            const double before = editor.session().time();
            editor.advance();
            if (editor.session().time() != before) ends.push_back(editor.session().time());
        }
        CHECK(editor.session().time() == target);
        return ends;
    };
    test::ScratchDir dir;
    TestShell shell;
    std::unique_ptr<Editor> editor = editor_on_box(dir, shell);
    const double two_steps_before = 48.0 / 250.0;  // the 250 steps' 50th ends at t = 0.2
    run_to(*editor, two_steps_before);
    editor->advance();  // a frame at the target: no step, so the next run's first chunk is one step
    const std::vector<double> ends = run_to(*editor, 1.0);
    INFO("the frames that stepped ended at " << ::Catch::Detail::stringify(ends));
    REQUIRE(ends.size() == 5);
    for (std::size_t i = 0; i < ends.size(); ++i) CHECK(ends[i] == Approx(0.2 * double(i + 1)).margin(1e-12));

    test::ScratchDir dir_through;
    TestShell shell_through;
    std::unique_ptr<Editor> through = editor_on_box(dir_through, shell_through);
    run_to(*through, 1.0);
    CHECK(editor->session().positions() == through->session().positions());
}

TEST_CASE("Frames: a preparation that leaves most of the frame's budget steps in the same frame", "[editor][frames]") {
    // Editor::integrate_for goes on from a preparation part to the next, and to
    // the first step, while the frame has used under half its budget: with a
    // budget of 100 s (the preparation takes far less, under AddressSanitizer
    // and on a busy machine too) the frame that prepares the run also steps;
    // with none it only prepares, each part in a frame of its own. Both end alike.
    std::vector<Vec3> ends[2];
    for (const int k : {0, 1}) {
        const double budget = k == 0 ? 0.0 : 1e5;
        INFO("budget " << budget << " ms");
        test::ScratchDir dir;
        TestShell shell;
        EditorOptions options = ShellEditor::options(dir);
        options.step_budget_ms = options.max_frame_ms = budget;
        Editor editor(shell, {}, "no GPU in this test", options);
        editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
        editor.session().set_target_time(1.0);
        editor.advance();
        if (budget == 0.0)
            CHECK(editor.session().time() == 0.0);
        else
            CHECK(editor.session().time() > 0.0);
        int frames = 1;
        for (; editor.session().moving() && frames < 10000; ++frames) editor.advance();
        CHECK(editor.session().time() == 1.0);
        ends[k] = editor.session().positions();
    }
    CHECK(ends[0] == ends[1]);
}

TEST_CASE("Frames: a pick's region is computed over frames the editor stays busy for, as at once", "[editor][frames]") {
    // A budget of 0 gives each frame one iteration of the blend's solve. The
    // pick's frame (the command) computes only which vertices move; the frames
    // after it the blend's values, and then the run to the target. A shell that
    // keeps its image draws only once the region is built.
    struct ImageShell final : Shell {
        Viewport viewport() const override { return {900, 600}; }
        void log(const std::string&) override {}
        void screenshot(const std::string&, bool) override {}
        bool keeps_image() const override { return true; }
    };
    test::ScratchDir dir;
    ImageShell shell;
    EditorOptions options = ShellEditor::options(dir);
    options.step_budget_ms = options.max_frame_ms = 0.0;
    Editor editor(shell, {}, "no GPU in this test", options);
    editor.command("load", {{"path", "builtin:sphere:3"}});
    EditorSession at_once;
    at_once.open_mesh("builtin:sphere:3");
    for (const double target : {0.0, 0.4}) {
        INFO("target " << target);
        editor.session().set_target_time(target);
        at_once.set_target_time(target);
        while (editor.busy()) editor.advance();
        run_to_target(at_once);
        editor.command("pick", {{"vertex", 40}, {"g_min", 0.2}, {"g_max", 0.9}});
        at_once.pick_geodesic(40, 0.2, 0.9);
        CHECK(editor.session().region_pending());
        CHECK(editor.busy());
        int frames = 0;
        while (editor.session().region_pending()) {
            editor.advance();
            ++frames;
            CHECK(editor.session().time() == 0.0);  // no step before the region is built
            if (editor.session().region_pending()) CHECK_FALSE(editor.draw_due());
        }
        CHECK(frames > 3);
        // The region's final s is drawn, unless the last result stays on show until the run ends.
        CHECK(editor.draw_due() == !editor.session().holding_result());
        CHECK(editor.session().holding_result() == (target > 0.0));
        CHECK(editor.session().s() == at_once.s());
        while (editor.busy()) editor.advance();
        run_to_target(at_once);
        CHECK(editor.session().time() == target);
        CHECK(editor.session().positions() == at_once.positions());
    }
}

TEST_CASE("Frames: an apply while a run catches up waits for it over frames and bakes what it reaches",
          "[editor][frames]") {
    // EditorSession::apply runs the rest of the run in one call; the editors' apply
    // (the command, its key) leaves the run to the frames, one step each here, and
    // the frame that reaches the target bakes: the base a session that applied at
    // once bakes, bit for bit. A command that changes the document first bakes a
    // due apply; one that changes the view leaves it waiting.
    const auto edited = [](Editor& editor) {
        editor.session().set_target_time(1.0);
        while (editor.session().moving()) editor.advance();
        std::vector<Vec3> points = editor.session().control_points();
        editor.session().move_control_point(3, points[3] + 0.1 * editor.session().diagonal() * Vec3(1.0, -0.5, 0.2));
        REQUIRE(editor.session().holding_result());
    };
    test::ScratchDir dir;
    TestShell shell;
    EditorOptions options = ShellEditor::options(dir);
    options.step_budget_ms = options.max_frame_ms = 0.0;  // a step a frame
    Editor at_once(shell, {}, "no GPU in this test", options);
    at_once.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
    edited(at_once);
    at_once.session().apply();
    const std::vector<Vec3> baked = at_once.session().base_positions();

    for (const bool by_key : {false, true}) {
        INFO((by_key ? "the key" : "the command"));
        Editor editor(shell, {}, "no GPU in this test", options);
        editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
        const std::vector<Vec3> at_rest = editor.session().base_positions();
        edited(editor);
        const std::size_t edits = editor.session().history().undo_count();
        if (by_key)
            CHECK(editor.key("a", false, false));
        else
            editor.command("apply");
        CHECK(editor.apply_due());
        CHECK(editor.session().moving());
        CHECK(editor.session().base_positions() == at_rest);
        editor.command("view", {{"name", "front"}});
        CHECK(editor.apply_due());
        int frames = 0;
        for (; editor.apply_due() && frames < 10000; ++frames) editor.advance();
        CHECK(frames > 2);
        CHECK(editor.session().base_positions() == baked);
        CHECK(editor.session().history().undo_count() == edits + 1);
        CHECK(editor.session().time() == 0.0);
        CHECK_FALSE(editor.session().moving());
    }

    // A press that turns the view (off the mesh, no control point there) leaves
    // the apply to the frames; one a tool takes (the brush, on the mesh) bakes it
    // first, as a command that changes the document does.
    for (const bool on_mesh : {false, true}) {
        INFO((on_mesh ? "a brush press on the mesh" : "an orbit press off the mesh"));
        Editor editor(shell, {}, "no GPU in this test", options);
        editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
        edited(editor);
        editor.command("apply");
        REQUIRE(editor.apply_due());
        if (on_mesh) editor.command("tool", {{"name", "paint inner"}});
        const Viewport v = editor.viewport();
        const glm::dvec2 at = on_mesh ? glm::dvec2(v.width / 2.0, v.height / 2.0) : glm::dvec2(2.0, 2.0);
        const Camera before = editor.camera();
        editor.press(at.x, at.y, false);
        editor.move(at.x + 30.0, at.y + 10.0);
        editor.release();
        if (on_mesh) {
            CHECK_FALSE(editor.apply_due());
            CHECK(editor.session().base_positions() == baked);
            continue;
        }
        CHECK(editor.apply_due());
        CHECK(editor.session().moving());
        CHECK(editor.camera().view() != before.view());  // it orbited
        int frames = 0;
        for (; editor.apply_due() && frames < 10000; ++frames) editor.advance();
        CHECK(frames > 2);
        CHECK(editor.session().base_positions() == baked);
    }

    // An undo right after the apply: the apply is baked first, and the undo takes
    // it back to the time it was of.
    Editor editor(shell, {}, "no GPU in this test", options);
    editor.open_default(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json", false);
    const std::vector<Vec3> at_rest = editor.session().base_positions();
    edited(editor);
    editor.command("apply");
    REQUIRE(editor.apply_due());
    editor.command("undo");
    CHECK_FALSE(editor.apply_due());
    CHECK(editor.session().base_positions() == at_rest);
    CHECK(editor.session().target_time() == 1.0);
    CHECK(editor.session().redo());
    CHECK(editor.session().base_positions() == baked);
}
