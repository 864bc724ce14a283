#include "breadcrumbs.hpp"

namespace loom::editor {

void Breadcrumbs::draw(EditorState& state, const std::string& graph_name) {
  crumbs_.clear();
  const std::vector<std::string> path = state.doc.path();
  if (path.empty()) return;
  std::vector<std::string> labels{graph_name};
  for (std::size_t depth = 0; depth < path.size(); ++depth) labels.push_back(path[depth]);
  labels.back() += " (" + state.doc.group_name() + ")";
  std::size_t go_to = path.size();
  for (std::size_t depth = 0; depth < labels.size(); ++depth) {
    if (depth > 0) {
      ImGui::SameLine();
      ImGui::TextDisabled(">");
      ImGui::SameLine();
    }
    ImGui::PushID(int(depth));
    if (depth + 1 < labels.size()) {
      if (ImGui::SmallButton(labels[depth].c_str())) go_to = depth;
    } else {
      ImGui::TextColored(ImVec4(0.8f, 0.65f, 1, 1), "%s", labels[depth].c_str());
    }
    crumbs_.emplace_back(ImGui::GetItemRectMin(), ImGui::GetItemRectMax());
    ImGui::PopID();
  }
  ImGui::SameLine();
  const std::filesystem::path file = state.doc.level_file();
  if (state.doc.in_repeat_body())
    ImGui::TextDisabled("  a Repeat body: its iterations keep no values to show");
  else if (!file.empty())
    ImGui::TextDisabled("  editing %s: Save writes it, for every graph that uses it", file.filename().c_str());
  else
    ImGui::TextDisabled("  editing the group: every node of this type changes");
  if (go_to < path.size()) state.leave(go_to);
}

}  // namespace loom::editor
