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

// Where the UI thread's CPU time of the last frame went (when profiling):
// ImGui building the draw lists, OpenGL drawing them (with llvmpipe on this
// thread, LP_NUM_THREADS=0, that is the rasterization, finished by glFinish),
// and the swap (under Xvfb: copying the frame to the X server).
struct FrameCost {
  double build_ms = 0, raster_ms = 0, swap_ms = 0;
  int vertices = 0, indices = 0, draw_calls = 0;
};

// A rectangle of the window filled by glClear before ImGui draws (window
// pixels, origin top-left): the fixed panes' backgrounds. llvmpipe clears
// without running a shader, while a window background drawn by ImGui shades
// (texture lookup and blend) every pixel it covers: the whole screen, per
// frame, was most of an idle frame's cost.
struct Backdrop {
  float x = 0, y = 0, width = 0, height = 0;
  float r = 0, g = 0, b = 0;  // 0..1
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
  // Cleared regions for the next frames (the rest: the default background).
  void set_backdrops(std::vector<Backdrop> backdrops) { backdrops_ = std::move(backdrops); }
  // Measures each frame's FrameCost (adds a glFinish per frame).
  void set_profiling(bool on) { profiling_ = on; }
  const FrameCost& last_cost() const { return cost_; }

 private:
  Rgba8Image read_back() const;
  GLFWwindow* window_ = nullptr;
  std::vector<Backdrop> backdrops_;
  bool profiling_ = false;
  double frame_start_ms_ = 0;
  FrameCost cost_;
};

// Writes a capture as PNG (atomically).
void save_png(const Rgba8Image& image, const std::filesystem::path& file);

}  // namespace loom::editor
