#include "loom/frame_pattern.hpp"

#include <cstdlib>

namespace loom {
namespace {

// At `pos` (a '{'): the width of a {frame} or {frame:N} token and its length,
// or length 0 when it is not one.
std::size_t token(const std::string& s, std::size_t pos, int* width) {
  static const std::string head = "{frame";
  if (s.compare(pos, head.size(), head) != 0) return 0;
  std::size_t p = pos + head.size();
  *width = 0;
  if (p < s.size() && s[p] == '}') return p + 1 - pos;
  if (p >= s.size() || s[p] != ':') return 0;
  std::size_t digits = ++p;
  while (p < s.size() && s[p] >= '0' && s[p] <= '9') ++p;
  if (p == digits || p - digits > 2 || p >= s.size() || s[p] != '}') return 0;
  *width = std::atoi(s.substr(digits, p - digits).c_str());
  return p + 1 - pos;
}

}  // namespace

std::string expand_frame_pattern(const std::string& path, int frame) {
  std::string out;
  for (std::size_t i = 0; i < path.size();) {
    int width = 0;
    std::size_t n = path[i] == '{' ? token(path, i, &width) : 0;
    if (n == 0) {
      out += path[i++];
      continue;
    }
    std::string number = std::to_string(frame < 0 ? -frame : frame);
    if (static_cast<int>(number.size()) < width) number.insert(0, static_cast<std::size_t>(width) - number.size(), '0');
    out += (frame < 0 ? "-" : "") + number;
    i += n;
  }
  return out;
}

bool has_frame_pattern(const std::string& path) { return expand_frame_pattern(path, 0) != expand_frame_pattern(path, 1); }

}  // namespace loom
