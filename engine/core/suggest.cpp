#include "loom/suggest.hpp"

#include <algorithm>
#include <cctype>
#include <tuple>

namespace loom {

namespace {

std::string folded(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::size_t edit_distance(std::string_view a_in, std::string_view b_in) {
  const std::string a = folded(a_in), b = folded(b_in);
  // Three rows of the dynamic-programming table (Wagner-Fischer), the oldest
  // for a swap of two neighbours (the optimal string alignment distance).
  std::vector<std::size_t> before(b.size() + 1), above(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) above[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      row[j] = std::min({above[j] + 1, row[j - 1] + 1, above[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, above);
    std::swap(above, row);
  }
  return above[b.size()];
}

std::vector<std::string> near_names(std::string_view name, const std::vector<std::string>& candidates,
                                    std::size_t limit) {
  const std::string key = folded(name);
  const std::size_t allowed = std::clamp<std::size_t>(key.size() / 3, 1, 3);
  // (rank, distance, candidate): rank 0 same letters, 1 near, 2 substring.
  std::vector<std::tuple<int, std::size_t, std::string>> found;
  for (const std::string& c : candidates) {
    if (c == name) continue;
    const std::string other = folded(c);
    const std::size_t d = edit_distance(key, other);
    if (d == 0) found.emplace_back(0, 0, c);
    else if (d <= allowed) found.emplace_back(1, d, c);
    else if (std::min(key.size(), other.size()) >= 4 &&
             (other.find(key) != std::string::npos || key.find(other) != std::string::npos))
      found.emplace_back(2, d, c);
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> names;
  for (const auto& f : found) {
    const std::string& c = std::get<2>(f);
    if (std::find(names.begin(), names.end(), c) == names.end() && names.size() < limit) names.push_back(c);
  }
  return names;
}

std::string unknown_node_type_message(const std::string& type, const std::vector<std::string>& known_types,
                                      const std::string& searched) {
  std::string text = "unknown node type \"" + type + "\"";
  const std::vector<std::string> near = near_names(type, known_types);
  for (std::size_t i = 0; i < near.size(); ++i)
    text += (i == 0 ? ": did you mean \"" : i + 1 == near.size() ? " or \"" : ", \"") + near[i] + "\"";
  if (!near.empty()) text += "?";
  if (!searched.empty()) text += " (" + searched + ")";
  text += "; a type from a plugin of your own: add the folder holding its libloom_NAME.so to "
          "LOOM_PLUGIN_PATH, or install the plugin into Loom's lib/loom/plugins";
  return text;
}

}  // namespace loom
