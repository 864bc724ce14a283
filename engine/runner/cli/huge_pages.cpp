#include "cli/huge_pages.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace loom::runner {

namespace {

// The commands that evaluate graphs, and so allocate what a graph needs: a
// run, and the local dispatcher of `submit` and `jobs resume`, whose tasks
// are forks of it. The others (--help, nodes, validate, info...) start once.
bool evaluates_graphs(char** argv) {
  const std::string command = argv[0] && argv[1] ? argv[1] : "";
  return command == "run" || command == "submit" || command == "jobs";
}

// THP's mode, as /sys/kernel/mm/transparent_hugepage/enabled marks it:
// "always [madvise] never".
bool huge_pages_on_request() {
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string text;
  std::getline(mode, text);
  return text.find("[madvise]") != std::string::npos;
}

}  // namespace

// A run touches most of its memory once: images, matrices and solver
// workspaces are made, filled and freed. With 4-KiB pages every 100 MB of it
// is 25,600 page faults, each a trip through the hypervisor on a virtual
// machine (10-40 µs measured here); with 2-MiB pages, 50. glibc asks for
// huge pages (madvise) for the memory malloc gets from the kernel when
// glibc.malloc.hugetlb=1.
void exec_with_huge_pages(char** argv) {
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  if (!evaluates_graphs(argv) || tunables.find("glibc.malloc.hugetlb") != std::string::npos || !huge_pages_on_request())
    return;
  const std::string with = tunables.empty() ? "glibc.malloc.hugetlb=1" : tunables + ":glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", with.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  if (set)  // no exec: on as we are, the environment as it was
    ::setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

}  // namespace loom::runner
