// Small reads of the document's JSON shared by GraphDocument's files.
#pragma once

#include "loom/value.hpp"

namespace loom::editor {

inline const json& empty_object() {
  static const json object = json::object();
  return object;
}

// Whether j is an object whose `key` holds an object.
inline bool holds_object(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_object();
}

}  // namespace loom::editor
