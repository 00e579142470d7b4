// The fold repair (deform/fold_repair.h): it leaves a mesh with no folds as it
// is, untangles a fan the map turned over, puts a vertex back where the map of
// its neighbours takes it, unfolds a needle turned over by its tiny height,
// moves only blend vertices, and a scene it repairs gives the placed result
// wherever it is placed. Built in parts (an editor's frame a part), it repairs
// as the one built whole.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "deform/cpu_steps.h"
#include "deform/fold_repair.h"
#include "deform/quality.h"
#include "io/mesh_file.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "scene/prepared_scene.h"
#include "scene/scene_transform.h"
#include "test_fold_support.h"

using namespace vfsd;

namespace {

// A random map x ↦ A x + t with A a rotation times a stretch of 0.5–2 along
// random axes: what a smooth field does to a small neighbourhood.
struct RandomAffine {
    glm::dmat3 a{1.0};
    Vec3 t{0.0};
    Vec3 operator()(const Vec3& x) const { return a * x + t; }
};

RandomAffine random_affine(std::mt19937& random) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0), stretch(0.5, 2.0);
    const auto axis = [&] { return glm::normalize(Vec3(unit(random), unit(random), unit(random)) + Vec3(1e-9)); };
    const glm::dmat3 turn(glm::rotate(glm::dmat4(1.0), 3.0 * unit(random), axis()));
    const glm::dmat3 frame(glm::rotate(glm::dmat4(1.0), 3.0 * unit(random), axis()));
    const glm::dmat3 scale(glm::scale(glm::dmat4(1.0), Vec3(stretch(random), stretch(random), stretch(random))));
    return {turn * frame * scale * glm::transpose(frame), 5.0 * Vec3(unit(random), unit(random), unit(random))};
}

std::vector<Vec3> mapped(const std::vector<Vec3>& x, const RandomAffine& map) {
    std::vector<Vec3> out;
    for (const Vec3& p : x) out.push_back(map(p));
    return out;
}

// A neighbour of v on the sphere.
std::uint32_t neighbour_of(const VertexRings& rings, std::uint32_t v) { return rings.neighbours[rings.begin(v)]; }

}  // namespace

TEST_CASE("the fold repair leaves a mesh the map did not fold bit for bit", "[deform][repair]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    const std::vector<double> s(sphere.positions.size(), 0.5);
    FoldRepair repair(sphere.positions, s, rings);
    REQUIRE(repair.active());
    std::mt19937 random(3);
    for (int trial = 0; trial < 10; ++trial) {
        std::vector<Vec3> x = mapped(sphere.positions, random_affine(random));
        const std::vector<Vec3> before = x;
        CHECK(repair.repair(x, rings, true) == 0);
        CHECK(x == before);
    }
    CHECK(repair.stats().steps_repaired == 0);
    CHECK(repair.stats().vertex_moves == 0);
}

TEST_CASE("the fold repair untangles a vertex pushed through its neighbour and puts it near the map's image",
          "[deform][repair]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    const std::vector<double> s(sphere.positions.size(), 0.5);
    std::mt19937 random(11);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(sphere.positions.size() - 1));
    for (int trial = 0; trial < 40; ++trial) {
        FoldRepair repair(sphere.positions, s, rings);
        const RandomAffine map = random_affine(random);
        std::vector<Vec3> x = mapped(sphere.positions, map);
        // Slide v past a neighbour, beyond it by 0.7 or 2 of their edge (further
        // than the vertex search's edge moves reach): its fan turns over.
        const std::uint32_t v = pick(random), a = neighbour_of(rings, v);
        x[v] = x[a] + (trial % 2 ? 2.0 : 0.7) * (x[a] - x[v]);
        const double pushed = glm::length(x[v] - map(sphere.positions[v]));
        REQUIRE(!flipped_triangle_list(mapped(sphere.positions, map), x, sphere.triangles).empty());
        CHECK(repair.repair(x, rings, true) == 0);
        CHECK(flipped_triangle_list(mapped(sphere.positions, map), x, sphere.triangles).empty());
        CHECK(repair.stats().steps_repaired == 1);
        CHECK(repair.stats().max_shift > 0.0);
        // The lift pulls v back across its fan (one mean edge at most) and settles it
        // toward its ring's affine image, which the ring fits reproduce: v ends
        // far nearer its image than it was pushed. Over 2,400 such trials (seeds
        // 0 to 59) it ended at most 0.61 of the way, and at 0.5 or more in 16:
        // libc++'s draws (the WebAssembly tests) met one of those.
        CHECK(glm::length(x[v] - map(sphere.positions[v])) < 0.7 * pushed);
    }
}

TEST_CASE("the fold repair built in parts repairs as the one built whole, bit for bit", "[deform][repair]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    std::vector<double> s;  // an inner cap, a blend band, an outer cap
    for (const Vec3& p : sphere.positions) s.push_back(std::clamp(0.5 + p.z, 0.0, 1.0));
    std::mt19937 random(12);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(sphere.positions.size() - 1));
    FoldRepair parts(sphere.positions, s, rings, {}, FoldRepair::InParts{});
    int built = 1;
    for (; !parts.built(); ++built) REQUIRE(parts.build_part(rings));
    CHECK(built > 1);
    CHECK_FALSE(parts.build_part(rings));
    const FoldRepair whole(sphere.positions, s, rings);
    CHECK(parts.checks().check == whole.checks().check);
    CHECK(parts.checks().neighbours == whole.checks().neighbours);
    CHECK(parts.checks().floor == whole.checks().floor);
    for (int trial = 0; trial < 10; ++trial) {
        FoldRepair a = parts, b = whole;  // the state at rest shared, the work state each its own
        std::vector<Vec3> x = mapped(sphere.positions, random_affine(random));
        std::uint32_t v = pick(random);
        while (!(s[v] > 0.0 && s[v] < 1.0)) v = pick(random);  // a blend vertex, pushed through a neighbour
        const std::uint32_t n = neighbour_of(rings, v);
        x[v] = x[n] + 0.7 * (x[n] - x[v]);
        std::vector<Vec3> y = x;
        CHECK(a.count_folds(x, rings, true) == b.count_folds(y, rings, true));
        CHECK(a.repair(x, rings, trial % 2 == 0) == b.repair(y, rings, trial % 2 == 0));
        CHECK(a.acted());
        CHECK(x == y);
    }
}

TEST_CASE("the neighbour test's measures with the affine test's added count and repair as both tests at once",
          "[deform][repair]") {
    // CpuSteps::settle_move tests a step that lands on a repair time only after
    // an affine test's time by the neighbour test, then adds the affine test's
    // measures for the repair: the count and the repair must be those of both
    // tests taken together, and of a repair that measures for itself.
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    std::vector<double> s;
    for (const Vec3& p : sphere.positions) s.push_back(std::clamp(0.5 + p.z, 0.0, 1.0));
    std::mt19937 random(31);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(sphere.positions.size() - 1));
    const FoldRepair at_rest(sphere.positions, s, rings);
    for (int trial = 0; trial < 12; ++trial) {
        std::vector<Vec3> x = sphere.positions;
        std::uint32_t v = pick(random);
        while (!(s[v] > 0.0 && s[v] < 1.0)) v = pick(random);  // a blend vertex
        const std::uint32_t n = neighbour_of(rings, v);
        const int kind = trial % 3;  // 0: pushed through a neighbour; 1: its fan mirrored; 2: nothing
        if (kind == 0) x[v] = x[n] + 0.7 * (x[n] - x[v]);
        if (kind == 1) {
            // Mirrored across a plane through v and its normal: the fan turns
            // over together, which the neighbour test misses in part and the
            // affine test finds.
            const Vec3 f = glm::normalize(glm::cross(sphere.positions[v], x[n] - x[v]));
            const auto mirror = [&](std::uint32_t u) { x[u] -= 2.0 * glm::dot(x[u] - sphere.positions[v], f) * f; };
            mirror(v);
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) mirror(rings.neighbours[k]);
        }
        x = mapped(x, random_affine(random));
        std::vector<Vec3> y = x, z = x;
        FoldRepair added = at_rest, both = at_rest, alone = at_rest;
        added.count_folds(mapped(sphere.positions, random_affine(random)), rings, true, true);  // an earlier test's state
        const std::size_t by_neighbours = added.count_folds(x, rings, false, true);
        const std::size_t by_both = added.count_folds_with_affine(x, rings);
        CHECK(by_both == both.count_folds(y, rings, true, true));
        CHECK(by_both >= by_neighbours);
        if (kind == 0) CHECK(by_both > 0);
        if (kind == 1) CHECK(by_both > by_neighbours);
        if (kind == 2) CHECK(by_both == 0);
        const std::size_t left = added.repair(x, rings, true, true, true);
        CHECK(left == both.repair(y, rings, true, true, true));
        CHECK(left == alone.repair(z, rings, true));
        CHECK(added.acted() == (by_both > 0));
        CHECK(x == y);
        CHECK(x == z);
    }
}

TEST_CASE("the lift's moves grow continuously from zero as a triangle passes its target", "[deform][repair]") {
    // A blend vertex slid toward a neighbour, by a share p of their edge: its
    // fan's triangles narrow and, past some p*, fall short of the lift's target
    // by more than its slack (1e-3 of its area term). Just past p*, the repair
    // moves the mesh by about that slack's worth (3e-5 to 5e-5 of an edge here),
    // more the further past; just before, not at all. (The rounds alone moved a
    // patch by a share of an edge as soon as a triangle folded, whatever the
    // fold's depth.)
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    const std::vector<double> s(sphere.positions.size(), 0.5);
    std::mt19937 random(17);
    for (int trial = 0; trial < 6; ++trial) {
        const RandomAffine map = random_affine(random);
        const std::vector<Vec3> start = mapped(sphere.positions, map);
        const std::uint32_t v = std::uniform_int_distribution<std::uint32_t>(
                                0, static_cast<std::uint32_t>(sphere.positions.size() - 1))(random),
                            a = neighbour_of(rings, v);
        const double edge = glm::length(start[a] - start[v]);
        const auto pushed = [&](double p) {
            std::vector<Vec3> x = start;
            x[v] = start[v] + p * (start[a] - start[v]);
            return x;
        };
        FoldRepair probe(sphere.positions, s, rings);
        double below = 0.0, above = 1.7;  // short at 1.7: the vertex is past its neighbour
        REQUIRE(probe.count_folds(pushed(above), rings, false) > 0);
        REQUIRE(probe.count_folds(pushed(below), rings, false) == 0);
        for (int k = 0; k < 60; ++k) {
            const double middle = 0.5 * (below + above);
            (probe.count_folds(pushed(middle), rings, false) > 0 ? above : below) = middle;
        }
        const auto largest_move = [&](double p, FoldRepairStats& stats) {
            FoldRepair repair(sphere.positions, s, rings);
            std::vector<Vec3> x = pushed(p);
            const std::vector<Vec3> before = x;
            repair.repair(x, rings, false);
            stats = repair.stats();
            double largest = 0.0;
            for (std::size_t u = 0; u < x.size(); ++u) largest = std::max(largest, glm::length(x[u] - before[u]));
            return largest / edge;
        };
        INFO("trial " << trial << ": short from p = " << above);
        FoldRepairStats stats;
        CHECK(largest_move(below, stats) == 0.0);
        CHECK(stats.steps_repaired == 0);
        std::vector<double> moves;
        for (const double past : {1e-9, 1e-6, 1e-3, 1e-1}) {
            moves.push_back(largest_move(above + past, stats));
            CHECK(stats.steps_repaired == 1);
            CHECK(stats.steps_untangled == 0);  // the lift alone: nothing folded is left for the rounds
        }
        INFO("moves, in edges: " << moves[0] << ", " << moves[1] << ", " << moves[2] << ", " << moves[3]);
        CHECK(moves[0] < 1e-4);
        CHECK(moves[1] < 1e-4);
        CHECK(moves[2] < 1e-2);
        CHECK(moves[0] <= moves[1]);
        CHECK(moves[1] <= moves[2]);
        CHECK(moves[2] <= moves[3]);
    }
}

TEST_CASE(
    "the repair's affine test finds no fold under any affine map of a rough mesh, and a vertex pushed "
    "past its neighbour",
    "[deform][repair]") {
    std::mt19937 random(7);
    std::size_t tipped = 0;  // what the neighbour test finds under the same maps
    for (int trial = 0; trial < 12; ++trial) {
        const TriangleMesh mesh = test::rough_sphere(0.05 * (trial % 4), random);
        const VertexRings rings = build_vertex_rings(mesh);
        const std::vector<double> s(mesh.positions.size(), 0.5);
        FoldRepair repair(mesh.positions, s, rings);
        std::vector<Vec3> x = mapped(mesh.positions, random_affine(random));
        INFO("trial " << trial);
        CHECK(repair.affine_folded(x, rings).empty());
        tipped += flipped_triangle_list(mesh.positions, x, mesh.triangles).size();
        const Triangle& picked = mesh.triangles[random() % mesh.triangles.size()];
        x[picked[0]] = x[picked[1]] + 0.5 * (x[picked[1]] - x[picked[0]]);  // past its neighbour
        const std::vector<std::uint32_t> found = repair.affine_folded(x, rings);
        REQUIRE(!found.empty());
        // The triangles of the vertex's fan, and the measure's own (deform/quality.h).
        const FoldChecks checks = repair.checks();
        std::vector<Triangle> found_triangles, measured;
        for (const std::uint32_t i : found) {
            const Triangle& t = checks.triangles[checks.check[i]];
            CHECK((t[0] == picked[0] || t[1] == picked[0] || t[2] == picked[0]));
            found_triangles.push_back(t);
        }
        for (const std::uint32_t t : reversed_triangle_list(mesh.positions, x, mesh.triangles))
            measured.push_back(mesh.triangles[t]);
        CHECK(found_triangles.size() == measured.size());
        CHECK(repair.repair(x, rings, true) == 0);
        CHECK(repair.affine_folded(x, rings).empty());
    }
    INFO("the neighbour test found " << tipped << " triangles under the affine maps alone");
    CHECK(tipped > 0);  // the reason the affine test exists: a rough mesh's bumps tip under a stretch
}

TEST_CASE("the volume is kept after every step, the steps the repair moved vertices in too", "[deform][repair]") {
    Scene scene = test::folding_box_scene();  // folds at most steps without the repair
    scene.options.repair_folds = scene.options.keep_volume = true;
    const PreparedScene prepared = prepare_scene(scene);
    Deformation d = prepared.start_deformation();
    const auto& before = prepared.file.mesh.positions;
    double worst = 0.0, worst_repaired = 0.0;
    std::size_t repaired = 0;
    for (int k = 1; k <= scene.options.steps; ++k) {
        d.advance(double(k) / scene.options.steps);
        const double error = measure_quality(before, d.positions(), prepared.file.mesh.triangles, prepared.region.s)
                                 .volume_error_percent;
        worst = std::max(worst, error);
        if (d.fold_repairs().steps_repaired != repaired) worst_repaired = std::max(worst_repaired, error);
        repaired = d.fold_repairs().steps_repaired;
    }
    INFO("worst volume error " << worst << " %, after a repaired step " << worst_repaired << " %");
    REQUIRE(repaired > 0);
    // The keeper's Newton steps after a repair restore the volume to rounding (one
    // step left 0.0092 % here); after any other step the one step, with the area
    // vectors of the step's midpoint, leaves its second-order rest (8.6e-4 % here).
    CHECK(worst_repaired < 1e-6);
    CHECK(worst < 0.005);
}

TEST_CASE("the repair runs every 1/20 in time and its affine test every 1/5, whatever the steps and either way",
          "[deform][repair]") {
    for (const int steps : {1, 3, 5, 10, 20, 25, 40, 250, 1000}) {
        int due = 0, due_back = 0, affine = 0, affine_back = 0;
        for (int k = 0; k < steps; ++k) {
            const double from = double(k) / steps, to = double(k + 1) / steps;
            due += FoldRepair::repair_due(from, to);
            due_back += FoldRepair::repair_due(to, from);
            affine += FoldRepair::affine_test_due(from, to);
            affine_back += FoldRepair::affine_test_due(to, from);
            if (FoldRepair::affine_test_due(from, to)) CHECK(FoldRepair::repair_due(from, to));
        }
        INFO(steps << " steps");
        CHECK(due == std::min(steps, FoldRepair::kRepairTimes));  // every step passes one at 20 or fewer
        CHECK(affine == std::min(steps, 5));
        CHECK(due_back == due);
        CHECK(affine_back == affine);
        CHECK(FoldRepair::repair_due(double(steps - 1) / steps, 1.0));  // the last step, t = 1, is repaired
        CHECK(FoldRepair::affine_test_due(double(steps - 1) / steps, 1.0));
    }
    // The repair time a forward step passes (strictly inside it), where a
    // controlled step that folded lands.
    CHECK(FoldRepair::repair_time_within(0.04, 0.06) == 0.05);
    CHECK(FoldRepair::repair_time_within(0.0, 0.2) == 0.05);    // the first of those it passes
    CHECK(FoldRepair::repair_time_within(0.04, 0.05) == -1.0);  // ends on it
    CHECK(FoldRepair::repair_time_within(0.05, 0.07) == -1.0);  // starts on it
    CHECK(FoldRepair::repair_time_within(0.06, 0.04) == -1.0);  // back
    CHECK(FoldRepair::repair_time_within(0.9, 1.0) == 0.95);
}

TEST_CASE(
    "a controlled step that passes a repair time and folds is tried again to end on it; without folds, no step "
    "more",
    "[deform][repair][steps]") {
    Scene scene = test::folding_box_scene();  // folds at most steps without the repair
    scene.options.repair_folds = true;
    for (const int steps : {40, 250, 1000}) {
        scene.options.steps = steps;
        Deformation d = prepare_scene(scene).start_deformation();
        d.advance(1.0);
        INFO(steps << " fixed steps: repaired after " << d.fold_repairs().steps_repaired);
        CHECK(d.fold_repairs().steps_repaired > 0);
        CHECK(d.fold_repairs().steps_repaired <= std::size_t(FoldRepair::kRepairTimes));
    }
    scene.options.tolerance = 5e-4;
    Deformation d = prepare_scene(scene).start_deformation();
    REQUIRE(d.error_controlled());
    d.advance(1.0);
    const std::vector<StepTry>& tries = d.step_tries();
    std::size_t landings = 0;
    for (std::size_t k = 0; k + 1 < tries.size(); ++k) {
        const StepTry& t = tries[k];
        if (t.taken || t.error > scene.options.tolerance) continue;  // taken, or over the tolerance
        ++landings;  // under the tolerance, not taken: it passed a repair time and folded
        const double land = FoldRepair::repair_time_within(t.time, t.time + t.length);
        REQUIRE(land > 0.0);
        const StepTry& next = tries[k + 1];
        CHECK(next.time == t.time);
        CHECK(next.taken);
        CHECK(std::abs(next.time + next.length - land) < 1e-12);
    }
    INFO(tries.size() << " tries, " << landings << " landed on a repair time");
    CHECK(landings > 0);
    CHECK(d.fold_repairs().steps_repaired <= std::size_t(FoldRepair::kRepairTimes));

    // Where nothing folds, the repair costs no step: fig. 4's bend takes the same
    // steps and gives the same result, bit for bit, with it and without.
    Scene bend = load_scene(std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig04-box-bend.json");
    bend.options.tolerance = 5e-4;
    std::vector<std::vector<Vec3>> results;
    std::vector<std::size_t> taken;
    for (const bool repair : {true, false}) {
        bend.options.repair_folds = repair;
        Deformation run = prepare_scene(bend).start_deformation();
        run.advance(1.0);
        REQUIRE(run.fold_repairs().steps_repaired == 0);
        results.push_back(run.positions());
        taken.push_back(run.step_milliseconds().size());
    }
    CHECK(taken[0] == taken[1]);
    CHECK(results[0] == results[1]);
}

TEST_CASE("the fold repair moves only blend vertices", "[deform][repair]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    std::mt19937 random(5);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(sphere.positions.size() - 1));
    for (int trial = 0; trial < 10; ++trial) {
        // s = 0 below a random height, 1 above another, blended between.
        std::vector<double> s;
        for (const Vec3& p : sphere.positions) s.push_back(glm::clamp((p.z + 0.3) / 0.6, 0.0, 1.0));
        FoldRepair repair(sphere.positions, s, rings);
        std::vector<Vec3> x = sphere.positions;
        std::uint32_t v = pick(random);
        while (!(s[v] > 0.0 && s[v] < 1.0)) v = pick(random);
        const std::uint32_t a = neighbour_of(rings, v);
        x[v] = x[a] + 0.7 * (x[a] - x[v]);
        const std::vector<Vec3> before = x;
        repair.repair(x, rings, true);
        for (std::size_t u = 0; u < x.size(); ++u)
            if (s[u] == 0.0 || s[u] == 1.0) CHECK(x[u] == before[u]);
        CHECK(x[v] != before[v]);
    }
}

TEST_CASE("a scene the fold repair acts on, turned, moved far away or mirrored, deforms into the placed result",
          "[deform][repair][invariance]") {
    Scene scene = test::folding_box_scene();  // folds without the repair
    scene.options.repair_folds = true;
    const MeshFile file = load_mesh_file("builtin:box");
    const auto deform = [](const Scene& sc, MeshFile f, FoldRepairStats& stats) {
        const PreparedScene prepared = prepare_scene(sc, std::move(f));
        Deformation d = prepared.start_deformation();
        d.advance(1.0);
        stats = d.fold_repairs();
        CHECK(count_flipped_triangles(prepared.file.mesh.positions, d.positions(), prepared.file.mesh.triangles) == 0);
        return d.positions();
    };
    FoldRepairStats stats;
    const std::vector<Vec3> result = deform(scene, file, stats);
    REQUIRE(stats.steps_repaired > 0);  // the repair acts on this scene
    for (const bool mirror : {false, true}) {
        Placement placement;
        placement.rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), 2.1, glm::normalize(Vec3(0.3, -0.8, 0.5))));
        if (mirror) placement.rotation = placement.rotation * glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1);
        placement.offset = Vec3(-120.0, 95.0, 140.0);  // about 100 diagonals from the origin
        MeshFile placed = file;
        place_mesh(placed.mesh, placement);
        FoldRepairStats placed_stats;
        const std::vector<Vec3> placed_result = deform(place_scene(scene, placement), placed, placed_stats);
        CHECK(placed_stats.steps_repaired == stats.steps_repaired);
        double worst = 0.0;
        for (std::size_t v = 0; v < result.size(); ++v)
            worst = std::max(worst, glm::length(placement.point(result[v]) - placed_result[v]));
        INFO("mirrored: " << mirror);
        // Placed, the ring passes' float sums differ in their last bits (1e-7 of an
        // edge at the first repair); the lift's moves are continuous in the
        // positions, not exactly reproducible, and on this box, short of its lift's
        // target at most repair times, those differences grow to 1e-5 of the size
        // by t = 1 (1e-6 when only the rounds acted, which act alike on positions
        // a little apart). Runs of different step counts differ by 1e-3.
        CHECK(worst / bounding_box(placed.mesh.positions).diagonal() < 1e-4);
    }
}

TEST_CASE("the fold repair unfolds a needle turned over by its tiny height, moving its corner by little",
          "[deform][repair]") {
    // A needle: a vertex v of the sphere moved at rest to a thousandth of its
    // base's length from the base, inside its triangle. Under a random affine
    // map it is then mirrored across its base: the needle turns over, and v lies
    // a few thousandths of an edge from where the map takes it, closer than the
    // ring and patch fits place a vertex.
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    const VertexRings rings = build_vertex_rings(sphere);
    const std::vector<double> s(sphere.positions.size(), 0.5);
    std::mt19937 random(17);
    std::uniform_int_distribution<std::size_t> pick(0, sphere.triangles.size() - 1);
    for (int trial = 0; trial < 20; ++trial) {
        const Triangle t = sphere.triangles[pick(random)];
        const std::uint32_t v = t[0], a = t[1], b = t[2];
        std::vector<Vec3> rest = sphere.positions;
        const Vec3 base = rest[b] - rest[a], foot = rest[a] + 0.5 * base;
        const Vec3 inward =
            glm::normalize(rest[v] - foot - glm::dot(rest[v] - foot, base) / glm::dot(base, base) * base);
        const double height = 1e-3 * glm::length(base);
        rest[v] = foot + height * inward;
        FoldRepair repair(rest, s, rings);
        const RandomAffine map = random_affine(random);
        std::vector<Vec3> x = mapped(rest, map);
        x[v] = map(foot - height * inward);  // across its base
        INFO("trial " << trial);
        REQUIRE(count_flipped_triangles(rest, x, sphere.triangles) > 0);
        const Vec3 image = map(rest[v]);
        repair.repair(x, rings, true);
        CHECK(count_flipped_triangles(rest, x, sphere.triangles) == 0);
        CHECK(reversed_triangle_list(rest, x, sphere.triangles).empty());
        // Near the map's image still: within half the needle's base.
        CHECK(glm::length(x[v] - image) < 0.5 * glm::length(map(rest[b]) - map(rest[a])));
    }
}

namespace {

// The way out: `d` run to t = 1 a step at a time, the time and shape at rest and after each step.
std::vector<std::pair<double, std::vector<Vec3>>> steps_to_end(Deformation& d) {
    std::vector<std::pair<double, std::vector<Vec3>>> way_out{{0.0, d.positions()}};
    while (d.time() < 1.0) {
        d.advance(1.0, 1);
        way_out.emplace_back(d.time(), d.positions());
    }
    return way_out;
}

}  // namespace

TEST_CASE("scrubbing back across the fold repair shows the way out's shapes, and t = 0 the rest positions",
          "[deform][repair][steps]") {
    // A step back does not undo the repair: scrubbing back on a scene the repair
    // acted on had ended 3e-2 of its size from the way out's shape, and 8e-2
    // from rest at t = 0. The deformation now starts again from rest and repeats
    // the way out's steps and tries: its bits, at fixed and controlled steps.
    Scene scene = test::folding_box_scene();  // folds without the repair
    scene.options.repair_folds = true;
    std::mt19937 random(41);
    for (const double tolerance : {0.0, 5e-4}) {
        for (const int steps : {40, 37}) {
            scene.options.steps = steps;
            scene.options.tolerance = tolerance;
            const PreparedScene p = prepare_scene(scene);
            Deformation d = p.start_deformation();
            const std::vector<std::pair<double, std::vector<Vec3>>> way_out = steps_to_end(d);
            INFO((tolerance > 0.0 ? "error-controlled" : "fixed")
                 << ", " << way_out.size() - 1 << " steps, " << d.fold_repairs().steps_repaired << " repaired");
            REQUIRE(d.fold_repairs().steps_repaired > 0);
            const double size = centred_diameter(p.file.mesh.positions);
            // Back and forth to times of the way out, drawn at random, and back to 0.
            for (int k = 0; k < 6; ++k) {
                const auto& [time, shape] =
                    way_out[std::uniform_int_distribution<std::size_t>(0, way_out.size() - 1)(random)];
                d.advance(time);
                REQUIRE(d.time() == time);
                double apart = 0.0;
                for (std::size_t v = 0; v < shape.size(); ++v)
                    apart = std::max(apart, glm::length(d.positions()[v] - shape[v]));
                INFO("at t = " << time << ": " << apart / size << " of the size from the way out");
                CHECK(d.positions() == shape);
            }
            d.advance(0.0);
            CHECK(d.positions() == p.file.mesh.positions);
            d.advance(1.0);
            CHECK(d.positions() == way_out.back().second);
        }
    }
}

TEST_CASE("a way back starts from the latest checkpoint at or before its target: the way out's shapes, fewer steps",
          "[deform][repair][steps]") {
    // Where the repair has acted, the way out keeps a checkpoint after the first
    // step at or past the last fifth of unit time short of its target, and a
    // way back that started again from rest one at each fifth it passes; a way
    // back across the repair, the first too, starts from the latest one at or
    // before its target: the same bits in fewer steps than from rest.
    Scene scene = test::folding_box_scene();  // folds without the repair
    scene.options.repair_folds = true;
    for (const double tolerance : {0.0, 5e-4}) {
        scene.options.steps = 40;
        scene.options.tolerance = tolerance;
        const PreparedScene p = prepare_scene(scene);
        Deformation d = p.start_deformation();
        const std::vector<std::pair<double, std::vector<Vec3>>> way_out = steps_to_end(d);
        INFO((tolerance > 0.0 ? "error-controlled" : "fixed") << ", " << way_out.size() - 1 << " steps");
        // way_out[k] is k steps from rest.
        const auto index_before = [&](double t) {
            std::size_t k = 0;
            while (k + 1 < way_out.size() && way_out[k + 1].first <= t) ++k;
            return k;
        };
        // The first step at or past t, where the checkpoint for t's fifth is taken.
        const auto checkpoint = [&](double t) {
            return index_before(t) + (way_out[index_before(t)].first < t ? 1 : 0);
        };
        Deformation probe = p.start_deformation();  // the repair acted by the checkpoint at 0.8
        probe.advance(way_out[checkpoint(0.8)].first);
        REQUIRE(probe.fold_repairs().steps_repaired > 0);
        const std::size_t late = index_before(0.95), early = index_before(0.5), earlier = index_before(0.3);
        REQUIRE(d.rewinds_to(way_out[late].first));
        CHECK(d.advance(way_out[late].first) == int(late - checkpoint(0.8)));  // the way out's own checkpoint
        CHECK(d.positions() == way_out[late].second);
        REQUIRE(d.rewinds_to(way_out[early].first));
        CHECK(d.advance(way_out[early].first) == int(early));  // none at or before 0.5 yet: from rest
        CHECK(d.positions() == way_out[early].second);
        REQUIRE(d.rewinds_to(way_out[earlier].first));
        const int taken = d.advance(way_out[earlier].first);
        CHECK(d.positions() == way_out[earlier].second);
        CHECK(taken == int(earlier - checkpoint(0.2)));  // kept on the way back from rest
        d.advance(0.0);
        CHECK(d.positions() == p.file.mesh.positions);
        d.advance(1.0);
        CHECK(d.positions() == way_out.back().second);
    }
}

TEST_CASE("past the way out's end, a run scrubbed back and forth goes on as one that was not",
          "[deform][repair][steps]") {
    // After the way back repeats the way out's tries, the steps beyond its last
    // time are new tries, as in a run that never went back: the same bits. (Back
    // to a time between two of the way out's, a step is cut to reach it, and
    // the run forward from there leaves the way out within its tolerance.)
    Scene scene = test::folding_box_scene();  // folds without the repair
    scene.options.repair_folds = true;
    scene.options.tolerance = 5e-4;
    const PreparedScene p = prepare_scene(scene);
    Deformation scrubbed = p.start_deformation(), straight = p.start_deformation();
    std::vector<double> way_out;
    while (scrubbed.time() < 0.6) {
        scrubbed.advance(0.6, 1);
        way_out.push_back(scrubbed.time());
    }
    straight.advance(0.6);
    REQUIRE(scrubbed.fold_repairs().steps_repaired > 0);
    for (const double share : {0.5, 0.75, 0.2}) {
        const double t = way_out[static_cast<std::size_t>(share * double(way_out.size()))];
        REQUIRE(scrubbed.rewinds_to(t));
        scrubbed.advance(t);
        scrubbed.advance(0.6);
    }
    scrubbed.advance(1.0);
    straight.advance(1.0);
    CHECK(scrubbed.step_errors().rejected == straight.step_errors().rejected);
    CHECK(scrubbed.step_tries().size() == straight.step_tries().size());
    CHECK(scrubbed.positions() == straight.positions());
}

TEST_CASE("a run keeps the affine test's sums from one test to the next and frees them at its target",
          "[deform][repair]") {
    // The sums of every star (FoldRepair::StarSums, per corner of a checked
    // triangle) are allocated once a run (at 2M vertices about 100 MB) and freed
    // when it reaches its target, so that the state's size between runs stays
    // what it was.
    Scene scene = test::folding_box_scene();
    scene.options.repair_folds = true;
    scene.options.steps = 40;
    const PreparedScene prepared = prepare_scene(scene);
    auto steps = std::make_unique<CpuSteps>(prepared.file.mesh.positions, prepared.rings, prepared.region,
                                            prepared.motion, scene.options);
    const CpuSteps& state = *steps;
    Deformation d(std::move(steps), scene.options);
    std::size_t blend = 0;
    for (const double s : prepared.region.s) blend += s > 0.0 && s < 1.0;
    REQUIRE(blend > 0);
    const std::size_t sums = blend * sizeof(FoldRepair::StarSums);  // at least: every blend vertex is a corner

    d.advance(1.0, 10);  // past the affine test at t = 0.2
    const std::size_t after_first = state.state_bytes();
    d.advance(1.0, 15);                         // past those at 0.4 and 0.6
    CHECK(state.state_bytes() == after_first);  // held, not allocated again
    d.advance(1.0);
    CHECK(d.time() == 1.0);
    CHECK(state.state_bytes() + sums <= after_first);  // freed at the target
    d.advance(0.5);                                    // a run back to its target frees them there too
    CHECK(state.state_bytes() + sums <= after_first);
}

TEST_CASE("a star's sums hold its normal as vertex_normal gives it, bit for bit, with and without a boundary",
          "[deform][repair]") {
    // The affine test takes each star's normal in the same ring walk as its
    // sums (FoldRepair::star_sums) and must read the same normal the other
    // passes take; its Σ yᵢ and Σ yᵢ pᵢᵀ are the plain sums over the ring.
    std::mt19937 random(7);
    for (const bool open : {false, true}) {
        TriangleMesh mesh = test::rough_sphere(0.03, random);
        if (open)  // a hole around the pole: the vertices on its border have an open wedge
            mesh.triangles.erase(std::remove_if(mesh.triangles.begin(), mesh.triangles.end(),
                                                [&](const Triangle& t) {
                                                    return mesh.positions[t[0]].z + mesh.positions[t[1]].z +
                                                               mesh.positions[t[2]].z >
                                                           2.4;
                                                }),
                                 mesh.triangles.end());
        const VertexRings rings = build_vertex_rings(mesh);
        const std::vector<Vec3> x = mapped(mesh.positions, random_affine(random));
        int open_wedges = 0;
        for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
            const FoldRepair::StarSums star = FoldRepair::star_sums(mesh.positions, x, rings, v);
            const Vec3 normal = vertex_normal(x, rings, v);
            REQUIRE(std::memcmp(&star.normal, &normal, sizeof normal) == 0);
            Vec3 sum(0.0);
            glm::dmat3 product(0.0);
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                const Vec3 y = x[rings.neighbours[k]] - x[v];
                sum += y, product += glm::outerProduct(y, mesh.positions[rings.neighbours[k]] - mesh.positions[v]);
                open_wedges += !rings.wedge[k];
            }
            CHECK(star.count == double(rings.end(v) - rings.begin(v) + 1));
            CHECK(star.sum == sum);
            CHECK(star.product == product);
        }
        CHECK((open_wedges > 0) == open);
    }
}
