// What the editor's views share for one frame: the model, the selection, the
// node being viewed and the newest evaluation. Owned by EditorApp.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>

#include "controller/evaluation_controller.hpp"
#include "model/graph_document.hpp"

namespace loom::editor {

struct EditorState {
  explicit EditorState(GraphDocument& d) : doc(d) {}
  GraphDocument& doc;
  std::set<std::string> selection;
  std::string viewed;  // the node whose outputs the viewers show
  std::shared_ptr<const Evaluation> eval;
  std::map<std::string, LiveNode> live;
  // Validation issues by node, then by input ("" for the node itself).
  std::map<std::string, std::map<std::string, std::string>> issues;

  const NodeReport* report(const std::string& id) const {
    if (!eval) return nullptr;
    auto it = eval->result.nodes.find(id);
    return it == eval->result.nodes.end() ? nullptr : &it->second;
  }
  // The newest evaluated value of an output of the viewed node, or empty.
  Value viewed_output(int index) const;
  // The newest value feeding a linked input, or empty.
  Value upstream_value(const std::string& id, const std::string& input) const;
};

}  // namespace loom::editor
