#pragma once
// Large blocks freed for the next run to take again. Each run allocates work
// arrays the size of the mesh (a 2M-vertex mesh's positions: 48 MB) and frees
// them at its end; glibc serves blocks over its mmap threshold (at most 32 MB by
// default) with fresh mappings, whose every page the kernel clears on first
// touch, and gives them back on free. Kept in the heap instead, the next run's
// arrays take the freed blocks as they are (docs/benchmarks.md, "Freed blocks
// kept for the next run": the 2M cylinder's curve edit 9–14 % faster).

#include <climits>  // the C library's own headers first: __GLIBC__

// Where keep_freed_memory marks the heap for huge pages: glibc on Linux, but
// not under a sanitizer, whose runtime brings its own operator new (GCC says
// so with __SANITIZE_ADDRESS__, clang with __has_feature).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VFSD_HEAP_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define VFSD_HEAP_SANITIZED 1
#endif
#endif
#if defined(__GLIBC__) && defined(__linux__) && !defined(VFSD_HEAP_SANITIZED)
#define VFSD_HEAP_HUGE_PAGES 1
#endif

namespace vfsd {

// From now on, freed memory stays in the process's heap for later allocations
// (glibc: no mmap threshold below 2 GiB, no trimming), and on Linux what the
// heap grows by for a large block (C++'s new of 64 KiB or more) is marked for
// transparent huge pages: a run's first touch of a fresh array then faults 2
// MiB at a time, not 4 KiB (docs/benchmarks.md, "The heap in huge pages": the
// 2M cylinder's first curve edit 15-40 % faster). The heap grows 16 MB beyond
// such a block, so that the smaller arrays after it (a 53k mesh's) come from
// marked memory too. Elsewhere does nothing.
// Programs call it first thing (cli/main.cpp, desktop/main.cpp).
void keep_freed_memory();

// Gives what the heap holds freed back to the system (a document closed: the
// next may be far smaller); what the heap grows by again is marked again. Does
// nothing where keep_freed_memory does nothing.
void return_freed_memory();

}  // namespace vfsd
