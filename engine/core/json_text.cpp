#include "json_text.hpp"

#include <algorithm>

#include "loom/graph.hpp"

namespace loom::detail {

namespace {

// A JSON text's deepest nesting of arrays and objects, scanning past strings;
// stops counting once past `limit`.
std::size_t nesting_depth(std::string_view text, std::size_t limit) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) return deepest;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

}  // namespace

bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : 9;
    if (n == 9 || (n > 0 && i + n >= s.size())) return false;
    for (std::size_t k = 1; k <= n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return false;
    // Overlong forms and surrogates.
    if (n == 1 && c < 0xC2) return false;
    if (n == 2) {
      const auto d = static_cast<unsigned char>(s[i + 1]);
      if ((c == 0xE0 && d < 0xA0) || (c == 0xED && d >= 0xA0)) return false;
    }
    if (n == 3) {
      const auto d = static_cast<unsigned char>(s[i + 1]);
      if ((c == 0xF0 && d < 0x90) || c > 0xF4 || (c == 0xF4 && d >= 0x90)) return false;
    }
    i += n + 1;
  }
  return true;
}

std::optional<std::string> parse_json_text(std::string_view text, json& out) {
  if (nesting_depth(text, kMaxJsonDepth) > kMaxJsonDepth)
    return "nested deeper than " + std::to_string(kMaxJsonDepth) + " arrays/objects";
  try {
    out = json::parse(text);
    return std::nullopt;
  } catch (const json::exception& e) {
    std::string what = e.what();
    auto p = what.find("] ");
    std::string message = p == std::string::npos ? what : what.substr(p + 2);
    if (message.size() > 300) message = message.substr(0, 300) + "...";
    return "not valid JSON: " + message;
  } catch (const std::exception& e) {
    return std::string("not valid JSON: ") + e.what();
  }
}

std::string pointer_escape(const std::string& token) {
  std::string out;
  for (char c : token) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string node_pointer(const std::string& id) { return "/nodes/" + pointer_escape(id); }

std::string input_pointer(const std::string& id, const std::string& input) {
  return node_pointer(id) + "/inputs/" + pointer_escape(input);
}

std::string cut(const std::string& s, std::size_t n) { return s.size() > n ? s.substr(0, n) + "..." : s; }

}  // namespace loom::detail
