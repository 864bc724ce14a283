#include "json_layout.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <optional>

namespace loom::editor {

namespace {

std::string escape_token(const std::string& key) {
  std::string out;
  for (char c : key) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return out;
}

// A recursive-descent walk over JSON text already known to parse.
class Scanner {
 public:
  Scanner(std::string_view text, JsonLayout& layout) : text_(text), layout_(layout) {}
  void value(const std::string& pointer) {
    if (at_ >= text_.size()) return;
    const char c = text_[at_];
    if (c == '{' || c == '[') return container(pointer, c == '{');
    const std::size_t start = at_;
    if (c == '"')
      string_token();
    else
      while (at_ < text_.size() && !std::strchr(",}] \t\r\n", text_[at_])) ++at_;
    layout_.tokens[pointer] = std::string(text_.substr(start, at_ - start));
  }
  std::string space() {
    const std::size_t start = at_;
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    return std::string(text_.substr(start, at_ - start));
  }

 private:
  void container(const std::string& pointer, bool object) {
    ++at_;
    JsonLayout::Container c;
    const char close = object ? '}' : ']';
    for (std::size_t index = 0;; ++index) {
      std::string lead = space();
      if (at_ >= text_.size() || text_[at_] == close) {
        c.close = std::move(lead);  // an empty container
        break;
      }
      std::string key = std::to_string(index), colon;
      if (object) {
        const std::size_t start = at_;
        string_token();
        key = json::parse(text_.substr(start, at_ - start)).get<std::string>();
        colon = space();
        colon += text_[at_++];  // ':'
        colon += space();
        c.keys.push_back(key);
      }
      value(pointer + "/" + escape_token(key));
      c.leads.push_back(std::move(lead));
      c.colons.push_back(std::move(colon));
      std::string after = space();
      if (at_ < text_.size() && text_[at_] == ',') {
        c.trails.push_back(std::move(after));
        ++at_;
      } else {
        c.trails.emplace_back();
        c.close = std::move(after);  // the last member: what is before the bracket
        break;
      }
    }
    if (at_ < text_.size()) ++at_;  // the closing bracket
    layout_.containers[pointer] = std::move(c);
  }
  void string_token() {
    for (++at_; at_ < text_.size() && text_[at_] != '"'; ++at_)
      if (text_[at_] == '\\') ++at_;
    ++at_;
  }
  std::string_view text_;
  JsonLayout& layout_;
  std::size_t at_ = 0;
};

// Keys the file did not have go after its own: these first, in this order
// (how graph files are written by hand), the rest alphabetically.
int preferred_rank(const std::string& key) {
  static const std::vector<std::string> order = {"loom", "seed", "time", "description", "type", "inputs", "from", "ui"};
  auto it = std::find(order.begin(), order.end(), key);
  return it == order.end() ? int(order.size()) : int(it - order.begin());
}

// Where on its line the text after `head` starts.
std::size_t line_column(const std::string& head) {
  const auto line = head.rfind('\n');
  return line == std::string::npos ? head.size() : head.size() - line - 1;
}

struct Member {
  std::string key;
  const json* value;
  int known;  // its index in the file's container, or -1
};

class Writer {
 public:
  explicit Writer(const JsonLayout& layout) : layout_(layout) {}

  // `indent`: the indentation of the line the value starts on; none inside a
  // one-line container (everything new there stays on that line). `column`:
  // where the value starts, for the one-line rule.
  std::string write(const json& v, const std::string& pointer, const std::optional<std::string>& indent,
                    std::size_t column) const {
    if (!v.is_structured()) return scalar(v, pointer);
    auto known = layout_.containers.find(pointer);
    if (known != layout_.containers.end() && !known->second.leads.empty())
      return write_known(v, pointer, known->second);
    // A new file's root and node table are never one line: a node a line at least.
    const bool one_line = !indent || v.empty() ||
                          (!pointer.empty() && pointer != "/nodes" &&
                           column + write(v, pointer, std::nullopt, 0).size() <= kOneLineColumns);
    std::string out = v.is_object() ? "{" : "[";
    const std::string inner = indent ? *indent + layout_.indent : std::string();
    bool first = true;
    for (const Member& m : members(v, pointer)) {
      const std::string head = (first ? "" : ",") + (one_line ? std::string(first ? "" : " ") : "\n" + inner) +
                               (v.is_object() ? json(m.key).dump() + ": " : "");
      first = false;
      out += head + write(*m.value, pointer + "/" + escape_token(m.key),
                          one_line ? std::nullopt : std::optional<std::string>(inner), line_column(head));
    }
    return out + (one_line || v.empty() ? "" : "\n" + *indent) + (v.is_object() ? "}" : "]");
  }

 private:
  // In the file's spacing; a new member is spaced like its last sibling.
  std::string write_known(const json& v, const std::string& pointer, const JsonLayout::Container& c) const {
    const std::vector<Member> list = members(v, pointer);
    std::string out = v.is_object() ? "{" : "[";
    bool first = true;
    for (const Member& m : list) {
      const std::size_t k = m.known >= 0 ? std::size_t(m.known) : c.leads.size() - 1;
      const std::string& lead = c.leads[k];
      const auto line = lead.rfind('\n');
      // A member on a line of its own is indented as its lead says; one
      // sharing a line stays on it (a one-line context).
      const std::optional<std::string> here =
          line == std::string::npos ? std::nullopt : std::optional<std::string>(lead.substr(line + 1));
      const std::string head = (first ? "" : ",") + lead + (v.is_object() ? json(m.key).dump() + c.colons[k] : "");
      first = false;
      out += head + write(*m.value, pointer + "/" + escape_token(m.key), here, line_column(head)) +
             (m.known >= 0 ? c.trails[k] : std::string());
    }
    return out + (list.empty() ? "" : c.close) + (v.is_object() ? "}" : "]");
  }
  std::string scalar(const json& v, const std::string& pointer) const {
    auto token = layout_.tokens.find(pointer);
    if (token != layout_.tokens.end()) {
      const json was = json::parse(token->second, nullptr, false);
      if (!was.is_discarded() && was == v && was.is_number_float() == v.is_number_float()) return token->second;
    }
    return v.dump();
  }
  // Members in the file's order, then new keys (see preferred_rank).
  std::vector<Member> members(const json& v, const std::string& pointer) const {
    auto known = layout_.containers.find(pointer);
    const JsonLayout::Container* c = known == layout_.containers.end() ? nullptr : &known->second;
    std::vector<Member> out;
    if (v.is_array()) {
      for (std::size_t i = 0; i < v.size(); ++i)
        out.push_back({std::to_string(i), &v[i], c && i < c->leads.size() ? int(i) : -1});
      return out;
    }
    if (c)
      for (std::size_t k = 0; k < c->keys.size(); ++k)
        if (v.contains(c->keys[k])) out.push_back({c->keys[k], &v.at(c->keys[k]), int(k)});
    std::vector<std::string> fresh;
    for (const auto& [key, child] : v.items())
      if (std::none_of(out.begin(), out.end(), [&](const Member& m) { return m.key == key; })) fresh.push_back(key);
    std::stable_sort(fresh.begin(), fresh.end(),
                     [](const std::string& a, const std::string& b) { return preferred_rank(a) < preferred_rank(b); });
    for (const auto& key : fresh) out.push_back({key, &v.at(key), -1});
    return out;
  }
  const JsonLayout& layout_;
};

}  // namespace

JsonLayout scan_json_layout(std::string_view text) {
  JsonLayout layout;
  // One level of indentation: the leading spaces of the first indented line.
  for (std::size_t line = text.find('\n'); line != std::string_view::npos; line = text.find('\n', line + 1)) {
    std::size_t end = line + 1;
    while (end < text.size() && text[end] == ' ') ++end;
    if (end > line + 1) {
      layout.indent.assign(end - line - 1, ' ');
      break;
    }
  }
  Scanner scanner(text, layout);
  scanner.space();
  scanner.value("");
  layout.after = scanner.space();
  return layout;
}

std::string write_json(const json& value, const JsonLayout& layout) {
  return Writer(layout).write(value, "", std::string(), 0) + layout.after;
}

}  // namespace loom::editor
