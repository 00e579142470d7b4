// `vfsd battery`: one scene run as the engine runs it, battery.json and
// battery.csv saying what it did (its runs too), the exit code 1 when a scene
// folds, and 2 for bad usage.

#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "mesh/geometry.h"
#include "scene/battery.h"
#include "scene/prepared_scene.h"
#include "scene/scene_run.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::ScratchDir;

namespace {

// Runs `vfsd battery ARGS` with stdout and stderr saved in `dir`; returns the exit code.
int battery(const ScratchDir& dir, const std::string& args) {
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' battery " + args + " >'" +
                                dir.file("stdout.txt") + "' 2>'" + dir.file("stderr.txt") + "'";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("vfsd battery runs a scene as the engine does, says what it did and exits 1 when it folds",
          "[battery][cli]") {
    // The flow alone (--scheme no-repair: no repair, no refinement) on the coarse
    // built-in scenes: the first that folds, then the same with the default
    // scheme, which repairs it.
    const std::vector<std::string> sources = battery_mesh_sources({}, false);
    for (int index = 0; index < 30; ++index) {
        BatteryScene b = generate_battery_scene(1, index, sources);
        b.scene.options.repair_folds = false;
        b.scene.options.fold_refinements = 0;
        PreparedScene prepared = prepare_scene(b.scene, b.mesh);
        const SceneRun run = run_scene(prepared);
        if (run.watch.folded_at_end == 0) continue;
        INFO(b.name << ": the flow alone folds " << run.watch.folded_at_end << " triangles");
        for (const std::string scheme : {"no-repair", "default"}) {
            INFO("--scheme " << scheme);
            ScratchDir dir;
            const int code = battery(dir, "--seed 1 --coarse --worst 0 --scheme " + scheme + " --only " +
                                              std::to_string(index) + " --out '" + dir.path().string() + "'");
            const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("battery.json")));
            REQUIRE(report["scenes"].size() == 1);
            const nlohmann::json& scene = report["scenes"][0];
            CHECK(scene["name"] == b.name);
            const nlohmann::json& runs = scene["runs"];  // every run made, the input mesh's first
            REQUIRE(runs.size() == std::size_t(scene["refinements"].get<int>()) + 1);
            CHECK(runs[0]["vertices"] == b.mesh.mesh.vertex_count());
            CHECK(runs.back()["folded_at_end"] == scene["flipped_triangles"]);
            if (scheme == "no-repair") {  // the engine's run, as run above
                CHECK(code == 1);
                CHECK(scene["passed"] == false);
                CHECK(scene["flipped_triangles"] == run.watch.folded_at_end);
                CHECK(runs[0]["folded_at_end"] == run.tried[0].folded_at_end);
                CHECK(runs[0]["folded_over_tenths"] == run.tried[0].folded_over_tenths);
                CHECK(scene["fold_repair_steps"] == 0);
            } else {
                CHECK(code == 0);
                CHECK(scene["passed"] == true);
                CHECK(scene["flipped_triangles"] == 0);
                CHECK(scene["fold_repair_steps"] > 0);
            }
            // battery.csv: a header and the scene.
            std::ifstream csv(dir.file("battery.csv"));
            std::string header, row, extra;
            REQUIRE(std::getline(csv, header));
            REQUIRE(std::getline(csv, row));
            CHECK_FALSE(std::getline(csv, extra));
            CHECK(header.rfind("name,", 0) == 0);
            CHECK(row.rfind(b.name + ",", 0) == 0);
        }
        return;
    }
    FAIL("the flow alone folded no scene of the battery");
}

namespace {
// The result of `b`'s scene in `steps` fixed steps (as `vfsd battery` runs its reference).
std::vector<Vec3> fixed_steps_result(BatteryScene b, int steps) {
    b.scene.options.tolerance = 0.0;
    b.scene.options.steps = steps;
    PreparedScene prepared = prepare_scene(b.scene, b.mesh);
    return run_scene(prepared).deformation->positions();
}

double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double largest = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) largest = std::max(largest, glm::length(a[v] - b[v]));
    return largest;
}
}  // namespace

TEST_CASE(
    "vfsd battery's error-controlled run reports its estimate, and --reference-check the reference's own distance "
    "from twice its steps",
    "[battery][cli]") {
    const std::vector<std::string> sources = battery_mesh_sources({}, false);
    const BatteryScene b = generate_battery_scene(1, 0, sources);
    constexpr int kReference = 40;
    ScratchDir dir;
    const std::string scene_args = "--seed 1 --coarse --worst 0 --only 0 --tolerance 1e-3 --reference-steps " +
                                   std::to_string(kReference) + " --out '" + dir.path().string() + "'";
    REQUIRE(battery(dir, scene_args + " --reference-check") == 0);
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir.file("battery.json")));
    REQUIRE(report["scenes"].size() == 1);
    const nlohmann::json& scene = report["scenes"][0];
    // Every step taken was estimated within the tolerance: the sum is at most steps × tolerance.
    const double estimated = scene["estimated_error_sum"].get<double>();
    CHECK(estimated > 0.0);
    CHECK(estimated <= scene["steps"].get<int>() * 1e-3);
    // The reference against twice its steps, as computed here.
    const std::vector<Vec3> reference = fixed_steps_result(b, kReference),
                            finer = fixed_steps_result(b, 2 * kReference);
    REQUIRE(reference.size() == finer.size());
    const double expected = largest_distance(reference, finer) / centred_diameter(b.mesh.mesh.positions);
    CHECK(expected > 0.0);
    CHECK(scene["reference_convergence_over_size"].get<double>() == Approx(expected).epsilon(1e-9));
    const nlohmann::json& summary = report["summary"];
    CHECK(summary["scenes_reference_converged"] == (expected <= 1e-3 ? 1 : 0));
    CHECK(test::read_bytes(dir.file("stdout.txt")).find(std::to_string(2 * kReference) + " fixed steps against them") !=
          std::string::npos);
    // Without --reference-check the reference's own distance is not measured.
    ScratchDir plain;
    REQUIRE(battery(plain, "--seed 1 --coarse --worst 0 --only 0 --tolerance 1e-3 --reference-steps " +
                               std::to_string(kReference) + " --out '" + plain.path().string() + "'") == 0);
    const nlohmann::json unchecked = nlohmann::json::parse(std::ifstream(plain.file("battery.json")));
    CHECK(unchecked["scenes"][0]["reference_convergence_over_size"] == -1.0);
    CHECK(unchecked["scenes"][0]["reference_distance_over_size"] == scene["reference_distance_over_size"]);
}

TEST_CASE("vfsd battery rejects bad usage with exit code 2 and says why", "[battery][cli]") {
    ScratchDir dir;
    const std::string out = " --out '" + dir.path().string() + "'";
    for (const std::string& args :
         {std::string("--count 0") + out, std::string("--count 1e12") + out, std::string("--count 2.5") + out,
          std::string("--seed -1") + out, std::string("--amplitude 0") + out, std::string("--scheme none") + out,
          std::string("--steps 10 --tolerance 1e-3") + out, std::string("--tolerance 1e-3 --reference-check") + out,
          std::string("--tolerance 1e-3 --baseline-steps 20") + out, std::string("--count 2")}) {
        INFO("vfsd battery " << args);
        CHECK(battery(dir, args) == 2);
        const std::string said = test::read_bytes(dir.file("stderr.txt"));
        CHECK(said.find("vfsd battery: ") != std::string::npos);
        CHECK_FALSE(std::ifstream(dir.file("battery.json")).good());  // nothing run, nothing written
    }
}
