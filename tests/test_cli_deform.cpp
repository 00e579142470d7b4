// `vfsd deform`: the scene contract, the report, the input's vertex order kept,
// and exit codes 0 (done), 1 (bad input), 2 (usage).

#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "deform/quality.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "scene/battery.h"
#include "scene/prepared_scene.h"
#include "scene/scene.h"
#include "scene/scene_run.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// Runs `vfsd deform ARGS` with stdout and stderr saved in `dir`; returns the exit code.
int deform(const ScratchDir& dir, const std::string& args) {
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' deform " + args + " >'" + dir.file("stdout.txt") +
                                "' 2>'" + dir.file("stderr.txt") + "'";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A scene that bends the top of a binary STL cube of 8 vertices (24 in the file).
std::string cube_scene(const ScratchDir& dir) {
    write_bytes(dir.file("cube.stl"), test::binary_stl(test::unit_cube()));
    const nlohmann::json scene = {
        {"mesh", "cube.stl"},
        {"region", {{"kind", "painted"}, {"inner", {{{"halfspace", {0, 0, 1, 0.9}}}}}, {"outer", {{{"halfspace", {0, 0, -1, -0.1}}}}}}},
        {"curve", {{"bezier", {{0.5, 0.5, 1.0}, {0.5, 0.5, 1.2}, {0.6, 0.5, 1.3}, {0.7, 0.5, 1.3}}}}},
        {"steps", 40}};
    write_bytes(dir.file("scene.json"), scene.dump());
    return dir.file("scene.json");
}

}  // namespace

TEST_CASE("vfsd deform writes the deformed mesh in the input's layout and a report", "[deform][cli]") {
    ScratchDir dir;
    const std::string scene = cube_scene(dir);
    REQUIRE(deform(dir, "'" + scene + "' --out '" + dir.file("out.obj") + "' --report '" + dir.file("r.json") +
                            "' --field-out '" + dir.file("s.txt") + "'") == 0);
    // STL stores 3 vertices per triangle: the output keeps all 36, in file order.
    const MeshFile input = read_mesh_file(dir.file("cube.stl"));
    const MeshFile written = read_mesh_file(dir.file("out.obj"));
    const TriangleMesh output = to_file_layout(written, written.mesh);
    CHECK(output.vertex_count() == input.file_vertex_count());
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("r.json")));
    for (const char* key : {"vertices", "triangles", "steps", "backend", "ms_per_step", "total_ms", "volume_before",
                            "volume_after", "volume_error_percent", "outer_max_displacement", "inner_rigid_residual",
                            "flipped_triangles", "reversed_triangles", "nonfinite_vertices"})
        CHECK(report.contains(key));
    CHECK(report["vertices"] == 8);
    CHECK(report["steps"] == 40);
    CHECK(report["backend"] == "cpu");
    CHECK(report["outer_max_displacement"] == 0.0);
    CHECK(report["volume_after"].get<double>() == Approx(signed_volume(output.positions, output.triangles)).epsilon(1e-6));
    // The signed change beside the error (the cube has no blend region, so its volume changes).
    const double before = report["volume_before"], after = report["volume_after"];
    const double change = report["volume_change_percent"];
    CHECK(change == Approx(100.0 * (after - before) / std::abs(before)));
    CHECK(std::abs(change) > 1.0);
    CHECK(report["volume_error_percent"].get<double>() == Approx(std::abs(change)));
    // The top corners (inner) moved, the bottom ones (outer) did not.
    for (std::size_t i = 0; i < output.vertex_count(); ++i) {
        const Vec3 before = input.mesh.positions[input.file_to_mesh[i]];
        if (before.z == 0.0) CHECK(glm::length(output.positions[i] - before) < 1e-6);
        if (before.z == 1.0) CHECK(glm::length(output.positions[i] - before) > 0.1);
    }
    std::ifstream field(dir.file("s.txt"));
    std::size_t lines = 0;
    for (double s; field >> s; ++lines) CHECK((s >= 0.0 && s <= 1.0));
    CHECK(lines == input.file_vertex_count());
}

TEST_CASE("vfsd deform takes error-controlled steps with --tolerance and reports them", "[deform][cli][step-control]") {
    ScratchDir dir;
    // The bar's handle scene: a blend region, so the steps have an estimate.
    const std::string scene = std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig13-bar-handle-bend.json";
    REQUIRE(deform(dir, "'" + scene + "' --tolerance 1e-3 --out '" + dir.file("out.ply") + "' --report '" +
                            dir.file("r.json") + "'") == 0);
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("r.json")));
    const nlohmann::json& control = report["step_control"];
    CHECK(control["error_controlled"] == true);
    CHECK(control["tolerance"] == 1e-3);
    CHECK(control["estimated_step_error_largest"].get<double>() <= 1e-3);
    CHECK(control["estimated_step_error_largest"].get<double>() > 0.0);
    CHECK(control["estimated_error_sum"].get<double>() >= control["estimated_step_error_largest"].get<double>());
    CHECK(control["rejected_steps"].get<int>() >= 0);
    // Every try as [t, h, estimate, taken]: as many taken as steps, the rest rejected.
    int taken = 0, rejected = 0;
    for (const nlohmann::json& t : control["tries"]) {
        REQUIRE(t.size() == 4);
        (t[3].get<bool>() ? taken : rejected) += 1;
    }
    CHECK(taken == report["steps"].get<int>());
    CHECK(rejected == control["rejected_steps"].get<int>());
    CHECK(report["steps"].get<int>() < 250 / 4);  // the file's fixed 250, replaced
    CHECK(report["target_time"] == 1.0);
    // --steps keeps fixed steps; both at once is a usage error (exit 2).
    REQUIRE(deform(dir, "'" + scene + "' --steps 30 --force --out '" + dir.file("out.ply") + "' --report '" +
                            dir.file("r.json") + "'") == 0);
    const nlohmann::json fixed = nlohmann::json::parse(std::ifstream(dir.file("r.json")));
    CHECK(fixed["step_control"]["error_controlled"] == false);
    CHECK(fixed["step_control"]["rejected_steps"] == 0);
    CHECK(fixed["step_control"]["tries"].empty());
    CHECK(deform(dir, "'" + scene + "' --steps 30 --tolerance 1e-3 --force --out '" + dir.file("out.ply") + "'") == 2);
    CHECK(deform(dir, "'" + scene + "' --tolerance 0.5 --force --out '" + dir.file("out.ply") + "'") == 2);
}

TEST_CASE("vfsd deform says when triangles fold, how many, from when and where", "[deform][cli]") {
    ScratchDir dir;
    // The box of fig. 5 twisted by 180° with sec. 5 as printed and no smoothing:
    // folds. The report lists exactly the triangles that face against their
    // neighbours in the written mesh; stderr says so.
    nlohmann::json scene = nlohmann::json::parse(std::ifstream(std::string(VFSD_SOURCE_DIR) +
                                                               "/assets/scenes/fig05-box-bend-twist.json"));
    scene["region"]["profile"] = "geodesic";
    scene.update({{"twist_degrees", {0, 180}},
                  {"stream_gauge", "paper"},
                  {"smoothing", "tangent"},
                  {"keep_volume", false},
                  {"fold_repair", false},
                  {"fold_refinement", 0},
                  {"smoothing_steps", 0},
                  {"steps", 40}});
    write_bytes(dir.file("twist.json"), scene.dump());
    REQUIRE(deform(dir, "'" + dir.file("twist.json") + "' --out '" + dir.file("out.ply") + "' --report '" +
                            dir.file("r.json") + "'") == 0);
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("r.json")));
    const MeshFile box = load_mesh_file("builtin:box");
    REQUIRE(report.contains("folds"));
    const nlohmann::json& folds = report["folds"];
    CHECK(folds["count"] == report["flipped_triangles"]);
    CHECK(folds["count"].get<int>() > 0);
    CHECK(folds["first_seen_after_step"].get<int>() > 0);
    CHECK(folds["first_seen_after_step"].get<int>() <= 40);
    CHECK(folds["first_seen_at_time"].get<double>() > 0.0);
    CHECK(folds["s_min"].get<double>() >= 0.0);
    CHECK(folds["s_min"].get<double>() <= folds["s_max"].get<double>());
    CHECK(folds["s_max"].get<double>() <= 1.0);
    const MeshFile written = read_mesh_file(dir.file("out.ply"));
    CHECK(folds["triangles"].get<std::vector<std::uint32_t>>() ==
          flipped_triangle_list(box.mesh.positions, written.mesh.positions, box.mesh.triangles));
    CHECK(test::read_bytes(dir.file("stderr.txt")).find("triangles folded (first seen after step") != std::string::npos);
    CHECK(report["fold_repair_steps"] == 0);

    // Refined where it folds, sec. 5 as printed folds more (its ∇r ripples grow
    // faster on a finer mesh): the first run is kept, mesh and folds alike, and
    // the report and stderr say which runs were made.
    scene["fold_refinement"] = 3;
    write_bytes(dir.file("refined.json"), scene.dump());
    REQUIRE(deform(dir, "'" + dir.file("refined.json") + "' --out '" + dir.file("refined.ply") + "' --report '" +
                            dir.file("refined-report.json") + "'") == 0);
    const nlohmann::json kept = nlohmann::json::parse(std::ifstream(dir.file("refined-report.json")));
    REQUIRE(kept.contains("refinement"));
    CHECK(kept["refinement"]["rounds"] == 0);
    CHECK(kept["refinement"]["vertices_added"] == 0);
    const nlohmann::json& tried = kept["refinement"]["runs"];
    REQUIRE(tried.size() >= 2);
    CHECK(tried[0]["vertices"] == box.mesh.vertex_count());
    CHECK(tried[0]["folded_at_end"] == kept["flipped_triangles"]);
    for (std::size_t k = 1; k < tried.size(); ++k) {
        CHECK(tried[k]["vertices"] > tried[k - 1]["vertices"]);
        CHECK(tried[k]["folded_at_end"] >= kept["flipped_triangles"]);
    }
    CHECK(test::read_bytes(dir.file("stderr.txt")).find("but no refined run folded fewer") != std::string::npos);
    CHECK(kept["vertices"] == box.mesh.vertex_count());
    CHECK(kept["flipped_triangles"] == report["flipped_triangles"]);
    scene["fold_refinement"] = 0;

    // The same scene with the fold repair: nothing folds, and the report says how
    // often and how far the repair moved vertices.
    scene["fold_repair"] = true;
    write_bytes(dir.file("repaired.json"), scene.dump());
    REQUIRE(deform(dir, "'" + dir.file("repaired.json") + "' --out '" + dir.file("repaired.ply") + "' --report '" +
                            dir.file("repaired-report.json") + "'") == 0);
    const nlohmann::json repaired = nlohmann::json::parse(std::ifstream(dir.file("repaired-report.json")));
    CHECK(repaired["flipped_triangles"] == 0);
    CHECK_FALSE(repaired.contains("folds"));
    CHECK(repaired["fold_repair_steps"].get<int>() > 0);
    CHECK(repaired["fold_repair_max_shift_over_diagonal"].get<double>() > 0.0);

    // A scene that folds nothing says nothing of folds.
    REQUIRE(deform(dir, "'" + cube_scene(dir) + "' --out '" + dir.file("cube.obj") + "' --report '" +
                            dir.file("cube.json") + "'") == 0);
    CHECK_FALSE(nlohmann::json::parse(std::ifstream(dir.file("cube.json"))).contains("folds"));
    CHECK(test::read_bytes(dir.file("stderr.txt")).find("folded") == std::string::npos);
}

TEST_CASE("vfsd deform refines the mesh where triangles fold and runs again, and says so", "[deform][cli]") {
    // The flow alone (no fold repair) on the battery's coarse scenes at full
    // amplitude: the first scene that refines in the engine (scene/scene_run.h),
    // written out with its placed mesh in double precision.
    const std::vector<std::string> sources = battery_mesh_sources({}, false);
    ScratchDir dir;
    for (int index = 0; index < 30; ++index) {
        BatteryScene b = generate_battery_scene(1, index, sources);
        b.scene.options.repair_folds = false;
        PreparedScene prepared = prepare_scene(b.scene, b.mesh);
        const SceneRun run = run_scene(prepared);
        if (run.refinements == 0) continue;
        INFO(b.name << ", refined " << run.refinements << " times");
        WriteOptions exact;
        exact.double_positions = true;
        write_mesh_file(dir.file("mesh.ply"), b.mesh.mesh, exact);
        Scene scene = b.scene;
        scene.mesh = "mesh.ply";
        write_bytes(dir.file("scene.json"), scene_to_json(scene).dump());
        REQUIRE(deform(dir, "'" + dir.file("scene.json") + "' --out '" + dir.file("out.ply") + "' --report '" +
                                dir.file("r.json") + "' --field-out '" + dir.file("s.txt") + "'") == 0);
        const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("r.json")));
        REQUIRE(report.contains("refinement"));
        const std::size_t vertices = prepared.file.mesh.vertex_count();
        CHECK(report["refinement"]["rounds"] == run.refinements);
        CHECK(report["refinement"]["vertices_before"] == b.mesh.mesh.vertex_count());
        CHECK(report["refinement"]["vertices_added"] == vertices - b.mesh.mesh.vertex_count());
        const nlohmann::json& runs = report["refinement"]["runs"];
        REQUIRE(runs.size() == run.tried.size());
        CHECK(runs[0]["vertices"] == b.mesh.mesh.vertex_count());
        CHECK(runs[run.refinements]["vertices"] == vertices);
        CHECK(runs[run.refinements]["folded_at_end"] == report["flipped_triangles"]);
        for (const nlohmann::json& r : runs) CHECK(r["folded_at_end"] >= report["flipped_triangles"]);
        CHECK(report["vertices"] == vertices);
        CHECK(report["flipped_triangles"] == count_flipped_triangles(prepared.file.mesh.positions,
                                                                     run.deformation->positions(),
                                                                     prepared.file.mesh.triangles));
        // The written mesh is the refined one, deformed as in the engine; s has a
        // value for each of its vertices.
        const MeshFile written = read_mesh_file(dir.file("out.ply"));
        REQUIRE(written.mesh.vertex_count() == vertices);
        CHECK(written.mesh.triangles == prepared.file.mesh.triangles);
        double worst = 0.0;
        for (std::size_t v = 0; v < vertices; ++v)
            worst = std::max(worst, glm::length(written.mesh.positions[v] - run.deformation->positions()[v]));
        CHECK(worst / bounding_box(b.mesh.mesh.positions).diagonal() < 1e-6);  // float PLY
        const std::string field = test::read_bytes(dir.file("s.txt"));
        CHECK(std::size_t(std::count(field.begin(), field.end(), '\n')) == vertices);
        CHECK(test::read_bytes(dir.file("stderr.txt")).find("the mesh was refined") != std::string::npos);

        // "fold_refinement": 0 runs the input mesh once, folds and all.
        scene.options.fold_refinements = 0;
        write_bytes(dir.file("once.json"), scene_to_json(scene).dump());
        REQUIRE(deform(dir, "'" + dir.file("once.json") + "' --out '" + dir.file("once.ply") + "' --report '" +
                                dir.file("once-report.json") + "'") == 0);
        const nlohmann::json once = nlohmann::json::parse(std::ifstream(dir.file("once-report.json")));
        CHECK_FALSE(once.contains("refinement"));
        CHECK(once["vertices"] == b.mesh.mesh.vertex_count());
        return;
    }
    FAIL("no scene of the battery refined");
}

TEST_CASE("vfsd deform refuses bad scenes with one line and exit code 1", "[deform][cli]") {
    ScratchDir dir;
    const std::string scene = cube_scene(dir);
    const std::string out = " --out '" + dir.file("out.ply") + "'";
    write_bytes(dir.file("broken.json"), "{\"mesh\": \"cube.stl\", \"region\": ");
    CHECK(deform(dir, "'" + dir.file("broken.json") + "'" + out) == 1);
    write_bytes(dir.file("bad_field.json"), R"({"mesh": "builtin:box", "region": {"kind": "geodesic", "seed": [0,0,0], "g_min": 2, "g_max": 1},
        "curve": {"bezier": [[0,0,0],[0,0,1],[0,0,2],[0,0,3]]}})");
    CHECK(deform(dir, "'" + dir.file("bad_field.json") + "'" + out) == 1);
    std::ifstream err(dir.file("stderr.txt"));
    std::string line, message;
    std::size_t lines = 0;
    while (std::getline(err, line)) message = line, ++lines;
    CHECK(lines == 1);
    CHECK(message.find("g_min < g_max") != std::string::npos);
    // Usage errors: no --out, an unknown backend, a non-integer step count.
    CHECK(deform(dir, "'" + scene + "'") == 2);
    CHECK(deform(dir, "'" + scene + "'" + out + " --backend vulkan") == 2);
    CHECK(deform(dir, "'" + scene + "'" + out + " --steps 2.5") == 2);
    CHECK(deform(dir, "'" + scene + "'" + out + " --threads 0") == 2);
    // The input is never overwritten, an existing output only with --force.
    CHECK(deform(dir, "'" + scene + "' --out '" + dir.file("cube.stl") + "' --force") == 1);
    REQUIRE(deform(dir, "'" + scene + "'" + out) == 0);
    CHECK(deform(dir, "'" + scene + "'" + out) == 1);
    CHECK(deform(dir, "'" + scene + "'" + out + " --force") == 0);
}

TEST_CASE("vfsd scene-keys lists every key a scene file has, as docs/scene-format.md does", "[deform][cli]") {
    ScratchDir dir;
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' scene-keys >'" + dir.file("keys.txt") + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    const std::string listing = test::read_bytes(dir.file("keys.txt"));
    std::ifstream doc_file(std::string(VFSD_SOURCE_DIR) + "/docs/scene-format.md");
    std::string doc((std::istreambuf_iterator<char>(doc_file)), std::istreambuf_iterator<char>());
    // The rows of the doc's key table (from its header to the first blank line) start with "| `key` |".
    const std::size_t table = doc.find("| key | value | default |");
    REQUIRE(table != std::string::npos);
    const std::size_t table_end = doc.find("\n\n", table);
    std::set<std::string> documented;
    for (std::size_t at = doc.find("\n| `", table); at < table_end; at = doc.find("\n| `", at + 1)) {
        const std::size_t end = doc.find('`', at + 4);
        documented.insert(doc.substr(at + 4, end - at - 4));
    }
    std::set<std::string> listed;
    for (const SceneKey& key : scene_keys()) {
        listed.insert(key.name);
        CHECK(listing.find(std::string(key.name) + " ") != std::string::npos);
    }
    CHECK(listed == documented);
    // A scene with every optional key set writes only listed keys.
    Scene scene = load_scene(std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig14-cylinder-knot.json");
    scene.motion.twist_plane = 0.5;
    scene.motion.stream_origin = Vec3(0.0);
    const nlohmann::json written = scene_to_json(scene);
    for (const auto& [key, value] : written.items()) {
        INFO(key);
        CHECK(listed.count(key) == 1);
    }
}
