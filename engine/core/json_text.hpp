// Internal: reading JSON text that a user wrote (graph files, --set values)
// without ever letting the JSON library's exceptions or a deep nesting escape.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "loom/node.hpp"

namespace loom::detail {

// Parses `text` into `out`. Any failure (syntax, a number beyond double,
// invalid UTF-8, nesting beyond kMaxJsonDepth) is returned as a message.
std::optional<std::string> parse_json_text(std::string_view text, json& out);

bool valid_utf8(std::string_view s);

// JSON pointer pieces: a token with '~' and '/' escaped, a node's pointer and
// one of its inputs'.
std::string pointer_escape(const std::string& token);
std::string node_pointer(const std::string& id);
std::string input_pointer(const std::string& id, const std::string& input);

// `s` cut to `n` bytes, with "..." when it was longer.
std::string cut(const std::string& s, std::size_t n);

}  // namespace loom::detail
