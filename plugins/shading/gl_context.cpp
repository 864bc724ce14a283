#include "gl_context.hpp"

#include <GL/osmesa.h>

#include <vector>

#include "loom/error.hpp"

namespace loom::shading {

// Owns the OSMesa context: destroyed also when the constructor throws after
// creating it (OSMesaMakeCurrent failing, no renderer string).
struct GlContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> buffer = std::vector<unsigned char>(4 * 4 * 4);
  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (context) OSMesaDestroyContext(context);
  }
};

namespace {
void* resolve(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

void make_current(OSMesaContext c, std::vector<unsigned char>& buffer) {
  if (!OSMesaMakeCurrent(c, buffer.data(), GL_UNSIGNED_BYTE, 4, 4))
    throw Error("OSMesaMakeCurrent failed: cannot use the OpenGL context");
}
}  // namespace

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                            OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                            OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!impl_->context)
    throw Error("OSMesa could not create an OpenGL 4.5 core-profile context (Mesa >= 20 with "
                "llvmpipe is needed: install libosmesa6; GALLIUM_DRIVER must not force softpipe)");
  make_current(impl_->context, impl_->buffer);
  gl_.load(&resolve);
  const auto* renderer = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
  OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
  if (!renderer) throw Error("the OpenGL context names no renderer");
  renderer_ = renderer;
}

GlContext::~GlContext() = default;

GlContext::Current::Current(GlContext& c) : c_(c), lock_(c.mutex_) {
  make_current(c_.impl_->context, c_.impl_->buffer);
}

GlContext::Current::~Current() {
  // Releasing the context lets the next holder make it current on its thread.
  OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
}

}  // namespace loom::shading
