#pragma once
// parallel_for: splits [0, n) into one contiguous chunk per hardware thread and
// runs them on a persistent pool (the calling thread takes the first chunk).
// Small ranges, and builds without threads (WebAssembly), run serially; so do
// calls while the pool finds the calling thread alone faster (it times each
// call site's jobs both ways now and then: KindSchedule below), and all calls
// while workers keep arriving late (another process on their cores). A worker's
// chunk that it has not begun when the caller is done with its own, the caller
// runs; threads waiting for work or for each other spin, but let another thread
// that wants their core run first.
// The passes of deform/passes.h use it; each call is a barrier. Calls from
// several threads take turns; `body` must not call parallel_for itself. An
// exception `body` throws on any thread reaches the caller once every chunk
// has returned (the first one, if several throw).

#include <cstddef>
#include <functional>
#include <vector>

namespace vfsd {

// Below this many items a call runs on the calling thread alone. Above it, the
// pool's timing decides per kind of job (parallel.cpp): a light pass on a few
// thousand items runs alone, the field's RK4 on a thousand in parallel. (It
// was 8192 before the pool chose per kind, which kept every pass of a blend
// region under 8192 vertices, the raised claw's 7442, on one thread.)
constexpr std::size_t kParallelGrain = 1024;

// Calls body(begin, end) on disjoint chunks covering [0, n); serially below
// `grain` items (a caller whose items are blocks of work passes a smaller one).
void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t grain = kParallelGrain);

// Σ over [0, n) in blocks of kSumBlock items, block_sum(begin, end) giving each
// block's sum, on all threads; then the blocks' sums in order. The order depends
// on n alone, so the same bits on any number of threads.
constexpr std::size_t kSumBlock = 1024;
template <class BlockSum>
double parallel_block_sum(std::size_t n, const BlockSum& block_sum) {
    const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
    std::vector<double> partial(blocks);
    parallel_for(
        blocks,
        [&](std::size_t first, std::size_t last) {
            for (std::size_t block = first; block < last; ++block) {
                const std::size_t begin = block * kSumBlock, end = begin + kSumBlock < n ? begin + kSumBlock : n;
                partial[block] = block_sum(begin, end);
            }
        },
        kParallelGrain / kSumBlock);
    double total = 0.0;
    for (const double p : partial) total += p;
    return total;
}

// Σ term(i) over [0, n) by parallel_block_sum, each block summed into four
// interleaved accumulators (no chain of dependent additions): term i into
// accumulator i mod 4, from the block's start, the terms after the last four
// into the first; then (a0 + a1) + (a2 + a3). A caller that computes four terms
// at a time in SIMD lanes and sums them so has the same bits.
template <class Term>
double parallel_sum(std::size_t n, const Term& term) {
    return parallel_block_sum(n, [&](std::size_t begin, std::size_t end) {
        double sum[4] = {0.0, 0.0, 0.0, 0.0};
        std::size_t i = begin;
        for (; i + 4 <= end; i += 4)
            sum[0] += term(i), sum[1] += term(i + 1), sum[2] += term(i + 2), sum[3] += term(i + 3);
        for (; i < end; ++i) sum[0] += term(i);
        return (sum[0] + sum[1]) + (sum[2] + sum[3]);
    });
}

// How the pool runs one kind of job: it times the kind both ways, alternately,
// until it has kProbeCalls timed calls each way (its first call, which warms
// caches and buffers, untimed), then runs the way with the lower median time
// per item for a while, then times it again. The while starts at kFirstChosenCalls calls and doubles each
// time the probe chooses as before, up to kMaxChosenCalls, so that a kind soon
// settles into its way and a change (a busy machine) is still found. Each kind
// keeps its own count: a kind called once a step is measured as well as the
// smoothing's sweep, called ten times a step (one window of calls over all kinds
// gave the rarer kinds a sample or two, and its choice then held for the whole
// of a bench).
class KindSchedule {
public:
    static constexpr int kProbeCalls = 4;
    static constexpr int kFirstChosenCalls = 256;
    static constexpr int kMaxChosenCalls = 4096;
    // The way of the kind's next call (true: the caller alone), and whether to
    // time it and record() what it took.
    bool next_alone(bool& timed);
    void record(bool alone, double seconds, double items);
    // Times the kind again from its next call, as if new (a busy spell ended).
    void restart() { *this = KindSchedule{}; }
    bool probing() const { return left_ == 0; }

private:
    int calls_ = 0;         // calls into the current probe
    int left_ = 0;          // calls left the way chosen; 0: probing
    int chosen_calls_ = 0;  // the last while (0: none yet)
    bool alone_ = false;
    int timed_[2] = {0, 0};                 // timed calls each way in the current probe
    double per_item_[2][kProbeCalls] = {};  // their seconds per item: [0] all threads, [1] alone
};

// Number of threads parallel_for uses (1 where threads are unavailable).
unsigned parallel_thread_count();
// 1 makes parallel_for run serially from now on, 0 gives it all threads again
// (for benchmarks that compare one thread with all).
void set_parallel_thread_limit(unsigned threads);

}  // namespace vfsd
