// The one integrator (deform/deformation.h): whatever backend takes the steps,
// Deformation walks the same time grid, checks the same options, times the steps
// and finds non-finite positions. A recording backend stands in for the CPU's
// and the GPU's, so every property is checked for synchronous and asynchronous
// backends alike.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "deform/deformation.h"

using namespace vfsd;

namespace {

struct Call {
    double time, h;
    int step;
};

// Records its calls; moves vertex 0 to x = time after each step, and makes
// vertex `poison` non-finite from step `poison_step` on.
struct Record {
    std::vector<Call> calls;
    int finishes = 0;
    int refused = 0;
};

// With `error_scale` > 0 it estimates each step's error as error_scale · h² · (1 +
// time), an error that grows along the way, as the step control assumes
// (StepControl::next_length), and refuses a step over its bound. With `growth`
// > 0, as error_scale · h² · exp(growth · (time + h / 2)) instead: a coefficient
// that grows by e every 1 / growth of unit time (the raised claw's last fifth
// doubled it every 0.02: growth 35).
struct Estimates {
    double error_scale = 0.0;
    std::vector<double> joins;
    double growth = 0.0;
    double error(double time, double h) const {
        return error_scale * h * h * (growth > 0.0 ? std::exp(growth * (time + 0.5 * h)) : 1.0 + time);
    }
};

class RecordingBackend final : public StepBackend {
public:
    RecordingBackend(Record& record, bool asynchronous, int poison_step = 0, Estimates estimates = {})
        : record_(record),
          asynchronous_(asynchronous),
          poison_step_(poison_step),
          estimates_(std::move(estimates)),
          positions_(3, Vec3(0.0)) {}
    bool estimates_error() const override { return estimates_.error_scale > 0.0; }
    std::vector<double> motion_joins() const override { return estimates_.joins; }
    const char* name() const override { return asynchronous_ ? "async" : "sync"; }
    bool asynchronous() const override { return asynchronous_; }
    void finish() const override { ++record_.finishes; }
    StepResult step(double time, double h, int step, double max_error) override {
        const double error = estimates_.error(time, h);
        if (estimates_error() && error > max_error) {
            ++record_.refused;
            return {false, error};
        }
        record_.calls.push_back({time, h, step});
        positions_[0].x = time + h;
        if (poison_step_ > 0 && step >= poison_step_) {
            if (!asynchronous_) throw nonfinite_position(2, step, time);
            positions_[2].y = std::numeric_limits<double>::quiet_NaN();
        }
        return {true, estimates_error() ? error : -1.0};
    }
    const std::vector<Vec3>& positions() const override { return positions_; }

private:
    Record& record_;
    bool asynchronous_;
    int poison_step_;
    Estimates estimates_;
    std::vector<Vec3> positions_;
};

Deformation recording(Record& record, bool asynchronous, int steps, int poison_step = 0) {
    DeformationOptions options;
    options.steps = steps;
    return Deformation(std::make_unique<RecordingBackend>(record, asynchronous, poison_step), options);
}

}  // namespace

TEST_CASE("every backend is driven along the grid k / steps, forward, back and to any target",
          "[deformation][integrator]") {
    std::mt19937 random(17);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const bool asynchronous : {false, true}) {
        CAPTURE(asynchronous);
        for (int trial = 0; trial < 50; ++trial) {
            const int steps = 1 + static_cast<int>(unit(random) * 40);
            Record record;
            Deformation d = recording(record, asynchronous, steps);
            double expected_time = 0.0;
            for (int move = 0; move < 6; ++move) {
                const double target = move % 3 == 2 ? -0.5 + 2.0 * unit(random) : unit(random);  // some outside [0,1]
                const int max_steps = move == 4 ? 1 + static_cast<int>(unit(random) * 3) : 1 << 30;
                const std::size_t before = record.calls.size();
                const int taken = d.advance(target, max_steps);
                REQUIRE(record.calls.size() - before == static_cast<std::size_t>(taken));
                REQUIRE(taken <= max_steps);
                for (std::size_t c = before; c < record.calls.size(); ++c) {
                    const Call& call = record.calls[c];
                    // Each step starts where the last ended, moves toward the
                    // target, ends on the grid or on the target, and never
                    // spans more than one grid cell.
                    CHECK(std::abs(call.time - expected_time) < 1e-15);
                    CHECK(call.step == static_cast<int>(c) + 1);
                    CHECK(std::abs(call.h) <= 1.0 / steps + 1e-12);
                    expected_time = call.time + call.h;
                    const double k = expected_time * steps;
                    const double clamped = std::clamp(target, 0.0, 1.0);
                    CHECK((std::abs(k - std::round(k)) < 1e-9 || std::abs(expected_time - clamped) < 1e-15));
                }
                if (max_steps == 1 << 30) CHECK(d.time() == std::clamp(target, 0.0, 1.0));
                CHECK(std::abs(d.positions()[0].x - d.time()) < 1e-15);
            }
            CHECK(d.step_milliseconds().size() == record.calls.size());
            if (asynchronous) CHECK(record.finishes > 0);
        }
    }
}

TEST_CASE("the integrator checks the options for every backend", "[deformation][integrator]") {
    for (const bool asynchronous : {false, true}) {
        Record record;
        DeformationOptions options;
        options.steps = 0;
        CHECK_THROWS_AS(Deformation(std::make_unique<RecordingBackend>(record, asynchronous), options), InputError);
        options.steps = 10;
        options.smoothing_steps = -1;
        CHECK_THROWS_AS(Deformation(std::make_unique<RecordingBackend>(record, asynchronous), options), InputError);
    }
}

TEST_CASE("a non-finite position stops a synchronous backend at once and is found in an asynchronous one's read-back",
          "[deformation][integrator][robustness]") {
    Record sync_record;
    Deformation sync = recording(sync_record, false, 10, 4);
    try {
        sync.advance(1.0);
        FAIL("the fourth step's non-finite vertex went unnoticed");
    } catch (const NumericalError& e) {
        CHECK_THAT(e.what(), Catch::Contains("step 4") && Catch::Contains("vertex 2"));
    }
    CHECK(std::abs(sync.time() - 0.3) < 1e-12);  // the last good step's end
    CHECK(std::isfinite(sync.positions()[2].y));

    Record async_record;
    Deformation async = recording(async_record, true, 10, 4);
    CHECK(async.advance(0.2) == 2);
    CHECK_NOTHROW(async.positions());
    CHECK(async.advance(1.0) == 8);  // queued work cannot stop part way
    CHECK(async_record.finishes == 2);
    CHECK_THROWS_WITH(async.positions(), Catch::Contains("async integration made vertex 2 non-finite"));
    CHECK_THROWS_AS(async.positions(), NumericalError);  // and keeps saying so
}

TEST_CASE("an asynchronous backend's steps are timed over its finish, one figure per step",
          "[deformation][integrator]") {
    Record record;
    Deformation d = recording(record, true, 8);
    d.advance(0.5);
    REQUIRE(d.step_milliseconds().size() == 4);
    for (const double ms : d.step_milliseconds()) CHECK(ms == d.step_milliseconds().front());
    CHECK(d.ms_per_step() == d.step_milliseconds().front());
    CHECK(std::string(d.backend_name()) == "async");
    CHECK(!d.device_vertices());
}

namespace {

Deformation controlled(Record& record, double tolerance, Estimates estimates, bool asynchronous = false) {
    DeformationOptions options;
    options.tolerance = tolerance;
    return Deformation(std::make_unique<RecordingBackend>(record, asynchronous, 0, std::move(estimates)), options);
}

}  // namespace

TEST_CASE("error-controlled steps keep each estimate within the tolerance, land on every join and grow where they can",
          "[deformation][integrator][step-control]") {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
        Estimates estimates;
        estimates.error_scale = std::pow(10.0, -4.0 + 5.0 * unit(random));
        for (int j = 0, joins = static_cast<int>(unit(random) * 5); j < joins; ++j)
            estimates.joins.push_back(0.05 + 0.9 * unit(random));
        std::sort(estimates.joins.begin(), estimates.joins.end());
        const double tolerance = std::pow(10.0, -5.0 + 3.0 * unit(random));
        CAPTURE(trial, estimates.error_scale, tolerance);
        Record record;
        Deformation d = controlled(record, tolerance, estimates);
        REQUIRE(d.error_controlled());
        d.advance(1.0);
        CHECK(d.time() == 1.0);
        double time = 0.0, longest = 0.0;
        for (const Call& call : record.calls) {
            CHECK(call.time == time);
            const double error = estimates.error(call.time, call.h);
            CHECK((error <= tolerance || call.h <= StepControl::kShortestStep));
            CHECK(call.h <= StepControl::kLongestStep + 1e-15);
            for (const double join : estimates.joins) CHECK(!(call.time < join && join < call.time + call.h));
            time = call.time + call.h;
            longest = std::max(longest, call.h);
        }
        for (const double join : estimates.joins)  // landed on exactly: some step ends there
            CHECK(std::any_of(record.calls.begin(), record.calls.end(),
                              [&](const Call& c) { return c.time + c.h == join; }));
        // Where the error allows it, steps grow from the first step's length.
        if (estimates.error_scale * StepControl::kLongestStep * StepControl::kLongestStep * 2.0 < tolerance &&
            estimates.joins.empty())
            CHECK(longest == StepControl::kLongestStep);
        CHECK(d.step_errors().rejected == record.refused);
        CHECK(d.step_errors().estimated_steps == static_cast<int>(record.calls.size()));
        CHECK(d.step_errors().largest <= tolerance);
    }
}

TEST_CASE("where the estimate grows along the way, the step control foresees it: few tries over the tolerance",
          "[deformation][integrator][step-control]") {
    // A coefficient (error / h²) growing by e every 1 / growth: the length that
    // kept the last step within the tolerance takes the next over it, unless
    // the control foresees the growth (StepControl::foreseen_length).
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int refused = 0, taken = 0;
    for (int trial = 0; trial < 40; ++trial) {
        Estimates estimates;
        estimates.growth = 2.0 + 38.0 * unit(random);
        const double tolerance = std::pow(10.0, -5.0 + 3.0 * unit(random));
        // The coefficient at t = 1 from 100 to a million tolerances.
        estimates.error_scale = tolerance * std::pow(10.0, 2.0 + 4.0 * unit(random)) * std::exp(-estimates.growth);
        CAPTURE(trial, estimates.growth, estimates.error_scale, tolerance);
        Record record;
        Deformation d = controlled(record, tolerance, estimates);
        d.advance(1.0);
        CHECK(d.time() == 1.0);
        for (const Call& call : record.calls)
            CHECK((estimates.error(call.time, call.h) <= tolerance || call.h <= StepControl::kShortestStep));
        refused += record.refused;
        taken += static_cast<int>(record.calls.size());
    }
    INFO(refused << " tries refused, " << taken << " steps taken");
    CHECK(refused * 20 <= taken);
}

TEST_CASE("a first step estimated far over the tolerance is tried again once, as short as its estimate asks",
          "[deformation][integrator][step-control]") {
    // The estimate grows as h², as the control assumes: the retry at
    // 0.9 √(tolerance / E) of the first step's length is within the tolerance
    // whenever that factor is at least StepControl::kMostShrinkRetry (E up to 81
    // tolerances; the raised claw's first step was estimated at 34), and at most
    // half the step's length.
    for (const double over : {2.0, 10.0, 30.0, 60.0, 80.0}) {
        const double tolerance = 1e-3;
        const double scale = over * tolerance / (StepControl::kFirstStep * StepControl::kFirstStep);
        Record record;
        Deformation d = controlled(record, tolerance, {scale, {}});
        CAPTURE(over);
        REQUIRE(d.advance(1.0, 1) == 1);
        CHECK(record.refused == 1);
        REQUIRE(record.calls.size() == 1);
        const double retry = record.calls[0].h;
        CHECK(retry == Approx(StepControl::kFirstStep * std::min(0.5, 0.9 / std::sqrt(over))).epsilon(1e-12));
        CHECK(scale * retry * retry <= tolerance);
    }
}

TEST_CASE("a time budget stops a synchronous backend after the step that spends it, at the same steps",
          "[deformation][integrator][step-control]") {
    // A budget of 0 is spent by any step: one step per call, a refused try
    // before it included; the steps are those of a call without a budget. An
    // asynchronous backend (the GPU's) queues its steps without waiting for
    // them, so the budget does not stop it.
    for (const double error_scale : {0.0, 3.0}) {
        CAPTURE(error_scale);
        const auto make = [&](Record& record, bool asynchronous) {
            if (error_scale == 0.0) return recording(record, asynchronous, 12);
            return controlled(record, 1e-3, {error_scale, {0.4}}, asynchronous);
        };
        Record whole_record, budget_record;
        Deformation whole = make(whole_record, false), budgeted = make(budget_record, false);
        const int steps = whole.advance(1.0);
        REQUIRE(steps > 3);
        int calls = 0;
        while (budgeted.time() != 1.0 && calls <= steps) {
            CHECK(budgeted.advance(1.0, 1 << 30, 0.0) == 1);
            ++calls;
        }
        CHECK(calls == steps);
        REQUIRE(budget_record.calls.size() == whole_record.calls.size());
        for (std::size_t c = 0; c < whole_record.calls.size(); ++c) {
            CHECK(budget_record.calls[c].time == whole_record.calls[c].time);
            CHECK(budget_record.calls[c].h == whole_record.calls[c].h);
        }
        CHECK(budget_record.refused == whole_record.refused);
        if (error_scale > 0.0) CHECK(whole_record.refused > 0);

        Record async_record;
        Deformation async = make(async_record, true);
        CHECK(async.advance(1.0, 1 << 30, 0.0) == steps);
    }
}

TEST_CASE("error-controlled steps take about twice as many steps for a quarter of the tolerance",
          "[deformation][integrator][step-control]") {
    // The estimate grows as h², so the steps needed grow as 1 / √tolerance.
    for (const double scale : {1.0, 30.0, 1000.0}) {
        Record coarse_record, fine_record;
        Deformation coarse = controlled(coarse_record, 1e-3, {scale, {}});
        Deformation fine = controlled(fine_record, 0.25e-3, {scale, {}});
        const double ratio = double(fine.advance(1.0)) / double(coarse.advance(1.0));
        CAPTURE(scale, coarse_record.calls.size(), fine_record.calls.size());
        CHECK(ratio > 1.5);
        CHECK(ratio < 2.6);
    }
}

TEST_CASE("error-controlled steps run back and forth along the times they reached, to any target",
          "[deformation][integrator][step-control]") {
    std::mt19937 random(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const bool asynchronous : {false, true}) {
        Record record;
        Deformation d = controlled(record, 1e-4, {0.5, {1.0 / 3.0, 2.0 / 3.0}}, asynchronous);
        d.advance(1.0);
        std::vector<double> forward;
        for (const Call& c : record.calls) forward.push_back(c.time + c.h);
        const int refused = record.refused;
        for (int move = 0; move < 20; ++move) {
            const double target = unit(random);
            const std::size_t before = record.calls.size();
            d.advance(target);
            CHECK(d.time() == target);
            CHECK(std::abs(d.positions()[0].x - target) < 1e-15);
            // Every step ends on a time reached before or on the target, and no
            // step is refused: those times' errors were checked on the way out.
            for (std::size_t c = before; c < record.calls.size(); ++c) {
                const double end = record.calls[c].time + record.calls[c].h;
                const bool on_grid = end == 0.0 || std::binary_search(forward.begin(), forward.end(), end);
                CHECK((on_grid || end == target));
            }
        }
        CHECK(record.refused == refused);
        // Back to 0 and out again: the same times as the first way out.
        d.advance(0.0);
        const std::size_t before = record.calls.size();
        d.advance(1.0);
        std::vector<double> again;
        for (std::size_t c = before; c < record.calls.size(); ++c)
            again.push_back(record.calls[c].time + record.calls[c].h);
        CHECK(again == forward);
    }
}

TEST_CASE("fixed steps end on the curve's joins too", "[deformation][integrator]") {
    Record record;
    DeformationOptions options;
    options.steps = 10;
    const std::vector<double> joins = {1.0 / 3.0, 0.5, 2.0 / 3.0};
    Deformation d(std::make_unique<RecordingBackend>(record, false, 0, Estimates{0.0, joins}), options);
    CHECK(!d.error_controlled());
    d.advance(1.0);
    CHECK(record.calls.size() == 12);  // 10 grid cells, two of them cut by a join (0.5 is on the grid)
    for (const Call& c : record.calls) {
        const double end = c.time + c.h, k = end * 10.0;
        CHECK((std::abs(k - std::round(k)) < 1e-9 || std::find(joins.begin(), joins.end(), end) != joins.end()));
    }
    d.advance(0.0);  // and back over the same times
    for (std::size_t c = 12; c < record.calls.size(); ++c)
        CHECK(record.calls[c].time + record.calls[c].h == record.calls[23 - c].time);
}

TEST_CASE("the tolerance is checked", "[deformation][integrator][step-control]") {
    Record record;
    for (const double bad : {-1e-3, 0.2, std::numeric_limits<double>::quiet_NaN()}) {
        DeformationOptions options;
        options.tolerance = bad;
        CHECK_THROWS_AS(Deformation(std::make_unique<RecordingBackend>(record, false), options), InputError);
    }
}
