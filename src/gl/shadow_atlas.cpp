// gl/shadow_atlas.cpp: see shadow_atlas.h.
#include "gl/shadow_atlas.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_library.h"
#include "gl/shader_sources.h"

namespace aniso::gl {

using render::LightKind;

ShadowAtlas::ShadowAtlas()
    : program_(std::make_unique<Program>(
          glsl_preamble(GlslDialect::Core330) + glsl_library_source() + std::string(embedded::gl_shader_shadow_map_vert),
          glsl_preamble(GlslDialect::Core330) + std::string(embedded::gl_shader_shadow_map_frag), "GL backend: shadow maps")) {}

ShadowAtlas::~ShadowAtlas() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (atlas_) glDeleteTextures(1, &atlas_);
}

void ShadowAtlas::build(const std::vector<render::Light>& lights, const std::vector<ShadowCaster>& casters, const Vec3& lo,
                        const Vec3& hi) {
  first_.assign(lights.size(), -1);
  shadowless_lights_ = 0;
  if (casters.empty() || lights.empty()) return;
  constexpr int kAtlas = 4096;
  int tiles = 0;
  for (const render::Light& l : lights) tiles += l.kind == LightKind::Point ? 6 : 1;
  tile_ = 1024;
  while (tile_ > 256 && tiles > (kAtlas / tile_) * (kAtlas / tile_)) tile_ /= 2;
  cols_ = kAtlas / tile_;
  const int capacity = cols_ * cols_;
  int next = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    const int need = lights[i].kind == LightKind::Point ? 6 : 1;
    if (next + need > capacity) {
      ++shadowless_lights_;
      continue;
    }
    first_[i] = next;
    next += need;
  }
  const int rows = (next + cols_ - 1) / cols_, cols_used = std::min(next, cols_);
  center_ = 0.5f * (lo + hi);
  radius_ = std::max(0.5f * glm::length(hi - lo), 1e-6f) * 1.01f;
  if (!atlas_) glGenTextures(1, &atlas_);
  glBindTexture(GL_TEXTURE_2D, atlas_);
  const glm::ivec2 size(cols_used * tile_, rows * tile_);
  if (size != atlas_size_) {  // the same lights moving (a dragged light) keep the texture
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, size.x, size.y, 0, GL_RED, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    atlas_size_ = size;
  }
  if (!fbo_) glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, atlas_, 0);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("the shadow-map atlas framebuffer is incomplete");
  const float far_value[4] = {3.0e38f, 0, 0, 0};  // nothing in the way
  glClearBufferfv(GL_COLOR, 0, far_value);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_MIN);
  glBlendFunc(GL_ONE, GL_ONE);
  Program& shadow = *program_;
  glUseProgram(shadow.id());
  shadow.set("u_center", center_);
  shadow.set("u_radius", radius_);
  for (size_t i = 0; i < lights.size(); ++i) {
    if (first_[i] < 0) continue;
    const render::Light& l = lights[i];
    const bool point = l.kind == LightKind::Point;
    shadow.set("u_mode", point ? 0 : 1);
    shadow.set("u_light", point ? l.position : l.to_light);
    for (int face = 0; face < (point ? 6 : 1); ++face) {
      // The cube face's axes as cube_face() in shaders/raster.frag.glsl numbers them.
      const int a = face / 2, b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
      glUniform3i(shadow.loc("u_axes"), a, b, c);
      shadow.set("u_sign", face % 2 == 0 ? 1.0f : -1.0f);
      const int tile = first_[i] + face;
      glViewport((tile % cols_) * tile_, (tile / cols_) * tile_, tile_, tile_);
      for (const ShadowCaster& m : casters) {
        glBindVertexArray(m.vao);
        glDrawArrays(GL_TRIANGLES, 0, m.count);
      }
    }
  }
  glBlendEquation(GL_FUNC_ADD);
  glDisable(GL_BLEND);
}

void ShadowAtlas::set_uniforms(Program& p) const {
  p.set("u_shadow_tile", std::max(tile_, 1));
  p.set("u_shadow_cols", cols_);
  p.set("u_shadow_center", center_);
  p.set("u_shadow_radius", radius_);
}

}  // namespace aniso::gl
