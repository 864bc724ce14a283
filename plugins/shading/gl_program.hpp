// A linked GLSL program and its uniforms by name.
#pragma once

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "gl_api.hpp"

namespace loom::shading {

class GlProgram {
 public:
  // Compiles and links the stages; throws loom::Error with the info log.
  GlProgram(const GlApi& gl, const char* name, const std::vector<std::pair<GLenum, const char*>>& stages);
  ~GlProgram();
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  void use() const { gl_.UseProgram(id_); }
  GLint location(const char* uniform);  // -1 when the linker dropped it
  void set(const char* u, int v) { gl_.Uniform1i(location(u), v); }
  void set(const char* u, bool v) { gl_.Uniform1i(location(u), v ? 1 : 0); }
  void set(const char* u, double v) { gl_.Uniform1f(location(u), static_cast<float>(v)); }
  void set(const char* u, const Eigen::Vector3d& v);
  void set(const char* u, const Eigen::Vector2d& v);
  void set(const char* u, const Eigen::Matrix4d& m);
  void set(const char* u, const Eigen::Matrix3d& m);

 private:
  const GlApi& gl_;
  GLuint id_ = 0;
  std::unordered_map<std::string, GLint> locations_;
};

}  // namespace loom::shading
