#include "base/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <typeinfo>
#include <utility>
#include <vector>

#if defined(VFSD_TBB)
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#endif

namespace vfsd {
namespace {

#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
constexpr bool kThreads = false;
#else
constexpr bool kThreads = true;
#endif

#if !defined(VFSD_TBB)
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
        std::this_thread::yield();  // a thread the system wants to run on this core goes first
    }
}

constexpr std::chrono::microseconds kSpin{200};

// On a busy machine the threads together can run far slower than the caller
// alone: a worker the system does not run holds up every job until it does;
// and a light job on few items gains less from a second thread than handing it
// over costs. So the pool times each kind of job (each call site's body) both
// ways and runs it the faster way (KindSchedule, parallel.h). Each kind is
// compared with itself: a step's passes differ per item by tens of times (a
// smoothing sweep against the field's RK4), and timing one window of jobs on
// all threads and the next alone compared different mixes of passes (on an idle
// 2-core machine it often chose the caller alone for all; docs/benchmarks.md).
//
// A worker that shares its core with another process runs in the system's
// time slices (milliseconds): a job it began just before its slice ended
// waits for the next. Few jobs do, but each waits tens of times its length,
// and a probe of a few jobs per kind rarely sees one. So when kLateWorkers of
// kLateWindow jobs on all threads left the caller waiting for a worker longer
// than its own share took plus kLateWait, every kind runs alone for a spell of
// kBusyCalls jobs, and then each is timed again. One late worker within
// kBusyCalls jobs of a spell's end starts the next, twice as long, up to
// kMaxBusyCalls: each late job costs a time slice, so a load that stays then
// costs a probe and one late job a long while, not four every few edits.
// Idle, a late worker is rare (a page touched for the first time, the system's
// own interruptions), and the probes give the kinds their second thread back.
// A worker waking from its sleep takes up to a tenth of a millisecond on a
// virtual machine (70–100 µs measured on the 2-core one, where a wait longer
// than 50 µs sent an idle bench alone for most of its run); a time slice is
// longer than kLateWait.
constexpr std::chrono::microseconds kLateWait{500};
constexpr int kLateWorkers = 4;
constexpr int kLateWindow = 256;
constexpr int kBusyCalls = 2048;
constexpr int kMaxBusyCalls = 32 * kBusyCalls;

// Workers wait for a generation number to change, claim their chunk of the
// current job, run it and count down; the caller runs its own chunk, claims and
// runs those no worker has claimed yet, and waits for the count to reach zero.
// Both wait by spinning first (spin_until), then on a condition variable.
class Pool {
public:
    explicit Pool(unsigned workers) : claimed_(workers + 1) {
        for (auto& c : claimed_) c.store(0, std::memory_order_relaxed);
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
        ++calls_;
        if (busy_left_ > 0) {  // a busy spell: every kind alone
            if (--busy_left_ == 0) {
                spell_end_ = calls_;
                for (Kind& k : kinds_) k.schedule.restart();
            }
            body(0, n);
            return;
        }
        KindSchedule& kind = kind_of(body.target_type());
        bool timed = false;
        const bool alone = kind.next_alone(timed);
        const auto start = std::chrono::steady_clock::now();
        if (alone)
            body(0, n);
        else
            count_late(!run_on_all(n, body));
        if (timed)
            kind.record(alone, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                        double(n));
    }

private:
    // Chunk 0 on the caller, chunk i on worker i, unless the caller, done with
    // its own, claims it first: a worker the system is not running (another
    // process on its core) or that is still waking up then holds up nothing,
    // and the caller waits only for chunks a worker has begun.
    // False if the caller then waited for a worker longer than its own share took.
    bool run_on_all(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        const auto start = std::chrono::steady_clock::now();
        unsigned long generation = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            body_ = &body;
            n_ = n;
            pending_.store(threads_.size(), std::memory_order_relaxed);
            generation = generation_.fetch_add(1, std::memory_order_release) + 1;
        }
        wake_.notify_all();
        run_chunk(0, n, body);
        for (unsigned index = 1; index < size(); ++index)
            if (claim(index, generation)) {
                run_chunk(index, n, body);
                pending_.fetch_sub(1, std::memory_order_acq_rel);
            }
        const auto done = [this] { return pending_.load(std::memory_order_acquire) == 0; };
        bool on_time = true;
        if (!done()) {
            const auto waiting = std::chrono::steady_clock::now();
            if (!spin_until(done, kSpin)) {
                std::unique_lock<std::mutex> lock(mutex_);
                done_.wait(lock, done);
            }
            on_time = std::chrono::steady_clock::now() - waiting <= waiting - start + kLateWait;
        }
        // Every chunk has returned: a chunk's exception now reaches the caller.
        std::exception_ptr failure;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            failure = std::exchange(failure_, nullptr);
        }
        if (failure) std::rethrow_exception(failure);
        return on_time;
    }

    // Starts a busy spell at kLateWorkers late jobs in kLateWindow, or at one
    // within kBusyCalls jobs of the last spell's end (the load stayed).
    void count_late(bool late) {
        late_workers_ += late ? 1 : 0;
        const bool again = spell_end_ > 0 && calls_ - spell_end_ < kBusyCalls;
        if (late_workers_ == (again ? 1 : kLateWorkers)) {
            busy_spell_ = again ? std::min(2 * busy_spell_, kMaxBusyCalls) : kBusyCalls;
            busy_left_ = busy_spell_;
            late_workers_ = window_calls_ = 0;
        } else if (++window_calls_ == kLateWindow) {
            late_workers_ = window_calls_ = 0;
        }
    }

    // True for the first to claim chunk `index` of job `generation`.
    bool claim(unsigned index, unsigned long generation) {
        unsigned long last = claimed_[index].load(std::memory_order_relaxed);
        while (last < generation)
            if (claimed_[index].compare_exchange_weak(last, generation, std::memory_order_acq_rel)) return true;
        return false;
    }

    // Runs chunk `index`; an exception it throws is kept (the first of a job's)
    // for the caller to rethrow once every chunk has returned.
    void run_chunk(unsigned index, std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        const std::size_t begin = n * index / size(), end = n * (index + 1) / size();
        if (begin >= end) return;
        try {
            body(begin, end);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!failure_) failure_ = std::current_exception();
        }
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
            if (!claim(index, seen)) continue;  // the caller ran it
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
    std::exception_ptr failure_;  // the current job's first exception, under mutex_
    std::atomic<unsigned long> generation_{0};
    std::vector<std::atomic<unsigned long>> claimed_;  // per chunk, the last job that claimed it
    bool stop_ = false;
    // Each kind's schedule. The kind is the body's type_info, told apart by
    // address (a lookup by name would compare mangled names on every call).
    struct Kind {
        const std::type_info* type;
        KindSchedule schedule;
    };
    KindSchedule& kind_of(const std::type_info& type) {
        for (Kind& k : kinds_)
            if (k.type == &type) return k.schedule;
        return kinds_.emplace_back(Kind{&type, KindSchedule{}}).schedule;
    }
    std::vector<Kind> kinds_;
    long calls_ = 0, spell_end_ = 0;  // calls so far; the call that ended the last busy spell
    int busy_left_ = 0, busy_spell_ = kBusyCalls;
    int late_workers_ = 0, window_calls_ = 0;
};

Pool& pool() {
    static Pool instance(kThreads ? std::max(1u, std::thread::hardware_concurrency()) - 1 : 0);
    return instance;
}

#endif  // !VFSD_TBB

std::atomic<unsigned> thread_limit{0};

}  // namespace

bool KindSchedule::next_alone(bool& timed) {
    if (left_ > 0) {
        --left_;
        timed = false;
        return alone_;
    }
    const int call = calls_++;
    timed = call > 0;
    return call % 2 == 1;  // all threads first (untimed), then alone and all in turn
}

void KindSchedule::record(bool was_alone, double seconds, double items) {
    const int way = was_alone ? 1 : 0;
    if (timed_[way] < kProbeCalls) per_item_[way][timed_[way]++] = seconds / std::max(1.0, items);
    if (calls_ <= 2 * kProbeCalls) return;
    // Each way by the median of its times per item: on a noisy machine one
    // call in a few takes several times its share, and a sum of four chose the
    // caller alone for passes twice as fast on two threads.
    double median[2];
    for (int w = 0; w < 2; ++w) {
        double* first = per_item_[w];
        std::sort(first, first + kProbeCalls);
        median[w] = 0.5 * (first[(kProbeCalls - 1) / 2] + first[kProbeCalls / 2]);
    }
    const bool alone = median[1] < median[0];
    chosen_calls_ =
        chosen_calls_ > 0 && alone == alone_ ? std::min(2 * chosen_calls_, kMaxChosenCalls) : kFirstChosenCalls;
    alone_ = alone;
    left_ = chosen_calls_;
    calls_ = timed_[0] = timed_[1] = 0;
}

unsigned parallel_thread_count() {
    const unsigned limit = thread_limit.load();
#if defined(VFSD_TBB)
    const unsigned all = static_cast<unsigned>(std::max(1, tbb::info::default_concurrency()));
#else
    const unsigned all = pool().size();
#endif
    return limit == 0 ? all : std::min(limit, all);
}

void set_parallel_thread_limit(unsigned threads) { thread_limit = threads; }

void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body, std::size_t grain) {
    if (n < grain || parallel_thread_count() == 1) {
        if (n > 0) body(0, n);
        return;
    }
#if defined(VFSD_TBB)
    // oneTBB's work stealing instead of the pool (VFSD_TBB, for comparison:
    // docs/benchmarks.md, "The pool against oneTBB"): chunks of at least a
    // quarter of the grain, split further as its partitioner sees fit.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(1, grain / 4)),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
#else
    pool().run(n, body);
#endif
}

}  // namespace vfsd
