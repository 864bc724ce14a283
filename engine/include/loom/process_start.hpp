// Host API. What a Loom program sets about its own process first, before it
// loads any plugin (docs/architecture.md, decisions 16 and 29). For `loom`
// and `loom-editor`; a host that is not a Loom program (Python) cannot.
#pragma once

#include "loom/export.hpp"

namespace loom {

// Call first in main, while the program has one thread.
// - OpenBLAS, which plugins' libraries bring in (OpenCV, SuiteSparse), starts
//   with one thread (decision 16), unless the user set OPENBLAS_NUM_THREADS:
//   it reads it once, as it is loaded; told later, its pool has already
//   started, and its thread spins through its timeout while the other
//   libraries load (a third of the CPU of `loom validate` of an image graph).
// - OpenMP, which CHOLMOD uses for small loops inside its factorization with
//   a team size fixed when it was compiled (CHOLMOD_OMP_NUM_THREADS: Debian's
//   starts 3 threads beside the caller even with OMP_NUM_THREADS=1), is
//   limited to one thread by OMP_THREAD_LIMIT=1, which bounds every team
//   and which libgomp reads as it is loaded, unless the user set it:
//   a team's wake-ups and barriers cost a 67,500-unknown Newton cloth a
//   quarter of its CPU on 2 cores, for loops that gain nothing from it.
// - When `evaluates_graphs` and the kernel gives huge pages to memory that
//   asks (THP "madvise", Debian's default), and GLIBC_TUNABLES does not
//   already say: sets glibc.malloc.hugetlb=1 and executes the program again
//   with the same arguments (glibc reads its tunables only at start), so that
//   malloc's memory comes in 2-MiB pages (decision 29). Returns, doing
//   nothing more, otherwise or if the exec fails.
LOOM_API void prepare_process(char** argv, bool evaluates_graphs);

}  // namespace loom
