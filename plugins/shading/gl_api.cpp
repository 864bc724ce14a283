#include "gl_api.hpp"

#include <cstdio>
#include <string>

#include "loom/error.hpp"

namespace loom::shading {

void GlApi::load(void* (*resolve)(const char*)) {
#define LOOM_GL_LOAD(type, name)                                                       \
  name = reinterpret_cast<type>(resolve("gl" #name));                                  \
  if (!name) throw Error("OpenGL function gl" #name " is not available from OSMesa");
  LOOM_GL_FUNCTIONS(LOOM_GL_LOAD)
#undef LOOM_GL_LOAD
}

void GlApi::check(const char* where) const {
  const GLenum e = GetError();
  if (e != GL_NO_ERROR)
    throw Error(std::string("OpenGL error 0x") + [&] {
      char buf[16];
      std::snprintf(buf, sizeof buf, "%04x", static_cast<unsigned>(e));
      return std::string(buf);
    }() + " in " + where);
}

}  // namespace loom::shading
