#include "window.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <time.h>

#include "fonts.hpp"
#include "loom/atomic_file.hpp"
#include "loom/error.hpp"

namespace loom::editor {

namespace {
std::string& last_glfw_error() {
  static std::string text;
  return text;
}
void glfw_error(int code, const char* text) { last_glfw_error() = std::to_string(code) + ": " + text; }
double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}
}  // namespace

Window::Window(const std::string& title, int width, int height, bool visible) {
  glfwSetErrorCallback(glfw_error);
  if (!glfwInit()) throw Error("cannot start GLFW (is there a display? DISPLAY is unset or Xvfb is not running): " +
                               last_glfw_error());
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw Error("cannot create an OpenGL 3.0 window: " + last_glfw_error());
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(visible ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the layout is fixed; nothing to remember
  ImGui::StyleColorsDark();
  load_fonts();
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 130");
}

Window::~Window() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool Window::should_close() const { return glfwWindowShouldClose(window_); }
void Window::set_should_close(bool close) { glfwSetWindowShouldClose(window_, close); }

int Window::width() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return w;
}

int Window::height() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return h;
}

void Window::begin_frame(const ScriptedInput* scripted) {
  if (profiling_) frame_start_ms_ = thread_cpu_ms();
  glfwPollEvents();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  if (scripted) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(scripted->mouse_x, scripted->mouse_y);
    for (int b = 0; b < 3; ++b) io.MouseDown[b] = scripted->mouse_down[b];
    io.MouseWheel = scripted->wheel;
    for (bool& k : io.KeysDown) k = false;
    for (int key : scripted->keys_down)
      if (key >= 0 && key < int(IM_ARRAYSIZE(io.KeysDown))) io.KeysDown[key] = true;
    io.KeyCtrl = scripted->ctrl;
    io.KeyShift = scripted->shift;
    io.KeyAlt = scripted->alt;
    io.KeySuper = false;
    io.InputQueueCharacters.resize(0);
    io.AddInputCharactersUTF8(scripted->text.c_str());
    // Scripted frames are paced by the script, not the clock.
    io.DeltaTime = 1.0f / 60.0f;
  }
  ImGui::NewFrame();
}

void Window::end_frame(Rgba8Image* capture) {
  ImGui::Render();
  const double built = profiling_ ? thread_cpu_ms() : 0;
  glViewport(0, 0, width(), height());
  glClearColor(0.10f, 0.10f, 0.11f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (!backdrops_.empty()) {
    const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
    const int h = height();
    glEnable(GL_SCISSOR_TEST);
    for (const Backdrop& b : backdrops_) {
      const int x0 = int(b.x * scale.x), y0 = int(b.y * scale.y);
      const int x1 = int((b.x + b.width) * scale.x), y1 = int((b.y + b.height) * scale.y);
      glScissor(x0, h - y1, x1 - x0, y1 - y0);
      glClearColor(b.r, b.g, b.b, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
  }
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  double drawn = 0;
  if (profiling_) {
    glFinish();
    drawn = thread_cpu_ms();
  }
  if (capture) *capture = read_back();
  glfwSwapBuffers(window_);
  if (profiling_) {
    const ImDrawData* data = ImGui::GetDrawData();
    cost_.build_ms = built - frame_start_ms_;
    cost_.raster_ms = drawn - built;
    cost_.swap_ms = thread_cpu_ms() - drawn;
    cost_.vertices = data->TotalVtxCount;
    cost_.indices = data->TotalIdxCount;
    cost_.draw_calls = 0;
    for (int i = 0; i < data->CmdListsCount; ++i) cost_.draw_calls += data->CmdLists[i]->CmdBuffer.Size;
  }
}

Rgba8Image Window::read_back() const {
  Rgba8Image image;
  image.width = width();
  image.height = height();
  image.pixels.resize(std::size_t(image.width) * image.height * 4);
  std::vector<std::uint8_t> flipped(image.pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, flipped.data());
  const std::size_t row = std::size_t(image.width) * 4;
  for (int y = 0; y < image.height; ++y)
    std::copy_n(&flipped[(image.height - 1 - y) * row], row, &image.pixels[y * row]);
  return image;
}

void save_png(const Rgba8Image& image, const std::filesystem::path& file) {
  cv::Mat rgba(image.height, image.width, CV_8UC4, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgra;
  cv::cvtColor(rgba, bgra, cv::COLOR_RGBA2BGRA);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", bgra, bytes)) throw Error("cannot encode " + file.string() + " as PNG");
  write_file_atomic(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace loom::editor
