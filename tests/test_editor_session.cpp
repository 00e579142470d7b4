// The editor session: what it saves is what `vfsd deform` computes, failed loads,
// saves, exports and integrations keep the last good state and say why, a plain
// mesh opens ready to deform, scripts parse.

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>

#include "base/error.h"
#include "deform/cpu_steps.h"
#include "deform/quality.h"
#include "editor/script.h"
#include "editor/session.h"
#include "io/mesh_file.h"
#include "region/selectors.h"
#include "test_editor_support.h"
#include "test_fold_support.h"
#include "test_io_support.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

using test::deform_scene_file;
using test::run_to_target;

SurfacePoint at_vertex_nearest(const EditorSession& session, Vec3 p) {
    return surface_point_at_vertex(session.triangles(), session.base_positions().size(),
                                   nearest_vertex(session.base_positions(), p));
}

// The folding box (which folds without the repair) opened in `session` with
// the repair and error-controlled steps, run to t = 1 a step at a time: the
// times and shapes of the way out.
std::vector<std::pair<double, std::vector<Vec3>>> repaired_way_out(EditorSession& session) {
    Scene scene = test::folding_box_scene();
    scene.options.repair_folds = true;
    scene.options.tolerance = 5e-4;
    scene.target_time = 0.0;
    session.open_scene(scene);
    std::vector<std::pair<double, std::vector<Vec3>>> way_out;
    session.set_target_time(1.0);
    while (session.moving()) {
        session.update(1);
        way_out.emplace_back(session.time(), session.positions());
    }
    REQUIRE(session.deformation()->fold_repairs().steps_repaired > 0);
    return way_out;
}

}  // namespace

TEST_CASE("EditorSession: save, load and deform give the session's own result", "[editor][session]") {
    test::ScratchDir dir;
    EditorSession session;
    Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json");
    scene.options.steps = 40;
    session.open_scene(scene);

    SECTION("painted labels and a dragged control point") {
        BrushSettings brush;
        brush.radius = 0.25;
        session.brush(at_vertex_nearest(session, {0.5, 0.0, 0.1}), brush);
        session.move_control_point(3, session.control_points()[3] + Vec3(0.0, 0.3, 0.1));
    }
    SECTION("a painted field, a twist and translation mode") {
        BrushSettings brush;
        brush.tool = BrushTool::paint_s;
        brush.radius = 0.4;
        brush.s_target = 0.2;
        session.brush(at_vertex_nearest(session, {0.5, 0.5, 0.5}), brush);
        MotionSpec curve = session.curve();
        curve.twist_degrees[1] = 40.0;
        curve.inner_motion = InnerMotionMode::Translation;
        session.set_curve(curve);
    }
    SECTION("a geodesic region") {
        session.pick_geodesic(nearest_vertex(session.base_positions(), {0.0, 0.0, 0.5}), 0.2, 0.6);
    }
    SECTION("after an apply, with the baked mesh saved beside the scene") {
        session.set_target_time(1.0);
        run_to_target(session);
        session.apply();
        session.move_control_point(3, session.control_points()[3] + Vec3(0.1, 0.0, 0.1));
    }
    session.set_target_time(0.75);
    run_to_target(session);
    REQUIRE(session.time() == 0.75);
    const std::string path = dir.file("saved.json");
    session.save_scene(path);
    CHECK(deform_scene_file(path) == session.positions());
}

TEST_CASE("EditorSession: a run prepared a part per frame steps as one that is not", "[editor][session]") {
    Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json");
    scene.options.steps = 40;
    EditorSession framed, plain;
    framed.open_scene(scene);
    plain.open_scene(scene);
    framed.set_target_time(0.0);
    CHECK_FALSE(framed.prepare_run());  // at its target: nothing to prepare
    framed.set_target_time(0.5);
    plain.set_target_time(0.5);
    CHECK(framed.prepare_run());  // the deformation
    CHECK(framed.prepare_run());  // the volume keeper and the fold repair's checks, at rest
    CHECK(framed.prepare_run());  // the fold repair's lift
    CHECK(framed.prepare_run());  // the fold repair's affine test
    CHECK(framed.prepare_run());  // the first step's estimates
    CHECK_FALSE(framed.prepare_run());
    CHECK(framed.time() == 0.0);
    run_to_target(framed);
    run_to_target(plain);
    CHECK(framed.positions() == plain.positions());
    CHECK_FALSE(framed.prepare_run());
}

TEST_CASE("EditorSession: export writes the current shape", "[editor][session]") {
    test::ScratchDir dir;
    EditorSession session;
    session.open_mesh("builtin:bar");
    session.set_target_time(1.0);
    run_to_target(session);
    session.export_mesh(dir.file("bent.obj"));
    const TriangleMesh written = load_mesh(dir.file("bent.obj"));
    REQUIRE(written.vertex_count() == session.positions().size());
    double worst = 0.0;
    for (std::size_t v = 0; v < written.vertex_count(); ++v)
        worst = std::max(worst, glm::length(written.positions[v] - session.positions()[v]));
    CHECK(worst < 1e-6 * session.diagonal());
}

TEST_CASE("EditorSession: a failed load keeps the current mesh and history", "[editor][session]") {
    test::ScratchDir dir;
    EditorSession session;
    session.open_mesh("builtin:bar");
    session.move_control_point(3, session.control_points()[3] + Vec3(0.5, 0.0, 0.0));
    const std::vector<double> s = session.s();
    test::write_bytes(dir.file("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    CHECK_THROWS_AS(session.open(dir.file("broken.obj")), InputError);
    CHECK_THROWS(session.open(dir.file("missing.ply")));
    CHECK_THROWS(session.open(dir.file("missing.json")));
    CHECK(session.mesh_name() == "builtin:bar");
    CHECK(session.s() == s);
    CHECK(session.history().undo_count() == 1);
}

TEST_CASE("EditorSession: a failed save or export changes nothing and says why", "[editor][session]") {
    test::ScratchDir dir;
    EditorSession session;
    session.open_mesh("builtin:bar");
    session.move_control_point(3, session.control_points()[3] + Vec3(0.5, 0.0, 0.0));
    session.set_target_time(0.5);
    run_to_target(session);
    session.save_scene(dir.file("kept.json"));
    const std::string kept = test::read_bytes(dir.file("kept.json"));
    const Scene scene = session.current_scene();
    const std::vector<Vec3> positions = session.positions();
    const std::uint64_t revision = session.document_revision();

    CHECK_THROWS_WITH(session.save_scene(dir.file("missing/scene.json")), Catch::Contains("missing/scene"));
    CHECK_THROWS_WITH(session.export_mesh(dir.file("missing/out.obj")), Catch::Contains("missing/out.obj"));
    CHECK_THROWS_AS(session.export_mesh(dir.file("out.xyz")), Error);
    std::filesystem::create_directory(dir.file("taken.json"));  // a folder where the file should go
    CHECK_THROWS_AS(session.save_scene(dir.file("taken.json")), IoError);
    CHECK(scene_to_json(session.current_scene()) == scene_to_json(scene));
    CHECK(session.positions() == positions);
    CHECK(session.document_revision() == revision);
    CHECK(session.history().undo_count() == 1);
    CHECK(test::read_bytes(dir.file("kept.json")) == kept);
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))  // no temporary file left behind
        CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
}

TEST_CASE("EditorSession: a non-finite integration stops at the last good shape with one message", "[editor][session]") {
    EditorSession session;
    Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json");
    scene.motion.curve.bezier = {{0, 0, 0.6}, {0, 0, 1e307}, {1e307, 0, 1e307}, {1e307, 1e307, 1e307}};
    scene.motion.inner_motion = InnerMotionMode::Translation;
    session.open_scene(scene);
    const std::size_t warnings = session.warnings().size();
    session.set_target_time(1.0);
    run_to_target(session);
    CHECK_FALSE(session.moving());
    CHECK(session.target_time() == session.time());
    CHECK(session.time() < 1.0);
    for (const Vec3& p : session.positions()) REQUIRE(std::isfinite(p.x + p.y + p.z));
    REQUIRE(session.warnings().size() == warnings + 1);
    CHECK_THAT(session.warnings().back(), Catch::StartsWith("deformation stopped: ") && Catch::Contains("non-finite"));
    // A usable curve deforms again and the message goes.
    MotionSpec curve = session.curve();
    curve.curve.bezier = {{0, 0, 0.6}, {0, 0, 0.8}, {0.1, 0, 1.0}, {0.3, 0, 1.1}};
    session.set_curve(curve);
    session.set_target_time(1.0);
    run_to_target(session);
    CHECK(session.time() == 1.0);
    CHECK(session.warnings().size() == warnings);
}

TEST_CASE("EditorSession: a plain mesh opens with a region and a curve that deform it", "[editor][session]") {
    EditorSession session;
    session.open_mesh("builtin:sphere");
    CHECK(session.warnings().empty());
    CHECK(std::count(session.s().begin(), session.s().end(), 0.0) > 0);
    session.play();
    run_to_target(session);
    CHECK(session.time() == 1.0);
    CHECK(session.stats().backend == "cpu");
    CHECK(session.stats().volume_error_percent < 2.0);
    CHECK(session.stats().flipped_triangles == 0);
}

TEST_CASE("EditorSession: each edit moves the revisions that follow what it changed", "[editor][session]") {
    EditorSession session;
    session.open_mesh("builtin:bar");
    // The names of the revisions that moved since the last call.
    std::uint64_t last[5] = {};
    const auto moved = [&] {
        const std::uint64_t now[5] = {session.revision(), session.mesh_revision(), session.positions_revision(),
                                      session.curve_revision(), session.document_revision()};
        static const char* names[5] = {"view", "mesh", "positions", "curve", "document"};
        std::string out;
        for (int i = 0; i < 5; ++i)
            if (now[i] != last[i]) out += (out.empty() ? "" : " ") + std::string(names[i]), last[i] = now[i];
        return out;
    };
    moved();

    session.set_target_time(0.5);
    CHECK(moved() == "document");
    session.set_target_time(0.5);
    CHECK(moved() == "");
    run_to_target(session);  // time advancing is no change to the document
    CHECK(moved() == "view positions");
    const RegionSpec geodesic = session.region().spec;
    // s changes; the last result stays on show until the new run is back at t = 0.5
    session.set_geodesic_range(0.9 * geodesic.g_min, geodesic.g_max);
    CHECK(moved() == "view curve document");  // the curve follows the new inner region
    // Nothing deformed yet: the view uploads nothing new.
    session.move_control_point(3, session.control_points()[3] + Vec3(0.1, 0.0, 0.0));
    CHECK(moved() == "curve document");
    session.set_force_cpu(true);
    CHECK(moved() == "");

    run_to_target(session);
    moved();
    session.apply();  // new base positions, region and curve
    CHECK(moved() == "view positions curve document");
    REQUIRE(session.undo());
    CHECK(moved() == "view positions curve document");
    session.open_mesh("builtin:bar");
    CHECK(moved() == "view mesh positions curve document");
}

TEST_CASE("Scripts: JSON lines and arrays parse; errors name the line", "[editor][script]") {
    const auto lines = parse_script("# a comment\n{\"action\": \"set-time\", \"t\": 1}\n\n{\"action\": \"undo\"}\n", "s.jsonl");
    REQUIRE(lines.size() == 2);
    CHECK(lines[1].name == "undo");
    CHECK(lines[1].where == "s.jsonl:4");
    const auto array = parse_script(" [{\"action\": \"redo\"}, {\"action\": \"apply\"}]", "s.json");
    REQUIRE(array.size() == 2);
    CHECK(array[1].where == "s.json[1]");
    CHECK_THROWS_WITH(parse_script("{\"action\": \"undo\"}\n{\"t\": 1}\n", "x"), Catch::Contains("x:2"));
    CHECK_THROWS_WITH(parse_script("{oops\n", "y"), Catch::Contains("y:1"));
}

TEST_CASE("The session says when its deformation started to fold", "[editor]") {
    EditorSession session;
    session.open_scene(test::folding_box_scene());
    CHECK(session.stats().first_fold_time == -1.0);
    session.play();
    run_to_target(session);
    CHECK(session.stats().flipped_triangles > 0);
    CHECK(session.folded_triangles().size() == session.stats().flipped_triangles);
    CHECK(session.folded_triangles() == flipped_triangle_list(load_mesh_file("builtin:box").mesh.positions,
                                                              session.positions(), session.triangles()));
    CHECK(session.stats().first_fold_time > 0.0);
    CHECK(session.stats().first_fold_time <= 1.0);
    session.set_target_time(0.0);  // back to the start: the record stays until the deformation is rebuilt
    run_to_target(session);
    CHECK(session.stats().first_fold_time > 0.0);
    session.set_force_cpu(true);  // the deformation is rebuilt
    CHECK(session.stats().first_fold_time == -1.0);
}

TEST_CASE("EditorSession: a scene opens playing to its target_time and finds its mesh by name beside it",
          "[editor][session][open]") {
    namespace fs = std::filesystem;
    test::ScratchDir dir;
    write_mesh_file(dir.file("bar.obj"), load_mesh_file("builtin:bar").mesh);
    EditorSession session;
    session.open_mesh(dir.file("bar.obj"));
    CHECK(session.target_time() == 0.0);  // a mesh opens at rest
    session.set_target_time(0.4);
    session.save_scene(dir.file("saved.json"));
    const std::vector<double> s = session.s();

    // The scene names its mesh in a folder that is not there.
    nlohmann::json scene = nlohmann::json::parse(test::read_bytes(dir.file("saved.json")));
    scene["mesh"] = "meshes/bar.obj";
    for (const char* folder : {"a", "b", "c"}) fs::create_directories(dir.file(folder));
    test::write_bytes(dir.file("a/scene.json"), scene.dump());
    test::write_bytes(dir.file("b/scene.json"), scene.dump());
    fs::copy_file(dir.file("bar.obj"), dir.file("a/bar.obj"));
    fs::copy_file(dir.file("bar.obj"), dir.file("c/bar.obj"));

    SECTION("beside the scene") {
        session.open(dir.file("a/scene.json"));
        CHECK(fs::equivalent(session.mesh_name(), dir.file("a/bar.obj")));
        CHECK(session.target_time() == 0.4);
        CHECK(session.s() == s);
        run_to_target(session);
        CHECK(session.time() == 0.4);
    }
    SECTION("missing: the error names it, and opening it next completes the scene") {
        try {
            session.open(dir.file("b/scene.json"));
            FAIL("the scene opened without its mesh");
        } catch (const MissingMesh& e) {
            CHECK(e.file == "bar.obj");
            CHECK(std::string(e.what()).find("choose bar.obj") != std::string::npos);
        }
        CHECK(session.missing_mesh() == "bar.obj");
        CHECK(session.target_time() == 0.4);  // the document before stays
        CHECK(fs::equivalent(session.mesh_name(), dir.file("bar.obj")));
        session.open(dir.file("c/bar.obj"));
        CHECK(session.missing_mesh().empty());
        CHECK(fs::equivalent(session.mesh_name(), dir.file("c/bar.obj")));
        CHECK(session.target_time() == 0.4);  // the scene's, not a mesh's rest
        CHECK(session.s() == s);
    }
    SECTION("several files at once: the scene with the mesh it names among them") {
        session.open(std::vector<std::string>{dir.file("c/bar.obj"), dir.file("b/scene.json")});
        CHECK(fs::equivalent(session.mesh_name(), dir.file("c/bar.obj")));
        CHECK(session.target_time() == 0.4);
        CHECK(session.s() == s);
        CHECK(EditorSession::main_file({dir.file("c/bar.obj"), dir.file("b/scene.json")}) == dir.file("b/scene.json"));
    }
}

TEST_CASE("EditorSession: an edit shows its result when it is computed, play and scrubbing show the way",
          "[editor][session][step-control]") {
    EditorSession session;
    session.open_mesh("builtin:box:6");  // a mesh opened: error-controlled steps
    session.set_target_time(1.0);
    run_to_target(session);
    const std::vector<Vec3> before = session.positions();
    REQUIRE(before != session.base_positions());
    CHECK(session.deformation()->error_controlled());

    // A curve edit starts again from t = 0; until the run is back at t = 1 the
    // last result stays on show, whatever steps are taken meanwhile.
    // The positions' revision (which a pick refits to) moves only when they do.
    const std::uint64_t shown = session.positions_revision();
    const SessionStats shown_stats = session.stats();
    REQUIRE(shown_stats.volume_error_percent > 0.0);
    session.move_control_point(3, session.control_points()[3] + Vec3(0.05, 0.1, 0.0));
    CHECK(session.holding_result());
    CHECK(session.positions() == before);
    CHECK(session.positions_revision() == shown);
    while (session.prepare_run()) {
    }
    CHECK(session.update(1) == 1);
    CHECK(session.time() > 0.0);
    CHECK(session.time() < 1.0);
    CHECK(session.positions() == before);
    CHECK(time_stat_text(session).rfind("updating ", 0) == 0);  // both editors say so
    // The stats are those of the result on show, not of the run's way there.
    CHECK(session.stats().volume_error_percent == shown_stats.volume_error_percent);
    CHECK(session.stats().flipped_triangles == shown_stats.flipped_triangles);
    // A second edit while it catches up keeps the last finished result.
    session.move_control_point(3, session.control_points()[3] + Vec3(0.0, 0.05, 0.0));
    CHECK(session.positions() == before);
    run_to_target(session);
    CHECK(!session.holding_result());
    CHECK(session.positions() == session.deformation()->positions());
    CHECK(session.positions() != before);
    CHECK(session.positions_revision() != shown);
    // (Its volume error is not compared with the held one's: the volume keeper
    // leaves both at rounding, 9e-14 %, the same figure.)
    CHECK(time_stat_text(session) == "1.000");

    // Scrubbing after an edit shows the way: positions follow the run's time.
    session.move_control_point(3, session.control_points()[3] + Vec3(-0.05, 0.0, 0.0));
    session.update(1);
    const std::uint64_t held = session.positions_revision();
    session.set_target_time(0.5);
    CHECK(!session.holding_result());
    CHECK(session.positions_revision() != held);  // from the held result to the run's positions
    run_to_target(session);
    CHECK(session.time() == 0.5);
    CHECK(session.positions() == session.deformation()->positions());
}

TEST_CASE("EditorSession: a curve edit's run starts from the last run's rest state, a region edit's does not",
          "[editor][session][rest]") {
    EditorSession session;
    session.open_mesh("builtin:cylinder:12");
    session.set_target_time(1.0);
    run_to_target(session);
    REQUIRE(session.deformation()->backend_name() == std::string("cpu"));
    const std::shared_ptr<const CpuRest> rest = session.deformation()->cpu_rest();
    REQUIRE(rest != nullptr);

    // Two curve edits, the second while the first's run catches up: both runs
    // start from the same rest state, and give what a session that never ran
    // before gives for that curve.
    const Vec3 end = session.control_points()[3];
    session.move_control_point(3, end + Vec3(0.1, 0.0, 0.05));
    session.update(2);
    CHECK(session.deformation()->cpu_rest() == rest);
    session.move_control_point(3, end + Vec3(0.15, -0.1, 0.0));
    run_to_target(session);
    CHECK(session.deformation()->cpu_rest() == rest);
    EditorSession fresh;
    fresh.open_mesh("builtin:cylinder:12");
    fresh.move_control_point(3, end + Vec3(0.15, -0.1, 0.0));
    fresh.set_target_time(1.0);
    run_to_target(fresh);
    CHECK(session.positions() == fresh.positions());

    // A region edit changes s: its run builds its own.
    session.set_region_band(0.5 * (session.region_band() + 1.0));
    run_to_target(session);
    REQUIRE(session.deformation()->cpu_rest() != nullptr);
    CHECK(session.deformation()->cpu_rest() != rest);
}

// Generated edits on generated meshes: picks at random vertices with random
// ranges, and strokes of the inner brush, each followed by an undo or not.
TEST_CASE(
    "EditorSession: a region computed in parts shows the same regions at once and deforms as one computed at once",
    "[editor][session][region]") {
    std::mt19937 random(23);
    std::uniform_real_distribution<double> fraction(0.0, 1.0);
    for (const char* mesh : {"builtin:sphere:3", "builtin:box:8"}) {
        EditorSession at_once, in_parts;
        in_parts.set_regions_in_parts(true);
        at_once.open_mesh(mesh);
        in_parts.open_mesh(mesh);
        // An open computes its region in parts too.
        REQUIRE(in_parts.region_pending());
        for (std::size_t v = 0; v < at_once.s().size(); ++v)
            REQUIRE((in_parts.s()[v] <= 0.0) == (at_once.s()[v] <= 0.0));
        in_parts.finish_region();
        CHECK(in_parts.s() == at_once.s());
        CHECK(in_parts.warnings() == at_once.warnings());
        const double diagonal = at_once.diagonal();
        for (int edit = 0; edit < 6; ++edit) {
            INFO(mesh << ", edit " << edit);
            const auto vertex = std::uint32_t(fraction(random) * double(at_once.base_positions().size() - 1));
            const std::uint64_t document = in_parts.document_revision();
            if (edit % 3 == 2) {
                BrushSettings brush;
                brush.radius = (0.05 + 0.1 * fraction(random)) * diagonal;
                const SurfacePoint at =
                    surface_point_at_vertex(at_once.triangles(), at_once.base_positions().size(), vertex);
                at_once.brush(at, brush);
                in_parts.brush(at, brush);
            } else {
                const double g_min = (0.05 + 0.1 * fraction(random)) * diagonal;
                const double g_max = g_min + (0.1 + 0.3 * fraction(random)) * diagonal;
                at_once.pick_geodesic(vertex, g_min, g_max);
                in_parts.pick_geodesic(vertex, g_min, g_max);
            }
            if (edit % 2 == 1) {
                REQUIRE(in_parts.region_pending());
                at_once.undo();
                in_parts.undo();
            }
            // The edit is in the document, and which vertices move shows at once, the
            // curve following the inner region as it does at once.
            CHECK(in_parts.document_revision() != document);
            CHECK(in_parts.region_pending());
            CHECK(in_parts.current_scene().region.kind == at_once.current_scene().region.kind);
            CHECK(in_parts.curve() == at_once.curve());
            for (std::size_t v = 0; v < at_once.s().size(); ++v) {
                REQUIRE((in_parts.s()[v] <= 0.0) == (at_once.s()[v] <= 0.0));
                REQUIRE((in_parts.s()[v] >= 1.0) == (at_once.s()[v] >= 1.0));
            }
            // The blend's values come a part at a time, whatever the target; then the
            // view is told (the revision), the document is not.
            const std::uint64_t shown = in_parts.revision(), saved = in_parts.document_revision();
            int parts = 0;
            while (in_parts.region_pending()) {
                REQUIRE(in_parts.prepare_run(0.0));
                ++parts;
            }
            CHECK(parts > 1);
            CHECK(in_parts.s() == at_once.s());
            CHECK(in_parts.revision() != shown);
            CHECK(in_parts.document_revision() == saved);
            CHECK(in_parts.warnings() == at_once.warnings());
        }
        // A read that must be final computes it to the end.
        at_once.pick_geodesic(1, 0.15 * diagonal, 0.4 * diagonal);
        in_parts.pick_geodesic(1, 0.15 * diagonal, 0.4 * diagonal);
        REQUIRE(in_parts.region_pending());
        in_parts.finish_region();
        CHECK_FALSE(in_parts.region_pending());
        CHECK(in_parts.s() == at_once.s());
        // An open that fails (a region that cannot be built) keeps the document,
        // its region computed.
        at_once.pick_geodesic(2, 0.1 * diagonal, 0.35 * diagonal);
        in_parts.pick_geodesic(2, 0.1 * diagonal, 0.35 * diagonal);
        REQUIRE(in_parts.region_pending());
        Scene bad = in_parts.current_scene();
        bad.region.kind = RegionSpec::Kind::geodesic;
        bad.region.g_min = 0.5, bad.region.g_max = 0.2;
        const std::vector<Vec3> base = in_parts.base_positions();
        CHECK_THROWS_AS(in_parts.open_scene(bad), InputError);
        CHECK(in_parts.base_positions() == base);
        CHECK(in_parts.history().undo_count() > 0);
        CHECK_FALSE(in_parts.region_pending());
        CHECK(in_parts.s() == at_once.s());
        // A run started while the region is pending computes it first: the same steps.
        at_once.pick_geodesic(0, 0.1 * diagonal, 0.3 * diagonal);
        in_parts.pick_geodesic(0, 0.1 * diagonal, 0.3 * diagonal);
        REQUIRE(in_parts.region_pending());
        at_once.set_target_time(0.5);
        in_parts.set_target_time(0.5);
        run_to_target(at_once);
        run_to_target(in_parts);
        CHECK_FALSE(in_parts.region_pending());
        CHECK(in_parts.positions() == at_once.positions());
    }
}

TEST_CASE("EditorSession: scrubbing back across the fold repair shows the way out's shapes once it gets there",
          "[editor][session][repair]") {
    // The deformation starts again from rest to go back across a step the
    // repair acted after (Deformation::advance); the shape on show stays until
    // it reaches the new time, then it is the way out's shape there, and at
    // t = 0 the mesh as it was.
    EditorSession session;
    const std::vector<std::pair<double, std::vector<Vec3>>> way_out = repaired_way_out(session);
    const std::vector<Vec3> at_end = session.positions();
    for (const std::size_t k : {way_out.size() / 2, way_out.size() / 5}) {
        const auto& [time, shape] = way_out[k];
        INFO("back to t = " << time);
        const std::vector<Vec3> shown = session.positions();
        session.set_target_time(time);
        REQUIRE(session.holding_result());
        session.update(1);
        CHECK(session.positions() == shown);  // the run is on its way from rest
        run_to_target(session);
        CHECK_FALSE(session.holding_result());
        CHECK(session.positions() == shape);
    }
    const std::uint64_t revision = session.positions_revision();
    session.set_target_time(0.0);
    run_to_target(session);
    CHECK(session.positions() == session.base_positions());
    CHECK(session.positions_revision() != revision);  // drawn again
    session.set_target_time(1.0);
    run_to_target(session);
    CHECK(session.positions() == at_end);
}

TEST_CASE("EditorSession: apply while a run catches up bakes what it catches up to, not the way there",
          "[editor][session]") {
    // The shape on show while an edit's run (or a way back from rest) catches up
    // is not the deformation at time(): apply runs to the target first and bakes
    // the shape a session that waited would bake.
    std::mt19937 random(17);
    std::uniform_real_distribution<double> offset(-0.1, 0.1);
    for (int draw = 0; draw < 4; ++draw) {
        const Vec3 move(offset(random), offset(random), offset(random));
        const int steps_before = draw % 3;  // applied at once, or after a step or two of the run
        INFO("draw " << draw << ", " << steps_before << " steps before apply");
        EditorSession hurried, waited;
        for (EditorSession* session : {&hurried, &waited}) {
            session->open_mesh("builtin:cylinder:12");
            session->set_target_time(1.0);
            run_to_target(*session);
            session->move_control_point(3, session->control_points()[3] + move);
        }
        REQUIRE(hurried.holding_result());
        while (hurried.prepare_run()) {
        }
        hurried.update(steps_before);
        REQUIRE(hurried.holding_result());
        const std::vector<Vec3> at_rest = hurried.base_positions(), on_show = hurried.positions();
        hurried.apply();
        run_to_target(waited);
        waited.apply();
        CHECK_FALSE(hurried.holding_result());
        CHECK(hurried.base_positions() == waited.base_positions());
        CHECK(hurried.base_positions() != at_rest);
        CHECK(hurried.base_positions() != on_show);  // the last edit's result, held on show
        REQUIRE(hurried.undo());
        CHECK(hurried.target_time() == 1.0);  // the time the bake was of
    }

    // Scrubbed back across the fold repair: the way out's shape at that time.
    EditorSession session;
    const std::vector<std::pair<double, std::vector<Vec3>>> way_out = repaired_way_out(session);
    const auto& [time, shape] = way_out[way_out.size() / 2];
    session.set_target_time(time);
    REQUIRE(session.holding_result());
    session.update(1);
    session.apply();
    CHECK(session.base_positions() == shape);
}
