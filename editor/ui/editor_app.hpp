// The editor: menus, the canvas, the property panel and the viewers over one
// GraphDocument, with evaluation in the background (EvaluationController).
//
// After every edit the graph is submitted again; what is submitted are the
// viewed node and every non-sink node (the preview), so every node shows a
// status but no file is written until "Write outputs" runs the sinks, as
// `loom run` would. The UI thread never waits for an evaluation.
#pragma once

#include <chrono>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "breadcrumbs.hpp"
#include "canvas.hpp"
#include "controller/evaluation_controller.hpp"
#include "controller/plugin_watcher.hpp"
#include "editor_state.hpp"
#include "file_dialog.hpp"
#include "image_viewer.hpp"
#include "mesh_viewer.hpp"
#include "loom/plugin_loader.hpp"
#include "model/graph_document.hpp"
#include "property_panel.hpp"
#include "render_viewport.hpp"
#include "timeline.hpp"
#include "draw_tool.hpp"
#include "poisson_tool.hpp"
#include "warp_tool.hpp"
#include "window.hpp"

namespace loom::editor {

struct EditorOptions {
  std::vector<std::filesystem::path> plugin_path;  // empty: the default search path
  std::filesystem::path output_dir = ".";          // where "Write outputs" writes
  std::filesystem::path config_dir;                // recent files; empty: ~/.config/loom
  int threads = 0;
};

// The split of the window between the panes, as fractions: the canvas's
// share of the width, the properties' share of the right column's height.
// The borders are dragged (splitters).
struct PaneSplit {
  float canvas = 0.6f, properties = 0.4f;
};
// Those panes in pixels for the current window.
struct PaneRects {
  ImVec2 at, size;    // the panes' area (without the time slider)
  float left = 0;     // the canvas's width
  float props = 0;    // the properties pane's height
};

// The last plugin hot reload: which plugins, when the rebuilt files were
// seen settled, and how long loading them took.
struct HotReload {
  std::vector<std::string> plugins;
  std::chrono::steady_clock::time_point detected{}, loaded{};
  double load_ms = 0;  // copying, loading and registering the new builds
  int count = 0;       // reloads so far
};

// What a menu asks for that may drop unsaved changes (asked about first).
enum class MenuAction { none, new_graph, open, quit };

class EditorApp {
 public:
  explicit EditorApp(EditorOptions options = {});
  ~EditorApp();

  // Throws GraphError when the file is not a graph (the document is unchanged).
  void open(const std::filesystem::path& file);
  // Saves, unless another program changed a file it would overwrite since
  // it was read or saved here (GraphDocument::changed_on_disk): then asks
  // first ("Overwrite" or "Cancel") and returns false.
  bool save(const std::filesystem::path& file);
  // The files the open "Changed on disk" question is about (empty: none),
  // and where its Overwrite button was drawn last frame.
  const std::vector<std::filesystem::path>& save_conflict() const { return conflict_.changed; }
  std::optional<std::pair<ImVec2, ImVec2>> overwrite_button() const { return overwrite_button_; }
  // One frame of UI, between Window::begin_frame and end_frame.
  void draw(Window& window);
  bool quit_requested() const { return quit_; }

  GraphDocument& document() { return doc_; }
  EditorState& state() { return state_; }
  Canvas& canvas() { return canvas_; }
  Breadcrumbs& breadcrumbs() { return breadcrumbs_; }
  PropertyPanel& properties() { return properties_; }
  Timeline& timeline() { return timeline_; }
  PaneSplit& panes() { return panes_; }
  PaneRects pane_rects() const;
  PoissonTool& poisson_tool() { return poisson_tool_; }
  DrawTool& draw_tool() { return draw_tool_; }
  // Where the viewer drew the image last frame (scale 0: no image shown).
  const ImageView& image_view() const { return image_view_; }
  const MeshViewer& mesh_viewer() const { return mesh_viewer_; }
  const ImageViewer& image_viewer() const { return image_viewer_; }
  ImageViewer& image_viewer() { return image_viewer_; }
  // The document revision whose result (or newest pass) the viewer drew last frame.
  std::uint64_t shown_revision() const { return shown_revision_; }
  EvaluationController& controller() { return *controller_; }
  const Registry& registry() const { return registry_; }
  const std::vector<std::filesystem::path>& recent_files() const { return recent_; }
  const std::string& message() const { return message_; }
  // Submits the current document now if it changed (draw() does this too).
  void sync_evaluation();
  // Whether the shown evaluation is of the current document (and frame, and
  // viewed node) and none is running.
  bool evaluation_current() const;
  const HotReload& last_reload() const { return last_reload_; }
  // Evaluates the sinks (writes files) on the next submission.
  void write_outputs() { write_outputs_ = true; }

 private:
  void draw_frame(Window& window);
  template <class Draw>
  void guarded(Draw&& draw);
  void group_menu();
  void group_into_file(const std::filesystem::path& file);
  void take_results();
  void menu_bar(Window& window);
  void shortcuts();
  void hot_reload();
  void offer_views();
  void viewer();
  void unsaved_prompt();
  void conflict_prompt();
  void save_over(const std::filesystem::path& file);
  void request(MenuAction action, std::filesystem::path file = {});
  void perform(MenuAction action, const std::filesystem::path& file);
  void remember(const std::filesystem::path& file);
  void load_recent();

  EditorOptions options_;
  Registry registry_;
  std::unique_ptr<PluginLoader> loader_;
  GraphDocument doc_;
  EditorState state_;
  std::unique_ptr<EvaluationController> controller_;
  std::unique_ptr<PluginWatcher> watcher_;
  std::vector<std::string> reload_pending_;  // rebuilt plugins waiting for the worker to stop
  HotReload last_reload_;
  Canvas canvas_;
  Breadcrumbs breadcrumbs_;
  PropertyPanel properties_;
  Timeline timeline_;
  ImageViewer image_viewer_;
  RenderViewport render_viewport_;
  MeshViewer mesh_viewer_;
  WarpTool warp_tool_;
  PoissonTool poisson_tool_;
  DrawTool draw_tool_;
  FileDialog files_;
  std::uint64_t submitted_revision_ = ~0ull;
  json submitted_document_;
  std::uint64_t evaluated_revision_ = ~0ull;  // the revision submitted_document_ came from
  int submitted_frame_ = 0;                   // 0: the graph has no time range
  std::string submitted_viewed_;              // whose cached frames were asked for
  std::string submitted_level_;               // the level previewed (GraphDocument::path_prefix)
  bool write_outputs_ = false, quit_ = false;
  MenuAction pending_action_ = MenuAction::none;
  std::filesystem::path pending_file_;
  bool prompt_open_ = false;
  // A save waiting for an answer: the file to write and what changed on disk.
  struct SaveConflict {
    std::filesystem::path file;
    std::vector<std::filesystem::path> changed;
    bool open_popup = false;
  };
  SaveConflict conflict_;
  std::optional<std::pair<ImVec2, ImVec2>> overwrite_button_;
  std::vector<std::filesystem::path> recent_;
  std::string message_;
  int viewed_output_ = 0;
  std::uint64_t shown_revision_ = 0;
  ImageView image_view_;
  PaneSplit panes_;
};

}  // namespace loom::editor
