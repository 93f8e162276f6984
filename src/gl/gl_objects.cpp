// gl/gl_objects.cpp: see gl_objects.h.
#include "gl/gl_objects.h"

#include <fmt/format.h>

#include "aniso/gl/gl_context.h"
#include "gl/gl_shader.h"

namespace aniso::gl {

Program::Program(const std::string& vertex, const std::string& fragment, const std::string& what)
    : id_(vertex_fragment_program(vertex, fragment, what)) {}

Program::~Program() {
  if (id_) glDeleteProgram(id_);
}

GLint Program::loc(const std::string& name) {
  const auto it = locations_.find(name);
  if (it != locations_.end()) return it->second;
  const GLint l = glGetUniformLocation(id_, name.c_str());
  locations_.emplace(name, l);
  return l;
}

FramebufferRestore::FramebufferRestore() {
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  glGetIntegerv(GL_VIEWPORT, viewport);
}

FramebufferRestore::~FramebufferRestore() {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
}

std::vector<float> read_rgba(GLuint fbo, int w, int h) {
  GLint old_read = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &old_read);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  std::vector<float> rgba(size_t(w) * size_t(h) * 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(old_read));
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw GlError(fmt::format("GL backend read-back: GL error 0x{:x}", err));
  return rgba;
}

}  // namespace aniso::gl
