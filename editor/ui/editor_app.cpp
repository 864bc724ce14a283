#include "editor_app.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>  // PushItemFlag(ImGuiItemFlags_NoTabStop)

#include "loom/atomic_file.hpp"
#include "loom/call_node.hpp"
#include "loom/mesh.hpp"
#include "value_views.hpp"

namespace loom::editor {

namespace fs = std::filesystem;

Value EditorState::upstream_value(const std::string& id, const std::string& input) const {
  auto l = doc.link(id, input);
  if (!eval || !l || !doc.has_node(l->node)) return {};
  return eval->output(engine_id(l->node), l->output);
}

Value EditorState::viewed_output(int index) const {
  const NodeType* t = eval && !viewed.empty() && doc.has_node(viewed) ? doc.node_type(viewed) : nullptr;
  if (!t || index < 0 || index >= int(t->spec.outputs.size())) return {};
  return eval->output(engine_id(viewed), t->spec.outputs[std::size_t(index)].name);
}

EditorApp::EditorApp(EditorOptions options)
    : options_(std::move(options)), doc_(registry_), state_(doc_) {
  loader_ = options_.plugin_path.empty() ? std::make_unique<PluginLoader>(registry_)
                                         : std::make_unique<PluginLoader>(registry_, options_.plugin_path);
  // Every plugin up front: the add-node menu lists all node types, and the
  // worker thread then only reads the registry.
  for (const PluginInfo& info : loader_->plugins()) {
    try {
      loader_->load_library(info.library);
    } catch (const std::exception& e) {
      message_ += std::string(e.what()) + "\n";
    }
  }
  offer_views();
  controller_ = std::make_unique<EvaluationController>(registry_, options_.threads);
  watcher_ = std::make_unique<PluginWatcher>(*loader_);
  if (options_.config_dir.empty()) {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    options_.config_dir = xdg && *xdg ? fs::path(xdg) / "loom" : fs::path(home ? home : ".") / ".config" / "loom";
  }
  load_recent();
}

EditorApp::~EditorApp() = default;

// The viewer shows linear images through the colour plugin's views when it
// is there: the DisplayView node's body, run on the shown image (call_node),
// so the viewer and a graph's DisplayView give the same pixels.
void EditorApp::offer_views() {
  const NodeType* type = registry_.find("DisplayView");
  const InputSpec* view = type ? type->spec.find_input("view") : nullptr;
  if (!view) return;
  image_viewer_.set_views(view->choices, [this](const Image& image, const std::string& name) {
    const NodeType* now = registry_.find("DisplayView");  // looked up again: a hot reload may replace it
    if (!now) throw Error("the DisplayView node (plugin color) is not loaded");
    NodeCall call;
    call.values.emplace("image", Value::make<Image>(image));
    if (!name.empty()) call.literals["view"] = name;  // empty: the display's default view
    call.id = "viewer";
    return call_node(*now, call).at(0).as<Image>();
  });
}

void EditorApp::open(const fs::path& file) {
  doc_.load(file);
  // Types provided on demand (the python plugin's py.MODULE.NAME): asked for
  // once the worker is idle, since it reads the registry.
  std::vector<std::string> missing;
  for (const auto& t : doc_.types_used())
    if (!doc_.find_type(t)) missing.push_back(t);
  if (!missing.empty()) {
    controller_->wait_idle();
    try {
      loader_->load_for(missing);
    } catch (const std::exception& e) {
      message_ += std::string(e.what()) + "\n";
    }
  }
  state_.selection.clear();
  state_.viewed.clear();
  state_.eval.reset();
  state_.issues.clear();
  canvas_.frame_all(state_);
  remember(doc_.file());
  message_ = "opened " + doc_.file().string();
}

bool EditorApp::save(const fs::path& file) {
  std::vector<fs::path> changed = doc_.changed_on_disk();
  // Saved elsewhere, the file read is not overwritten (group files still are).
  if (fs::absolute(file) != doc_.file())
    changed.erase(std::remove(changed.begin(), changed.end(), doc_.file()), changed.end());
  if (!changed.empty()) {
    conflict_ = {file, changed, true};
    return false;
  }
  save_over(file);
  return true;
}

void EditorApp::save_over(const fs::path& file) {
  doc_.save(file);
  remember(doc_.file());
  message_ = "saved " + doc_.file().string();
}

// Another program changed a file Save would overwrite: overwrite it (then do
// what waited for the save), or keep the file and the unsaved work.
void EditorApp::conflict_prompt() {
  if (conflict_.open_popup) {
    ImGui::OpenPopup("Changed on disk");
    conflict_.open_popup = false;
  }
  overwrite_button_.reset();
  if (!ImGui::BeginPopupModal("Changed on disk", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  for (const auto& f : conflict_.changed) ImGui::Text("%s was changed by another program", f.string().c_str());
  ImGui::Text("since it was opened or last saved here. Saving overwrites those changes.");
  if (ImGui::Button("Overwrite")) {
    try {
      save_over(conflict_.file);
      perform(std::exchange(pending_action_, MenuAction::none), pending_file_);
    } catch (const std::exception& e) {
      message_ = e.what();
    }
    conflict_ = {};
    ImGui::CloseCurrentPopup();
  }
  overwrite_button_ = std::make_pair(ImGui::GetItemRectMin(), ImGui::GetItemRectMax());
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    pending_action_ = MenuAction::none;
    message_ = "not saved: " + conflict_.changed.front().string() + " changed on disk";
    conflict_ = {};
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

void EditorApp::load_recent() {
  std::ifstream in(options_.config_dir / "editor-recent.json");
  if (!in) return;
  try {
    for (const auto& f : json::parse(in)) recent_.push_back(f.get<std::string>());
  } catch (const std::exception&) {
    recent_.clear();  // a damaged list is not worth a message
  }
}

void EditorApp::remember(const fs::path& file) {
  recent_.erase(std::remove(recent_.begin(), recent_.end(), file), recent_.end());
  recent_.insert(recent_.begin(), file);
  if (recent_.size() > 10) recent_.resize(10);
  json list = json::array();
  for (const auto& f : recent_) list.push_back(f.string());
  try {
    write_file_atomic(options_.config_dir / "editor-recent.json", list.dump(1));
  } catch (const std::exception& e) {
    message_ = std::string("cannot remember recent files: ") + e.what();
  }
}

void EditorApp::sync_evaluation() {
  if (!reload_pending_.empty()) return;  // the registry is about to change
  const auto range = doc_.time_range();
  const int frame = range ? doc_.frame() : 0;
  // The level shown decides which inner nodes the preview asks for.
  const std::string level = doc_.path_prefix();
  if (doc_.revision() == submitted_revision_ && frame == submitted_frame_ && state_.viewed == submitted_viewed_ &&
      level == submitted_level_ && !write_outputs_)
    return;
  submitted_revision_ = doc_.revision();
  // Layout edits (moving, collapsing) change nothing evaluated: the running
  // evaluation goes on, and its result stays current.
  json evaluated = doc_.evaluated_part();
  const bool changed = evaluated != submitted_document_ || frame != submitted_frame_ || level != submitted_level_;
  if (!changed && state_.viewed == submitted_viewed_ && !write_outputs_) return;
  submitted_document_ = evaluated;
  evaluated_revision_ = doc_.revision();
  submitted_frame_ = frame;
  submitted_viewed_ = state_.viewed;
  submitted_level_ = level;
  EvalRequest r;
  r.document = std::move(evaluated);
  r.file = doc_.file().empty() ? fs::current_path() / "untitled.json" : doc_.file();
  r.output_dir = options_.output_dir;
  r.revision = doc_.revision();
  if (range) r.frames = write_outputs_ ? FrameRange{range->start, range->end} : FrameRange{frame, frame};
  r.frames_of = state_.viewed.empty() ? std::string() : state_.engine_id(state_.viewed);
  // The preview: every node of the top graph and of the level shown, by the
  // paths the engine gives inner nodes.
  if (!write_outputs_) r.preview = level;
  // Viewing another node changes nothing evaluated (every non-sink node is
  // already), only whose cached frames are marked: it waits for the run.
  // A drag cancels a run only once it has shown a pass (a progressive
  // render): the next one then answers within a pass, not a whole render.
  controller_->submit(std::move(r), /*cancel_running=*/changed && (!doc_.merging() || controller_->refining()));
  write_outputs_ = false;
}

bool EditorApp::evaluation_current() const {
  const auto& e = state_.eval;
  return !controller_->busy() && e && e->revision == evaluated_revision_ && submitted_revision_ == doc_.revision() &&
         submitted_frame_ == (doc_.time_range() ? doc_.frame() : 0) && e->frame == submitted_frame_ &&
         e->preview == std::optional<std::string>(doc_.path_prefix());
}

// A rebuilt plugin is loaded again once the worker has let go of the
// registry; the next submission then re-evaluates what uses its nodes (their
// hashes hold the new build), while the session's cache keeps every other
// result. The document is not touched.
void EditorApp::hot_reload() {
  using Clock = std::chrono::steady_clock;
  if (reload_pending_.empty()) {
    reload_pending_ = watcher_->rebuilt();
    if (reload_pending_.empty()) return;
    last_reload_.detected = Clock::now();
    controller_->cancel();
  }
  if (controller_->busy()) return;
  const auto start = Clock::now();
  std::string failed;
  std::vector<std::string> done;
  for (const std::string& plugin : reload_pending_) {
    try {
      loader_->reload(plugin);
      done.push_back(plugin);
    } catch (const std::exception& e) {
      failed += std::string(e.what()) + "\n";
    }
    watcher_->reloaded(plugin);  // a broken build is not retried until it changes again
  }
  reload_pending_.clear();
  last_reload_.loaded = Clock::now();
  last_reload_.load_ms = std::chrono::duration<double, std::milli>(last_reload_.loaded - start).count();
  last_reload_.plugins = done;
  ++last_reload_.count;
  std::string names;
  for (const auto& p : done) names += (names.empty() ? "" : ", ") + p;
  char text[64];
  std::snprintf(text, sizeof text, " in %.0f ms", last_reload_.load_ms);
  message_ = failed + (done.empty() ? "" : "reloaded plugin " + names + text);
  submitted_document_ = json();  // evaluate again, whatever changed
  submitted_revision_ = ~0ull;
}

void EditorApp::take_results() {
  state_.live = controller_->live();
  auto finished = controller_->take_finished();
  if (!finished) return;
  state_.eval = *finished;
  // A run of the sinks ("Write outputs") has no preview values (and, with
  // frames, ends at the last frame): preview the current frame again.
  if (!state_.eval->preview && !doc_.node_ids().empty()) {
    submitted_document_ = json();
    submitted_revision_ = ~0ull;
  }
  state_.issues.clear();
  for (const NodeIssue& issue : state_.eval->issues) {
    if (issue.node.empty())
      message_ = issue.message;
    else
      state_.issues[issue.node][issue.input] = issue.message;
  }
  if (!state_.eval->error.empty()) message_ = state_.eval->error;
}

void EditorApp::request(MenuAction action, fs::path file) {
  if (doc_.dirty()) {
    pending_action_ = action;
    pending_file_ = std::move(file);
    prompt_open_ = true;
    return;
  }
  perform(action, file);
}

void EditorApp::perform(MenuAction action, const fs::path& file) {
  if (action == MenuAction::new_graph) {
    doc_.clear();
    state_.selection.clear();
    state_.viewed.clear();
    state_.eval.reset();
    state_.issues.clear();
  } else if (action == MenuAction::open && file.empty()) {
    files_.open("open", "Open a graph", doc_.file().empty() ? fs::current_path() : doc_.file().parent_path(), false);
  } else if (action == MenuAction::open) {
    try {
      open(file);
    } catch (const std::exception& e) {
      message_ = e.what();
    }
  } else if (action == MenuAction::quit) {
    quit_ = true;
  }
}

void EditorApp::unsaved_prompt() {
  if (prompt_open_) {
    ImGui::OpenPopup("Unsaved changes");
    prompt_open_ = false;
  }
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
  ImGui::Text("%s has unsaved changes.", doc_.file().empty() ? "This graph" : doc_.file().filename().c_str());
  if (ImGui::Button("Save")) {
    if (doc_.file().empty()) {
      files_.open("save", "Save the graph as", fs::current_path() / "untitled.json", true);
    } else if (save(doc_.file())) {
      perform(std::exchange(pending_action_, MenuAction::none), pending_file_);
    }
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Discard")) {
    perform(pending_action_, pending_file_);
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    pending_action_ = MenuAction::none;
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

void EditorApp::menu_bar(Window& window) {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New")) request(MenuAction::new_graph);
    if (ImGui::MenuItem("Open...", "Ctrl+O")) request(MenuAction::open);
    if (ImGui::BeginMenu("Open Recent", !recent_.empty())) {
      for (const auto& f : recent_)
        if (ImGui::MenuItem(f.string().c_str())) request(MenuAction::open, f);
      ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Save", "Ctrl+S")) {
      if (doc_.file().empty())
        files_.open("save", "Save the graph as", fs::current_path() / "untitled.json", true);
      else
        save(doc_.file());
    }
    if (ImGui::MenuItem("Save As..."))
      files_.open("save", "Save the graph as", doc_.file().empty() ? fs::current_path() : doc_.file(), true);
    ImGui::Separator();
    if (ImGui::MenuItem("Quit")) request(MenuAction::quit);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    if (ImGui::MenuItem(("Undo " + doc_.undo_label()).c_str(), "Ctrl+Z", false, doc_.can_undo())) doc_.undo();
    if (ImGui::MenuItem(("Redo " + doc_.redo_label()).c_str(), "Ctrl+Shift+Z", false, doc_.can_redo())) doc_.redo();
    ImGui::Separator();
    group_menu();
    ImGui::Separator();
    if (ImGui::MenuItem("Frame all", "F")) canvas_.frame_all(state_);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Graph")) {
    if (ImGui::MenuItem("Write outputs (run the sinks)", "Ctrl+R")) write_outputs();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("into %s", fs::absolute(options_.output_dir).c_str());
    ImGui::EndMenu();
  }
  // The evaluation state, right of the menus.
  const auto& eval = state_.eval;
  std::string status = controller_->busy() ? "evaluating..." : "idle";
  if (eval && !controller_->busy()) {
    char text[96];
    std::snprintf(text, sizeof text, "evaluated in %.1f ms%s", eval->seconds * 1e3,
                  !eval->issues.empty() ? ", invalid graph" : !eval->result.ok() ? ", a node failed" : "");
    status = text;
  }
  ImGui::SameLine(ImGui::GetWindowWidth() - 420);
  ImGui::TextDisabled("%s%s | %.1f ms/frame", doc_.dirty() ? "* " : "", status.c_str(),
                      1000.0f / std::max(ImGui::GetIO().Framerate, 1.0f));
  ImGui::EndMainMenuBar();
  if (window.should_close()) {
    window.set_should_close(false);
    request(MenuAction::quit);
  }
}

void EditorApp::group_menu() {
  const std::vector<std::string> selected(state_.selection.begin(), state_.selection.end());
  try {
    if (ImGui::MenuItem("Group", "Ctrl+G", false, !selected.empty())) state_.selection = {doc_.group(selected)};
    if (ImGui::MenuItem("Group into a file...", nullptr, false, !selected.empty()))
      files_.open("group-file", "Write the group as", doc_.file().empty() ? fs::current_path() / "group.json"
                                                                          : doc_.file().parent_path() / "group.json",
                  true);
    if (ImGui::MenuItem("Ungroup", "Ctrl+Shift+G", false, !selected.empty())) ungroup_selection(state_);
  } catch (const std::exception& e) {
    message_ = e.what();
  }
  if (ImGui::MenuItem("Leave group", nullptr, false, !doc_.path().empty())) state_.leave(doc_.path().size() - 1);
}

void EditorApp::group_into_file(const fs::path& file) {
  try {
    const std::vector<std::string> selected(state_.selection.begin(), state_.selection.end());
    state_.selection = {doc_.group_to_file(selected, file)};
    message_ = "wrote the group " + file.string();
  } catch (const std::exception& e) {
    message_ = e.what();
  }
}

void EditorApp::shortcuts() {
  ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput || !io.KeyCtrl) return;
  if (ImGui::IsKeyPressed(GLFW_KEY_Z) && !io.KeyShift) doc_.undo();
  if ((ImGui::IsKeyPressed(GLFW_KEY_Z) && io.KeyShift) || ImGui::IsKeyPressed(GLFW_KEY_Y)) doc_.redo();
  if (ImGui::IsKeyPressed(GLFW_KEY_S)) {
    if (doc_.file().empty())
      files_.open("save", "Save the graph as", fs::current_path() / "untitled.json", true);
    else
      save(doc_.file());
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_O)) request(MenuAction::open);
  if (ImGui::IsKeyPressed(GLFW_KEY_R)) write_outputs();
}

void EditorApp::viewer() {
  image_view_ = ImageView{};
  image_view_.scale = 0;
  const std::string& id = state_.viewed;
  if (id.empty() || !doc_.has_node(id)) {
    ImGui::TextDisabled("Click a node to view its outputs.");
    return;
  }
  const NodeType* t = doc_.node_type(id);
  if (!t || t->spec.outputs.empty()) {
    ImGui::TextDisabled("%s has no outputs to view.", id.c_str());
    return;
  }
  viewed_output_ = std::clamp(viewed_output_, 0, int(t->spec.outputs.size()) - 1);
  ImGui::SetNextItemWidth(200);
  if (ImGui::BeginCombo("output", t->spec.outputs[std::size_t(viewed_output_)].name.c_str())) {
    for (std::size_t o = 0; o < t->spec.outputs.size(); ++o)
      if (ImGui::Selectable(t->spec.outputs[o].name.c_str(), int(o) == viewed_output_)) viewed_output_ = int(o);
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  // A progressive render's newest pass stands in for the result until it comes.
  const auto pass =
      RenderViewport::newest_pass(state_, *controller_, id, t->spec.outputs[std::size_t(viewed_output_)].name);
  const bool refining = pass && RenderViewport::refining(state_, *pass);
  const Value value = refining ? pass->value : state_.viewed_output(viewed_output_);
  const bool stale = !evaluation_current();
  const auto& eval = state_.eval;
  if (pass) {
    ImGui::TextDisabled("%s%s", refining ? "refining: " : "", RenderViewport::status(*pass).c_str());
  } else if (value && eval && eval->frame > 0) {
    ImGui::TextDisabled("frame %d: %s%s", eval->frame, value.summary().c_str(), stale ? " (updating)" : "");
  } else {
    ImGui::TextDisabled("%s%s", value ? value.summary().c_str() : "not evaluated", stale ? " (updating)" : "");
  }
  shown_revision_ = refining ? pass->revision : eval ? eval->revision : 0;
  // The interactive tools draw on the viewed image and write node inputs.
  const bool poisson = PoissonTool::applies(state_, id), drawing = DrawTool::applies(state_, id);
  const bool camera = RenderViewport::applies(state_, id) && render_viewport_.toolbar(state_, id);
  Value shown = value;
  if (poisson && poisson_tool_.toolbar()) {
    shown = state_.upstream_value(id, "source");
    if (!shown) ImGui::TextDisabled("the source is not evaluated yet");
  }
  if (drawing) draw_tool_.toolbar();
  if (!shown) return;
  if (shown.is<Image>()) {
    image_view_ = image_viewer_.draw(shown.as<Image>(), shown.shared<Image>().get(), !camera);
    if (camera) render_viewport_.draw(state_, id, image_view_);
    if (WarpTool::applies(state_, id)) warp_tool_.draw(state_, id, image_view_);
    if (poisson) poisson_tool_.draw(state_, id, image_view_);
    if (drawing) draw_tool_.draw(state_, id, image_view_);
  } else if (shown.is<Mesh>()) {
    mesh_viewer_.draw(shown.as<Mesh>(), shown.shared<Mesh>().get());
  } else {
    draw_value(value);
  }
}

namespace {

// A pane border dragged with the mouse (Debian's ImGui 1.86 has no docking):
// a thin window on top of the border holding an invisible button. Returns the
// border's new position in pixels, kept within [lo, hi].
float splitter(const char* id, ImVec2 at, ImVec2 size, bool vertical, float position, float lo, float hi) {
  ImGui::SetNextWindowPos(at);
  ImGui::SetNextWindowSize(size);
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1, 1));
  ImGui::Begin(id, nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoMove |
                                ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
  ImGui::InvisibleButton("border", size);
  if (ImGui::IsItemHovered() || ImGui::IsItemActive())
    ImGui::SetMouseCursor(vertical ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
  if (ImGui::IsItemActive()) position += vertical ? ImGui::GetIO().MouseDelta.x : ImGui::GetIO().MouseDelta.y;
  const ImU32 line = ImGui::IsItemHovered() || ImGui::IsItemActive() ? IM_COL32(120, 160, 255, 255)
                                                                        : IM_COL32(70, 70, 80, 255);
  const ImVec2 mid(at.x + size.x * 0.5f, at.y + size.y * 0.5f);
  ImGui::GetWindowDrawList()->AddLine(vertical ? ImVec2(mid.x, at.y) : ImVec2(at.x, mid.y),
                                      vertical ? ImVec2(mid.x, at.y + size.y) : ImVec2(at.x + size.x, mid.y), line,
                                      2);
  ImGui::End();
  ImGui::PopStyleVar(2);
  return std::clamp(position, lo, hi);
}

}  // namespace

PaneRects EditorApp::pane_rects() const {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  PaneRects r;
  r.at = vp->WorkPos;
  r.size = vp->WorkSize;
  if (doc_.time_range()) r.size.y -= Timeline::kHeight;
  r.left = std::floor(r.size.x * panes_.canvas);
  r.props = std::floor(r.size.y * panes_.properties);
  return r;
}

// No editor action may end the process and lose unsaved work: whatever a
// frame throws becomes the message over the canvas, and ImGui's stacks are
// unwound to the frame's start so the next frame draws normally.
void EditorApp::draw(Window& window) {
  try {
    draw_frame(window);
  } catch (const std::exception& e) {
    ImGui::ErrorCheckEndFrameRecover(nullptr);
    message_ = e.what();
  }
}

// One pane's contents; what it throws is shown, and the pane's window is
// unwound to its Begin so the other panes still draw this frame.
template <class Draw>
void EditorApp::guarded(Draw&& draw) {
  try {
    draw();
  } catch (const std::exception& e) {
    ImGui::ErrorCheckEndWindowRecover(nullptr);
    message_ = e.what();
  }
}

void EditorApp::draw_frame(Window& window) {
  hot_reload();
  take_results();
  shortcuts();
  menu_bar(window);
  const PaneRects r = pane_rects();
  const ImVec2 at = r.at, size = r.size;
  const float left = r.left, props = r.props;
  const bool timed = doc_.time_range().has_value();
  // The panes' backgrounds are cleared by the window, not drawn by ImGui
  // (see Backdrop): llvmpipe then shades only what is on them.
  const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                 ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoBackground;
  const float panel = 0.062f;  // ImGui's dark WindowBg (0.06 at 94%) over the clear colour
  window.set_backdrops({{at.x, at.y, left, size.y, 30 / 255.0f, 30 / 255.0f, 34 / 255.0f},
                        {at.x + left, at.y, size.x - left, size.y + (timed ? Timeline::kHeight : 0), panel, panel,
                         panel},
                        {at.x, at.y + size.y, left, timed ? Timeline::kHeight : 0, panel, panel, panel}});
  // Tab is the node search here, never ImGui's "focus the next text field".
  ImGui::PushItemFlag(ImGuiItemFlags_NoTabStop, true);

  ImGui::SetNextWindowPos(at);
  ImGui::SetNextWindowSize(ImVec2(left, size.y));
  ImGui::Begin(doc_.file().empty() ? "untitled###canvas" : (doc_.file().filename().string() + "###canvas").c_str(),
               nullptr, fixed | ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  if (!message_.empty()) {
    ImGui::TextWrapped("%s", message_.c_str());
    ImGui::SameLine();
    if (ImGui::SmallButton("x")) message_.clear();
  }
  guarded([&] {
    breadcrumbs_.draw(state_, doc_.file().empty() ? "untitled" : doc_.file().filename().string());
    canvas_.draw(state_);
  });
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(at.x + left, at.y));
  ImGui::SetNextWindowSize(ImVec2(size.x - left, props));
  ImGui::Begin("Properties", nullptr, fixed | ImGuiWindowFlags_HorizontalScrollbar);
  guarded([&] { properties_.draw(state_, files_); });
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(at.x + left, at.y + props));
  ImGui::SetNextWindowSize(ImVec2(size.x - left, size.y - props));
  ImGui::Begin("Viewer", nullptr, fixed | ImGuiWindowFlags_NoScrollWithMouse);
  guarded([&] { viewer(); });
  ImGui::End();

  panes_.canvas = splitter("##split canvas", ImVec2(at.x + left - 4, at.y), ImVec2(8, size.y), true, left,
                           std::min(300.0f, size.x * 0.5f), size.x - std::min(360.0f, size.x * 0.5f)) /
                  size.x;
  panes_.properties = splitter("##split properties", ImVec2(at.x + left + 4, at.y + props - 4),
                               ImVec2(size.x - left - 4, 8), false, props, std::min(120.0f, size.y * 0.5f),
                               size.y - std::min(160.0f, size.y * 0.5f)) /
                      size.y;
  if (timed) {
    ImGui::SetNextWindowPos(ImVec2(at.x, at.y + size.y));
    ImGui::SetNextWindowSize(ImVec2(size.x, Timeline::kHeight));
    ImGui::Begin("Time", nullptr, fixed | ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoScrollbar);
    timeline_.draw(state_, evaluation_current());
    ImGui::End();
  }
  ImGui::PopItemFlag();

  files_.draw();
  if (auto file = files_.take("open")) perform(MenuAction::open, *file);
  if (auto file = files_.take("group-file")) group_into_file(*file);
  if (auto file = files_.take("save")) {
    try {
      if (save(*file)) perform(std::exchange(pending_action_, MenuAction::none), pending_file_);
    } catch (const std::exception& e) {
      message_ = e.what();
      pending_action_ = MenuAction::none;
    }
  }
  unsaved_prompt();
  conflict_prompt();
  timeline_.tick(state_, evaluation_current());
  sync_evaluation();
}

}  // namespace loom::editor
