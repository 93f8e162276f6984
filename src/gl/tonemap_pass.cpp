// gl/tonemap_pass.cpp: see tonemap_pass.h.
#include "gl/tonemap_pass.h"

#include <cmath>
#include <string>

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_library.h"
#include "gl/gl_objects.h"
#include "gl/shader_sources.h"

namespace aniso::gl {

TonemapPass::TonemapPass()
    : program_(std::make_unique<Program>(glsl_preamble(GlslDialect::Core330) + std::string(embedded::gl_shader_fullscreen_vert),
                                         glsl_preamble(GlslDialect::Core330) + std::string(glsl_tonemap_source()) +
                                             std::string(embedded::gl_shader_tonemap_pass_frag),
                                         "GL backend: tone mapping")) {
  glGenVertexArrays(1, &empty_vao_);
}

TonemapPass::~TonemapPass() {
  if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
}

void TonemapPass::draw(unsigned texture, glm::ivec2 size, const render::ToneMapOptions& tm) const {
  GLint vp[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, vp);
  Program& p = *program_;
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(p.id());
  p.set("u_src", 0);
  p.set("u_scale", std::exp2(tm.exposure_stops));
  p.set("u_aces", int(tm.curve == render::ToneMap::Aces));
  p.set("u_exact", int(vp[2] == size.x && vp[3] == size.y));
  p.set("u_viewport_origin", glm::vec2(float(vp[0]), float(vp[1])));
  p.set("u_viewport_size", glm::vec2(float(vp[2]), float(vp[3])));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, GLuint(texture));
  // Bilinear when the viewport is not the image's size (the explorer's window).
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw GlError(fmt::format("GL backend draw_tonemapped: GL error 0x{:x}", err));
}

}  // namespace aniso::gl
