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
