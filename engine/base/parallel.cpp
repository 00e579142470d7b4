#include "base/parallel.h"

#include <algorithm>
#include <atomic>
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

// Workers wait for a generation number to change, run their chunk of the
// current job, and count down; the caller waits for the count to reach zero.
class Pool {
public:
    explicit Pool(unsigned workers) {
        for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this, i] { work(i + 1); });
    }
    ~Pool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
            ++generation_;
        }
        wake_.notify_all();
        for (std::thread& t : threads_) t.join();
    }
    unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1; }

    void run(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        std::lock_guard<std::mutex> one_caller(call_mutex_);  // callers take turns
        {
            std::lock_guard<std::mutex> lock(mutex_);
            body_ = &body;
            n_ = n;
            pending_ = threads_.size();
            ++generation_;
        }
        wake_.notify_all();
        run_chunk(0, n, body);
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [this] { return pending_ == 0; });
    }

private:
    void run_chunk(unsigned index, std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) const {
        const std::size_t begin = n * index / size(), end = n * (index + 1) / size();
        if (begin < end) body(begin, end);
    }

    void work(unsigned index) {
        unsigned long seen = 0;
        for (;;) {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return generation_ != seen; });
            seen = generation_;
            if (stop_) return;
            const auto* body = body_;
            const std::size_t n = n_;
            lock.unlock();
            run_chunk(index, n, *body);
            lock.lock();
            if (--pending_ == 0) done_.notify_one();
        }
    }

    std::vector<std::thread> threads_;
    std::mutex mutex_, call_mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, std::size_t)>* body_ = nullptr;
    std::size_t n_ = 0, pending_ = 0;
    unsigned long generation_ = 0;
    bool stop_ = false;
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

void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    if (n < kParallelGrain || parallel_thread_count() == 1) {
        if (n > 0) body(0, n);
        return;
    }
    pool().run(n, body);
}

}  // namespace vfsd
