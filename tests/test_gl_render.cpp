// tests/test_gl_render.cpp: the GL backend of the renderer (src/gl/scene_raster.h) against the CPU
// path tracer's direct lighting (max_depth 1) of the same scene, pixel by pixel: every model with
// a GLSL twin, the tangent sources (angle, procedural fields, a tangent map, mesh tangents, OBJ UV
// tangents), point and directional lights, shadows of analytic shapes; and the rasteriser's API
// (cheap material / camera changes, the program cache). On llvmpipe in CI; without GL the tests
// skip with the reason.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gl/scene_raster.h"
#include "glsl_util.h"
#include "render/geometry.h"
#include "render/integrator.h"
#include "test_util.h"

namespace aniso::test {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// The tolerance of GL against CPU (docs/scenes.md, "GL backend"): a pixel agrees when
//   |gl - cpu| <= kRelTol * cpu + kAbsTol * peak   (per channel; peak = the CPU image's largest value)
// Compared are the interior pixels: those whose 5 x 5 grid of camera rays over the pixel's square
// (corners included) all hit the same object (SceneGeometry, on the CPU), so that neither image's
// estimate of a silhouette's coverage enters. What is left of the difference is the CPU's noise
// (its sub-pixel positions are 256 Sobol' points; the GL backend's are a regular 8 x 8 grid: both
// integrate the radiance over the pixel's square) and float rounding in the GLSL twin.
constexpr double kRelTol = 0.02;
constexpr double kAbsTol = 0.002;
constexpr int kSize = 64;
constexpr int kCpuSpp = 256;
constexpr int kGlSubsamples = 8;

json camera_json() { return {{"position", {0.0, 0.6, 3.4}}, {"look_at", {0.0, 0.0, 0.0}}, {"fov_deg", 38.0}}; }

json scene_json(const json& objects, const json& lights) {
  return {{"camera", camera_json()},
          {"film", {{"width", kSize}, {"height", kSize}, {"spp", kCpuSpp}}},
          {"integrator", {{"max_depth", 1}}},
          {"lights", lights},
          {"objects", objects}};
}

json point_light() { return json::array({{{"type", "point"}, {"position", {2.0, 2.5, 3.0}}, {"intensity", 14.0}}}); }

// 5 x 5 rays over each pixel's square: true where all of them hit the same object.
std::vector<bool> interior_mask(const render::Scene& scene) {
  render::SceneGeometry geo(scene);
  render::PathTracer tracer(scene, geo);
  const int W = scene.film.width, H = scene.film.height;
  std::vector<bool> mask(size_t(W) * size_t(H), false);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      int first = -2;
      bool same = true;
      for (int j = 0; j <= 4 && same; ++j)
        for (int i = 0; i <= 4 && same; ++i) {
          render::SurfaceHit hit;
          const render::Ray ray = tracer.camera_ray(float(x) + float(i) / 4.0f, float(y) + float(j) / 4.0f);
          const int id = geo.intersect(ray, INFINITY, &hit) ? hit.object : -1;
          if (first == -2) first = id;
          same = id == first;
        }
      mask[size_t(y) * size_t(W) + size_t(x)] = same && first >= 0;
    }
  return mask;
}

struct Comparison {
  render::Image cpu, gl;
  int interior = 0, bad = 0;
  double worst_excess = 0.0;  // largest |gl - cpu| / (tolerance) among interior pixels
  std::string worst;          // where and what
  double peak = 0.0, lit = 0.0;  // the CPU image's peak; the fraction of interior pixels above 1% of it
};

Comparison compare_scene(const json& doc, const std::string& name) {
  const render::Scene scene = render::parse_scene(doc, name, ANISO_SOURCE_DIR "/examples");
  Comparison c;
  render::RenderOptions ro;
  ro.spp = kCpuSpp;
  c.cpu = render::render(scene, ro);
  gl::SceneRasterizer raster(scene, gl::RasterSettings{kGlSubsamples});
  raster.render();
  c.gl = raster.read_back();
  const std::vector<bool> mask = interior_mask(scene);
  for (float v : c.cpu.rgb) c.peak = std::max(c.peak, double(v));
  int lit = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      if (!mask[size_t(y) * kSize + size_t(x)]) continue;
      ++c.interior;
      const RGB a = c.cpu.at(x, y), b = c.gl.at(x, y);
      lit += max_component(a) > 0.01 * c.peak ? 1 : 0;
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        const double tol = kRelTol * a[k] + kAbsTol * c.peak;
        const double excess = std::abs(double(b[k]) - double(a[k])) / tol;
        ok = ok && std::isfinite(b[k]) && excess <= 1.0;
        if (excess > c.worst_excess) {
          c.worst_excess = excess;
          c.worst = fmt::format("pixel ({}, {}) channel {}: cpu {:.5g}, gl {:.5g}", x, y, k, a[k], b[k]);
        }
      }
      c.bad += ok ? 0 : 1;
    }
  c.lit = c.interior ? double(lit) / c.interior : 0.0;
  return c;
}

void expect_parity(const json& doc, const std::string& name) {
  const Comparison c = compare_scene(doc, name);
  // ANISO_GL_TEST_DUMP=dir: both images side by side (CPU left, GL right) as dir/<name>.png.
  if (const char* dump = std::getenv("ANISO_GL_TEST_DUMP")) {
    render::Image both(2 * kSize, kSize);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        both.set(x, y, c.cpu.at(x, y));
        both.set(kSize + x, y, c.gl.at(x, y));
      }
    render::write_image(fmt::format("{}/{}.png", dump, name), both);
  }
  fmt::print("{}: {} interior pixels, {:.0f}% lit, worst {:.3f} x the tolerance ({})\n", name, c.interior, 100.0 * c.lit,
             c.worst_excess, c.worst);
  EXPECT_GT(c.interior, kSize * kSize / 8) << name << ": the object covers too little of the image to compare";
  // A highlight alone (a metal, a Lafortune lobe without diffuse) lights a few percent of the sphere.
  EXPECT_GT(c.lit, 0.04) << name << ": too few lit pixels to compare";
  EXPECT_EQ(c.bad, 0) << name << ": " << c.bad << " of " << c.interior << " interior pixels differ beyond the tolerance; worst "
                      << c.worst << " (" << c.worst_excess << " x the tolerance)";
}

// --- every model with a GLSL twin ----------------------------------------------------------------

class GlRenderModels : public ::testing::TestWithParam<NamedMaterial> {};

TEST_P(GlRenderModels, PointLitSphereMatchesCpuDirectLighting) {
  ANISO_REQUIRE_GL();
  const json objects = json::array(
      {{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", GetParam().json}, {"tangent", {{"angle_deg", 30}}}}});
  expect_parity(scene_json(objects, point_light()), GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(All, GlRenderModels, ::testing::ValuesIn(all_model_materials()), material_name);

}  // namespace
}  // namespace aniso::test
