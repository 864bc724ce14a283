// The GL objects the llvmpipe limit runs draw with (bench_shading limits):
// a context of their own made as Render's is (GlContext), framebuffers like
// Render's, full-screen triangles and a grid of small triangles, and the
// fragment programs (constant colour, depth only, the 5x5 PCF's gathers).
#pragma once

#include <functional>
#include <memory>

#include "gl_context.hpp"
#include "gl_program.hpp"
#include "llvmpipe_limits.hpp"

namespace loom::shading {

// A framebuffer like Render's: RGBA16F colour (none for a depth map) and a
// 32-bit float depth buffer. The depth buffer is attached also where the
// depth test is off: without one, llvmpipe drops every earlier command of a
// tile an opaque triangle covers, and N full-screen quads would cost one.
struct Framebuffer {
  int width = 0, height = 0;
  bool color = true;
  GLuint fbo = 0, color_texture = 0, depth_texture = 0;
};

// The context and its objects; each of quads() and grid() is one timed frame.
class LimitRig {
 public:
  enum class Target { image, image_msaa, shadow_map };
  enum class Shading { constant, depth_only, pcf };

  explicit LimitRig(const RenderFrame& f);
  ~LimitRig();
  LimitRig(const LimitRig&) = delete;
  LimitRig& operator=(const LimitRig&) = delete;

  // One frame: clear, `quads` full-screen triangles each nearer than the
  // last (depth test GL_LESS for the shadow map, off for the image), glFinish.
  void quads(Target t, Shading s, int quads);
  // One frame: clear, the grid of small triangles once (depth test on, as
  // Render's), glFinish. half_culled: every other triangle wound the other
  // way and culled, as Render culls the hidden half of a closed mesh (the
  // target's sphere): the same triangles through the vertex stage, half of
  // them rasterized.
  void grid(Target t, Shading s, bool half_culled = false);
  long long grid_triangles() const { return grid_indices_ / 3; }
  long long pixels(Target t) const;

 private:
  void frame(Target t, GlProgram& p, bool depth_test, const std::function<void()>& draw, int draws);
  GlProgram& program(bool grid, Shading s);
  const Framebuffer& framebuffer(Target t) const;

  GlContext context_;
  RenderFrame render_;
  Framebuffer image_, image_msaa_, shadow_map_;
  std::unique_ptr<GlProgram> programs_[2][3];  // [grid][shading]; the grid has no PCF
  GLuint empty_vao_ = 0, grid_vao_ = 0, grid_buffer_ = 0, grid_half_culled_buffer_ = 0;
  int grid_columns_ = 0;
  GLsizei grid_indices_ = 0;
};

}  // namespace loom::shading
