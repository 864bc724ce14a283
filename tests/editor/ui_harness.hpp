// A scripted driver for the editor under Xvfb: a hidden window, the real
// EditorApp, and mouse/keyboard state fed frame by frame (ImGui 1.86 reads
// input state per frame, it has no event queue).
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include "run_loom.hpp"
#include "test_files.hpp"
#include "ui/editor_app.hpp"

namespace loom::editor::test {

// A graph written to a file of the test's temporary folder.
inline std::filesystem::path write_graph(const json& doc, const std::string& name) {
  const std::filesystem::path file = loom::test::temp_dir() / name;
  std::ofstream(file) << doc.dump(1);
  return file;
}

struct Harness {
  Window window;
  EditorApp app;
  ScriptedInput input;
  Rgba8Image last;

  // `test_plugins`: also the test fixtures' node types (Integrate, ...).
  static EditorOptions options(bool test_plugins = false) {
    EditorOptions o;
    o.plugin_path = {LOOM_PLUGIN_DIR};
    if (test_plugins) o.plugin_path.push_back(LOOM_TEST_PLUGIN_DIR);
    o.output_dir = loom::test::temp_dir();
    o.config_dir = loom::test::temp_dir();
    o.threads = 2;
    return o;
  }
  Harness(int width = 1400, int height = 820, bool test_plugins = false)
      : window("loom-editor test", width, height, false), app(options(test_plugins)) {
    frame(2);
  }

  void frame(int n = 1, bool capture = false) {
    for (int i = 0; i < n; ++i) {
      window.begin_frame(&input);
      app.draw(window);
      window.end_frame(capture && i == n - 1 ? &last : nullptr);
      input.wheel = 0;
      input.text.clear();
    }
  }
  // Frames until the evaluation of the current document has been shown.
  bool settle(double timeout = 60) {
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      frame();
      if (app.evaluation_current()) {
        frame(2);  // let the views draw the new results
        return true;
      }
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout) return false;
    }
  }
  void move(ImVec2 to, int steps = 4) {
    const ImVec2 from(input.mouse_x, input.mouse_y);
    for (int i = 1; i <= steps; ++i) {
      const float t = float(i) / float(steps);
      input.mouse_x = from.x + (to.x - from.x) * t;
      input.mouse_y = from.y + (to.y - from.y) * t;
      frame();
    }
  }
  void jump(ImVec2 to) {
    input.mouse_x = to.x;
    input.mouse_y = to.y;
    frame();
  }
  void click(ImVec2 at, int button = 0) {
    jump(at);
    input.mouse_down[button] = true;
    frame();
    input.mouse_down[button] = false;
    frame();
  }
  void drag(ImVec2 from, ImVec2 to, int button = 0, int steps = 8) {
    jump(from);
    input.mouse_down[button] = true;
    frame();
    move(to, steps);
    input.mouse_down[button] = false;
    frame();
  }
  void key(int glfw_key, bool ctrl = false, bool shift = false) {
    input.ctrl = ctrl;
    input.shift = shift;
    input.keys_down = {glfw_key};
    frame();
    input.keys_down.clear();
    frame();
    input.ctrl = input.shift = false;
  }
  void type(const std::string& text) {
    input.text = text;
    frame();
  }
  Rgba8Image screenshot(const std::string& name) {
    frame(1, true);
    const auto dir = std::filesystem::path(LOOM_BINARY_DIR) / "editor-screenshots";
    std::filesystem::create_directories(dir);
    save_png(last, dir / (name + ".png"));
    return last;
  }
};

}  // namespace loom::editor::test
