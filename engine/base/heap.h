#pragma once
// Large blocks freed for the next run to take again. Each run allocates work
// arrays the size of the mesh (a 2M-vertex mesh's positions: 48 MB) and frees
// them at its end; glibc serves blocks over its mmap threshold (at most 32 MB by
// default) with fresh mappings, whose every page the kernel clears on first
// touch, and gives them back on free. Kept in the heap instead, the next run's
// arrays take the freed blocks as they are (docs/benchmarks.md, "Freed blocks
// kept for the next run": the 2M cylinder's curve edit 9–14 % faster).

namespace vfsd {

// From now on, freed memory stays in the process's heap for later allocations
// (glibc: no mmap threshold below 2 GiB, no trimming); elsewhere does nothing.
// Programs call it first thing (cli/main.cpp, desktop/main.cpp).
void keep_freed_memory();

// Gives what the heap holds freed back to the system (a document closed: the
// next may be far smaller). Does nothing where keep_freed_memory does nothing.
void return_freed_memory();

}  // namespace vfsd
