// export/preview.cpp: --preview, the source and the target model side by side, shaded by aniso.
#include "aniso/export/export.h"

#include <cmath>

#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"

namespace aniso::exporter {

void write_preview(const std::string& path, const MaterialD& source, const TargetBrdf& target, const std::string& left,
                   const std::string& right, int size) {
  const int label = size / 8, w = 2 * size, h = size + label;
  render::Image img(w, size);
  const glm::dvec3 lights[2] = {glm::normalize(glm::dvec3(-0.5, 0.6, 1.0)), glm::normalize(glm::dvec3(0.7, -0.3, 0.8))};
  const double power[2] = {2.5, 1.0};
  for (int side = 0; side < 2; ++side)
    for (int py = 0; py < size; ++py)
      for (int px = 0; px < size; ++px) {
        const double x = (px + 0.5) / size * 2.0 - 1.0, y = 1.0 - (py + 0.5) / size * 2.0, r2 = x * x + y * y;
        if (r2 >= 1.0) continue;
        const glm::dvec3 n(x, y, std::sqrt(1.0 - r2));
        const glm::dvec3 t = glm::normalize(glm::dvec3(n.z, 0.0, -n.x)), b = glm::cross(n, t);
        const auto local = [&](const glm::dvec3& v) { return Vec3d(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); };
        const Vec3d wo = local(glm::dvec3(0.0, 0.0, 1.0));
        glm::dvec3 c(0.0);
        for (int l = 0; l < 2; ++l) {
          const Vec3d wi = local(lights[l]);
          if (!(wi.z > 0.0) || !(wo.z > 0.0)) continue;
          glm::dvec3 f;
          if (side == 0) {
            const RGBT<double> s = source.f(wi, wo);
            f = glm::dvec3(s.x, s.y, s.z);
          } else {
            f = target.f(wi, wo);
          }
          c += f * wi.z * power[l];
        }
        img.set(side * size + px, py, RGB(float(c.x), float(c.y), float(c.z)));
      }
  if (!path.ends_with(".png")) {
    // .pfm / .exr: the linear radiance of both spheres, without labels (the Blender check of
    // tests/blender_export_render.py compares it with Cycles' rendering, pixel by pixel).
    render::write_image(path, img);
    return;
  }
  const render::DisplayImage shaded = render::tonemap(img, {});
  render::DisplayImage out(w, h, 255);
  render::blit(out, shaded, 0, 0);
  const float ph = float(label) * 0.55f;
  render::draw_text(out, 6, size + label / 5, left, ph, {0, 0, 0});
  render::draw_text(out, size + 6, size + label / 5, right, ph, {0, 0, 0});
  render::write_png(path, out);
}

}  // namespace aniso::exporter
