// Graph files stay hand-editable: the editor writes a document back in the
// layout of the file it read. The layout records, per JSON pointer, each
// object's key order, the white space around each member (so one-line
// nodes, wrapped lines and one-number-per-line dumps all come back as they
// were) and the text of each number and string; writing puts keys in that
// order (new keys after them, spaced like their last sibling) and reuses the
// original text of every value that did not change ("1e5" stays "1e5").
// What the file did not have is written compactly: a container whose
// one-line form is short (a position, a link, a short array) on one line,
// others one member per line.
//
// So an unchanged document is written back byte for byte, and a one-value
// edit changes one line of the file.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "loom/value.hpp"

namespace loom::editor {

struct JsonLayout {
  struct Container {
    std::vector<std::string> keys;  // objects: in the file's order
    // Per member, in the file's order: the text before it (after the '{',
    // '[' or ','), between its key and its value (": "), and after it.
    std::vector<std::string> leads, colons, trails;
    std::string close;  // before the closing bracket
  };
  std::map<std::string, Container> containers;  // by JSON pointer ("" is the root)
  std::map<std::string, std::string> tokens;    // numbers and strings as written
  std::string indent = "  ";                    // one level of the file's indentation
  std::string after = "\n";                    // after the document: its last newline, or none
};

// New containers whose one-line form (with its key and indentation) fits in
// this many columns are written on one line.
constexpr std::size_t kOneLineColumns = 100;

// The layout of JSON text that parses (as the document read from it did).
JsonLayout scan_json_layout(std::string_view text);
// `value` written in `layout`, ending as the file did (a new file: a newline).
std::string write_json(const json& value, const JsonLayout& layout);

}  // namespace loom::editor
