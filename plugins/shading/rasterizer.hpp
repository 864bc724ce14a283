// Render: a Scene rasterized by OpenGL 4.5 core through OSMesa (llvmpipe).
// The context and the compiled programs live in a Rasterizer, kept between
// evaluations in the node's scratch; every render sets all the GL state it
// uses, so nothing carries over from one run to the next.
#pragma once

#include <functional>
#include <memory>

#include <opencv2/core.hpp>

#include "loom/scene.hpp"

namespace loom::shading {

enum class ShadowFilter { off, hard, pcf, pcss };

// The first max_lights lights are drawn, and the first max_shadows of them
// that cast shadows get shadow maps.
constexpr int max_lights = 8, max_shadows = 4;

struct RenderOptions {
  int width = 960, height = 540;
  int samples = 4;                    // MSAA samples per pixel (1: none)
  ShadowFilter shadows = ShadowFilter::pcf;
  int shadow_resolution = 2048;       // texels per side of each shadow map
  double shadow_bias = 1.0;           // constant depth bias, in shadow-map texels
  double shadow_slope_bias = 1.0;     // times tan(angle to the light), in texels
  int pcf_size = 5;                   // PCF kernel: k x k texels
  double light_size = 0.1;            // PCSS: emitter radius (point, spot) or tan(angular radius) (directional)
  int tessellation = 16;              // displacement mapping: subdivisions per triangle edge
  double point_radius = 0.02;         // radius of points without their own
  double line_width = 1.0;            // pixels
  bool wireframe = false;
  Eigen::Vector3d wireframe_color{0, 0, 0};
  bool aux = false;                   // also render normal, position/depth and shadow images
  // Asked between the render's phases and batches of triangles; throws to
  // cancel (empty: never asked).
  std::function<void()> check_cancelled;
};

struct RenderImages {
  cv::Mat color;     // CV_32FC4: linear radiance, alpha = coverage
  cv::Mat normal;    // CV_32FC3: world-space unit normal (0 on the background)   [aux]
  cv::Mat position;  // CV_32FC4: world position, w = depth along the view axis   [aux]
  cv::Mat shadow;    // CV_32FC1: visibility of the first shadowed light (1 lit)  [aux]
};

struct RenderTimings {
  double upload = 0, shadows = 0, draw = 0, readback = 0;  // seconds
  // The process's CPU seconds in each (all threads, llvmpipe's included: a
  // benchmark's figure, less moved by the machine's load than wall time;
  // other work in the same process counts too).
  double upload_cpu = 0, shadows_cpu = 0, draw_cpu = 0, readback_cpu = 0;
};

class Rasterizer {
 public:
  // Creates the OSMesa context and compiles every program; throws loom::Error.
  Rasterizer();
  ~Rasterizer();

  // Thread-safe (one render at a time). Throws loom::Error on an invalid scene.
  RenderImages render(const Scene& scene, const RenderOptions& options, RenderTimings* timings = nullptr);

  double context_seconds() const;   // creating the context
  double compile_seconds() const;   // compiling and linking the programs
  int max_samples() const;
  const std::string& renderer() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace loom::shading
