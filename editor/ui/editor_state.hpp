// What the editor's views share for one frame: the model, the selection, the
// node being viewed and the newest evaluation. Owned by EditorApp.
#pragma once

#include <filesystem>
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

  // Set when the canvas shows another level (a group entered or left): the
  // canvas frames it once.
  bool level_changed = false;

  // The engine names a node inside the group entered by its path ("look.render").
  std::string engine_id(const std::string& id) const { return doc.path_prefix() + id; }
  // The node's last report: from the running evaluation once the node has
  // finished there, else the newest evaluation's (a flat node's, or a group
  // instance's summary).
  const NodeReport* report(const std::string& id) const {
    const std::string path = engine_id(id);
    if (auto it = live.find(path); it != live.end() && !it->second.running) return &it->second.report;
    return eval ? eval->report(path) : nullptr;
  }
  // What the node is doing in the running evaluation, or null when it is
  // not running; a group node runs while one of its inner nodes does.
  const LiveNode* live_node(const std::string& id) const {
    const auto running = [&](const std::string& path) -> const LiveNode* {
      auto it = live.find(path);
      return it != live.end() && it->second.running ? &it->second : nullptr;
    };
    const std::string path = engine_id(id);
    if (const LiveNode* node = running(path)) return node;
    if (live.empty() || !eval || !eval->view) return nullptr;
    for (const auto& inner : eval->view->inner_nodes(path))
      if (const LiveNode* node = running(inner)) return node;
    return nullptr;
  }
  // Enters a group node (an inline group, a group file, a Repeat body) in
  // this document: the instance's values stay shown.
  void enter(const std::string& id) {
    if (doc.enter(id)) show_level();
  }
  void leave(std::size_t depth) {
    if (depth >= doc.path().size()) return;
    doc.leave(depth);
    show_level();
  }
  void show_level() {
    selection.clear();
    viewed.clear();
    level_changed = true;
  }
  // The newest evaluated value of an output of the viewed node, or empty.
  Value viewed_output(int index) const;
  // The newest value feeding a linked input, or empty.
  Value upstream_value(const std::string& id, const std::string& input) const;
};

}  // namespace loom::editor
