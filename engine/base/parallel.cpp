#include "base/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace vfsd {
namespace {

#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
constexpr bool kThreads = false;
#else
constexpr bool kThreads = true;
#endif

// Spins for up to `budget` on `ready` before giving up. A deformation step is
// a dozen parallel_for calls microseconds apart (one per pass and smoothing
// step): waking a sleeping thread through the kernel takes about as long as a
// small pass, so both sides spin briefly first and sleep only when idle.
template <class Ready>
bool spin_until(const Ready& ready, std::chrono::microseconds budget) {
    const auto deadline = std::chrono::steady_clock::now() + budget;
    for (;;) {
        for (int i = 0; i < 64; ++i) {
            if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        }
        if (std::chrono::steady_clock::now() > deadline) return ready();
    }
}

constexpr std::chrono::microseconds kSpin{200};

// On a busy machine the threads together can run far slower than the caller
// alone: a worker the system does not run holds up every job until it does.
// So the pool measures: every kProbeCalls + kProbeCalls + kChosenCalls jobs it
// runs kProbeCalls on all threads and kProbeCalls on the caller alone, timing
// each, and the next kChosenCalls the faster way (per item, over a few steps'
// worth of passes each). Idle, the probe on the caller alone costs about half a
// percent; busy, the probe on all threads about as much.
constexpr int kProbeCalls = 64;
constexpr int kChosenCalls = 16384;

// Workers wait for a generation number to change, run their chunk of the
// current job, and count down; the caller waits for the count to reach zero.
// Both wait by spinning first (spin_until), then on a condition variable.
class Pool {
public:
    explicit Pool(unsigned workers) {
        for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this, i] { work(i + 1); });
    }
    ~Pool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        for (std::thread& t : threads_) t.join();
    }
    unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1; }

    void run(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        std::lock_guard<std::mutex> one_caller(call_mutex_);  // callers take turns
        if (phase_ == Phase::chosen) {
            if (alone_chosen_)
                body(0, n);
            else
                run_on_all(n, body);
        } else {
            const bool alone = phase_ == Phase::probe_alone;
            const auto start = std::chrono::steady_clock::now();
            if (alone)
                body(0, n);
            else
                run_on_all(n, body);
            probe_[alone].add(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), n);
        }
        if (--calls_left_ > 0) return;
        switch (phase_) {
            case Phase::chosen: phase_ = Phase::probe_all, calls_left_ = kProbeCalls, probe_[0] = probe_[1] = {}; break;
            case Phase::probe_all: phase_ = Phase::probe_alone, calls_left_ = kProbeCalls; break;
            case Phase::probe_alone:
                alone_chosen_ = probe_[1].per_item() < probe_[0].per_item();
                phase_ = Phase::chosen, calls_left_ = kChosenCalls;
                break;
        }
    }

private:
    void run_on_all(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            body_ = &body;
            n_ = n;
            pending_.store(threads_.size(), std::memory_order_relaxed);
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        run_chunk(0, n, body);
        const auto done = [this] { return pending_.load(std::memory_order_acquire) == 0; };
        if (spin_until(done, kSpin)) return;
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, done);
    }

    void run_chunk(unsigned index, std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) const {
        const std::size_t begin = n * index / size(), end = n * (index + 1) / size();
        if (begin < end) body(begin, end);
    }

    void work(unsigned index) {
        unsigned long seen = 0;
        const auto new_job = [&] { return generation_.load(std::memory_order_acquire) != seen; };
        for (;;) {
            if (!spin_until(new_job, kSpin)) {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, new_job);
            }
            const std::function<void(std::size_t, std::size_t)>* body;
            std::size_t n;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                seen = generation_.load(std::memory_order_relaxed);
                if (stop_) return;
                body = body_;
                n = n_;
            }
            run_chunk(index, n, *body);
            if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                std::lock_guard<std::mutex> lock(mutex_);  // the caller may be between its check and its wait
                done_.notify_one();
            }
        }
    }

    std::vector<std::thread> threads_;
    std::mutex mutex_, call_mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, std::size_t)>* body_ = nullptr;
    std::size_t n_ = 0;
    std::atomic<std::size_t> pending_{0};
    std::atomic<unsigned long> generation_{0};
    bool stop_ = false;
    // The measurement above: timed jobs on all threads [0] and on the caller alone [1].
    struct Probe {
        double seconds = 0.0;
        double items = 0.0;
        void add(double s, std::size_t n) { seconds += s, items += double(n); }
        double per_item() const { return items > 0.0 ? seconds / items : 0.0; }
    };
    enum class Phase { chosen, probe_all, probe_alone };
    Phase phase_ = Phase::probe_all;  // measure from the first jobs on
    int calls_left_ = kProbeCalls;
    bool alone_chosen_ = false;
    Probe probe_[2];
};

Pool& pool() {
    static Pool instance(kThreads ? std::max(1u, std::thread::hardware_concurrency()) - 1 : 0);
    return instance;
}

std::atomic<unsigned> thread_limit{0};

}  // namespace

unsigned parallel_thread_count() {
    const unsigned limit = thread_limit.load();
    return limit == 0 ? pool().size() : std::min(limit, pool().size());
}

void set_parallel_thread_limit(unsigned threads) { thread_limit = threads; }

void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body, std::size_t grain) {
    if (n < grain || parallel_thread_count() == 1) {
        if (n > 0) body(0, n);
        return;
    }
    pool().run(n, body);
}

}  // namespace vfsd
