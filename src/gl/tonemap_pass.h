// gl/tonemap_pass.h: the GL backend's display pass (private to src/gl): a float RGB texture drawn
// tone-mapped into the bound draw framebuffer and viewport, through the one GLSL tone map
// (aniso/image/tonemap.glsl, the twin of render::tonemap: 2^exposure, the ACES curve or a clamp,
// the sRGB transfer function; written as is, so GL_FRAMEBUFFER_SRGB must be off).
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "aniso/image/tonemap.h"

namespace aniso::gl {

class Program;

class TonemapPass {
 public:
  TonemapPass();  // compiles the pass; GlError when it does not compile
  ~TonemapPass();
  TonemapPass(const TonemapPass&) = delete;
  TonemapPass& operator=(const TonemapPass&) = delete;

  // Covers the current viewport with `texture` (size texels, RGB linear radiance). A viewport of
  // the texture's size reads one texel per pixel (texelFetch: NaN and inf stay in their pixel);
  // any other size is filtered bilinearly (sets the texture's filters to GL_LINEAR). Disables
  // depth test and blending; changes the program, vertex array and texture unit 0.
  void draw(unsigned texture, glm::ivec2 size, const render::ToneMapOptions& tm) const;

 private:
  std::unique_ptr<Program> program_;
  unsigned empty_vao_ = 0;
};

}  // namespace aniso::gl
