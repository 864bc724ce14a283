#include "loom/process_start.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace loom {

namespace {

// THP's mode, as /sys/kernel/mm/transparent_hugepage/enabled marks it:
// "always [madvise] never".
bool huge_pages_on_request() {
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string text;
  std::getline(mode, text);
  return text.find("[madvise]") != std::string::npos;
}

// A program touches most of what it allocates once: images, matrices and
// solver workspaces are made, filled and freed. With 4-KiB pages every 100 MB
// of it is 25,600 page faults, each a trip through the hypervisor on a
// virtual machine (10-40 µs measured here); with 2-MiB pages, 50. glibc asks
// for huge pages (madvise) for the memory malloc gets from the kernel when
// glibc.malloc.hugetlb=1.
void exec_with_huge_pages(char** argv) {
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos || !huge_pages_on_request()) return;
  const std::string with = tunables.empty() ? "glibc.malloc.hugetlb=1" : tunables + ":glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", with.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  if (set)  // no exec: on as we are, the environment as it was
    ::setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

}  // namespace

void prepare_process(char** argv, bool evaluates_graphs) {
  ::setenv("OPENBLAS_NUM_THREADS", "1", /*overwrite=*/0);
  ::setenv("OMP_THREAD_LIMIT", "1", /*overwrite=*/0);
  if (evaluates_graphs) exec_with_huge_pages(argv);
}

}  // namespace loom
