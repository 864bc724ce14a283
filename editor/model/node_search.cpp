#include "node_search.hpp"

#include <algorithm>
#include <cctype>

namespace loom::editor {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// Where the words of a CamelCase or snake_case name start: "MPMEmitBox" -> 0, 3, 7.
std::vector<std::size_t> word_starts(const std::string& name) {
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    const auto before = i > 0 ? static_cast<unsigned char>(name[i - 1]) : '_';
    const auto after = i + 1 < name.size() ? static_cast<unsigned char>(name[i + 1]) : 'A';
    const bool boundary = !std::isalnum(before) || (std::isupper(c) && std::islower(before)) ||
                          (std::isupper(c) && std::isupper(before) && std::islower(after)) ||
                          (std::isdigit(c) && !std::isdigit(before));
    if (std::isalnum(c) && boundary) starts.push_back(i);
  }
  return starts;
}

}  // namespace

SearchMatch match_node_type(const NodeSpec& spec, const std::string& query) {
  std::string compact;
  for (char c : lower(query))
    if (!std::isspace(static_cast<unsigned char>(c))) compact += c;
  if (compact.empty()) return SearchMatch::exact;
  const std::string name = lower(spec.name);
  if (name == compact) return SearchMatch::exact;
  if (starts_with(name, compact)) return SearchMatch::prefix;
  for (std::size_t start : word_starts(spec.name))
    if (starts_with(name.substr(start), compact)) return SearchMatch::word;
  if (name.find(compact) != std::string::npos) return SearchMatch::inside;
  if (lower(spec.plugin).find(compact) != std::string::npos) return SearchMatch::plugin;
  if (lower(spec.description).find(lower(query)) != std::string::npos) return SearchMatch::description;
  return SearchMatch::none;
}

std::vector<const NodeType*> search_node_types(const Registry& registry, const std::string& query) {
  return search_node_types(registry.all(), query);
}

std::vector<const NodeType*> search_node_types(std::vector<const NodeType*> candidates, const std::string& query) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const NodeType* a, const NodeType* b) { return a->spec.name < b->spec.name; });
  std::vector<std::pair<SearchMatch, const NodeType*>> found;
  for (const NodeType* t : candidates) {
    const SearchMatch m = match_node_type(t->spec, query);
    if (m != SearchMatch::none) found.emplace_back(m, t);
  }
  // Sorted by name above, and this sort is stable: by name within a rank.
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<const NodeType*> types;
  for (const auto& [match, t] : found) types.push_back(t);
  return types;
}

}  // namespace loom::editor
