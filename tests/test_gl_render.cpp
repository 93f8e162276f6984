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
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include "aniso/image/image_io.h"
#include "aniso/measured/merl.h"
#include "aniso/render/geometry.h"
#include "aniso/render/integrator.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"
#include "cli_fixture.h"
#include "gl/scene_raster.h"
#include "glsl_util.h"
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

// 5 x 5 camera rays over each pixel's square (corners included): true where all of them hit the
// same object at nearly the same distance (within 5 %: no silhouette of an object against itself)
// and see the same lights unshadowed (no shadow edge in the pixel).
std::vector<bool> interior_mask(const render::Scene& scene) {
  render::SceneGeometry geo(scene);
  render::PathTracer tracer(scene, geo);
  const int W = scene.film.width, H = scene.film.height;
  std::vector<bool> mask(size_t(W) * size_t(H), false);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      int first = -2;
      uint64_t first_shadows = 0;
      float t_min = INFINITY, t_max = 0.0f;
      bool same = true;
      for (int j = 0; j <= 4 && same; ++j)
        for (int i = 0; i <= 4 && same; ++i) {
          render::SurfaceHit hit;
          const render::Ray ray = tracer.camera_ray(float(x) + float(i) / 4.0f, float(y) + float(j) / 4.0f);
          const int id = geo.intersect(ray, INFINITY, &hit) ? hit.object : -1;
          uint64_t shadows = 0;
          if (id >= 0) {
            t_min = std::min(t_min, hit.t), t_max = std::max(t_max, hit.t);
            for (size_t l = 0; l < scene.lights.size() && l < 64; ++l) {
              const render::Light& light = scene.lights[l];
              const Vec3 to = light.kind == render::LightKind::Directional ? light.to_light : light.position - hit.p;
              const float dist = light.kind == render::LightKind::Directional ? INFINITY : glm::length(to) * (1.0f - 1e-3f);
              const Vec3 d = glm::normalize(to);
              if (geo.occluded(render::Ray{render::SceneGeometry::offset_origin(hit.p, hit.ng, d), d}, dist))
                shadows |= 1ull << l;
            }
          }
          if (first == -2) first = id, first_shadows = shadows;
          same = id == first && shadows == first_shadows;
        }
      mask[size_t(y) * size_t(W) + size_t(x)] = same && first >= 0 && t_max - t_min <= 0.05f * t_min;
    }
  return mask;
}

struct Comparison {
  render::Image cpu, gl;
  int interior = 0, bad = 0;
  double worst_excess = 0.0;     // largest |gl - cpu| / (tolerance) among interior pixels
  std::string worst;             // where and what
  double peak = 0.0, lit = 0.0;  // the CPU image's peak; the fraction of interior pixels above 1% of it
  std::vector<bool> mask;        // the interior pixels
};

Comparison compare_scene(const json& doc, const std::string& name, int cpu_spp = kCpuSpp, int gl_subsamples = kGlSubsamples) {
  const render::Scene scene = render::parse_scene(doc, name, ANISO_SOURCE_DIR "/examples");
  Comparison c;
  render::RenderOptions ro;
  ro.spp = cpu_spp;
  c.cpu = render::render(scene, ro);
  gl::SceneRasterizer raster(scene, gl::RasterSettings{gl_subsamples});
  raster.render();
  c.gl = raster.read_back();
  c.mask = interior_mask(scene);
  const std::vector<bool>& mask = c.mask;
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

void expect_parity(const json& doc, const std::string& name, int cpu_spp = kCpuSpp, int gl_subsamples = kGlSubsamples) {
  const Comparison c = compare_scene(doc, name, cpu_spp, gl_subsamples);
  // ANISO_GL_TEST_DUMP=dir: both images side by side (CPU left, GL right) as dir/<name>.png.
  if (const char* dump = std::getenv("ANISO_GL_TEST_DUMP")) {
    // CPU, GL, and 10 x |GL - CPU|, each scaled up 3 x (nearest).
    constexpr int s = 3;
    render::Image both(3 * s * kSize, s * kSize);
    for (int y = 0; y < s * kSize; ++y)
      for (int x = 0; x < s * kSize; ++x) {
        const RGB a = c.cpu.at(x / s, y / s), b = c.gl.at(x / s, y / s);
        both.set(x, y, a);
        both.set(s * kSize + x, y, b);
        both.set(2 * s * kSize + x, y, 10.0f * glm::abs(b - a));
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
  const json objects = json::array({{{"shape", "sphere"},
                                     {"center", {0, 0, 0}},
                                     {"radius", 1.0},
                                     {"material", GetParam().json},
                                     {"tangent", {{"angle_deg", 30}}}}});
  expect_parity(scene_json(objects, point_light()), GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(All, GlRenderModels, ::testing::ValuesIn(all_model_materials()), material_name);

// --- tangent sources, shapes, lights ----------------------------------------------------------------

const json kBrushed = {{"model", "ward"}, {"kd", 0.08}, {"ks", 0.5}, {"alpha_x", 0.05}, {"alpha_y", 0.35}};

json with_material(json object, const json& material = kBrushed) {
  object["material"] = material;
  return object;
}

TEST(GlRender, AngleOnADisc) {
  ANISO_REQUIRE_GL();
  const json disc = with_material(
      {{"shape", "disc"}, {"center", {0, 0, 0}}, {"normal", {0, 1, 0.8}}, {"radius", 1.3}, {"tangent", {{"angle_deg", -50}}}});
  expect_parity(scene_json(json::array({disc}), point_light()), "angle_disc");
}

TEST(GlRender, ConcentricFieldOnADisc) {
  ANISO_REQUIRE_GL();
  const json disc = with_material({{"shape", "disc"},
                                   {"center", {0, 0, 0}},
                                   {"normal", {0, 1, 0.8}},
                                   {"radius", 1.3},
                                   {"tangent", {{"field", "concentric"}}}});
  expect_parity(scene_json(json::array({disc}), point_light()), "concentric_disc");
}

TEST(GlRender, SwirlFieldOnADisc) {
  ANISO_REQUIRE_GL();
  const json disc = with_material({{"shape", "disc"},
                                   {"center", {0, 0, 0}},
                                   {"normal", {0, 1, 0.8}},
                                   {"radius", 1.3},
                                   {"tangent", {{"field", "swirl"}, {"swirl_deg", 30}, {"angle_deg", 10}}}});
  expect_parity(scene_json(json::array({disc}), point_light()), "swirl_disc");
}

TEST(GlRender, RadialFieldOnARectangle) {
  ANISO_REQUIRE_GL();
  const json rect = with_material({{"shape", "rectangle"},
                                   {"center", {0, 0, 0}},
                                   {"normal", {0, 1, 0.7}},
                                   {"u", {1, 0, 0.2}},
                                   {"size", {2.4, 1.8}},
                                   {"tangent", {{"field", "radial"}, {"center", {0.3, 0.1, 0}}}}});
  expect_parity(scene_json(json::array({rect}), point_light()), "radial_rectangle");
}

TEST(GlRender, ProjectedAndNoiseFieldsOnSpheres) {
  ANISO_REQUIRE_GL();
  const json a = with_material({{"shape", "sphere"},
                                {"center", {-0.6, 0, 0}},
                                {"radius", 0.55},
                                {"tangent", {{"field", "projected"}, {"direction", {1, 1, 0}}}}});
  const json b = with_material({{"shape", "sphere"},
                                {"center", {0.6, 0, 0}},
                                {"radius", 0.55},
                                {"tangent", {{"field", "noise"}, {"scale", 3}, {"strength", 0.6}}}});
  expect_parity(scene_json(json::array({a, b}), point_light()), "projected_noise_spheres");
}

TEST(GlRender, TangentMapOnARectangle) {
  ANISO_REQUIRE_GL();
  // examples/assets/checker_tangents.png: patches brushed at 0 and 90 degrees with 45-degree seams.
  // The seams run obliquely across the image (u turned by 25 degrees): a seam along an image axis
  // is where the GL backend's grid of sub-samples is weakest (scene_raster.cpp).
  const json map = {{"map", "assets/checker_tangents.png"}, {"encoding", "angle"}};
  const json rect = with_material({{"shape", "rectangle"},
                                   {"center", {0, 0, 0}},
                                   {"normal", {0, 1, 0.9}},
                                   {"u", {1, 0, 0.47}},
                                   {"size", {2.2, 2.2}},
                                   {"tangent", map}});
  // Its 45-degree seams are lines a third of a pixel wide, bright where the highlight crosses them:
  // both sides need more samples per pixel to agree there (at 256 spp and k = 8 the CPU's noise and
  // the grid's placement of the lines each reached 1.5 x the tolerance on a few seam pixels; at
  // 1024 spp and k = 16 the worst is 0.56 x, at 2048 and 16 0.36 x).
  expect_parity(scene_json(json::array({rect}), point_light()), "tangent_map_rectangle", 1024, 16);
}

TEST(GlRender, SmoothTangentMapsOnASphereBothEncodings) {
  ANISO_REQUIRE_GL();
  // A smooth map written here (the checker's seams are finer than a pixel on a sphere this size):
  // angle v = x / W + 0.5 y / H (mod 1: 0 and 1 are the same orientation, so the u seam is smooth),
  // read through the sphere's (u, v) with wrap-around; and an "xy" map of the same directions.
  const fs::path dir = fs::path(::testing::TempDir()) / fmt::format("aniso_gl_map_{}", getpid());
  fs::create_directories(dir);
  constexpr int W = 24, H = 12;
  render::DisplayImage angle(W, H), xy(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double v = std::fmod(double(x) / W + 0.5 * double(y) / H, 1.0);
      const size_t i = 3 * (size_t(y) * W + size_t(x));
      angle.rgb[i] = angle.rgb[i + 1] = angle.rgb[i + 2] = uint8_t(std::lround(255.0 * v));
      xy.rgb[i] = uint8_t(std::lround(255.0 * (0.5 + 0.5 * std::cos(M_PI * v))));
      xy.rgb[i + 1] = uint8_t(std::lround(255.0 * (0.5 + 0.5 * std::sin(M_PI * v))));
      xy.rgb[i + 2] = 0;
    }
  render::write_png((dir / "angle.png").string(), angle);
  render::write_png((dir / "xy.png").string(), xy);
  const json a = with_material({{"shape", "sphere"},
                                {"center", {-0.55, 0, 0}},
                                {"radius", 0.6},
                                {"tangent", {{"map", (dir / "angle.png").string()}, {"encoding", "angle"}}}});
  const json b = with_material({{"shape", "sphere"},
                                {"center", {0.65, 0, 0}},
                                {"radius", 0.6},
                                {"tangent", {{"map", (dir / "xy.png").string()}, {"encoding", "xy"}, {"angle_deg", 20}}}});
  expect_parity(scene_json(json::array({a, b}), point_light()), "tangent_map_spheres");
  fs::remove_all(dir);
}

TEST(GlRender, TorusMeshWithItsTangents) {
  ANISO_REQUIRE_GL();
  const json torus = with_material(
      {{"shape", "torus"}, {"center", {0, 0, 0}}, {"major_radius", 1.0}, {"minor_radius", 0.4}, {"rotate_deg", {50, 0, 0}}});
  expect_parity(scene_json(json::array({torus}), point_light()), "torus");
}

TEST(GlRender, ObjMeshWithUvTangentsAndWithTriangleTangents) {
  ANISO_REQUIRE_GL();
  // examples/assets/vase.obj has normals and UVs: {"field": "uv"} gives smooth per-vertex tangents
  // (computed by the scene reader); without it each triangle's dp/du from its UVs.
  const json uv = with_material({{"shape", "mesh"},
                                 {"file", "assets/vase.obj"},
                                 {"translate", {-0.6, -0.9, 0}},
                                 {"scale", 0.9},
                                 {"tangent", {{"field", "uv"}}}});
  const json tri = with_material({{"shape", "mesh"}, {"file", "assets/vase.obj"}, {"translate", {0.6, -0.9, 0}}, {"scale", 0.9}});
  expect_parity(scene_json(json::array({uv, tri}), point_light()), "vase_obj");
}

TEST(GlRender, DirectionalLight) {
  ANISO_REQUIRE_GL();
  const json sphere =
      with_material({{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"tangent", {{"angle_deg", 70}}}},
                    {{"model", "ggx"}, {"kd", 0.15}, {"f0", {0.9, 0.7, 0.4}}, {"alpha_x", 0.08}, {"alpha_y", 0.3}});
  const json lights = json::array({{{"type", "directional"}, {"to_light", {-0.5, 0.8, 0.6}}, {"irradiance", 2.5}}});
  expect_parity(scene_json(json::array({sphere}), lights), "directional");
}

TEST(GlRender, ShadowsOfAnalyticShapesAndBothLightKinds) {
  ANISO_REQUIRE_GL();
  const json floor = with_material(
      {{"shape", "rectangle"}, {"center", {0, -0.6, 0}}, {"normal", {0, 1, 0}}, {"u", {1, 0, 0}}, {"size", {3.0, 3.0}}},
      {{"model", "lambert"}, {"kd", 0.6}});
  const json ball = with_material({{"shape", "sphere"}, {"center", {-0.3, 0, 0}}, {"radius", 0.5}});
  const json card = with_material({{"shape", "disc"}, {"center", {0.7, 0.1, 0.4}}, {"normal", {0.3, 1, 0.2}}, {"radius", 0.3}});
  const json lights = json::array({{{"type", "point"}, {"position", {0.5, 2.5, 1.0}}, {"intensity", 8.0}},
                                   {{"type", "directional"}, {"to_light", {-0.6, 0.7, 0.2}}, {"irradiance", 1.0}}});
  const Comparison c = compare_scene(scene_json(json::array({floor, ball, card}), lights), "shadows");
  EXPECT_EQ(c.bad, 0) << c.worst;
  // The shadows are there: the floor under the ball (pixel column of the ball, below it) is darker
  // than the open floor, in both images.
  EXPECT_GT(c.interior, kSize * kSize / 3);
}

TEST(GlRender, MeshShadowsFromShadowMaps) {
  ANISO_REQUIRE_GL();
  // A torus over a floor, lit by a point and a directional light: its shadows on the floor (and on
  // itself) come from the shadow maps; the interior mask leaves out the pixels a shadow edge
  // crosses (the CPU's shadow rays decide that).
  const json floor = with_material(
      {{"shape", "rectangle"}, {"center", {0, -0.7, 0}}, {"normal", {0, 1, 0}}, {"u", {1, 0, 0}}, {"size", {3.2, 3.2}}},
      {{"model", "lambert"}, {"kd", 0.6}});
  const json torus = with_material(
      {{"shape", "torus"}, {"center", {0, -0.1, 0}}, {"major_radius", 0.7}, {"minor_radius", 0.25}, {"rotate_deg", {25, 0, 0}}});
  const json lights = json::array({{{"type", "point"}, {"position", {0.6, 2.2, 0.8}}, {"intensity", 7.0}},
                                   {{"type", "directional"}, {"to_light", {-0.5, 0.8, 0.1}}, {"irradiance", 0.8}}});
  const json doc = scene_json(json::array({floor, torus}), lights);
  const Comparison c = compare_scene(doc, "mesh_shadows");
  EXPECT_EQ(c.bad, 0) << c.bad << " of " << c.interior << "; worst " << c.worst;
  EXPECT_GT(c.interior, kSize * kSize / 3);
  // The test exercises the shadows: interior pixels the CPU finds lit by neither light (a Lambert
  // floor or the torus's own underside), where the GL image must then be black too.
  int dark = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (c.mask[size_t(y) * kSize + size_t(x)] && max_component(c.cpu.at(x, y)) == 0.0f) {
        ++dark;
        EXPECT_EQ(max_component(c.gl.at(x, y)), 0.0f) << x << ", " << y;
      }
  EXPECT_GT(dark, 20) << "too few pixels in full shadow to test the shadow maps";
  fmt::print("mesh_shadows: {} interior pixels, worst {:.3f} x the tolerance ({}), {} dark\n", c.interior, c.worst_excess,
             c.worst, dark);
}

TEST(GlRender, CameraInsideASphereAndOffAxisMeshes) {
  ANISO_REQUIRE_GL();
  // Inside a big sphere the proxy cube's far faces find the hits (no culling); a small sphere and a
  // torus sit inside too, with the light.
  json doc = scene_json(json::array({with_material({{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 6.0}},
                                                   {{"model", "lambert"}, {"kd", 0.5}}),
                                     with_material({{"shape", "sphere"}, {"center", {0.8, -0.2, -1.0}}, {"radius", 0.6}}),
                                     with_material({{"shape", "torus"},
                                                    {"center", {-0.9, 0.1, -0.5}},
                                                    {"major_radius", 0.5},
                                                    {"minor_radius", 0.2},
                                                    {"rotate_deg", {70, 20, 0}}})}),
                        json::array({{{"type", "point"}, {"position", {0.5, 1.5, 1.5}}, {"intensity", 10.0}}}));
  expect_parity(doc, "inside_sphere");
}

TEST(GlRender, ManyLightsTakeSeveralPasses) {
  ANISO_REQUIRE_GL();
  json lights = json::array();
  for (int i = 0; i < 40; ++i) {  // more than one pass holds (32)
    const double a = 2.0 * M_PI * i / 40.0;
    lights.push_back(
        {{"type", "point"}, {"position", {2.5 * std::cos(a), 1.5 + 0.02 * i, 2.5 * std::sin(a)}}, {"intensity", 0.6}});
  }
  json doc = scene_json(json::array({with_material({{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}})}), lights);
  doc["integrator"]["light_selection"] = "all";  // the CPU samples every light: no selection noise
  expect_parity(doc, "forty_lights", 64);        // a smooth, broadly lit sphere: 64 samples per pixel suffice
}

// The shaders are GLSL 3.30 core (what a GL 3.3 window context, the explorer's, accepts), for every
// test material: glslangValidator, independent of the driver the other tests run on.
TEST(GlRasterizer, ShadersAreGlsl330Core) {
  ANISO_REQUIRE_GLSLANG();
  std::set<std::string> seen;  // one check per shader: Ward's forms, for one, are uniforms of the same one
  for (const NamedMaterial& m : all_model_materials()) {
    const gl::RasterShaderSources src = gl::raster_shader_sources(parse_material(m.json, m.name));
    if (!seen.insert(src.fragment).second) continue;
    EXPECT_EQ(src.vertex.rfind("#version 330 core\n", 0), 0u);
    EXPECT_EQ(src.fragment.rfind("#version 330 core\n", 0), 0u);
    EXPECT_EQ(glslang_errors(src.vertex, "vert", "raster"), "") << m.name;
    EXPECT_EQ(glslang_errors(src.fragment, "frag", "raster"), "") << m.name;
  }
}

// --- the rasteriser's API: what the explorer changes per frame -----------------------------------

render::Scene sphere_scene(const json& material) {
  const json objects = json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", material}}});
  json doc = scene_json(objects, point_light());
  doc["film"] = {{"width", 32}, {"height", 24}, {"spp", 16}};
  return render::parse_scene(doc, "api test", "");
}

render::Image gl_image(const render::Scene& scene) {
  gl::SceneRasterizer r(scene, gl::RasterSettings{2});
  r.render();
  return r.read_back();
}

TEST(GlRasterizer, SameStructureMaterialChangesAreUniformsOnlyAndEqualAFreshBuild) {
  ANISO_REQUIRE_GL();
  const json a = {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.05}, {"alpha_y", 0.3}};
  const json b = {{"model", "ward"},        {"kd", 0.3}, {"ks", 0.2}, {"alpha_x", 0.2}, {"alpha_y", 0.1}, {"form", "angle"},
                  {"normalization", "duer"}};
  render::Scene scene = sphere_scene(a);
  gl::SceneRasterizer r(scene, gl::RasterSettings{2});
  EXPECT_EQ(r.program_count(), 1u);
  r.set_material(0, parse_material(b, "b"));
  EXPECT_EQ(r.program_count(), 1u) << "Ward's parameters, form and normalisation are uniforms: no new program";
  r.render();
  const render::Image changed = r.read_back();
  EXPECT_EQ(changed.rgb, gl_image(sphere_scene(b)).rgb) << "set_material gives the image of a rasteriser built with it";
  EXPECT_NE(changed.rgb, gl_image(scene).rgb);
  // Another structure (a Lafortune material with two lobes) compiles once, then comes from the cache.
  const json l2 = {{"model", "lafortune"},
                   {"lobes", json::array({{{"cxy", -1.0}, {"cz", 1.0}, {"n", 20.0}}, {{"cxy", 0.5}, {"cz", 0.5}, {"n", 3.0}}})}};
  r.set_material(0, parse_material(l2, "l2"));
  EXPECT_EQ(r.program_count(), 2u);
  r.set_material(0, parse_material(a, "a"));
  r.set_material(0, parse_material(l2, "l2"));
  EXPECT_EQ(r.program_count(), 2u);
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(sphere_scene(l2)).rgb);
}

TEST(GlRasterizer, CameraLightsTangentAndSizeChangesEqualAFreshBuild) {
  ANISO_REQUIRE_GL();
  const json m = {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.05}, {"alpha_y", 0.3}};
  const render::Scene base = sphere_scene(m);
  gl::SceneRasterizer r(base, gl::RasterSettings{2});
  render::Scene changed = base;
  changed.camera.position = Vec3(1.0f, 1.5f, 3.0f);
  changed.camera.fov_deg = 30.0f;
  changed.lights[0].position = Vec3(-2.0f, 1.0f, 2.0f);
  changed.lights.push_back(
      render::Light{render::LightKind::Directional, Vec3(0.0f), glm::normalize(Vec3(0, 1, 1)), RGB(0.5f), 0.0f});
  changed.objects[0].tangent.field.kind = TangentFieldKind::Projected;
  changed.objects[0].tangent.field.direction = Vec3(0, 1, 0);
  changed.objects[0].tangent.field.angle = 0.3f;
  changed.film.width = 40;
  changed.film.height = 20;
  r.set_camera(changed.camera);
  r.set_lights(changed.lights);
  r.set_tangent_field(0, changed.objects[0].tangent.field);
  r.set_size(40, 20);
  EXPECT_EQ(r.program_count(), 1u);
  r.render();
  const render::Image img = r.read_back();
  EXPECT_EQ(img.width, 40);
  EXPECT_EQ(img.height, 20);
  EXPECT_EQ(img.rgb, gl_image(changed).rgb);
}

TEST(GlRasterizer, MovingALightRedrawsTheMeshShadowMaps) {
  ANISO_REQUIRE_GL();
  json doc = scene_json(
      json::array(
          {with_material(
               {{"shape", "rectangle"}, {"center", {0, -0.7, 0}}, {"normal", {0, 1, 0}}, {"u", {1, 0, 0}}, {"size", {3.0, 3.0}}},
               {{"model", "lambert"}, {"kd", 0.6}}),
           with_material({{"shape", "torus"}, {"center", {0, -0.1, 0}}, {"major_radius", 0.7}, {"minor_radius", 0.25}})}),
      point_light());
  doc["film"] = {{"width", 32}, {"height", 24}, {"spp", 4}};
  const render::Scene a = render::parse_scene(doc, "a", "");
  render::Scene b = a, c = a;
  b.lights[0].position = Vec3(-1.5f, 2.0f, 0.5f);
  c.lights[0].power = RGB(3.0f);  // power alone: the same maps
  gl::SceneRasterizer r(a, gl::RasterSettings{2});
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(a).rgb);
  r.set_lights(b.lights);
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(b).rgb);
  EXPECT_NE(gl_image(b).rgb, gl_image(a).rgb);
  r.set_lights(c.lights);
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(c).rgb);
}

TEST(GlRasterizer, SetTangentUploadsAndRemovesAMap) {
  ANISO_REQUIRE_GL();
  const json m = {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.05}, {"alpha_y", 0.3}};
  const render::Scene plain = sphere_scene(m);
  json doc = scene_json(json::array({{{"shape", "sphere"},
                                      {"center", {0, 0, 0}},
                                      {"radius", 1.0},
                                      {"material", m},
                                      {"tangent", {{"map", "assets/checker_tangents.png"}, {"angle_deg", 10}}}}}),
                        point_light());
  doc["film"] = {{"width", 32}, {"height", 24}, {"spp", 16}};
  const render::Scene mapped = render::parse_scene(doc, "mapped", ANISO_SOURCE_DIR "/examples");
  gl::SceneRasterizer r(plain, gl::RasterSettings{2});
  r.set_tangent(0, mapped.objects[0].tangent);
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(mapped).rgb);
  r.set_tangent(0, plain.objects[0].tangent);
  r.render();
  EXPECT_EQ(r.read_back().rgb, gl_image(plain).rgb);
  render::TangentSource uv = plain.objects[0].tangent;
  uv.uv_tangents = true;
  EXPECT_THROW(r.set_tangent(0, uv), std::invalid_argument);
}

TEST(GlRasterizer, DrawTonemappedGivesThePngWritersBytes) {
  ANISO_REQUIRE_GL();
  gl::SceneRasterizer r(sphere_scene({{"model", "ggx"}, {"kd", 0.3}, {"f0", 0.5}, {"alpha_x", 0.1}, {"alpha_y", 0.3}}),
                        gl::RasterSettings{2});
  r.render();
  for (const render::ToneMapOptions tm :
       {render::ToneMapOptions{0.0f, render::ToneMap::Aces}, render::ToneMapOptions{1.5f, render::ToneMap::Clamp}}) {
    const render::DisplayImage want = render::tonemap(r.read_back(), tm);
    GLuint tex = 0, fbo = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 32, 24, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glViewport(0, 0, 32, 24);
    r.draw_tonemapped(tm);
    std::vector<uint8_t> got(32 * 24 * 4);
    glReadPixels(0, 0, 32, 24, GL_RGBA, GL_UNSIGNED_BYTE, got.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    int worst = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x)
        for (int k = 0; k < 3; ++k)
          worst = std::max(worst, std::abs(int(got[(size_t(23 - y) * 32 + size_t(x)) * 4 + size_t(k)]) -
                                           int(want.rgb[(size_t(y) * 32 + size_t(x)) * 3 + size_t(k)])));
    EXPECT_LE(worst, 1) << "a byte of the window's picture differs from the PNG's by more than rounding";
  }
}

TEST(GlRasterizer, CoverageIsTheFractionOfSubSamplesOnASurface) {
  ANISO_REQUIRE_GL();
  gl::SceneRasterizer r(sphere_scene({{"model", "lambert"}, {"kd", 0.5}}), gl::RasterSettings{4});
  r.render();
  const std::vector<float> cov = r.read_coverage();
  ASSERT_EQ(cov.size(), 32u * 24u);
  EXPECT_EQ(cov[0], 0.0f);             // a corner: background
  EXPECT_EQ(cov[12 * 32 + 16], 1.0f);  // the centre: the sphere
  int partial = 0;
  for (float c : cov) {
    EXPECT_TRUE(c == 0.0f || c == 1.0f || (c > 0.0f && c < 1.0f && std::fabs(c * 16.0f - std::round(c * 16.0f)) < 1e-4f));
    partial += c > 0.0f && c < 1.0f ? 1 : 0;
  }
  EXPECT_GT(partial, 10) << "the silhouette's pixels are partly covered";
}

TEST(GlRasterizer, CallsRestoreTheCallersFramebufferAndViewport) {
  ANISO_REQUIRE_GL();
  gl::SceneRasterizer r(sphere_scene({{"model", "lambert"}, {"kd", 0.5}}), gl::RasterSettings{1});
  GLuint fbo = 0;
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(3, 4, 50, 60);
  r.render();
  r.set_size(20, 10);  // reallocates the targets
  r.set_lights({});
  r.render();
  GLint bound = 0, vp[4];
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
  glGetIntegerv(GL_VIEWPORT, vp);
  EXPECT_EQ(GLuint(bound), fbo);
  EXPECT_EQ(vp[0], 3);
  EXPECT_EQ(vp[1], 4);
  EXPECT_EQ(vp[2], 50);
  EXPECT_EQ(vp[3], 60);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteFramebuffers(1, &fbo);
  EXPECT_NE(r.color_texture(), 0u);
  EXPECT_NE(r.framebuffer(), 0u);
}

// Measured materials (docs/glsl.md "Measured materials"): a MERL table (a Ward BRDF tabulated) and
// a small anisotropic tensor file, shaded through their GLSL twins from the tables texture, match
// the CPU's direct lighting as the analytic models do.
std::string write_ward_merl(const fs::path& dir) {
  const std::string path = (dir / "ward.binary").string();
  if (!fs::exists(path))
    write_merl(path, tabulate_merl(build<double>({{"model", "ward"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", 0.2}, {"alpha", 0.25}})));
  return path;
}
std::string write_small_tensor(const fs::path& dir) {
  const std::string path = (dir / "ggx.bsdf").string();
  const rgl::ExportOptions o = small_rgl_options();
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(rgl::export_rgl(
      rgl::brdf_source(
          build<double>({{"model", "ggx"}, {"kd", 0.1}, {"f0", {0.9, 0.6, 0.3}}, {"alpha_x", 0.1}, {"alpha_y", 0.3}})),
      o));
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  return path;
}

TEST(GlRender, MeasuredMaterialsMatchCpuDirectLighting) {
  ANISO_REQUIRE_GL();
  const fs::path dir = fs::path(::testing::TempDir()) / fmt::format("aniso_gl_measured_{}", getpid());
  fs::create_directories(dir);
  for (const std::string& file : {write_ward_merl(dir), write_small_tensor(dir)}) {
    const json objects = json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", file}}});
    expect_parity(scene_json(objects, point_light()), fs::path(file).stem().string());
  }
  // Both in one scene: each object's draw binds its own tables texture, so a MERL table and a
  // tensor file render side by side, each as it does alone.
  const json objects =
      json::array({{{"shape", "sphere"}, {"center", {-1.1, 0, 0}}, {"radius", 0.9}, {"material", write_ward_merl(dir)}},
                   {{"shape", "sphere"}, {"center", {1.1, 0, 0}}, {"radius", 0.9}, {"material", write_small_tensor(dir)}}});
  expect_parity(scene_json(objects, point_light()), "merl_and_tensor");
  fs::remove_all(dir);
}

// --- the command line ---------------------------------------------------------------------------------

class GlRenderCli : public Cli {
 protected:
  std::string scene_file(const json& lights, const json& material = kBrushed) {
    const json objects = json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", material}}});
    json doc = scene_json(objects, lights);
    doc["film"] = {{"width", 48}, {"height", 32}, {"spp", 4}};
    return write("scene.json", doc.dump());
  }
};

TEST_F(GlRenderCli, BackendGlWritesTheImageAndSaysWhatItLeavesOut) {
  ANISO_REQUIRE_GL();
  json lights = point_light();
  lights.push_back({{"type", "sphere"}, {"center", {-3, 3, 0}}, {"radius", 0.5}, {"radiance", 10}});
  const std::string scene = scene_file(lights);
  const Result r = run({"render", scene, "--backend", "gl", "-o", (dir_ / "out.pfm").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrote")) << r.out;
  EXPECT_TRUE(contains(r.err, "warning: --backend gl: 1 sphere light is not rendered")) << r.err;
  const render::Image img = render::read_image((dir_ / "out.pfm").string(), "test");
  ASSERT_EQ(img.width, 48);
  ASSERT_EQ(img.height, 32);
  // The same image as the rasteriser in this process (4 spp: 2 x 2 sub-samples).
  render::Scene s = render::load_scene(scene);
  gl::SceneRasterizer raster(s, gl::RasterSettings{gl::subsamples_for_spp(4)});
  raster.render();
  const render::Image ref = raster.read_back();
  ASSERT_EQ(ref.rgb.size(), img.rgb.size());
  double peak = 0.0;
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    EXPECT_EQ(img.rgb[i], ref.rgb[i]) << i;
    peak = std::max(peak, double(img.rgb[i]));
  }
  EXPECT_GT(peak, 0.1);
  const Result png = run({"render", scene, "--backend", "gl", "-o", (dir_ / "out.png").string()});
  EXPECT_EQ(png.code, 0) << png.err;
  EXPECT_TRUE(fs::exists(dir_ / "out.png"));
}

TEST_F(GlRenderCli, UnknownBackendExits2) {
  expect_input_error(run({"render", scene_file(point_light()), "--backend", "vulkan"}), {"--backend", "vulkan"});
}

TEST_F(GlRenderCli, MeasuredMaterialRenders) {
  ANISO_REQUIRE_GL();
  const std::string merl = write_ward_merl(dir_);
  const Result r = run({"render", scene_file(point_light(), merl), "--backend", "gl", "-o", (dir_ / "x.pfm").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const render::Image img = render::read_image((dir_ / "x.pfm").string(), "test");
  float peak = 0.0f;
  for (float v : img.rgb) peak = std::max(peak, v);
  EXPECT_GT(peak, 0.05f);
}

TEST_F(GlRenderCli, NothingToLightExits2) {
  const json sphere_light = json::array({{{"type", "sphere"}, {"center", {-3, 3, 0}}, {"radius", 0.5}, {"radiance", 10}}});
  expect_input_error(run({"render", scene_file(sphere_light), "--backend", "gl"}), {"no point or directional light"});
  expect_input_error(run({"render", "--backend", "gl"}), {"the gallery is lit by sphere lights"});
}

TEST_F(GlRenderCli, NoGlExits2WithTheReason) {
  setenv("ANISO_GL_PLATFORM", "none", 1);
  const Result r = run({"render", scene_file(point_light()), "--backend", "gl", "-o", (dir_ / "x.png").string()});
  unsetenv("ANISO_GL_PLATFORM");
  expect_input_error(r, {"--backend gl: no OpenGL context could be made", "ANISO_GL_PLATFORM=none"});
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

}  // namespace
}  // namespace aniso::test
