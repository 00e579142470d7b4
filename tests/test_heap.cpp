// base/heap.h: a freed block the size of a large mesh's positions stays in the
// heap for the next run, and goes back to the system when a document closes.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

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

#if defined(VFSD_HEAP_HUGE_PAGES)
#include <sys/stat.h>

#include <cstdint>
#include <sstream>
#include <string>

namespace {

// The flags /proc/self/smaps gives the mapping that holds `address` ("" if none does).
std::string mapping_flags(std::uintptr_t address) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream range(line);
        if (range >> std::hex >> begin >> dash >> end && dash == '-' && line.find(':') > line.find(' ')) {
            inside = begin <= address && address < end;
        } else if (inside && line.rfind("VmFlags:", 0) == 0) {
            return line.substr(8) + " ";
        }
    }
    return "";
}

}  // namespace

TEST_CASE("keep_freed_memory: the heap a large block grows is marked for transparent huge pages", "[heap]") {
    struct stat info;
    if (stat("/sys/kernel/mm/transparent_hugepage", &info) != 0) {
        WARN("this kernel has no transparent huge pages: nothing to mark");
        return;
    }
    vfsd::keep_freed_memory();
    constexpr std::size_t kBytes = std::size_t(160) << 20;  // larger than any block freed before: the heap grows
    constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
    // Twice: the second time after the heap's freed memory went back to the
    // system, so that the heap grows again where it had been marked before.
    for (const bool returned : {false, true}) {
        char* block = new char[kBytes];
        const std::uintptr_t middle = (reinterpret_cast<std::uintptr_t>(block) + kBytes / 2) & ~(kHugePage - 1);
        const std::string flags = mapping_flags(middle);
        INFO("memory returned before: " << returned << "; VmFlags:" << flags);
        CHECK(flags.find(" hg ") != std::string::npos);  // MADV_HUGEPAGE
        delete[] block;
        vfsd::return_freed_memory();
    }
}

#endif

#if defined(VFSD_HEAP_HUGE_PAGES)
#include <vector>

TEST_CASE("keep_freed_memory: a block that grows the heap leaves marked, untouched room after it for the next ones",
          "[heap]") {
    struct stat info;
    if (stat("/sys/kernel/mm/transparent_hugepage", &info) != 0) {
        WARN("this kernel has no transparent huge pages: nothing to mark");
        return;
    }
    vfsd::keep_freed_memory();
    vfsd::return_freed_memory();
    // A 53k mesh's array each (1.3 MB), until one grows the heap (the first
    // may come from memory freed before).
    constexpr std::size_t kBytes = std::size_t(1300) << 10;
    std::vector<std::unique_ptr<char[]>> blocks;
    std::uintptr_t grown_for = 0;
    for (int i = 0; i < 1000 && grown_for == 0; ++i) {
        const auto before = reinterpret_cast<std::uintptr_t>(sbrk(0));
        blocks.emplace_back(new char[kBytes]);
        if (reinterpret_cast<std::uintptr_t>(sbrk(0)) != before) {
            grown_for = reinterpret_cast<std::uintptr_t>(blocks.back().get()) + kBytes;
        }
    }
    REQUIRE(grown_for != 0);
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
    INFO("the heap ends " << (end - grown_for) << " bytes after the block that grew it");
    CHECK(end - grown_for >= (std::uintptr_t(15) << 20));  // the top pad: more than ten such arrays
    const std::string flags = mapping_flags(grown_for + (std::uintptr_t(12) << 20));
    INFO("VmFlags 12 MB after it:" << flags);
    CHECK(flags.find(" hg ") != std::string::npos);  // marked before anything touched it
}

#endif
