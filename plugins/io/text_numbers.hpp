// Strict number parsing for the text mesh formats: a token is a number or an
// error naming the file and line; no locale, no silent zero.
#pragma once

#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "loom/error.hpp"

namespace loom::io {

struct TextPlace {
  const std::string& file;
  long line = 0;
  std::string where() const { return file + ":" + std::to_string(line); }
};

inline double parse_finite(std::string_view token, const TextPlace& at) {
  double v = 0;
  const char* end = token.data() + token.size();
  auto [p, ec] = std::from_chars(token.data(), end, v);
  if (ec != std::errc() || p != end)
    throw Error(at.where() + ": expected a number, got \"" + std::string(token.substr(0, 40)) + "\"");
  if (!std::isfinite(v)) throw Error(at.where() + ": the number " + std::string(token.substr(0, 40)) + " is not finite");
  return v;
}

inline long long parse_integer(std::string_view token, const TextPlace& at) {
  long long v = 0;
  const char* end = token.data() + token.size();
  auto [p, ec] = std::from_chars(token.data(), end, v);
  if (ec != std::errc() || p != end)
    throw Error(at.where() + ": expected an integer, got \"" + std::string(token.substr(0, 40)) + "\"");
  return v;
}

// Splits off the next whitespace-separated token of `rest`.
inline std::string_view next_token(std::string_view& rest) {
  std::size_t b = rest.find_first_not_of(" \t\r\f\v");
  if (b == std::string_view::npos) {
    rest = {};
    return {};
  }
  std::size_t e = rest.find_first_of(" \t\r\f\v", b);
  std::string_view t = rest.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b);
  rest = e == std::string_view::npos ? std::string_view{} : rest.substr(e);
  return t;
}

// Line by line over a buffer; returns false at the end.
inline bool next_line(std::string_view& text, std::string_view& line) {
  if (text.empty()) return false;
  std::size_t e = text.find('\n');
  line = text.substr(0, e);
  text = e == std::string_view::npos ? std::string_view{} : text.substr(e + 1);
  return true;
}

}  // namespace loom::io
