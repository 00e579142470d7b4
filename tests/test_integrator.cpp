// The one integrator (deform/deformation.h): whatever backend takes the steps,
// Deformation walks the same time grid, checks the same options, times the steps
// and finds non-finite positions. A recording backend stands in for the CPU's
// and the GPU's, so every property is checked for synchronous and asynchronous
// backends alike.
#include <catch2/catch.hpp>

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
};

class RecordingBackend final : public StepBackend {
public:
    RecordingBackend(Record& record, bool asynchronous, int poison_step = 0)
        : record_(record), asynchronous_(asynchronous), poison_step_(poison_step), positions_(3, Vec3(0.0)) {}
    const char* name() const override { return asynchronous_ ? "async" : "sync"; }
    bool asynchronous() const override { return asynchronous_; }
    void finish() const override { ++record_.finishes; }
    void step(double time, double h, int step) override {
        record_.calls.push_back({time, h, step});
        positions_[0].x = time + h;
        if (poison_step_ > 0 && step >= poison_step_) {
            if (!asynchronous_) throw nonfinite_position(2, step, time);
            positions_[2].y = std::numeric_limits<double>::quiet_NaN();
        }
    }
    const std::vector<Vec3>& positions() const override { return positions_; }

private:
    Record& record_;
    bool asynchronous_;
    int poison_step_;
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
