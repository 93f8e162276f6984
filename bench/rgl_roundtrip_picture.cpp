// bench/rgl_roundtrip_picture.cpp: docs/images/rgl_roundtrip.png (docs/rgl.md, "Picture"). For
// brushed-gold and matte-steel: the material's f, the f of its default spectral .bsdf as aniso's
// reader gives it (RglT::f, pbrt-v4's MeasuredBxDF::f, reduced to RGB), and 4 x |difference|, on a
// sphere lit by two distant lights, direct lighting only (no noise: f is seen as it is).
//
//   aniso_rgl_roundtrip_picture OUT.png
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "aniso/data/metals.h"
#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/rgl/tensor.h"

namespace aniso {
namespace {

using render::DisplayImage;
using render::Image;

constexpr int kSize = 200, kGap = 8, kLabel = 28;

// Radiance of the unit sphere seen along -z (orthographic): the tangent follows the horizontal
// circles (x axis of the shading frame = up x n), two distant lights of irradiance 3 (front-left)
// and 4 (behind, right) at normal incidence.
template <typename F> Image shade(const F& f) {
  const Vec3d up(0, 1, 0), view(0, 0, 1);
  const Vec3d lights[2] = {glm::normalize(Vec3d(-0.6, 0.35, 1.0)), glm::normalize(Vec3d(1.0, 0.15, -0.4))};
  const double power[2] = {3.0, 4.0};
  Image img(kSize, kSize);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const double px = (x + 0.5) / kSize * 2.0 - 1.0, py = 1.0 - (y + 0.5) / kSize * 2.0, r2 = px * px + py * py;
      if (r2 >= 1.0) continue;
      const Vec3d n(px, py, std::sqrt(1.0 - r2));
      const Vec3d t = glm::normalize(glm::cross(up, n)), b = glm::cross(n, t);
      auto local = [&](const Vec3d& w) { return Vec3d(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)); };
      const Vec3d wo = local(view);
      glm::dvec3 c(0.0);
      for (int l = 0; l < 2; ++l) {
        const Vec3d wi = local(lights[l]);
        if (wi.z > 0.0 && wo.z > 0.0) c += f(wi, wo) * wi.z * power[l];
      }
      img.set(x, y, RGB(float(c.x), float(c.y), float(c.z)));
    }
  return img;
}

int run(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: aniso_rgl_roundtrip_picture OUT.png\n");
    return 2;
  }
  DisplayImage canvas(3 * kSize + 4 * kGap, 2 * (kSize + kLabel), 255);
  const char* names[2] = {"brushed-gold", "matte-steel"};
  for (int row = 0; row < 2; ++row) {
    const MaterialDesc desc = load_material(names[row]);
    const MaterialD m = build_material<double>(desc);
    const MetalData* metal = desc.model == "metal" && desc.params.has("metal") ? find_metal(desc.params.text("metal")) : nullptr;
    rgl::BrdfSource src = rgl::brdf_source(m, metal);
    src.description = names[row];
    rgl::ExportOptions opt;  // the defaults: a spectral file, as `aniso export-rgl` writes
    const auto data = rgl::rgl_from_tensor(
        rgl::parse_tensor(rgl::serialize_tensor(rgl::export_rgl(src, opt)), std::string(names[row]) + ".bsdf"));
    const RglT<double> file = rgl::rgl_kernel<double>(*data);
    const Image a = shade([&](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(wi, wo)); });
    const Image b = shade([&](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(file.f(wi, wo)); });
    Image d(kSize, kSize);
    for (size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] = 4.0f * std::abs(a.rgb[i] - b.rgb[i]);
    const Image* panels[3] = {&a, &b, &d};
    const std::string labels[3] = {std::string(names[row]) + ": material", std::string(names[row]) + ": its .bsdf (pbrt-v4 f)",
                                   std::string(names[row]) + ": 4 x |difference|"};
    for (int col = 0; col < 3; ++col) {
      const int x0 = kGap + col * (kSize + kGap), y0 = row * (kSize + kLabel);
      render::draw_text(canvas, x0, y0 + 6, labels[col], 13.0f, glm::u8vec3(0));
      render::blit(canvas, render::tonemap(*panels[col], {}), x0, y0 + kLabel);
    }
  }
  render::write_png(argv[1], canvas);
  return 0;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) { return aniso::run(argc, argv); }
