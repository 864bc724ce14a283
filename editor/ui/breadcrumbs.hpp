// The path of the group being edited, across the top of the canvas:
// "graph.json > look (Studio) > inner (Inner)". Clicking a crumb goes up to
// that level. Nothing is drawn at the top graph.
#pragma once

#include <utility>
#include <vector>

#include <imgui.h>

#include "editor_state.hpp"

namespace loom::editor {

class Breadcrumbs {
 public:
  void draw(EditorState& state, const std::string& graph_name);
  // Where each crumb was drawn last frame (0: the top graph), for scripted tests.
  const std::vector<std::pair<ImVec2, ImVec2>>& crumbs() const { return crumbs_; }

 private:
  std::vector<std::pair<ImVec2, ImVec2>> crumbs_;
};

}  // namespace loom::editor
