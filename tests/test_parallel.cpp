// parallel_for and parallel_sum (base/parallel.h): every index once, whatever
// the range, the thread limit or other callers; sums with the same bits on one
// thread and on all.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "base/parallel.h"

using namespace vfsd;

namespace {

// Runs parallel_for over [0, n) and checks that each index was visited once
// (counted in atomics: Catch's assertions are for the test's own thread).
void check_each_once(std::size_t n, std::size_t grain) {
    std::vector<std::atomic<int>> visits(n);
    std::atomic<std::size_t> calls{0}, bad_chunks{0};
    parallel_for(
        n,
        [&](std::size_t begin, std::size_t end) {
            if (!(begin < end && end <= n)) bad_chunks.fetch_add(1);
            for (std::size_t i = begin; i < end && i < n; ++i) visits[i].fetch_add(1);
            calls.fetch_add(1);
        },
        grain);
    std::size_t wrong = 0;
    for (const auto& v : visits) wrong += v.load() != 1;
    INFO("n = " << n << ", grain = " << grain << ", " << calls.load() << " chunks");
    CHECK(bad_chunks == 0);
    CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("parallel_for visits every index once, on any number of threads", "[parallel]") {
    for (const unsigned limit : {0u, 1u, 2u})
        for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(7), kParallelGrain - 1, kParallelGrain,
                                    kParallelGrain + 1, std::size_t(8193), std::size_t(100000)})
            for (const std::size_t grain : {std::size_t(1), kParallelGrain}) {
                set_parallel_thread_limit(limit);
                check_each_once(n, grain);
            }
    set_parallel_thread_limit(0);
}

TEST_CASE("parallel_for from several threads at once: the calls take turns", "[parallel]") {
    std::vector<std::thread> callers;
    std::atomic<std::size_t> wrong{0};
    for (int t = 0; t < 4; ++t)
        callers.emplace_back([&] {
            for (int call = 0; call < 200; ++call) {
                const std::size_t n = 9000 + 37 * call;
                std::vector<int> visits(n, 0);  // each call's own
                parallel_for(n, [&](std::size_t begin, std::size_t end) {
                    for (std::size_t i = begin; i < end; ++i) visits[i] += 1;
                });
                for (const int v : visits) wrong += v != 1;
            }
        });
    for (std::thread& t : callers) t.join();
    CHECK(wrong == 0);
}

TEST_CASE("An exception in any chunk reaches the caller once every chunk has returned", "[parallel]") {
    // The item that throws in the caller's chunk (0) or the last worker's (n - 1);
    // the other chunks take a while, so that a caller that rethrew at once would
    // leave one of them running on the body it had freed.
    const std::size_t n = 4 * kParallelGrain;
    for (const std::size_t thrower : {std::size_t(0), n - 1})
        for (int call = 0; call < 20; ++call) {
            std::atomic<int> started{0}, returned{0};
            const auto body = [&](std::size_t begin, std::size_t end) {
                started.fetch_add(1);
                struct Count {
                    std::atomic<int>& returned;
                    ~Count() { returned.fetch_add(1); }
                } count{returned};
                if (thrower >= begin && thrower < end) throw std::runtime_error("item " + std::to_string(thrower));
                const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2);
                while (std::chrono::steady_clock::now() < until) std::this_thread::yield();
            };
            CHECK_THROWS_WITH(parallel_for(n, body), "item " + std::to_string(thrower));
            CHECK(returned.load() == started.load());
        }
    check_each_once(100000, kParallelGrain);  // and the pool goes on
}

TEST_CASE("parallel_sum gives the same bits on one thread and on all", "[parallel]") {
    const auto term = [](std::size_t i) { return std::sin(double(i)) / (1.0 + double(i % 97)); };
    for (const std::size_t n : {std::size_t(10), std::size_t(50000), std::size_t(1000003)}) {
        set_parallel_thread_limit(1);
        const double one = parallel_sum(n, term);
        set_parallel_thread_limit(0);
        for (int again = 0; again < 20; ++again) CHECK(parallel_sum(n, term) == one);
    }
}

TEST_CASE("parallel_for keeps every index once with a busy thread beside it", "[parallel]") {
    // Threads spinning on every core: the pool's workers run late or not at all,
    // and it may fall back to the calling thread; nothing may be lost or doubled.
    std::atomic<bool> stop{false};
    std::vector<std::thread> busy;
    for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t)
        busy.emplace_back([&] {
            for (volatile unsigned long spin = 0; !stop.load(std::memory_order_relaxed); spin = spin + 1) {
            }
        });
    for (int call = 0; call < 1000; ++call) check_each_once(20000 + call, kParallelGrain);
    stop = true;
    for (std::thread& t : busy) t.join();
}

namespace {

// Drives a KindSchedule for `calls` calls of a kind whose jobs take
// seconds_all on all threads and seconds_alone alone (a fake clock), and
// returns the ways it ran them (true: alone).
std::vector<bool> schedule_ways(KindSchedule& schedule, int calls, double seconds_all, double seconds_alone) {
    std::vector<bool> ways;
    for (int call = 0; call < calls; ++call) {
        bool timed = false;
        const bool alone = schedule.next_alone(timed);
        if (timed) schedule.record(alone, alone ? seconds_alone : seconds_all, 1000.0);
        ways.push_back(alone);
    }
    return ways;
}

// The lengths of the runs of calls made `way` in a row, from call `from` on
// (one the calls end in left out: it may have gone on).
std::vector<int> runs_of(const std::vector<bool>& ways, bool way, std::size_t from = 0) {
    std::vector<int> runs;
    int run = 0;
    for (std::size_t i = from; i < ways.size(); ++i) {
        if (ways[i] == way) {
            ++run;
        } else if (run > 0) {
            runs.push_back(run);
            run = 0;
        }
    }
    return runs;
}

// The runs longer than a probe: the whiles a way was chosen for.
std::vector<int> chosen_runs(const std::vector<bool>& ways, bool way, std::size_t from = 0) {
    std::vector<int> runs;
    for (const int run : runs_of(ways, way, from))
        if (run > 2 * KindSchedule::kProbeCalls + 1) runs.push_back(run);
    return runs;
}

int longest(const std::vector<int>& runs) { return runs.empty() ? 0 : *std::max_element(runs.begin(), runs.end()); }

}  // namespace

TEST_CASE("Each kind of job is timed both ways, then runs its faster way for longer and longer", "[parallel]") {
    const int probe = 2 * KindSchedule::kProbeCalls + 1;
    for (const bool alone_is_faster : {false, true}) {
        INFO("alone faster: " << alone_is_faster);
        KindSchedule schedule;
        const double fast = 1e-4, slow = 2e-4;
        const std::vector<bool> ways =
            schedule_ways(schedule, 20000, alone_is_faster ? slow : fast, alone_is_faster ? fast : slow);
        // The first probe: the first call on all threads (untimed), then the two ways in turn.
        int alone_in_probe = 0;
        for (int i = 0; i < probe; ++i) alone_in_probe += ways[i];
        CHECK_FALSE(ways[0]);
        CHECK(alone_in_probe == KindSchedule::kProbeCalls);
        // Then the faster way, for whiles that double from the first to the longest
        // (a while ends in the next probe, whose calls that way join it).
        const std::vector<int> runs = chosen_runs(ways, alone_is_faster, probe);
        REQUIRE(runs.size() >= 4);
        CHECK(runs[0] >= KindSchedule::kFirstChosenCalls);
        CHECK(runs[0] < 2 * KindSchedule::kFirstChosenCalls);
        for (std::size_t i = 1; i < runs.size(); ++i) CHECK(runs[i] >= runs[i - 1]);
        CHECK(runs.back() >= KindSchedule::kMaxChosenCalls);
        CHECK(runs.back() <= KindSchedule::kMaxChosenCalls + probe);
        // The slower way only in probes: never twice in a row.
        CHECK(longest(runs_of(ways, !alone_is_faster, probe)) == 1);
    }
}

TEST_CASE("A kind whose faster way changes soon takes the new way", "[parallel]") {
    // Settled on all threads for the longest while, then the machine gets busy:
    // alone is faster from then on. Within the longest while and a probe, the
    // kind runs alone, and on all threads only in its probes.
    KindSchedule schedule;
    schedule_ways(schedule, 20000, 1e-4, 2e-4);
    const int probe = 2 * KindSchedule::kProbeCalls + 1;
    const std::vector<bool> busy = schedule_ways(schedule, 4 * KindSchedule::kMaxChosenCalls, 2e-4, 1e-4);
    const std::size_t settled = KindSchedule::kMaxChosenCalls + probe;
    CHECK(longest(runs_of(busy, false, settled)) == 1);
    CHECK(longest(chosen_runs(busy, true, settled)) >= KindSchedule::kMaxChosenCalls);
    // A new choice starts with the first while again.
    CHECK(chosen_runs(busy, true)[0] < 2 * KindSchedule::kFirstChosenCalls);
    // A restarted kind probes afresh, with the first while.
    schedule.restart();
    CHECK(schedule.probing());
    const std::vector<bool> again = schedule_ways(schedule, 1000, 1e-4, 2e-4);
    REQUIRE_FALSE(chosen_runs(again, false).empty());
    CHECK(chosen_runs(again, false)[0] < 2 * KindSchedule::kFirstChosenCalls);
}

TEST_CASE("A kind's choice survives one call in a probe that took several times its share", "[parallel]") {
    // Twice as fast on all threads, but in every probe one call on all threads
    // is held up ten times over (the machine interrupted it): all threads
    // still win. A sum of the four calls would choose the caller alone.
    KindSchedule schedule;
    int all_calls = 0;
    std::vector<bool> ways;
    for (int call = 0; call < 3000; ++call) {
        bool timed = false;
        const bool alone = schedule.next_alone(timed);
        double seconds = alone ? 2e-4 : 1e-4;
        if (!alone && timed && all_calls++ % KindSchedule::kProbeCalls == 0) seconds *= 10.0;
        if (timed) schedule.record(alone, seconds, 1000.0);
        ways.push_back(alone);
    }
    const int probe = 2 * KindSchedule::kProbeCalls + 1;
    CHECK(longest(runs_of(ways, true, probe)) == 1);  // alone only within probes
    CHECK(longest(chosen_runs(ways, false, probe)) >= KindSchedule::kFirstChosenCalls);
}
