// A headless OpenGL 4.5 core-profile context from OSMesa (Mesa's llvmpipe:
// software rasterization, no display, no GPU). Draws go to framebuffer
// objects; the context's own buffer is a placeholder.
//
// A context is current on one thread at a time: callers hold lock() while
// they use it (TBB may run a node on a different worker each evaluation).
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "gl_api.hpp"

namespace loom::shading {

class GlContext {
 public:
  // Throws loom::Error when OSMesa cannot give a 4.5 core context.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes the context current on the calling thread; the returned lock keeps
  // other threads out until it is released (the context is released too).
  class Current {
   public:
    explicit Current(GlContext& c);
    ~Current();
    Current(const Current&) = delete;
    Current& operator=(const Current&) = delete;

   private:
    GlContext& c_;
    std::unique_lock<std::mutex> lock_;
  };

  const GlApi& gl() const { return gl_; }
  const std::string& renderer() const { return renderer_; }  // "llvmpipe (LLVM 15...)"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::mutex mutex_;
  GlApi gl_;
  std::string renderer_;
};

}  // namespace loom::shading
