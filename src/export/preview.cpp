// export/preview.cpp: the check in image space (image_check) and --preview, the source and the
// target model side by side in the same scene, shaded by aniso.
#include "aniso/export/export.h"

#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"

namespace aniso::exporter {

namespace {

using Brdf = std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)>;

// The directional albedo rho(wo) = integral f cos_i dw_i, tabulated over the viewing direction in
// the surface frame and interpolated bilinearly: the uniform environment's radiance is
// kCheckEnvironment rho(wo) (a uniform environment of radiance L reflects L rho(wo)). The table:
// theta_o at 16 nodes from 0 to 89 degrees, phi_o at 16 over the circle (periodic); each entry a
// quadrature over the half vector (wi = reflect(wo, h), dw_i = 4 (wo.h) dw_h), theta_h on a quadratic
// grid dense near the normal, where sharp lobes are (48 x 24 cells).
class AlbedoTable {
 public:
  static constexpr int kTheta = 16, kPhi = 16;
  static constexpr double kThetaMax = 89.0 * kPi<double> / 180.0;
  explicit AlbedoTable(const Brdf& f) {
    constexpr int nt = 48, np = 24;
    for (int i = 0; i < kTheta; ++i)
      for (int j = 0; j < kPhi; ++j) {
        const double to = kThetaMax * i / (kTheta - 1), po = 2.0 * kPi<double> * j / kPhi;
        const Vec3d wo(std::sin(to) * std::cos(po), std::sin(to) * std::sin(po), std::cos(to));
        glm::dvec3 sum(0.0);
        for (int a = 0; a < nt; ++a) {
          const double u = (a + 0.5) / nt, th = u * u * kPi<double> / 2.0, dth = 2.0 * u / nt * kPi<double> / 2.0;
          for (int b = 0; b < np; ++b) {
            const double ph = (b + 0.5) * 2.0 * kPi<double> / np;
            const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
            const double oh = glm::dot(wo, h);
            if (!(oh > 0.0)) continue;
            const Vec3d wi = 2.0 * oh * h - wo;
            if (!(wi.z > 0.0)) continue;
            sum += f(wi, wo) * (wi.z * 4.0 * oh * std::sin(th) * dth * (2.0 * kPi<double> / np));
          }
        }
        table_[i * kPhi + j] = sum;
      }
  }
  glm::dvec3 operator()(const Vec3d& wo) const {
    const double to = std::acos(std::clamp(wo.z, -1.0, 1.0));
    double po = std::atan2(wo.y, wo.x);
    if (po < 0.0) po += 2.0 * kPi<double>;
    const double x = std::clamp(to / kThetaMax * (kTheta - 1), 0.0, double(kTheta - 1)), y = po / (2.0 * kPi<double>)*kPhi;
    const int i0 = std::min(int(x), kTheta - 2), j0 = int(y) % kPhi, j1 = (j0 + 1) % kPhi;
    const double fx = x - i0, fy = y - std::floor(y);
    const auto at = [&](int i, int j) { return table_[i * kPhi + j]; };
    return (1 - fx) * ((1 - fy) * at(i0, j0) + fy * at(i0, j1)) + fx * ((1 - fy) * at(i0 + 1, j0) + fy * at(i0 + 1, j1));
  }

 private:
  std::array<glm::dvec3, kTheta * kPhi> table_{};
};

const glm::dvec3 kSun = glm::normalize(glm::dvec3(-0.5, 0.6, 1.0));

// One sphere of the standard scene into img at column x0; returns {mean, lit mean} of its luminance
// and, in rgb, its mean RGB.
std::pair<double, double> shade(const Brdf& f, int size, int x0, render::Image* img, glm::dvec3& rgb) {
  const AlbedoTable rho(f);
  double sum = 0.0, lit = 0.0;
  rgb = glm::dvec3(0.0);
  size_t count = 0, n_lit = 0;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      const double x = (px + 0.5) / size * 2.0 - 1.0, y = 1.0 - (py + 0.5) / size * 2.0, r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      const glm::dvec3 nrm(x, y, std::sqrt(1.0 - r2));
      const glm::dvec3 t = glm::normalize(glm::dvec3(nrm.z, 0.0, -nrm.x)), b = glm::cross(nrm, t);
      const auto local = [&](const glm::dvec3& v) { return Vec3d(glm::dot(v, t), glm::dot(v, b), glm::dot(v, nrm)); };
      const Vec3d wo = local(glm::dvec3(0.0, 0.0, 1.0)), wi = local(kSun);
      glm::dvec3 c = kCheckEnvironment * rho(wo);
      if (wi.z > 0.0 && wo.z > 0.0) c += f(wi, wo) * wi.z * kCheckSunIrradiance;
      const double lum = (c.x + c.y + c.z) / 3.0;
      sum += lum, rgb += c, ++count;
      if (glm::dot(nrm, kSun) >= 0.5) lit += lum, ++n_lit;
      if (img) img->set(x0 + px, py, RGB(float(c.x), float(c.y), float(c.z)));
    }
  if (count) rgb /= double(count);
  return {count ? sum / double(count) : 0.0, n_lit ? lit / double(n_lit) : 0.0};
}

glm::dvec3 chromaticity(const glm::dvec3& c) {
  const double s = c.x + c.y + c.z;
  return s > 0.0 ? c / s : glm::dvec3(1.0 / 3.0);
}

double relative(double target, double source) {
  return source > 0.0 ? std::abs(target / source - 1.0) : (target > 0.0 ? INFINITY : 0.0);
}

}  // namespace

ImageCheck image_check(const MaterialD& source, const TargetBrdf& target, int size, render::Image* image) {
  ImageCheck c;
  c.size = size;
  const Brdf fs = [&](const Vec3d& wi, const Vec3d& wo) {
    const RGBT<double> v = source.f(wi, wo);
    return glm::dvec3(v.x, v.y, v.z);
  };
  const Brdf ft = [&](const Vec3d& wi, const Vec3d& wo) { return target.f(wi, wo); };
  std::tie(c.mean_source, c.lit_source) = shade(fs, size, 0, image, c.rgb_source);
  std::tie(c.mean_target, c.lit_target) = shade(ft, size, size, image, c.rgb_target);
  c.mean_difference = relative(c.mean_target, c.mean_source);
  c.lit_difference = relative(c.lit_target, c.lit_source);
  const glm::dvec3 d = glm::abs(chromaticity(c.rgb_target) - chromaticity(c.rgb_source));
  c.chromaticity_difference = std::max({d.x, d.y, d.z});
  return c;
}

void write_preview(const std::string& path, const MaterialD& source, const TargetBrdf& target, const std::string& left,
                   const std::string& right, int size) {
  const int label = size / 8, w = 2 * size, h = size + label;
  render::Image img(w, size);
  image_check(source, target, size, &img);
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
