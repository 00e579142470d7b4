// base/heap.h: a freed block the size of a large mesh's positions stays in the
// heap for the next run, and goes back to the system when a document closes.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <unistd.h>

#include "base/heap.h"

// glibc's own allocator only: AddressSanitizer replaces it.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>

namespace {

// The process's resident bytes (/proc/self/statm's second field, in pages).
long resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * sysconf(_SC_PAGESIZE);
}

}  // namespace

TEST_CASE("keep_freed_memory: a freed 64 MB block is taken again from the heap, and return_freed_memory gives it back",
          "[heap]") {
    vfsd::keep_freed_memory();
    constexpr std::size_t kBytes = std::size_t(64) << 20;  // over glibc's largest default mmap threshold (32 MB)
    const std::size_t mapped = mallinfo2().hblkhd;
    char* block = static_cast<char*>(std::malloc(kBytes));
    REQUIRE(block != nullptr);
    std::memset(block, 1, kBytes);
    CHECK(mallinfo2().hblkhd == mapped);  // from the heap, not a mapping of its own
    std::free(block);
    CHECK(mallinfo2().fordblks >= kBytes);  // kept free in the heap, its pages with it
    const long kept = resident_bytes();
    char* again = static_cast<char*>(std::malloc(kBytes));
    REQUIRE(again != nullptr);
    CHECK(mallinfo2().fordblks < kBytes);  // the next one took it
    std::memset(again, 2, kBytes);
    CHECK(resident_bytes() - kept < long(kBytes / 4));  // no fresh pages: they were there
    std::free(again);
    vfsd::return_freed_memory();
    CHECK(kept - resident_bytes() >= long(kBytes / 2));  // back to the system
}

#endif
