// A CPU deformation's rest state (deform/cpu_steps.h: the work order, the keepers
// and the estimates at rest) does not depend on the motion, so a curve edit may
// start its run from the last run's: on generated scenes (any mesh, placement,
// region kind, motion and sign of twist) the run from it must be the run from
// scratch, bit for bit, and a rest state must refuse a mesh, region or options
// it was not built for.
#include <catch2/catch.hpp>

#include "deform/cpu_steps.h"
#include "deform/deformation.h"
#include "mesh/geometry.h"
#include "scene/battery.h"
#include "scene/prepared_scene.h"

using namespace vfsd;

namespace {

const std::vector<std::string>& sources() {
    static const std::vector<std::string> coarse = battery_mesh_sources({}, false);
    return coarse;
}

// The same scene with another motion: the curve's end moved by a tenth of the
// mesh's size (the handle's target, for a handle) and the twist turned the other way.
Scene edited_motion(Scene scene, double size) {
    CurveSpec& curve = scene.motion.curve;
    const Vec3 offset(0.1 * size, -0.05 * size, 0.03 * size);
    if (curve.is_handle)
        curve.to.position += offset;
    else
        curve.bezier.back() += offset;
    scene.motion.twist_degrees[1] = -scene.motion.twist_degrees[1] - 40.0;
    return scene;
}

struct Result {
    std::vector<Vec3> positions;
    int steps = 0;
    StepErrors errors;
    FoldRepairStats repairs;
};

Result run(Deformation& d) {
    Result r;
    r.steps = d.advance(1.0);
    r.positions = d.positions();
    r.errors = d.step_errors();
    r.repairs = d.fold_repairs();
    return r;
}

}  // namespace

TEST_CASE("a run from an earlier run's rest state is the run from scratch", "[deform][rest]") {
    for (int index = 0; index < 8; ++index) {
        const BatteryScene b = generate_battery_scene(3, index, sources(), 0.6);
        for (const bool midpoint : {true, false}) {
            INFO(b.name << (midpoint ? ", midpoint ∇r" : ", ∇r at the step's start"));
            Scene scene = b.scene;
            scene.options.gradients_at_midpoint = midpoint;
            scene.options.tolerance = midpoint ? kSceneTolerance : 0.0;
            scene.options.steps = 30;
            const PreparedScene first = prepare_scene(scene, b.mesh);
            Deformation before = first.start_deformation();
            CHECK(before.cpu_rest() == nullptr);  // nothing built yet
            run(before);
            const std::shared_ptr<const CpuRest> rest = before.cpu_rest();
            REQUIRE(rest != nullptr);
            CHECK(rest->fits(first.file.mesh.positions, first.rings, first.region, first.scene.options));

            const double size = bounding_box(first.file.mesh.positions).diagonal();
            const PreparedScene edited =
                prepare_scene(edited_motion(scene, size), first.file, first.rings, first.region);
            Deformation fresh = edited.start_deformation();
            Deformation reused(rest, edited.motion, edited.scene.options);
            CHECK_FALSE(reused.prepare_first_step());  // everything at rest is there
            const Result a = run(fresh), r = run(reused);
            CHECK(r.positions == a.positions);
            CHECK(r.steps == a.steps);
            CHECK(r.errors.rejected == a.errors.rejected);
            CHECK(r.repairs.steps_repaired == a.repairs.steps_repaired);
            CHECK(r.repairs.vertex_moves == a.repairs.vertex_moves);
            CHECK(r.positions != first.file.mesh.positions);
            // The run from it left it as it was: a second run from it is the same.
            Deformation again(rest, edited.motion, edited.scene.options);
            CHECK(run(again).positions == a.positions);
        }
    }
}

TEST_CASE("a rest state fits only the mesh, region and options it was built for", "[deform][rest]") {
    const BatteryScene b = generate_battery_scene(3, 1, sources(), 0.6);
    const PreparedScene p = prepare_scene(b.scene, b.mesh);
    Deformation d = p.start_deformation();
    REQUIRE(d.prepare_first_step());
    CHECK(d.cpu_rest() == nullptr);  // a part of the keepers, not yet the estimates at rest
    while (d.prepare_first_step()) continue;
    const std::shared_ptr<const CpuRest> rest = d.cpu_rest();
    REQUIRE(rest != nullptr);
    const auto& positions = p.file.mesh.positions;
    CHECK(rest->fits(positions, p.rings, p.region, p.scene.options));

    std::vector<Vec3> moved = positions;
    moved[moved.size() / 2].x = std::nextafter(moved[moved.size() / 2].x, 1e300);
    CHECK_FALSE(rest->fits(moved, p.rings, p.region, p.scene.options));

    Region region = p.region;
    std::size_t blend = 0;
    while (!(region.s[blend] > 0.0 && region.s[blend] < 1.0)) ++blend;
    region.s[blend] *= 0.5;
    CHECK_FALSE(rest->fits(positions, p.rings, region, p.scene.options));
    Region sphere = p.region;
    sphere.sphere_tool = SphereTool{Vec3(0.0), 0.1, 0.2};
    CHECK_FALSE(rest->fits(positions, p.rings, sphere, p.scene.options));

    // The same positions with one triangle's corners in another order: other rings.
    TriangleMesh turned = p.file.mesh;
    std::swap(turned.triangles[0][1], turned.triangles[0][2]);
    CHECK_FALSE(rest->fits(positions, build_vertex_rings(turned), p.region, p.scene.options));

    for (int change = 0; change < 7; ++change) {
        DeformationOptions options = p.scene.options;
        switch (change) {
            case 0: options.smoothing_steps += 1; break;
            case 1: options.smoothing_weight *= 0.5; break;
            case 2: options.gradients_at_midpoint = !options.gradients_at_midpoint; break;
            case 3: options.fit_stream_gauge = !options.fit_stream_gauge; break;
            case 4: options.tangent_smoothing = !options.tangent_smoothing; break;
            case 5: options.keep_volume = !options.keep_volume; break;
            case 6: options.repair_folds = !options.repair_folds; break;
        }
        INFO("option change " << change);
        CHECK_FALSE(rest->fits(positions, p.rings, p.region, options));
    }
    // What the steps alone read (their count, the tolerance) may differ.
    DeformationOptions other_steps = p.scene.options;
    other_steps.steps += 7;
    other_steps.tolerance *= 2.0;
    CHECK(rest->fits(positions, p.rings, p.region, other_steps));
}

TEST_CASE("the sphere tool keeps no rest state, and a rest state not yet built is refused", "[deform][rest]") {
    const BatteryScene b = generate_battery_scene(3, 0, sources(), 0.6);
    const PreparedScene p = prepare_scene(b.scene, b.mesh);
    Region sphere;
    const double size = bounding_box(p.file.mesh.positions).diagonal();
    sphere.sphere_tool = SphereTool{p.file.mesh.positions[0], 0.1 * size, 0.4 * size};
    Deformation tool(p.file.mesh.positions, p.rings, sphere, p.motion, p.scene.options);
    tool.prepare_first_step();
    tool.advance(0.5);
    CHECK(tool.positions() != p.file.mesh.positions);  // it moved the mesh
    CHECK(tool.cpu_rest() == nullptr);

    Deformation d = p.start_deformation();
    d.prepare_first_step();  // a part of the keepers, not yet the estimates: not handed out
    REQUIRE(d.cpu_rest() == nullptr);
    CHECK_THROWS_AS(Deformation(std::shared_ptr<const CpuRest>(), p.motion, p.scene.options), std::invalid_argument);
}
