// gl/gl_objects.h: the GL backend's small GL helpers (private to src/gl): a linked program with
// its uniform locations cached, the caller's framebuffer bindings put back at the end of a public
// call, a framebuffer's float read-back. OpenGL 3.3 core; the caller's context is current.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

namespace aniso::gl {

// A linked vertex + fragment program with its uniform locations looked up once each.
class Program {
 public:
  // GlError naming `what` (and carrying the driver's log) when a stage does not compile or link.
  Program(const std::string& vertex, const std::string& fragment, const std::string& what);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  // -1 for a name the program does not use (optimised away): glUniform* ignores location -1.
  GLint loc(const std::string& name);
  // Setters for the bound program (glUseProgram(id()) first).
  void set(const std::string& name, float v) { glUniform1f(loc(name), v); }
  void set(const std::string& name, int v) { glUniform1i(loc(name), v); }
  void set(const std::string& name, const glm::vec2& v) { glUniform2f(loc(name), v.x, v.y); }
  void set(const std::string& name, const glm::vec3& v) { glUniform3f(loc(name), v.x, v.y, v.z); }
  void set(const std::string& name, const glm::ivec2& v) { glUniform2i(loc(name), v.x, v.y); }

 private:
  GLuint id_ = 0;
  std::unordered_map<std::string, GLint> locations_;
};

// Puts back the caller's framebuffer bindings and viewport when a public call ends (the explorer
// draws its window between our calls).
struct FramebufferRestore {
  GLint draw = 0, read = 0, viewport[4] = {0, 0, 0, 0};
  FramebufferRestore();
  ~FramebufferRestore();
  FramebufferRestore(const FramebufferRestore&) = delete;
  FramebufferRestore& operator=(const FramebufferRestore&) = delete;
};

// The w x h RGBA float pixels of fbo's colour attachment 0, GL's row order (row 0 at the bottom);
// the read framebuffer binding is put back. GlError on a GL error.
std::vector<float> read_rgba(GLuint fbo, int w, int h);

}  // namespace aniso::gl
