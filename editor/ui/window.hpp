// The editor's window: GLFW, an OpenGL 3 context and Dear ImGui with its
// GLFW and OpenGL 3 backends (built into Debian's libimgui 1.86).
//
// Scripted input: ImGui 1.86 has no event queue (io.AddMousePosEvent is 1.87),
// so a test sets the input state of each frame itself. begin_frame() lets the
// GLFW backend fill io from the window, then applies a ScriptedInput over it,
// so a test drives the real UI code frame by frame without a person.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

struct GLFWwindow;

namespace loom::editor {

struct ScriptedInput {
  float mouse_x = -1, mouse_y = -1;  // window pixels
  bool mouse_down[3] = {false, false, false};
  float wheel = 0;
  bool ctrl = false, shift = false, alt = false;
  std::vector<int> keys_down;  // GLFW key codes held this frame
  std::string text;            // characters typed this frame
};

struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // RGBA, top row first
  const std::uint8_t* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * 4]; }
};

class Window {
 public:
  // Throws loom::Error if GLFW or the OpenGL context cannot be created (no
  // display). `visible` false: an offscreen window for tests and captures.
  Window(const std::string& title, int width, int height, bool visible = true);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  bool should_close() const;
  void set_should_close(bool close);
  // Polls events (or not, when scripted) and starts an ImGui frame.
  void begin_frame(const ScriptedInput* scripted = nullptr);
  // Renders ImGui and swaps buffers; with `capture`, first reads the frame
  // back (glReadPixels of the back buffer: works for hidden windows too).
  void end_frame(Rgba8Image* capture = nullptr);
  int width() const;
  int height() const;
  GLFWwindow* handle() const { return window_; }

 private:
  Rgba8Image read_back() const;
  GLFWwindow* window_ = nullptr;
};

// Writes a capture as PNG (atomically).
void save_png(const Rgba8Image& image, const std::filesystem::path& file);

}  // namespace loom::editor
