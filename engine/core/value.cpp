#include "loom/value.hpp"

#include "loom/input_declaration.hpp"  // type_names

#include <deque>
#include <map>
#include <mutex>

namespace loom {
namespace {

struct TypeTable {
  std::mutex mutex;
  std::deque<TypeInfo> storage;  // stable addresses
  std::map<std::string, const TypeInfo*, std::less<>> by_name;
};

TypeTable& table() {
  static TypeTable t;
  return t;
}

}  // namespace

const TypeInfo& register_type(TypeInfo info) {
  auto& t = table();
  std::lock_guard lock(t.mutex);
  if (auto it = t.by_name.find(info.name); it != t.by_name.end()) return *it->second;
  const TypeInfo& stored = t.storage.emplace_back(std::move(info));
  t.by_name.emplace(stored.name, &stored);
  return stored;
}

const TypeInfo& register_alias(std::string name, std::string description,
                               const TypeInfo& storage) {
  TypeInfo info = storage;
  info.name = std::move(name);
  info.description = std::move(description);
  return register_type(std::move(info));
}

const TypeInfo* find_type(std::string_view name) {
  auto& t = table();
  std::lock_guard lock(t.mutex);
  auto it = t.by_name.find(name);
  return it == t.by_name.end() ? nullptr : it->second;
}

std::vector<std::string> type_names() {
  auto& t = table();
  std::lock_guard lock(t.mutex);
  std::vector<std::string> names;
  for (const auto& [name, type] : t.by_name) names.push_back(name);
  return names;
}

}  // namespace loom
