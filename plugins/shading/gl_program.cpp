#include "gl_program.hpp"

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
      GLint ok = 0;
      gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
      if (!ok) {
        char log[4096] = {};
        gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
        throw Error(std::string("shader of program '") + name + "' does not compile: " + log);
      }
      gl.AttachShader(id_, s);
    }
    gl.LinkProgram(id_);
    GLint ok = 0;
    gl.GetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
      char log[4096] = {};
      gl.GetProgramInfoLog(id_, sizeof log, nullptr, log);
      throw Error(std::string("program '") + name + "' does not link: " + log);
    }
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
