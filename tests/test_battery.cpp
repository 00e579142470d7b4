// The scene battery (engine/scene/battery.h) on the coarse built-in meshes: the
// scenes are reproducible and cover every kind, and the deformation keeps the
// method's promises on them: at a quarter of the battery's full amplitude (bends
// to 45°, twists to ±45°, handles turned to 22.5°) no triangle folds, the outer
// region stays, the inner region is rigid and the volume is kept. At full
// amplitude the same holds with the default scheme; the flow alone (without the
// fold repair, deform/fold_repair.h) folds on more than a quarter of the scenes
// (docs/method.md, "Keeping the promise", says where the folds come from), and
// refining its mesh where it folds (scene/scene_run.h) takes scenes off that list
// and never folds more. Scenes run as `vfsd deform` runs them (run_scene).
// test_gpu_deformation.cpp runs the GPU passes on these scenes.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <random>
#include <set>

#include "deform/quality.h"
#include "io/mesh_file.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh_fixtures.h"
#include "scene/battery.h"
#include "scene/prepared_scene.h"
#include "scene/scene_run.h"
#include "test_io_support.h"

using namespace vfsd;

namespace {

constexpr std::uint64_t kSeed = 1;
constexpr int kScenes = 30;

const std::vector<std::string>& sources() {
    static const std::vector<std::string> coarse = battery_mesh_sources({}, false);
    return coarse;
}

struct Run {
    DeformationQuality quality;
    std::vector<Vec3> result;
    FoldRepairStats repairs;
    int refinements = 0;
    TriangleMesh rest;            // the mesh the result belongs to (refined where it folded)
    std::vector<RunTried> tried;  // the runs run_scene made
};

// As `vfsd deform` runs a scene (scene/scene_run.h).
Run deform(const BatteryScene& b, DeformationOptions options) {
    Scene scene = b.scene;
    scene.options = options;
    PreparedScene prepared = prepare_scene(scene, b.mesh);
    const SceneRun run = run_scene(prepared);
    const Deformation& d = *run.deformation;
    return {
        measure_quality(prepared.file.mesh.positions, d.positions(), prepared.file.mesh.triangles, prepared.region.s),
        d.positions(),
        d.fold_repairs(),
        run.refinements,
        prepared.file.mesh,
        run.tried};
}

void check_promises(const BatteryScene& b, const DeformationQuality& q) {
    INFO(b.name << ": " << q.flipped_triangles << " folds, volume " << q.volume_error_percent << " %, outer "
                << q.outer_max_displacement << ", inner " << q.inner_rigid_residual);
    CHECK(q.nonfinite_vertices == 0);
    CHECK(q.inner_vertices > 0);
    CHECK(q.outer_vertices > 0);
    CHECK(q.outer_max_displacement == 0.0);
    CHECK(q.inner_rigid_residual <= 1e-9);  // of the diagonal
    CHECK(q.volume_error_percent <= 0.01);
}

}  // namespace

TEST_CASE("battery scenes are reproducible and cover every region kind, motion, sign and placement", "[battery]") {
    std::set<std::string> regions, motions;
    int mirrored = 0, twists_left = 0, twists_right = 0, far = 0;
    for (int index = 0; index < kScenes; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, sources());
        const BatteryScene again = generate_battery_scene(kSeed, index, sources());
        CHECK(again.name == b.name);
        CHECK(again.mesh.mesh.positions == b.mesh.mesh.positions);
        CHECK(scene_to_json(again.scene) == scene_to_json(b.scene));
        regions.insert(b.region_kind);
        motions.insert(b.motion_kind == "handle" ? "handle" : "curve");
        mirrored += b.placement.mirrors();
        twists_left += b.twist_degrees < 0.0;
        twists_right += b.twist_degrees > 0.0;
        const double diagonal = bounding_box(b.mesh.mesh.positions).diagonal();
        far += glm::length(bounding_box(b.mesh.mesh.positions).centre()) > 10.0 * diagonal;
        CHECK(b.blend_rings >= kBatteryBlendRings);
    }
    CHECK(regions == std::set<std::string>{"geodesic", "selectors", "vertex-lists", "painted-s"});
    CHECK(motions == std::set<std::string>{"curve", "handle"});
    CHECK(mirrored > 0);
    CHECK(far > kScenes / 2);  // most placed 10 to 100 diagonals from the origin
    CHECK(twists_left > 0);
    CHECK(twists_right > 0);
    CHECK(generate_battery_scene(kSeed + 1, 0, sources()).scene.motion.curve.bezier !=
          generate_battery_scene(kSeed, 0, sources()).scene.motion.curve.bezier);
}

// CGAL's coarse anchor (scripts/get-cgal-meshes) is too short for a blend region
// of 6 rings about many of its vertices: the generator lays the region out about
// another seed until one is (before, 7 of the 300 docs/ scenes had 2 to 5 rings).
TEST_CASE("battery scenes on a coarse CAD mesh still have a blend region 6 rings wide", "[battery][cgal]") {
    const std::string anchor = VFSD_SOURCE_DIR "/assets/cgal/anchor.off";
    if (!std::filesystem::exists(anchor)) {
        WARN("skipped: " << anchor << " is absent (run scripts/get-cgal-meshes)");
        return;
    }
    const std::vector<std::string> only_anchor = {anchor};
    for (int index = 0; index < 40; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, only_anchor);
        INFO(b.name);
        CHECK(b.blend_rings >= kBatteryBlendRings);
    }
}

TEST_CASE(
    "battery meshes must be closed, consistently wound, in one piece and large enough (any surface: large enough)",
    "[battery]") {
    CHECK(battery_mesh_unusable(load_mesh_file("builtin:sphere:3")).empty());
    CHECK(battery_mesh_unusable(load_mesh_file("builtin:sphere:1")).find("vertices") != std::string::npos);
    TriangleMesh open = load_mesh_file("builtin:sphere:3").mesh;
    open.triangles.pop_back();
    CHECK(battery_mesh_unusable(weld_mesh(open, "off")).find("open") != std::string::npos);
    // Triangles wound against their neighbours in the file: welding turns them,
    // and the battery takes the mesh only when told to take any surface.
    TriangleMesh wound = load_mesh_file("builtin:sphere:3").mesh;
    for (std::size_t t = 0; t < wound.triangles.size(); t += 7) std::swap(wound.triangles[t][0], wound.triangles[t][1]);
    CHECK(battery_mesh_unusable(weld_mesh(wound, "off")).find("wound inconsistently") != std::string::npos);
    CHECK(battery_mesh_unusable(weld_mesh(wound, "off"), true).empty());
    CHECK(battery_mesh_unusable(weld_mesh(open, "off"), true).empty());
    TriangleMesh two = load_mesh_file("builtin:sphere:3").mesh;
    const auto n = static_cast<std::uint32_t>(two.positions.size());
    const std::size_t triangles = two.triangles.size();
    for (std::uint32_t v = 0; v < n; ++v) two.positions.push_back(two.positions[v] + Vec3(5.0, 0.0, 0.0));
    for (std::size_t t = 0; t < triangles; ++t) two.triangles.push_back(two.triangles[t] + Triangle(n));
    CHECK(battery_mesh_unusable(weld_mesh(two, "off")) == "more than one piece");
    CHECK(battery_mesh_unusable(weld_mesh(two, "off"), true).empty());
}

TEST_CASE("battery at a quarter amplitude: no folds, outer in place, inner rigid, volume kept", "[battery][deform]") {
    std::size_t folds = 0;
    for (int index = 0; index < kScenes; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, sources(), 0.25);
        const Run run = deform(b, b.scene.options);
        std::printf("battery 1/4 %-40s folds %3zu (reversed %3zu) volume %.2e %%\n", b.name.c_str(),
                    run.quality.flipped_triangles, run.quality.reversed_triangles, run.quality.volume_error_percent);
        check_promises(b, run.quality);
        CHECK(run.quality.flipped_triangles == 0);
        folds += run.quality.flipped_triangles;
    }
    std::printf("battery seed %d, amplitude 1/4, %d coarse built-in scenes: %zu folded triangles\n", int(kSeed),
                kScenes, folds);
}

TEST_CASE("battery at full amplitude: no folds, outer in place, inner rigid, volume kept; the flow alone folds",
          "[battery][deform]") {
    std::size_t flow_folds = 0, flow_folded = 0, paper_folds = 0, paper_folded = 0, repaired_scenes = 0;
    std::size_t refined_folds = 0, refined_folded = 0, refined_scenes = 0, kept_fewer_at_end = 0;
    for (int index = 0; index < kScenes; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, sources());
        const Run run = deform(b, b.scene.options);  // the default: harmonic profile, fold repair, refinement
        check_promises(b, run.quality);
        CHECK(run.quality.flipped_triangles == 0);
        repaired_scenes += run.repairs.steps_repaired > 0;
        DeformationOptions flow = b.scene.options;  // the same without the repair and the refinement
        flow.repair_folds = false;
        flow.fold_refinements = 0;
        const Run alone = deform(b, flow);
        check_promises(b, alone.quality);
        flow_folds += alone.quality.flipped_triangles, flow_folded += alone.quality.flipped_triangles > 0;
        // The flow alone on a mesh refined where it folds (scene/scene_run.h): never
        // more folds; the input's vertices first, where they were; the promises kept.
        flow.fold_refinements = DeformationOptions{}.fold_refinements;
        const Run refined = deform(b, flow);
        INFO(b.name << ": refined " << refined.refinements << " times");
        check_promises(b, refined.quality);
        CHECK(refined.quality.flipped_triangles <= alone.quality.flipped_triangles);
        CHECK(refined.rest.vertex_count() <= 2 * b.mesh.mesh.vertex_count());
        CHECK(std::equal(b.mesh.mesh.positions.begin(), b.mesh.mesh.positions.end(), refined.rest.positions.begin()));
        CHECK((refined.refinements > 0) == (refined.rest.vertex_count() > b.mesh.mesh.vertex_count()));
        // Of the runs made, the result folds fewest at the end, then over the
        // tenths (the first of equals).
        REQUIRE(refined.tried.size() > std::size_t(refined.refinements));
        CHECK(refined.tried.front().vertices == b.mesh.mesh.vertex_count());
        CHECK(refined.tried.front().folded_at_end == alone.quality.flipped_triangles);
        const RunTried& kept = refined.tried[std::size_t(refined.refinements)];
        CHECK(kept.vertices == refined.rest.vertex_count());
        CHECK(kept.folded_at_end == refined.quality.flipped_triangles);
        for (std::size_t k = 0; k < refined.tried.size(); ++k) {
            const RunTried& t = refined.tried[k];
            CHECK(kept.folded_at_end <= t.folded_at_end);
            if (t.folded_at_end == kept.folded_at_end) {
                CHECK(kept.folded_over_tenths <= t.folded_over_tenths);
                if (t.folded_over_tenths == kept.folded_over_tenths) CHECK(k >= std::size_t(refined.refinements));
            }
        }
        kept_fewer_at_end +=
            kept.folded_over_tenths >
            std::min_element(refined.tried.begin(), refined.tried.end(), [](const RunTried& a, const RunTried& b) {
                return a.folded_over_tenths < b.folded_over_tenths;
            })->folded_over_tenths;
        refined_scenes += refined.refinements > 0;
        refined_folds += refined.quality.flipped_triangles, refined_folded += refined.quality.flipped_triangles > 0;
        BatteryScene printed_scene = b;  // secs. 5 and 6 as printed, for comparison
        printed_scene.scene.region.profile = RegionSpec::Profile::geodesic;
        DeformationOptions paper = paper_steps(b.scene.options);
        paper.tangent_smoothing = true;
        const Run printed = deform(printed_scene, paper);
        paper_folds += printed.quality.flipped_triangles, paper_folded += printed.quality.flipped_triangles > 0;
    }
    std::printf(
        "battery seed %d, full amplitude, %d coarse built-in scenes: 0 fold with the default (the repair acted on "
        "%zu); the flow alone folds %zu scenes (%zu triangles), refined where it folds %zu (%zu; %zu scenes "
        "refined; %zu kept a run folding fewer at the end than the one folding fewest over the tenths); secs. 5 "
        "and 6 as printed: %zu scenes (%zu triangles)\n",
        int(kSeed), kScenes, repaired_scenes, flow_folded, flow_folds, refined_folded, refined_folds, refined_scenes,
        kept_fewer_at_end, paper_folded, paper_folds);
    CHECK(flow_folds <= paper_folds);
    CHECK(flow_folded > kScenes / 4);  // the scenes are hard enough to need the repair
    CHECK(refined_scenes > 0);
    CHECK(refined_folded < flow_folded);  // refining takes scenes off the list
}

// The battery on meshes as users have them (vfsd battery --any-mesh): a sphere
// with holes, a cylinder whose file winds a third of its triangles the other
// way, and two spheres touching at a vertex, written as files and read back.
// No fold, the outer region in place, the inner one rigid, and the volume kept
// where the surface encloses one.
TEST_CASE("battery at full amplitude on meshes with holes, mixed winding and a pinch: the promises kept",
          "[battery][deform][hostile]") {
    test::ScratchDir dir;
    TriangleMesh holes = make_builtin_mesh("sphere", 4);
    for (std::size_t t = 0; t < holes.triangles.size(); t += 97) holes.triangles[t] = holes.triangles.back();
    holes.triangles.resize(holes.triangles.size() - 1);
    TriangleMesh wound = make_builtin_mesh("cylinder", 24);
    for (std::size_t t = 0; t < wound.triangles.size(); t += 3) std::swap(wound.triangles[t][1], wound.triangles[t][2]);
    std::mt19937 random(3);
    const TriangleMesh pinched = fixtures::pinched_spheres(random);
    std::vector<std::string> files;
    for (const auto& [name, mesh] : {std::pair<const char*, const TriangleMesh&>{"holes.off", holes},
                                     {"wound.off", wound},
                                     {"pinched.off", pinched}}) {
        write_mesh_file(dir.file(name), mesh);
        CHECK(battery_mesh_unusable(load_mesh_file(dir.file(name)), true).empty());
        files.push_back(dir.file(name));
    }
    CHECK(!battery_mesh_unusable(load_mesh_file(files[0])).empty());  // not for the default battery
    std::size_t without_volume = 0;
    for (int index = 0; index < 9; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, files);
        const Run run = deform(b, b.scene.options);
        INFO(b.name << ": " << run.quality.flipped_triangles << " folds, volume " << run.quality.volume_error_percent
                    << " %, outer " << run.quality.outer_max_displacement << ", inner "
                    << run.quality.inner_rigid_residual);
        CHECK(run.quality.flipped_triangles == 0);
        CHECK(run.quality.nonfinite_vertices == 0);
        CHECK(run.quality.outer_max_displacement == 0.0);
        CHECK(run.quality.inner_rigid_residual <= 1e-9);
        if (run.quality.volume_defined)
            CHECK(run.quality.volume_error_percent <= 0.01);
        else
            ++without_volume;
    }
    CHECK(without_volume > 0);  // the sphere with holes has none
    CHECK(without_volume < 9);
}

TEST_CASE("battery at full amplitude: error-controlled steps land near many fixed steps, where the repair acts too",
          "[battery][deform][steps]") {
    // The repair acts at the same times in both runs (deform/fold_repair.h), on
    // shapes as close as their integration. Repairing after every step that
    // folded instead, 3 of these 15 repaired scenes were within 1e-3; with the
    // rounds alone (no lift), 14 of 15.
    std::size_t compared = 0, within = 0, repaired = 0, repaired_within = 0;
    double farthest = 0.0;
    for (int index = 0; index < kScenes; ++index) {
        const BatteryScene b = generate_battery_scene(kSeed, index, sources());
        DeformationOptions controlled = b.scene.options, fixed = b.scene.options;
        controlled.tolerance = 5e-4;
        fixed.tolerance = 0.0;
        fixed.steps = 1000;
        const Run run = deform(b, controlled), reference = deform(b, fixed);
        for (const Run* r : {&run, &reference})
            CHECK(r->repairs.steps_repaired <= std::size_t(FoldRepair::kRepairTimes));
        if (run.result.size() != reference.result.size()) continue;  // refined differently
        double distance = 0.0;
        for (std::size_t v = 0; v < run.result.size(); ++v)
            distance = std::max(distance, glm::length(run.result[v] - reference.result[v]));
        distance /= centred_diameter(run.rest.positions);
        const bool repair = run.repairs.steps_repaired > 0 || reference.repairs.steps_repaired > 0;
        std::printf("battery %-40s %s %.1e of the size from 1000 fixed steps\n", b.name.c_str(),
                    repair ? "repaired" : "        ", distance);
        ++compared, within += distance <= 1e-3;
        repaired += repair, repaired_within += repair && distance <= 1e-3;
        if (!repair) CHECK(distance <= 1e-3);
        farthest = std::max(farthest, distance);
    }
    std::printf(
        "battery seed %d, full amplitude: %zu of %zu scenes within 1e-3 of 1000 fixed steps (repaired: %zu of "
        "%zu); farthest %.2g\n",
        int(kSeed), within, compared, repaired_within, repaired, farthest);
    CHECK(compared >= std::size_t(kScenes - 2));
    CHECK(repaired >= 10);                       // the repair acts on enough scenes to tell
    CHECK(3 * repaired_within >= 2 * repaired);  // 11 of 15 here
    CHECK(5 * within >= 4 * compared);           // 26 of 30
}
