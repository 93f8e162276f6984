// apps/aniso/view_gl.h: the explorer's own small GL pieces (OpenGL 3.3 core, entry points through
// libepoxy): offscreen targets, the display pass (linear radiance -> tone-mapped sRGB, and the
// A/B difference image) and the 3D lobe plot's mesh. Scenes are rasterised by gl/scene_raster.h;
// nothing here shades a material.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/image/image.h"
#include "view/plots.h"

namespace aniso::viewgl {

// A colour texture (RGBA8) with a depth buffer, as a framebuffer to draw into.
class RenderTarget {
 public:
  RenderTarget() = default;
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;
  void resize(int width, int height);  // reallocates only when the size changes
  void bind() const;                   // binds the framebuffer and sets the viewport
  unsigned texture() const { return tex_; }
  int width() const { return w_; }
  int height() const { return h_; }

 private:
  unsigned fbo_ = 0, tex_ = 0, depth_ = 0;
  int w_ = 0, h_ = 0;
};

// Linear radiance textures (RGBA, alpha = coverage) to display colours in the bound target:
// exposure, the tone curve of image/tonemap.h (Narkowicz 2015 ACES fit, then the sRGB OETF) over
// a background where coverage is below 1. Difference mode shows |A - B| * gain instead, tone-mapped
// the same way (black: equal).
class DisplayPass {
 public:
  DisplayPass();
  ~DisplayPass();
  void draw(unsigned radiance_a, unsigned radiance_b, bool difference, float exposure_stops, float gain,
            const glm::vec3& background) const;

 private:
  unsigned program_ = 0, vao_ = 0;
};

// The 3D lobe: a mesh of r(wo) * wo (view/plots.h), the normal, the tangent and the light drawn as
// lines, seen by an orbit camera.
class LobeRenderer {
 public:
  LobeRenderer();
  ~LobeRenderer();
  void upload(const view::LobeMesh& mesh, const glm::vec3& wi_local);
  // Draws into the bound target (width / height: its aspect).
  void draw(int width, int height, float yaw_deg, float pitch_deg) const;

 private:
  unsigned program_ = 0, vao_ = 0, vbo_ = 0, ibo_ = 0, line_vao_ = 0, line_vbo_ = 0;
  int index_count_ = 0;
};

// An 8-bit sRGB image as a texture (row 0 of the image at texture row 0: ImGui's uv (0, 0) is the
// image's top-left corner).
class ImageTexture {
 public:
  ImageTexture() = default;
  ~ImageTexture();
  ImageTexture(const ImageTexture&) = delete;
  ImageTexture& operator=(const ImageTexture&) = delete;
  void upload(const render::DisplayImage& img);
  unsigned texture() const { return tex_; }
  int width() const { return w_; }
  int height() const { return h_; }

 private:
  unsigned tex_ = 0;
  int w_ = 0, h_ = 0;
};

// The default framebuffer's back buffer (what was just drawn) as an image, row 0 at the top.
render::DisplayImage read_window(int width, int height);

}  // namespace aniso::viewgl
