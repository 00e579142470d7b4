// The frame pacer on a simulated clock: cheap draws every frame after the step
// budget; costly draws, where the shell keeps its image, about a quarter of the
// run, with no frame much longer than the longest allowed; a pause of the loop is
// not taken for a draw; the desktop (no kept image) draws every frame; a renderer
// still busy with the last draw gets no new one, and its time is the draw's cost.
#include <catch2/catch.hpp>

#include <algorithm>
#include <utility>

#include "editor/frame_pacer.h"

using vfsd::editor::FramePacer;

namespace {

struct Run {
    int frames = 0, draws = 0;
    double steps_ms = 0.0, draw_ms = 0.0, longest_frame_ms = 0.0;
    double longest_without_draw_ms = 0.0;  // between the ends of two draws
};

// `frames` frames of a running deformation: each integrates what the plan says
// (at least one step of `step_ms`) and draws for `draw_ms` when it says so.
Run simulate(FramePacer& pacer, double& clock, int frames, double step_ms, double draw_ms, bool keeps_image) {
    Run run;
    double drawn_at = clock;
    for (int f = 0; f < frames; ++f) {
        const double start = clock;
        const FramePacer::Plan plan = pacer.plan(clock, true, keeps_image);
        const int steps = std::max(1, int(plan.integrate_ms / step_ms));
        clock += steps * step_ms;
        run.steps_ms += steps * step_ms;
        pacer.integrated(clock, plan.draw);
        if (plan.draw) {
            clock += draw_ms;
            run.draw_ms += draw_ms;
            ++run.draws;
            run.longest_without_draw_ms = std::max(run.longest_without_draw_ms, clock - drawn_at);
            drawn_at = clock;
        }
        ++run.frames;
        run.longest_frame_ms = std::max(run.longest_frame_ms, clock - start);
    }
    return run;
}

}  // namespace

TEST_CASE("frame pacer: a cheap draw, or any draw without a kept image, is made every frame after the step budget",
          "[editor][pacer]") {
    for (const auto& [draw_ms, keeps_image] : {std::pair{3.0, true}, std::pair{60.0, false}}) {
        FramePacer pacer(15.0, 80.0);
        double clock = 0.0;
        const Run run = simulate(pacer, clock, 200, 1.0, draw_ms, keeps_image);
        CHECK(run.draws == run.frames);
        CHECK(run.steps_ms == Approx(200 * 15.0));
        CHECK(pacer.draw_ms() == Approx(draw_ms));
    }
}

TEST_CASE("frame pacer: a costly draw on a kept image takes about a quarter of the run", "[editor][pacer]") {
    for (const double draw_ms : {30.0, 60.0, 120.0}) {
        for (const double step_ms : {2.0, 20.0}) {
            FramePacer pacer(15.0, 80.0);
            double clock = 0.0;
            const Run run = simulate(pacer, clock, 300, step_ms, draw_ms, true);
            INFO("draw " << draw_ms << " ms, step " << step_ms << " ms: " << run.draws << " draws in " << run.frames
                         << " frames, steps " << run.steps_ms << " ms, drawing " << run.draw_ms << " ms");
            CHECK(pacer.draw_ms() == Approx(draw_ms).epsilon(1e-3));
            const double drawing_share = run.draw_ms / (run.draw_ms + run.steps_ms);
            CHECK(drawing_share <= 0.3);
            CHECK(run.longest_without_draw_ms <= 1000.0);  // it keeps showing progress
            // No frame longer than the longest allowed, or a draw after the step budget
            // (the first frames, before the draw's cost is known), give or take a step.
            CHECK(run.longest_frame_ms <= std::max(80.0, draw_ms + 15.0) + step_ms);
        }
    }
}

TEST_CASE("frame pacer: a pause of the loop is not a draw, nor is a frame that does not run", "[editor][pacer]") {
    FramePacer pacer(15.0, 80.0);
    double clock = 0.0;
    simulate(pacer, clock, 20, 1.0, 5.0, true);
    // The run ends with a drawn frame, the loop sleeps ten seconds, a new run starts.
    const FramePacer::Plan idle = pacer.plan(clock, false, true);
    CHECK(idle.draw);
    pacer.integrated(clock, true);
    clock += 10000.0;
    const FramePacer::Plan next = pacer.plan(clock, true, true);
    CHECK(next.draw);
    CHECK(next.integrate_ms == Approx(15.0));
    CHECK(pacer.draw_ms() == Approx(5.0));
}

TEST_CASE("frame pacer: the renderer's own time counts, and a busy renderer gets no costly draw", "[editor][pacer]") {
    FramePacer pacer(15.0, 80.0);
    double clock = 0.0;
    simulate(pacer, clock, 10, 2.0, 1.0, true);  // the frames wait 1 ms after a draw
    CHECK_FALSE(pacer.draws_costly());
    pacer.renderer_finished(90.0);  // but the renderer took 90 ms to finish the draw
    CHECK(pacer.draw_ms() == Approx(90.0));
    CHECK(pacer.draws_costly());
    // Long after the last draw (the loop paused meanwhile), a draw is due unless the renderer is still busy.
    pacer.plan(clock, false, true);
    pacer.integrated(clock, false);
    clock += 1000.0;
    CHECK(pacer.plan(clock, true, true, false).draw);
    const FramePacer::Plan busy = pacer.plan(clock, true, true, true);
    CHECK_FALSE(busy.draw);
    CHECK(busy.integrate_ms == Approx(80.0));  // the frame fills with steps instead
}
