// A long step may run over frames (Deformation::prepare_step: ∇r and the gauge
// at its middle with the error estimate in one call, the move in the next, at a
// fold repair's time the volume keeper and the fold test with the move or, at
// the affine test's, in the next, and the repair in the next advance()). On generated scenes
// (any mesh, placement, region kind, motion and sign of twist), with
// error-controlled steps and fixed ones, forward and back, the run in pieces
// must be the run in whole steps, bit for bit, its rejected tries included
// (and those that land on a fold repair's time); a prepared try that no step
// takes must leave a valid run.
#include <limits>

#include <catch2/catch.hpp>

#include "deform/deformation.h"
#include "deform/fold_repair.h"
#include "mesh/geometry.h"
#include "scene/battery.h"
#include "scene/prepared_scene.h"

using namespace vfsd;

namespace {

const std::vector<std::string>& sources() {
    static const std::vector<std::string> coarse = battery_mesh_sources({}, false);
    return coarse;
}

// Every step toward `target` prepared piece by piece, then taken alone; returns
// the steps, the pieces prepared in `pieces`, and those that ended a try not
// taken (StepPiece::retried) in `retried`.
int advance_in_pieces(Deformation& d, double target, int& pieces, int& retried) {
    int steps = 0;
    while (d.time() != target) {
        // Back across a step the fold repair acted after, advance() starts again
        // from rest or a checkpoint (Deformation::advance): no piece prepares that.
        if (d.rewinds_to(target)) CHECK(d.advance(target, 0) == 0);
        if (d.time() == target) break;  // from a checkpoint taken at the target itself
        int before = pieces;
        for (StepPiece piece; (piece = d.prepare_step(target)) != StepPiece::none;) {
            REQUIRE(piece != StepPiece::waiting);  // the CPU's pieces do not wait
            ++pieces;
            retried += piece == StepPiece::retried;
        }
        CHECK(pieces >= before + 2);  // the estimates and the move, at least
        steps += d.advance(target, 1);
    }
    CHECK(d.prepare_step(target) == StepPiece::none);  // at the target: nothing to prepare
    return steps;
}

// The pieces a run in pieces prepares, by its tries: one for a try over the
// tolerance (the estimates); two for a step (the estimates, the move), and a
// third where it passes a time of the fold repair's affine test (the volume
// keeper's move and the fold test; at its other times they join the move). A
// try that passed a repair time and folded (under the tolerance, not taken)
// ends at its test, and is tried again to end there, in pieces too.
int expected_pieces(const std::vector<StepTry>& tries, double tolerance) {
    int pieces = 0;
    for (const StepTry& t : tries) {
        const bool over = !t.taken && t.error > tolerance;
        pieces += over ? 1 : 2 + FoldRepair::affine_test_due(t.time, t.time + t.length);
    }
    return pieces;
}

// The same for `steps` fixed steps from t = 0 to 1.
int expected_fixed_pieces(int steps) {
    int pieces = 0;
    for (int k = 0; k < steps; ++k)
        pieces += 2 + FoldRepair::affine_test_due(k / double(steps), (k + 1) / double(steps));
    return pieces;
}

// Seed 5's scene `index`, its steps error-controlled or 30 fixed ones, and its name.
std::pair<PreparedScene, std::string> battery_scene(int index, bool controlled) {
    const BatteryScene b = generate_battery_scene(5, index, sources(), 1.0);
    Scene scene = b.scene;
    scene.options.tolerance = controlled ? kSceneTolerance : 0.0;
    scene.options.steps = 30;
    return {prepare_scene(scene, b.mesh), b.name + (controlled ? ", error-controlled" : ", 30 fixed steps")};
}

bool same_tries(const std::vector<StepTry>& a, const std::vector<StepTry>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].time != b[i].time || a[i].length != b[i].length || a[i].error != b[i].error ||
            a[i].taken != b[i].taken)
            return false;
    return true;
}

}  // namespace

TEST_CASE("a step run in pieces is the step run whole, on generated scenes", "[deform][editor]") {
    int rejected = 0, landings = 0, repaired = 0;
    for (int index = 0; index < 8; ++index) {
        for (const bool controlled : {true, false}) {
            const auto [p, name] = battery_scene(index, controlled);
            INFO(name);
            Deformation whole = p.start_deformation(), halves = p.start_deformation();
            const int whole_steps = whole.advance(1.0);
            int pieces = 0, retried = 0;
            CHECK(advance_in_pieces(halves, 1.0, pieces, retried) == whole_steps);
            if (controlled)
                CHECK(pieces == expected_pieces(whole.step_tries(), kSceneTolerance));
            else
                CHECK(pieces == expected_fixed_pieces(30));
            // A piece says so where it ended a try not taken: the next piece starts the step again.
            int not_taken = 0;
            for (const StepTry& t : whole.step_tries()) not_taken += !t.taken;
            CHECK(retried == not_taken);
            CHECK(halves.positions() == whole.positions());
            CHECK(same_tries(halves.step_tries(), whole.step_tries()));
            CHECK(halves.step_errors().rejected == whole.step_errors().rejected);
            CHECK(halves.fold_repairs().steps_repaired == whole.fold_repairs().steps_repaired);
            rejected += whole.step_errors().rejected;
            for (const StepTry& t : whole.step_tries()) landings += !t.taken && t.error <= kSceneTolerance;
            repaired += int(whole.fold_repairs().steps_repaired);
            // Back to t = 0.4 along the times reached.
            whole.advance(0.4);
            advance_in_pieces(halves, 0.4, pieces, retried);
            CHECK(halves.positions() == whole.positions());
        }
    }
    CHECK(rejected > 0);  // the pieces were held to rejected tries too
    CHECK(landings > 0);  // and to tries that folded at a repair's time and landed on it
    CHECK(repaired > 0);  // and to steps the repair acted after
}

TEST_CASE("a prepared step that the next advance does not take leaves a valid run", "[deform][editor]") {
    const BatteryScene b = generate_battery_scene(5, 2, sources(), 1.0);
    Scene scene = b.scene;
    scene.options.tolerance = kSceneTolerance;
    const PreparedScene p = prepare_scene(scene, b.mesh);
    // The same stops, one of them with a step prepared toward t = 1 that the
    // advance to 0.35 does not take (in effect a rejected try).
    Deformation plain = p.start_deformation(), retargeted = p.start_deformation();
    for (Deformation* d : {&plain, &retargeted}) {
        d->advance(0.3);
        if (d == &retargeted) REQUIRE(retargeted.prepare_step(1.0) == StepPiece::done);
        d->advance(0.35);
        CHECK(d->time() == 0.35);
        d->advance(1.0);
        CHECK(d->time() == 1.0);
    }
    const auto& a = plain.positions();
    const auto& r = retargeted.positions();
    const double size = centred_diameter(a);
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - r[v]));
    INFO("largest distance from the run without the unused try: " << worst / size << " of the size");
    CHECK(worst < 10.0 * kSceneTolerance * size);
}

TEST_CASE("a run that stops before each step through the affine test's times is the run whole", "[deform][editor]") {
    for (int index = 0; index < 4; ++index) {
        for (const bool controlled : {true, false}) {
            const auto [p, name] = battery_scene(index, controlled);
            INFO(name);
            Deformation whole = p.start_deformation(), stopping = p.start_deformation();
            const int steps = whole.advance(1.0);
            int calls = 0, taken = 0;
            while (stopping.time() != 1.0 && calls <= steps) {
                // Each call's first step may be one (the caller's to run in pieces), no later one.
                const int n = stopping.advance(1.0, 1 << 30, std::numeric_limits<double>::infinity(), true);
                CHECK(n >= 1);
                taken += n, ++calls;
                if (stopping.time() != 1.0) CHECK(stopping.next_step_tests_affine(1.0));
            }
            CHECK(taken == steps);
            // The affine test runs at 0.2, 0.4, 0.6 and 0.8 (before t = 1): four stops at least.
            CHECK(calls >= 5);
            CHECK(stopping.positions() == whole.positions());
            CHECK(same_tries(stopping.step_tries(), whole.step_tries()));
        }
    }
}
