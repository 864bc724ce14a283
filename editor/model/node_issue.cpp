#include "node_issue.hpp"

namespace loom::editor {

std::vector<std::string> pointer_tokens(const std::string& pointer) {
  std::vector<std::string> tokens;
  if (pointer.empty() || pointer[0] != '/') return tokens;
  std::string token;
  for (std::size_t i = 1; i <= pointer.size(); ++i) {
    if (i == pointer.size() || pointer[i] == '/') {
      tokens.push_back(std::move(token));
      token.clear();
    } else if (pointer[i] == '~' && i + 1 < pointer.size() && (pointer[i + 1] == '0' || pointer[i + 1] == '1')) {
      token += pointer[++i] == '0' ? '~' : '/';  // RFC 6901, one pass left to right
    } else {
      token += pointer[i];
    }
  }
  return tokens;
}

NodeIssue locate_issue(const GraphIssue& issue) {
  NodeIssue located{{}, {}, issue.pointer, issue.message};
  const auto tokens = pointer_tokens(issue.pointer);
  if (tokens.size() >= 2 && tokens[0] == "nodes") {
    located.node = tokens[1];
    if (tokens.size() >= 4 && tokens[2] == "inputs") located.input = tokens[3];
  }
  return located;
}

}  // namespace loom::editor
