// aniso/image/image.h: the two image types every image reader, writer and drawer works on: Image
// (linear RGB radiance, what the renderer produces and the EXR / PFM / HDR files hold) and
// DisplayImage (8-bit sRGB, what PNGs hold and the gallery and plots are drawn on).
//
// The library aniso::image (include/aniso/image, src/image): these types, the image files
// (image_io.h), tone mapping (tonemap.h) and drawing with the label font (canvas.h). The renderer,
// the fitter's plots and the exports' previews all use it; it needs neither Embree nor Ceres. The
// names are in aniso::render (render::Image, render::write_image, ...), the renderer's namespace,
// whose scenes, integrator and gallery use them unqualified.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "aniso/core/math.h"

namespace aniso::render {

// Linear RGB (float, Rec.709 primaries, docs/conventions.md), row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, row-major, row 0 = top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
  RGB at(int x, int y) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return RGB(rgb[i], rgb[i + 1], rgb[i + 2]);
  }
  void set(int x, int y, const RGB& c) {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    rgb[i] = c.x, rgb[i + 1] = c.y, rgb[i + 2] = c.z;
  }
};

// 8-bit sRGB-encoded display image (what PNGs hold), row 0 at the top.
struct DisplayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3

  DisplayImage() = default;
  DisplayImage(int w, int h, uint8_t fill = 0) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, fill) {}
};

}  // namespace aniso::render
