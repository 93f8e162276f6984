// tests/test_render.cpp: the path tracer against values computed independently of it: the white
// furnace, direct lighting of a sphere computed from the camera, the geometry and the reference BRDF
// formulas (tests/reference), agreement of the three estimators (mis, bsdf, light) in expectation
// and MIS's lower variance, the tangent sources (rotation, concentric symmetry, tangent maps), and
// determinism across thread counts.
#include <atomic>
#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "reference/reference_brdfs.h"
#include "render/integrator.h"
#include "render/scene.h"

namespace aniso::render {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

Scene scene_from(const json& j) { return parse_scene(j, "test scene", ""); }

json sphere_scene(const json& material, int size, int spp) {
  return {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", 35}}},
          {"film", {{"width", size}, {"height", size}, {"spp", spp}}},
          {"integrator", {{"max_depth", 16}}},
          {"objects", json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", material}}})}};
}

Image render_json(const json& j, uint64_t seed = 1, int threads = 0, RenderStats* st = nullptr) {
  RenderOptions o;
  o.seed = seed;
  o.threads = threads;
  return render(scene_from(j), o, st);
}

float mean_channel(const Image& img, int x0, int y0, int x1, int y1, int c) {
  double s = 0;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += img.at(x, y)[c], ++n;
  return float(s / n);
}

// --- white furnace ----------------------------------------------------------------------------

// In a uniform white environment, a surface that reflects everything it receives is invisible:
// every pixel is 1. Materials that lose energy are <= 1.
TEST(RenderFurnace, LambertAlbedoOneIsInvisible) {
  json j = sphere_scene({{"model", "lambert"}, {"kd", 1.0}}, 32, 64);
  j["environment"] = {{"type", "uniform"}, {"radiance", 1.0}};
  RenderStats st;
  const Image img = render_json(j, 7, 0, &st);
  EXPECT_EQ(st.nonfinite, 0u);
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < img.rgb.size(); ++i) sum += img.rgb[i], sum2 += double(img.rgb[i]) * img.rgb[i];
  const double n = double(img.rgb.size()), mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  // Each sample of a convex Lambert sphere in a uniform furnace is 1 up to MIS weighting noise.
  EXPECT_NEAR(mean, 1.0, 2e-3) << "sd " << sd;
  EXPECT_LT(sd, 0.05);
  // The centre pixels see only the sphere.
  EXPECT_NEAR(mean_channel(img, 12, 12, 20, 20, 1), 1.0f, 0.01f);
}

TEST(RenderFurnace, EnergyConservingMaterialsStayBelowOne) {
  for (const json& m : {json{{"model", "ashikhmin-shirley"}, {"rd", 0.5}, {"rs", 0.5}, {"n_u", 20}, {"n_v", 200}},
                        json{{"model", "ward"}, {"kd", 0.0}, {"ks", 1.0}, {"alpha_x", 0.1}, {"alpha_y", 0.3}, {"normalization", "balanced"}},
                        json{{"model", "ward"}, {"kd", 0.5}, {"ks", 0.5}, {"alpha_x", 0.2}, {"alpha_y", 0.2}, {"normalization", "balanced"}}}) {
    json j = sphere_scene(m, 24, 64);
    j["environment"] = {{"type", "uniform"}, {"radiance", 1.0}};
    const Image img = render_json(j, 3);
    // Interior pixels (the sphere's disc covers the middle): their mean, with room for the Monte
    // Carlo noise of 64 x 64 samples (single pixels scatter by a few percent at 64 spp).
    for (int c = 0; c < 3; ++c) EXPECT_LE(mean_channel(img, 8, 8, 16, 16, c), 1.01f) << m.dump();
  }
}

// --- direct lighting from first principles ----------------------------------------------------

// A sphere under one directional light, direct lighting only: each pixel is the average over its
// footprint of f(wi, wo) E cos(theta_i), computed here in double precision with our own camera,
// ray-sphere intersection and frame (the sphere's natural tangent, +y x n), and the reference Ward.
TEST(RenderDirect, SphereUnderDirectionalLightMatchesIndependentComputation) {
  const int W = 40, H = 30;
  const double ax = 0.15, ay = 0.4, kd = 0.2, ks = 0.6;
  const aniso_ref::V3 to_light = aniso_ref::normalize({0.4, 0.7, 0.6});
  const double E = 2.5;
  json j = {{"camera", {{"position", {0.3, 0.5, 3.5}}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", 40}}},
            {"film", {{"width", W}, {"height", H}, {"spp", 256}}},
            {"integrator", {{"max_depth", 1}, {"strategy", "light"}}},
            {"lights", json::array({{{"type", "directional"}, {"to_light", {to_light.x, to_light.y, to_light.z}}, {"irradiance", E}}})},
            {"objects", json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0},
                                      {"material", {{"model", "ward"}, {"kd", kd}, {"ks", ks}, {"alpha_x", ax}, {"alpha_y", ay}}}}})}};
  const Image img = render_json(j, 11);

  // Independent camera: pinhole, vertical fov, pixel (0, 0) top-left.
  using V = aniso_ref::V3;
  const auto sub = [](V a, V b) { return V{a.x - b.x, a.y - b.y, a.z - b.z}; };
  const auto mul = [](V a, double s) { return V{a.x * s, a.y * s, a.z * s}; };
  const auto cross = [](V a, V b) { return V{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  const V eye{0.3, 0.5, 3.5};
  const V fwd = aniso_ref::normalize(sub(V{0, 0, 0}, eye));
  const V right = aniso_ref::normalize(cross(fwd, V{0, 1, 0}));
  const V up = cross(right, fwd);
  const double th = std::tan(20.0 * aniso_ref::kPi / 180.0), aspect = double(W) / H;
  // Radiance along the ray through film point (px, py); -1 if it misses the sphere.
  const auto radiance = [&](double px, double py) {
    const double sx = (2 * px / W - 1) * th * aspect, sy = (1 - 2 * py / H) * th;
    const V d = aniso_ref::normalize(aniso_ref::add(fwd, aniso_ref::add(mul(right, sx), mul(up, sy))));
    const double b = aniso_ref::dot(eye, d), c = aniso_ref::dot(eye, eye) - 1.0, disc = b * b - c;
    if (disc <= 0) return -1.0;
    const double t = -b - std::sqrt(disc);
    const V n = aniso_ref::add(eye, mul(d, t));  // unit: the sphere has radius 1 at the origin
    const V tan_raw{n.z, 0.0, -n.x};
    const V tt = aniso_ref::normalize(tan_raw), bb = cross(n, tt);
    const auto local = [&](V w) { return V{aniso_ref::dot(w, tt), aniso_ref::dot(w, bb), aniso_ref::dot(w, n)}; };
    const V wo = local(mul(d, -1.0)), wi = local(to_light);
    if (wi.z <= 0 || wo.z <= 0) return 0.0;
    const auto f = aniso_ref::ward(aniso_ref::grey(kd), aniso_ref::grey(ks), ax, ay, aniso_ref::WardForm::Vector,
                                   aniso_ref::WardNorm::Ward1992, wi, wo);
    return f[0] * E * wi.z;
  };
  int checked = 0;
  double worst = 0, sum_err = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      // Interior pixels only: every point of the footprint on the sphere (corners and centre hit).
      bool inside = true;
      for (double cx : {0.0, 1.0})
        for (double cy : {0.0, 1.0}) inside = inside && radiance(x + cx, y + cy) >= 0;
      if (!inside) continue;
      double ref = 0;
      const int k = 16;  // 16 x 16 midpoint rule over the pixel footprint
      for (int i = 0; i < k; ++i)
        for (int jj = 0; jj < k; ++jj) ref += radiance(x + (i + 0.5) / k, y + (jj + 0.5) / k);
      ref /= k * k;
      const double got = img.at(x, y).x;
      // The renderer's 256 jittered samples of the integrand over the footprint: within 6% where
      // the highlight varies fast inside one pixel, 1% on average (+ an absolute floor for the
      // dark limb and the terminator).
      const double err = std::fabs(got - ref) / std::max(ref, 0.05);
      worst = std::max(worst, err);
      sum_err += err;
      EXPECT_LT(err, 0.06) << "pixel " << x << "," << y << " got " << got << " expected " << ref;
      ++checked;
    }
  EXPECT_GT(checked, 150);
  EXPECT_LT(sum_err / checked, 0.01);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// Units of the point light: f I cos(theta_i) / d^2.
TEST(RenderDirect, PointLightUnits) {
  json j = {{"camera", {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", 2}}},
            {"film", {{"width", 4}, {"height", 4}, {"spp", 16}}},
            {"integrator", {{"max_depth", 1}}},
            {"lights", json::array({{{"type", "point"}, {"position", {0, 0, 3}}, {"intensity", 8.0}}})},
            {"objects", json::array({{{"shape", "rectangle"}, {"center", {0, 0, 0}}, {"normal", {0, 0, 1}}, {"u", {1, 0, 0}},
                                      {"size", {10, 10}}, {"material", {{"model", "lambert"}, {"kd", 0.5}}}}})}};
  const Image img = render_json(j);
  // Near the axis: f = 0.5 / pi, cos = 1, d = 3.
  EXPECT_NEAR(img.at(1, 1).x, 0.5 / M_PI * 8.0 / 9.0, 2e-4);
}

// --- estimators ----------------------------------------------------------------------------------

// A glossy anisotropic sphere lit by a sphere light and a sky: mis, bsdf and light sampling
// estimate the same pixel values; MIS has the lowest variance.
TEST(RenderEstimators, MisBsdfAndLightAgreeAndMisHasLowerVariance) {
  json base = sphere_scene({{"model", "ward"}, {"kd", 0.1}, {"ks", 0.5}, {"alpha_x", 0.08}, {"alpha_y", 0.3}}, 16, 16);
  base["environment"] = {{"type", "sky"}, {"zenith", 0.3}, {"horizon", 0.6}, {"ground", 0.1}, {"resolution", 64}};
  base["lights"] = json::array({{{"type", "sphere"}, {"center", {-2, 2, 3}}, {"radius", 0.4}, {"radiance", 20.0}}});
  base["integrator"]["max_depth"] = 3;
  const int seeds = 12;
  struct Est {
    std::vector<double> mean, var;  // per pixel (green channel), over seeds
  };
  std::map<std::string, Est> est;
  for (const char* strategy : {"mis", "bsdf", "light"}) {
    json j = base;
    j["integrator"]["strategy"] = strategy;
    std::vector<std::vector<float>> runs;
    for (int s = 0; s < seeds; ++s) {
      const Image img = render_json(j, uint64_t(100 + s));
      std::vector<float> g;
      for (int i = 0; i < img.width * img.height; ++i) g.push_back(img.rgb[size_t(3 * i + 1)]);
      runs.push_back(g);
    }
    Est e;
    const size_t n = runs[0].size();
    e.mean.assign(n, 0.0);
    e.var.assign(n, 0.0);
    for (const auto& r : runs)
      for (size_t i = 0; i < n; ++i) e.mean[i] += r[i] / seeds;
    for (const auto& r : runs)
      for (size_t i = 0; i < n; ++i) e.var[i] += (r[i] - e.mean[i]) * (r[i] - e.mean[i]) / (seeds - 1);
    est[strategy] = e;
  }
  // Agreement of the image means: a z-test with the seed-to-seed variance.
  for (const char* other : {"bsdf", "light"}) {
    double d = 0, v = 0;
    for (size_t i = 0; i < est["mis"].mean.size(); ++i) {
      d += est["mis"].mean[i] - est[other].mean[i];
      v += (est["mis"].var[i] + est[other].var[i]) / seeds;
    }
    EXPECT_LT(std::fabs(d), 4.0 * std::sqrt(v)) << "mis vs " << other;
  }
  double vm = 0, vb = 0, vl = 0;
  for (size_t i = 0; i < est["mis"].var.size(); ++i) vm += est["mis"].var[i], vb += est["bsdf"].var[i], vl += est["light"].var[i];
  EXPECT_LT(vm, vb) << "MIS variance " << vm << " vs BSDF " << vb;
  EXPECT_LT(vm, vl) << "MIS variance " << vm << " vs light " << vl;
}

// --- tangents ------------------------------------------------------------------------------------

json lit_by_directional(json j) {
  j["integrator"] = {{"max_depth", 1}, {"strategy", "light"}};
  j["lights"] = json::array({{{"type", "directional"}, {"to_light", {0.3, 0.5, 0.8}}, {"irradiance", 3.0}}});
  return j;
}

// Rotating the tangent by 90 degrees is the same as swapping alpha_x and alpha_y (the models
// depend on h.x^2 and h.y^2 only). With one directional light and next-event estimation only,
// each sample is a deterministic function of its sub-pixel position: same seed, same image.
TEST(RenderTangents, Rotation90EqualsSwappingAlphas) {
  json a = lit_by_directional(sphere_scene({{"model", "ward"}, {"kd", 0.0}, {"ks", 1.0}, {"alpha_x", 0.05}, {"alpha_y", 0.3}}, 32, 4));
  a["objects"][0]["tangent"] = {{"angle_deg", 90}};
  json b = lit_by_directional(sphere_scene({{"model", "ward"}, {"kd", 0.0}, {"ks", 1.0}, {"alpha_x", 0.3}, {"alpha_y", 0.05}}, 32, 4));
  const Image ia = render_json(a, 5), ib = render_json(b, 5);
  double max_diff = 0, max_val = 0;
  for (size_t i = 0; i < ia.rgb.size(); ++i) {
    max_diff = std::max(max_diff, double(std::fabs(ia.rgb[i] - ib.rgb[i])));
    max_val = std::max(max_val, double(ia.rgb[i]));
  }
  EXPECT_GT(max_val, 0.1);
  EXPECT_LT(max_diff, 1e-4 * max_val);
  // And it is not the same picture as the unrotated material.
  json c = a;
  c["objects"][0].erase("tangent");
  const Image ic = render_json(c, 5);
  double diff_c = 0;
  for (size_t i = 0; i < ia.rgb.size(); ++i) diff_c = std::max(diff_c, double(std::fabs(ia.rgb[i] - ic.rgb[i])));
  EXPECT_GT(diff_c, 0.1 * max_val);
}

// A concentrically brushed disc seen along its axis, lit along its axis: the picture is the same
// after a quarter turn.
TEST(RenderTangents, ConcentricDiscIsRotationallySymmetric) {
  json j = {{"camera", {{"position", {0, 4, 0}}, {"look_at", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov_deg", 35}}},
            {"film", {{"width", 32}, {"height", 32}, {"spp", 64}}},
            {"integrator", {{"max_depth", 1}, {"strategy", "light"}}},
            {"lights", json::array({{{"type", "point"}, {"position", {0.0, 3.0, 0.0}}, {"intensity", 10.0}}})},
            {"objects", json::array({{{"shape", "disc"}, {"center", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"radius", 1.1},
                                      {"tangent", {{"field", "concentric"}}},
                                      {"material", {{"model", "ward"}, {"kd", 0.0}, {"ks", 1.0}, {"alpha_x", 0.05}, {"alpha_y", 0.4}}}}})}};
  const Image img = render_json(j, 9);
  // Mean absolute difference: the pixels next to the centre, where the concentric field turns
  // through every direction inside one pixel, carry most of the sampling noise.
  double sum_diff = 0, sum_val = 0, max_val = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const float v = img.at(x, y).x, r = img.at(31 - y, x).x;  // the pixel a quarter turn away
      sum_diff += std::fabs(v - r);
      sum_val += v;
      max_val = std::max(max_val, double(v));
    }
  EXPECT_GT(max_val, 0.05);
  EXPECT_LT(sum_diff, 0.03 * sum_val);
  // The radial field on the same disc gives a different picture (the field is in effect).
  json k = j;
  k["objects"][0]["tangent"] = {{"field", "radial"}};
  const Image ik = render_json(k, 9);
  double diff = 0;
  for (size_t i = 0; i < img.rgb.size(); ++i) diff = std::max(diff, double(std::fabs(img.rgb[i] - ik.rgb[i])));
  EXPECT_GT(diff, 0.1 * max_val);
}

// A tangent map holding one constant angle gives the picture angle_deg gives.
TEST(RenderTangents, ConstantTangentMapEqualsAngleDeg) {
  const fs::path dir = fs::temp_directory_path() / "aniso_test_tangent_map";
  fs::create_directories(dir);
  const fs::path map = dir / "angle30.pfm";
  {
    // PFM: "PF", size, -1 (little-endian), then floats. Value 1/6 -> angle pi/6 = 30 degrees.
    std::ofstream out(map, std::ios::binary);
    out << "PF\n4 4\n-1.0\n";
    for (int i = 0; i < 16 * 3; ++i) {
      const float v = 1.0f / 6.0f;
      out.write(reinterpret_cast<const char*>(&v), 4);
    }
  }
  const json mat = {{"model", "ward"}, {"kd", 0.0}, {"ks", 1.0}, {"alpha_x", 0.05}, {"alpha_y", 0.4}};
  json rect = {{"camera", {{"position", {0, 2.5, 2.5}}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", 40}}},
               {"film", {{"width", 24}, {"height", 24}, {"spp", 4}}},
               {"objects", json::array({{{"shape", "rectangle"}, {"center", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"u", {1, 0, 0}},
                                         {"size", {3, 3}}, {"material", mat}}})}};
  rect = lit_by_directional(rect);
  json a = rect, b = rect;
  a["objects"][0]["tangent"] = {{"map", map.string()}, {"encoding", "angle"}};
  b["objects"][0]["tangent"] = {{"angle_deg", 30}};
  const Image ia = render_json(a, 2), ib = render_json(b, 2);
  double max_diff = 0, max_val = 0;
  for (size_t i = 0; i < ia.rgb.size(); ++i) {
    max_diff = std::max(max_diff, double(std::fabs(ia.rgb[i] - ib.rgb[i])));
    max_val = std::max(max_val, double(ia.rgb[i]));
  }
  EXPECT_GT(max_val, 1e-3);
  EXPECT_LT(max_diff, 1e-3 * max_val);
  fs::remove_all(dir);
}

// --- determinism ----------------------------------------------------------------------------------

TEST(RenderDeterminism, SameImageForAnyThreadCount) {
  json j = sphere_scene({{"model", "ward"}, {"kd", 0.2}, {"ks", 0.4}, {"alpha_x", 0.1}, {"alpha_y", 0.3}}, 40, 8);
  j["environment"] = {{"type", "sky"}, {"resolution", 64}, {"sun_radiance", 500.0}, {"sun_radius_deg", 2.0}};
  const Image a = render_json(j, 42, 1), b = render_json(j, 42, 2), c = render_json(j, 43, 2);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);
}

TEST(RenderCancel, CancelledRenderIsAWholeImageWithFewerSamples) {
  json j = sphere_scene({{"model", "lambert"}, {"kd", 0.5}}, 16, 64);
  j["environment"] = {{"type", "uniform"}, {"radiance", 1.0}};
  std::atomic<bool> cancel{false};
  RenderOptions o;
  o.cancel = &cancel;
  o.threads = 1;
  int calls = 0;
  o.progress = [&](double f) {
    if (++calls == 1 && f > 0) cancel = true;
  };
  RenderStats st;
  const Image img = render(scene_from(j), o, &st);
  EXPECT_TRUE(st.cancelled);
  EXPECT_LT(st.spp_done, 64);
  // The corner pixels see the environment: 1 wherever the pixel got samples; the image is whole
  // only when a pass finished, which it may not have: no pixel is above 1 or NaN.
  for (float v : img.rgb) EXPECT_TRUE(std::isfinite(v) && v <= 1.0001f);
}

}  // namespace
}  // namespace aniso::render

namespace aniso::render {
namespace {

// Every shipped example scene is valid (the reader accepts it and its meshes and maps load).
TEST(RenderExamples, EveryExampleSceneLoads) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(ANISO_SOURCE_DIR) / "examples")) {
    if (e.path().extension() != ".json") continue;
    EXPECT_NO_THROW(load_scene(e.path().string())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 4);
}

}  // namespace
}  // namespace aniso::render
