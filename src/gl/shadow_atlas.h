// gl/shadow_atlas.h: the meshes' shadow maps of the GL backend (private to src/gl). Meshes cannot
// be ray-tested per fragment, so they cast their shadows through one R32F atlas of square tiles:
// 6 per point light (cube faces), 1 per directional light (orthographic over the scene's bounding
// sphere). A texel holds the distance from the light to the nearest mesh surface (point) or the
// height towards the light above the plane through the sphere's centre (directional); the scene
// pass reads it in mesh_shadowed() (shaders/raster.frag.glsl), the shadow pass draws it
// (shaders/shadow_map.*.glsl).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <epoxy/gl.h>

#include "aniso/core/math.h"
#include "aniso/render/scene.h"
#include "gl/gl_objects.h"

namespace aniso::gl {

// A mesh's triangles (its vertex array, gl/raster_geometry.h Vertex) to draw into the atlas.
struct ShadowCaster {
  GLuint vao = 0;
  GLsizei count = 0;
};

class ShadowAtlas {
 public:
  ShadowAtlas();  // compiles the shadow pass; GlError when it does not compile
  ~ShadowAtlas();
  ShadowAtlas(const ShadowAtlas&) = delete;
  ShadowAtlas& operator=(const ShadowAtlas&) = delete;

  // Lays the tiles out for `lights` (point and directional only) and draws `casters` into them;
  // the directional tiles cover the sphere about the box [lo, hi] (every object's bounds). Tiles
  // of 1024 texels, halved until every light's tiles fit in 4096 x 4096 (64 MB of R32F), down to
  // 256; lights beyond 256 tiles get none (gl_unsupported says so). Nothing is drawn without
  // casters or lights. Changes the bound framebuffer, viewport, program, vertex array and blending
  // (left disabled, equation GL_FUNC_ADD), disables GL_DEPTH_TEST and GL_CULL_FACE.
  void build(const std::vector<render::Light>& lights, const std::vector<ShadowCaster>& casters, const Vec3& lo, const Vec3& hi);
  // The scene program's u_shadow_* uniforms (bound program p); the atlas itself is texture(), on
  // the unit u_shadow_atlas names.
  void set_uniforms(Program& p) const;
  // The first tile of light i (its index in build()'s `lights`), or -1: no shadow map.
  int first_tile(size_t i) const { return i < first_.size() ? first_[i] : -1; }
  // The R32F atlas texture, 0 before a build() with casters and lights.
  GLuint texture() const { return atlas_; }
  // Lights of the last build() beyond the atlas's budget: meshes cast no shadow from them.
  size_t shadowless_lights() const { return shadowless_lights_; }

 private:
  std::unique_ptr<Program> program_;
  GLuint atlas_ = 0, fbo_ = 0;
  int tile_ = 0, cols_ = 1;
  glm::ivec2 atlas_size_{0};
  std::vector<int> first_;  // per light: first tile, or -1
  Vec3 center_{0.0f};
  float radius_ = 1.0f;
  size_t shadowless_lights_ = 0;
};

}  // namespace aniso::gl
