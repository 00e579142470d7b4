// The editors' autosave: written only after a change and at most once per
// interval; restored it gives the saved session back (scene and shape); a
// corrupt or truncated autosave is reported and ignored without touching the
// current session; a failed save is a warning, never an exception; clear
// removes it.

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <optional>

#include "base/error.h"
#include "editor/autosave.h"
#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

using namespace std::chrono_literals;

void run_to_target(EditorSession& session) {
    while (session.moving()) session.update(5);
}

SurfacePoint at_vertex_nearest(const EditorSession& session, Vec3 p) {
    return surface_point_at_vertex(session.triangles(), session.base_positions().size(),
                                   nearest_vertex(session.base_positions(), p));
}

// The session's scene as JSON without the mesh path (a restored session edits
// the autosave's copy of the mesh).
nlohmann::json scene_without_mesh(const EditorSession& session) {
    nlohmann::json j = scene_to_json(session.current_scene());
    j.erase("mesh");
    return j;
}

void open_box(EditorSession& session) {
    Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json");
    scene.options.steps = 40;
    session.open_scene(scene);
}

void drag_last_point(EditorSession& session, Vec3 by) {
    const std::size_t last = session.control_points().size() - 1;
    session.move_control_point(last, session.control_points()[last] + by);
}

bool has_slot_files(const test::ScratchDir& dir) {
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
        if (entry.path().filename().string().rfind("session-", 0) == 0) return true;
    return false;
}

// Puts an environment variable back as it was.
class EnvironmentKept {
public:
    explicit EnvironmentKept(const char* name) : name_(name) {
        const char* value = std::getenv(name);
        if (value) value_ = value;
    }
    ~EnvironmentKept() {
        if (value_) ::setenv(name_, value_->c_str(), 1);
        else ::unsetenv(name_);
    }

private:
    const char* name_;
    std::optional<std::string> value_;
};

}  // namespace

TEST_CASE("Autosave: nothing is written while nothing changed", "[editor][autosave]") {
    test::ScratchDir dir;
    EditorSession session;
    open_box(session);
    Autosave autosave(dir.file("autosave"), 10.0);
    autosave.mark_saved(session);
    const auto t0 = Autosave::Clock::now();
    CHECK_FALSE(autosave.maybe_save(session, t0));
    // Time advancing toward the target is not a change of the document.
    session.set_target_time(0.5);
    REQUIRE(autosave.maybe_save(session, t0));
    const std::uint64_t revision = session.document_revision();
    run_to_target(session);
    CHECK(session.document_revision() == revision);
    CHECK_FALSE(autosave.maybe_save(session, t0 + 60s));
}

TEST_CASE("Autosave: an edit is written, at most once per interval", "[editor][autosave]") {
    test::ScratchDir dir;
    EditorSession session;
    open_box(session);
    Autosave autosave(dir.file("autosave"), 10.0);
    autosave.mark_saved(session);
    CHECK_FALSE(autosave.find());

    const auto t0 = Autosave::Clock::now();
    drag_last_point(session, {0.0, 0.2, 0.1});
    REQUIRE(autosave.maybe_save(session, t0));
    const auto first = autosave.find();
    REQUIRE(first);
    CHECK(first->mesh == "builtin:box");
    CHECK(first->written > 0);
    CHECK(first->written_text().size() == 16);  // "YYYY-MM-DD HH:MM"

    drag_last_point(session, {0.0, 0.1, 0.0});
    CHECK_FALSE(autosave.maybe_save(session, t0 + 5s));  // within the interval
    CHECK(autosave.maybe_save(session, t0 + 11s));
    CHECK_FALSE(autosave.maybe_save(session, t0 + 30s));  // nothing new
    // A save goes to another slot than the last; the manifest names the newest.
    CHECK(autosave.find()->scene != first->scene);
}

TEST_CASE("Autosave: restore gives the saved session back", "[editor][autosave]") {
    test::ScratchDir dir;
    EditorSession session;
    std::string mesh_name;
    SECTION("painted labels and a dragged control point") {
        open_box(session);
        BrushSettings brush;
        brush.radius = 0.25;
        session.brush(at_vertex_nearest(session, {0.5, 0.0, 0.1}), brush);
        drag_last_point(session, {0.0, 0.3, 0.1});
        mesh_name = "builtin:box";
    }
    SECTION("after an apply: the baked mesh is saved") {
        open_box(session);
        session.set_target_time(1.0);
        run_to_target(session);
        session.apply();
        drag_last_point(session, {0.1, 0.0, 0.1});
        mesh_name = "builtin:box";
    }
    SECTION("a mesh file that is gone by the time of the restore: the autosave keeps a copy") {
        write_mesh_file(dir.file("bar.obj"), load_mesh("builtin:bar"));
        session.open_mesh(dir.file("bar.obj"));
        drag_last_point(session, {0.3, 0.0, 0.0});
        mesh_name = dir.file("bar.obj");
    }
    session.set_target_time(0.6);
    run_to_target(session);
    Autosave autosave(dir.file("autosave"));
    REQUIRE(autosave.save(session));
    std::filesystem::remove(dir.file("bar.obj"));

    // A restarted editor: a new session and a new Autosave on the same folder.
    EditorSession restored;
    restored.open_mesh("builtin:sphere");
    Autosave again(dir.file("autosave"));
    const auto info = again.find();
    REQUIRE(info);
    CHECK(info->mesh == mesh_name);
    REQUIRE(again.restore(restored));
    CHECK(scene_without_mesh(restored) == scene_without_mesh(session));
    CHECK(restored.target_time() == 0.6);
    CHECK(restored.history().undo_count() == 0);
    run_to_target(restored);
    CHECK(restored.positions() == session.positions());
    CHECK(restored.warnings() == session.warnings());

    // Nothing to save until the restored session changes; then the user's mesh name stays.
    CHECK_FALSE(again.maybe_save(restored));
    drag_last_point(restored, {0.0, 0.0, 0.05});
    REQUIRE(again.maybe_save(restored));
    CHECK(again.find()->mesh == mesh_name);
}

TEST_CASE("Autosave: a restored session's own mesh file is never written over", "[editor][autosave]") {
    test::ScratchDir dir;
    {
        EditorSession baked;
        open_box(baked);
        baked.set_target_time(1.0);
        run_to_target(baked);
        baked.apply();
        REQUIRE(Autosave(dir.path().string()).save(baked));
    }
    // Restored, the session's base mesh is the autosave's file; apply again, save
    // into every slot, undo the apply: the autosave has the restored base again.
    EditorSession restored;
    Autosave autosave(dir.path().string());
    REQUIRE(autosave.restore(restored));
    const std::vector<Vec3> base = restored.base_positions();
    restored.set_target_time(1.0);
    run_to_target(restored);
    restored.apply();
    for (int k = 0; k < 3; ++k) {
        drag_last_point(restored, {0.0, 0.0, 0.05});
        REQUIRE(autosave.save(restored));
    }
    for (int k = 0; k < 4; ++k) REQUIRE(restored.undo());
    REQUIRE(restored.base_positions() == base);
    REQUIRE(autosave.save(restored));
    EditorSession again;
    REQUIRE(Autosave(dir.path().string()).restore(again));
    CHECK(again.base_positions() == base);
}

TEST_CASE("Autosave: a corrupt or truncated autosave is reported and ignored", "[editor][autosave]") {
    test::ScratchDir dir;
    const std::string folder = dir.file("autosave");
    {
        EditorSession saved;
        open_box(saved);
        drag_last_point(saved, {0.0, 0.2, 0.0});
        REQUIRE(Autosave(folder).save(saved));
    }
    const std::string manifest = folder + "/autosave.json";
    const std::string scene = folder + "/session-a.json";
    SECTION("a truncated scene") {
        const std::string text = test::read_bytes(scene);
        test::write_bytes(scene, text.substr(0, text.size() / 2));
    }
    SECTION("an empty scene") { test::write_bytes(scene, ""); }
    SECTION("a truncated manifest") { test::write_bytes(manifest, "{\"scene\": \"session-a.js"); }
    SECTION("a manifest naming a file outside the autosave") {
        test::write_bytes(manifest, "{\"scene\": \"../../etc/passwd\", \"mesh\": \"x\", \"written\": 1}");
    }
    SECTION("a scene whose mesh is gone") {
        nlohmann::json j = nlohmann::json::parse(test::read_bytes(scene));
        j["mesh"] = "missing.ply";
        test::write_bytes(scene, j.dump());
    }

    EditorSession session;
    session.open_mesh("builtin:bar");
    drag_last_point(session, {0.5, 0.0, 0.0});
    const std::vector<Vec3> points = session.control_points();
    Autosave autosave(folder);
    CHECK_FALSE(autosave.find());
    CHECK_THAT(autosave.problem(), Catch::StartsWith("autosave ignored: ") && Catch::Contains(folder));
    CHECK_FALSE(autosave.restore(session));
    CHECK(session.mesh_name() == "builtin:bar");
    CHECK(session.control_points() == points);
    CHECK(session.history().undo_count() == 1);
    const auto warnings = session.warnings();
    CHECK(std::count(warnings.begin(), warnings.end(), autosave.problem()) == 1);
    // The next autosave replaces it.
    REQUIRE(autosave.save(session));
    REQUIRE(autosave.find());
    CHECK(autosave.find()->mesh == "builtin:bar");
    CHECK(session.warnings().size() == warnings.size() - 1);
}

TEST_CASE("Autosave: a failed save is a warning, and the next success clears it", "[editor][autosave]") {
    test::ScratchDir dir;
    test::write_bytes(dir.file("blocker"), "a file where the folder should be");
    EditorSession session;
    session.open_mesh("builtin:bar");
    drag_last_point(session, {0.5, 0.0, 0.0});
    const std::uint64_t revision = session.document_revision();
    const std::size_t warnings = session.warnings().size();
    Autosave autosave(dir.file("blocker/autosave"));
    bool saved = true;
    CHECK_NOTHROW(saved = autosave.save(session));
    CHECK_FALSE(saved);
    REQUIRE_FALSE(session.warnings().empty());
    CHECK_THAT(session.warnings().back(), Catch::StartsWith("autosave failed: "));
    CHECK(session.document_revision() == revision);
    std::filesystem::remove(dir.file("blocker"));
    CHECK(autosave.save(session));
    CHECK(session.warnings().size() == warnings);
}

TEST_CASE("Autosave: clear removes it and nothing else", "[editor][autosave]") {
    test::ScratchDir dir;
    EditorSession session;
    write_mesh_file(dir.file("bar.obj"), load_mesh("builtin:bar"));
    session.open_mesh(dir.file("bar.obj"));
    session.set_target_time(1.0);
    run_to_target(session);
    session.apply();
    Autosave autosave(dir.path().string());
    REQUIRE(autosave.save(session));
    drag_last_point(session, {0.0, 0.0, 0.1});
    REQUIRE(autosave.save(session));  // two slots in use
    REQUIRE(has_slot_files(dir));
    autosave.clear();
    CHECK_FALSE(autosave.find());
    CHECK(autosave.problem().empty());
    CHECK_FALSE(has_slot_files(dir));
    CHECK_FALSE(std::filesystem::exists(dir.file("autosave.json")));
    CHECK(std::filesystem::exists(dir.file("bar.obj")));
}

TEST_CASE("Autosave: the start-up offer stands until answered", "[editor][autosave]") {
    test::ScratchDir dir;
    {
        EditorSession edited;
        open_box(edited);
        drag_last_point(edited, {0.0, 0.2, 0.0});
        REQUIRE(Autosave(dir.path().string()).save(edited));
    }
    EditorSession session;
    session.open_mesh("builtin:bar");
    Autosave autosave(dir.path().string());
    autosave.mark_saved(session);
    autosave.offer_restore(session);
    REQUIRE(autosave.offer());
    CHECK(autosave.offer()->mesh == "builtin:box");
    // Unanswered, the offer keeps the autosave: a change of the session is not saved over it.
    drag_last_point(session, {0.2, 0.0, 0.0});
    CHECK_FALSE(autosave.maybe_save(session));
    SECTION("discarded") {
        CHECK_FALSE(autosave.answer(session, false));
        CHECK(session.mesh_name() == "builtin:bar");
        CHECK_FALSE(autosave.find());
        CHECK_FALSE(autosave.maybe_save(session));  // the session as it is needs no saving
    }
    SECTION("restored") {
        CHECK(autosave.answer(session, true));
        CHECK(session.mesh_name() == "builtin:box");
    }
    CHECK_FALSE(autosave.offer());
    CHECK_THROWS_AS(autosave.answer(session, true), InputError);
}

TEST_CASE("Autosave: the default folder follows VFSD_AUTOSAVE_DIR, then XDG_STATE_HOME", "[editor][autosave]") {
    const EnvironmentKept autosave_dir("VFSD_AUTOSAVE_DIR"), state_home("XDG_STATE_HOME");
    ::setenv("VFSD_AUTOSAVE_DIR", "/tmp/vfsd-here", 1);
    CHECK(default_autosave_directory() == "/tmp/vfsd-here");
    ::unsetenv("VFSD_AUTOSAVE_DIR");
    ::setenv("XDG_STATE_HOME", "/tmp/state", 1);
    CHECK(default_autosave_directory() == "/tmp/state/vfsd/autosave");
    ::unsetenv("XDG_STATE_HOME");
    CHECK_THAT(default_autosave_directory(), Catch::EndsWith("/.local/state/vfsd/autosave"));
}
