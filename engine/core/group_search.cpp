// Where group files named by a node's type are found: beside the graph
// (a ".json" path), on LOOM_GRAPH_PATH, then in Loom's shipped graphs/lib.
#include <dlfcn.h>

#include <cstdlib>

#include "loom/graph.hpp"
#include "loom/search_path.hpp"

namespace loom {

namespace fs = std::filesystem;

namespace {

// <libdir>/../share/loom/graphs/lib: the build copies graphs/lib there and the
// install puts it there, beside libloom itself (the runner, the editor and
// Python all load the same libloom).
fs::path shipped_library() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&shipped_library), &info) == 0 || !info.dli_fname) return {};
  return (fs::absolute(info.dli_fname).parent_path() / ".." / "share" / "loom" / "graphs" / "lib")
      .lexically_normal();
}

}  // namespace

std::vector<fs::path> graph_search_path() {
  std::vector<fs::path> path = search_path_from_env("LOOM_GRAPH_PATH");
  if (fs::path lib = shipped_library(); !lib.empty()) path.push_back(lib);
  return path;
}

fs::path find_group_file(const std::string& type, const fs::path& file) {
  std::error_code ec;
  const bool is_path = type.size() > 5 && type.compare(type.size() - 5, 5, ".json") == 0;
  if (is_path) {
    const fs::path p = file.empty() ? fs::path(type) : file.parent_path() / type;
    return fs::is_regular_file(p, ec) ? fs::absolute(p).lexically_normal() : fs::path();
  }
  if (type.empty() || type.find('/') != std::string::npos || type.front() == '.') return {};
  for (const fs::path& dir : graph_search_path())
    if (fs::is_regular_file(dir / (type + ".json"), ec)) return dir / (type + ".json");
  return {};
}

}  // namespace loom
