// Transparent huge pages for the memory `loom` allocates (docs/architecture.md,
// decision 29).
#pragma once

namespace loom::runner {

// For the commands that evaluate graphs (run, submit, jobs), when the kernel
// gives huge pages only to memory that asks for them (THP "madvise",
// Debian's default) and GLIBC_TUNABLES does not already say,
// sets glibc.malloc.hugetlb=1 and executes `loom` again with the same
// arguments: glibc reads its tunables only when a process starts. Returns
// (doing nothing) otherwise, or if the exec fails.
void exec_with_huge_pages(char** argv);

}  // namespace loom::runner
