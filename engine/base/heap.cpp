#include "base/heap.h"

#include <climits>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#if defined(VFSD_HEAP_HUGE_PAGES)
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#endif

namespace vfsd {

#if defined(VFSD_HEAP_HUGE_PAGES)
namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;  // x86-64's and arm64's transparent huge page
constexpr std::size_t kLargeBlock = std::size_t(64) << 10;     // smaller ones seldom grow the heap
// What the heap grows by beyond each block that grows it (glibc's M_TOP_PAD,
// 128 KiB by default): eight huge pages, marked with the block, so that the
// next arrays (a 53k mesh's are 1.3 MB each) come from marked, untouched memory
// rather than each growing the heap by less than a huge page.
constexpr int kTopPad = 16 << 20;

// The heap's end up to which it is advised (0: not at all, keep_freed_memory not called).
std::atomic<std::uintptr_t> g_advised_end{0};

// What the heap has grown by since it was last advised, in whole huge pages,
// marked for transparent huge pages (as glibc's glibc.malloc.hugetlb=1 tunable
// marks the heap it grows, which only the environment at start-up can set):
// the pages a run first touches there come 512 to a fault.
void advise_grown_heap() {
    std::uintptr_t from = g_advised_end.load(std::memory_order_relaxed);
    if (from == 0) return;
    const std::uintptr_t to = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHugePage - 1);
    if (to <= from || !g_advised_end.compare_exchange_strong(from, to, std::memory_order_relaxed)) return;
    madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);  // none where the kernel has none: as before
}

}  // namespace
#endif

void keep_freed_memory() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, INT_MAX);
    mallopt(M_TRIM_THRESHOLD, -1);  // never, but for return_freed_memory
#endif
#if defined(VFSD_HEAP_HUGE_PAGES)
    mallopt(M_TOP_PAD, kTopPad);
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
    std::uintptr_t none = 0;
    g_advised_end.compare_exchange_strong(none, (end + kHugePage - 1) & ~(kHugePage - 1));
#endif
}

void return_freed_memory() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
#if defined(VFSD_HEAP_HUGE_PAGES)
    // The trim may have lowered the heap's end: what grows there again is new
    // memory, to be advised again.
    const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHugePage - 1);
    std::uintptr_t advised = g_advised_end.load(std::memory_order_relaxed);
    while (advised > end && !g_advised_end.compare_exchange_weak(advised, end, std::memory_order_relaxed)) {
    }
#endif
}

}  // namespace vfsd

#if defined(VFSD_HEAP_HUGE_PAGES)
// The C++ allocation every std::vector goes through: malloc, as the standard
// library's own, with the heap grown for a large block advised (above). The
// standard library's delete frees with free(), and its other forms of new call
// this one.
void* operator new(std::size_t size) {
    if (size == 0) size = 1;
    void* block = nullptr;
    while (!(block = std::malloc(size))) {
        const std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
    if (size >= vfsd::kLargeBlock) vfsd::advise_grown_heap();
    return block;
}
#endif
