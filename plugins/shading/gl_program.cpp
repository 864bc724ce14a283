#include "gl_program.hpp"

#include <string>

#include "loom/error.hpp"

namespace loom::shading {

namespace {

// A program's shaders, deleted when it is linked or when building it throws.
struct Shaders {
  const GlApi& gl;
  std::vector<GLuint> ids;
  ~Shaders() {
    for (GLuint s : ids) gl.DeleteShader(s);
  }
};

// Throws `failure` and the info log when a compile or link step failed.
template <class Status, class InfoLog>
void require_success(GLuint id, GLenum pname, Status status, InfoLog info_log, const std::string& failure) {
  GLint ok = 0;
  status(id, pname, &ok);
  if (ok) return;
  char log[4096] = {};
  info_log(id, sizeof log, nullptr, log);
  throw Error(failure + log);
}

}  // namespace

GlProgram::GlProgram(const GlApi& gl, const char* name,
                     const std::vector<std::pair<GLenum, const char*>>& stages)
    : gl_(gl) {
  id_ = gl.CreateProgram();
  try {
    Shaders shaders{gl, {}};
    shaders.ids.reserve(stages.size());
    for (const auto& [kind, source] : stages) {
      shaders.ids.push_back(gl.CreateShader(kind));
      const GLuint s = shaders.ids.back();
      gl.ShaderSource(s, 1, &source, nullptr);
      gl.CompileShader(s);
      require_success(s, GL_COMPILE_STATUS, gl.GetShaderiv, gl.GetShaderInfoLog,
                      std::string("shader of program '") + name + "' does not compile: ");
      gl.AttachShader(id_, s);
    }
    gl.LinkProgram(id_);
    require_success(id_, GL_LINK_STATUS, gl.GetProgramiv, gl.GetProgramInfoLog,
                    std::string("program '") + name + "' does not link: ");
  } catch (...) {
    gl.DeleteProgram(id_);  // the destructor does not run for a constructor that throws
    throw;
  }
}

GlProgram::~GlProgram() { gl_.DeleteProgram(id_); }

GLint GlProgram::location(const char* uniform) {
  auto it = locations_.find(uniform);
  if (it == locations_.end()) it = locations_.emplace(uniform, gl_.GetUniformLocation(id_, uniform)).first;
  return it->second;
}

void GlProgram::set(const char* u, const Eigen::Vector3d& v) {
  gl_.Uniform3f(location(u), static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}
void GlProgram::set(const char* u, const Eigen::Vector2d& v) {
  gl_.Uniform2f(location(u), static_cast<float>(v.x()), static_cast<float>(v.y()));
}
void GlProgram::set(const char* u, const Eigen::Matrix4d& m) {
  const Eigen::Matrix4f f = m.cast<float>();  // column-major, as GL wants
  gl_.UniformMatrix4fv(location(u), 1, GL_FALSE, f.data());
}
void GlProgram::set(const char* u, const Eigen::Matrix3d& m) {
  const Eigen::Matrix3f f = m.cast<float>();
  gl_.UniformMatrix3fv(location(u), 1, GL_FALSE, f.data());
}

}  // namespace loom::shading
