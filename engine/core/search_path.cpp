#include "loom/search_path.hpp"

#include <cstdlib>
#include <iostream>
#include <string>

namespace loom {

std::vector<std::filesystem::path> search_path_from_env(const char* variable) {
  std::vector<std::filesystem::path> path;
  const char* value = std::getenv(variable);
  const std::string s = value ? value : "";
  for (std::size_t start = 0; start < s.size();) {
    const std::size_t end = std::min(s.find(':', start), s.size());
    const std::filesystem::path entry = s.substr(start, end - start);
    if (entry.is_absolute())
      path.push_back(entry.lexically_normal());
    else if (!entry.empty())
      std::cerr << "warning: " << variable << " entry \"" << entry.string()
                << "\" ignored: search path folders must be absolute paths\n";
    start = end + 1;
  }
  return path;
}

}  // namespace loom
