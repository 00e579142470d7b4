#pragma once
// parallel_for: splits [0, n) into one contiguous chunk per hardware thread and
// runs them on a persistent pool (the calling thread takes the first chunk).
// Small ranges, and builds without threads (WebAssembly), run serially. The
// passes of deform/passes.h use it; each call is a barrier. Calls from several
// threads take turns; `body` must not call parallel_for itself.

#include <cstddef>
#include <functional>

namespace vfsd {

// Below this many items a call runs on the calling thread alone.
constexpr std::size_t kParallelGrain = 8192;

// Calls body(begin, end) on disjoint chunks covering [0, n).
void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body);

// Number of threads parallel_for uses (1 where threads are unavailable).
unsigned parallel_thread_count();
// 1 makes parallel_for run serially from now on, 0 gives it all threads again
// (for benchmarks that compare one thread with all).
void set_parallel_thread_limit(unsigned threads);

}  // namespace vfsd
