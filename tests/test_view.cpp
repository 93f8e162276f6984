// tests/test_view.cpp: the explorer's logic without a window (src/view): the plots' data against
// the scalar evaluator, the sliders against the parameter tables, --set and the load actions
// (errors keep the last good state), and the progressive preview against the renderer.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <unistd.h>

#include <gtest/gtest.h>

#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/render/integrator.h"
#include "aniso/stats/albedo.h"
#include "test_util.h"
#include "view/explorer.h"
#include "view/frame_times.h"
#include "view/plots.h"
#include "view/preview.h"

namespace aniso {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

Vec3T<double> dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi<double> / 180.0, p = phi_deg * kPi<double> / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

class ViewPlots : public ::testing::TestWithParam<test::NamedMaterial> {};

// Every polar sample is the evaluator's value at the direction its signed angle names, computed
// here from the angle alone.
TEST_P(ViewPlots, PolarSlicesAreTheEvaluatorsValues) {
  const MaterialT<double> m = test::build<double>(GetParam().json);
  const Vec3T<double> wi = dir(35.0, 20.0);
  for (double plane : {20.0, 110.0})
    for (bool times_cos : {false, true}) {
      const auto slice = view::polar_slice(m, wi, plane, 181, times_cos);
      ASSERT_EQ(slice.size(), 181u);
      for (size_t i = 0; i < slice.size(); ++i) {
        const double theta = -90.0 + double(i);
        EXPECT_NEAR(slice[i].theta_deg, theta, 1e-12);
        // Negative angles lie in the half-plane at plane + 180 degrees.
        const Vec3T<double> wo = theta >= 0 ? dir(theta, plane) : dir(-theta, plane + 180.0);
        const RGBT<double> f = m.f(wi, wo);
        const double lum = 0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z;
        const double expected = lum * (times_cos ? std::max(0.0, wo.z) : 1.0);
        EXPECT_NEAR(slice[i].value, expected, 1e-9 * std::max(1.0, std::abs(expected))) << "theta " << theta;
        EXPECT_NEAR(slice[i].f.x, f.x, 1e-9 * std::max(1.0, std::abs(f.x)));
      }
    }
}

// The albedo curve (batch sampler, SIMD) equals the scalar sampler fed the same uniforms, and
// agrees with the independent importance-sampled estimate of stats/albedo.h within 5 standard
// errors plus the stratified estimate's own error (bounded here by 2 % of the value).
TEST_P(ViewPlots, AlbedoCurveIsTheSamplersMean) {
  const MaterialT<double> m = test::build<double>(GetParam().json);
  const int ns = 1024;
  const auto curve = view::albedo_curve(m, 30.0, 7, ns);
  ASSERT_EQ(curve.size(), 7u);
  EXPECT_DOUBLE_EQ(curve.front().theta_deg, 0.0);
  EXPECT_DOUBLE_EQ(curve.back().theta_deg, 89.0);
  for (const auto& p : curve) {
    const Vec3T<double> wo = dir(p.theta_deg, 30.0);
    glm::dvec3 sum(0.0);
    for (int j = 0; j < ns; ++j) {
      double uc, u0, u1;
      view::albedo_uniforms(j, ns, &uc, &u0, &u1);
      const BSDFSampleT<double> s = m.sample(wo, uc, Vec2T<double>(u0, u1));
      if (s.valid) sum += glm::dvec3(s.weight.x, s.weight.y, s.weight.z);
    }
    sum /= double(ns);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.albedo[c], sum[c], 1e-5 * std::max(1.0, sum[c])) << "theta " << p.theta_deg;
    if (p.theta_deg > 80.0) continue;  // grazing: the stratified 1024 samples are too few for a 2 % bound
    const AlbedoEstimate ref = albedo_importance(m, wo, test::scaled(1 << 16), 7);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(p.albedo[c], ref.mean[c], 5.0 * ref.std_error[c] + 0.02 * ref.mean[c] + 1e-6) << "theta " << p.theta_deg;
  }
}

// Each lobe vertex lies at r * wo with r = luminance(f) (x cos) / max over the grid.
TEST_P(ViewPlots, LobeMeshRadiiAreTheEvaluatorsValues) {
  const MaterialT<double> m = test::build<double>(GetParam().json);
  const Vec3T<double> wi = dir(40.0, 60.0);
  const view::LobeMesh mesh = view::lobe_mesh(m, wi, 16, 24, true);
  ASSERT_EQ(mesh.values.size(), size_t(17 * 24));
  ASSERT_EQ(mesh.indices.size(), size_t(16 * 24 * 6));
  ASSERT_GT(mesh.max_value, 0.0);
  double max_r = 0.0;
  for (size_t k = 0; k < mesh.values.size(); ++k) {
    const glm::dvec3 p(mesh.positions[3 * k], mesh.positions[3 * k + 1], mesh.positions[3 * k + 2]);
    const double r = glm::length(p);
    max_r = std::max(max_r, r);
    if (r < 1e-6) continue;
    const Vec3T<double> wo = p / r;
    const RGBT<double> f = m.f(wi, wo);
    const double expected = (0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z) * wo.z / mesh.max_value;
    EXPECT_NEAR(r, expected, 1e-5 * std::max(1.0, expected));  // float positions
  }
  EXPECT_NEAR(max_r, 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Models, ViewPlots, ::testing::ValuesIn(test::all_model_materials()), test::material_name);

// An isotropic Ward lobe peaks in the plane of incidence at the mirror direction (theta_o =
// -theta_i: the half-plane opposite the light), and the perpendicular slice is symmetric.
TEST(ViewPlot, IsotropicPeakAtTheMirrorDirection) {
  const MaterialT<double> m = test::build<double>({{"model", "ward"}, {"kd", 0.0}, {"ks", 0.5}, {"alpha", 0.1}});
  const auto slice = view::polar_slice(m, dir(40.0, 0.0), 0.0, 721, false);
  const auto peak = std::max_element(slice.begin(), slice.end(), [](auto& a, auto& b) { return a.value < b.value; });
  EXPECT_NEAR(peak->theta_deg, -40.0, 0.5);
  const auto perp = view::polar_slice(m, dir(40.0, 0.0), 90.0, 181, false);
  for (size_t i = 0; i < perp.size(); ++i) EXPECT_NEAR(perp[i].value, perp[perp.size() - 1 - i].value, 1e-9 * perp[i].value);
}

TEST(ViewPlot, RadiusScales) {
  EXPECT_DOUBLE_EQ(view::plot_radius(0.5, 1.0, false), 0.5);
  EXPECT_DOUBLE_EQ(view::plot_radius(1.0, 1.0, true), 1.0);
  EXPECT_NEAR(view::plot_radius(1e-2, 1.0, true), 0.5, 1e-12);  // 2 of 4 decades down
  EXPECT_DOUBLE_EQ(view::plot_radius(1e-6, 1.0, true), 0.0);
  EXPECT_DOUBLE_EQ(view::plot_radius(NAN, 1.0, true), 0.0);
  EXPECT_DOUBLE_EQ(view::plot_radius(1.0, 0.0, false), 0.0);
}

// Lambert's albedo is kd at every angle, whatever the samples.
TEST(ViewPlot, LambertAlbedoCurveIsFlat) {
  const MaterialT<double> m = test::build<double>({{"model", "lambert"}, {"kd", {0.8, 0.5, 0.2}}});
  for (const auto& p : view::albedo_curve(m, 0.0, 10, 256)) {
    EXPECT_NEAR(p.albedo.x, 0.8, 1e-6);
    EXPECT_NEAR(p.albedo.z, 0.2, 1e-6);
  }
}

// The sliders are the table's entries: Ward has alpha_x and alpha_y (not the "alpha" shorthand)
// with the table's range, its choices for form; a metal's lobe keys sit under "lobe.".
TEST(ViewSliders, FromTheParameterTables) {
  const view::MaterialSlot ward = view::load_slot(R"({"model": "ward", "alpha": 0.2})");
  const auto sliders = view::slider_specs(ward);
  std::set<std::string> keys;
  for (const auto& s : sliders) keys.insert(s.key);
  EXPECT_TRUE(keys.count("alpha_x") && keys.count("alpha_y") && keys.count("kd") && keys.count("ks") && keys.count("form"));
  EXPECT_FALSE(keys.count("alpha"));
  const ParamSpec* alpha_x = find_model_spec("ward")->find("alpha_x");
  for (const auto& s : sliders)
    if (s.key == "alpha_x") {
      EXPECT_EQ(s.spec, alpha_x);
      EXPECT_GE(s.lo, alpha_x->min);
      EXPECT_LE(s.hi, alpha_x->max);
      EXPECT_DOUBLE_EQ(s.value.get<double>(), 0.2);
      EXPECT_NE(s.doc.find(std::string(alpha_x->doc)), std::string::npos);
    }
  const auto metal = view::slider_specs(view::load_slot("brushed-gold"));
  bool lobe_alpha = false, lobe_model = false;
  for (const auto& s : metal) lobe_alpha |= s.key == "lobe.alpha_x", lobe_model |= s.key == "lobe.model";
  EXPECT_TRUE(lobe_alpha && lobe_model);
  const auto laf = view::slider_specs(view::load_slot("matte-steel"));
  bool lobe_n = false;
  for (const auto& s : laf) lobe_n |= s.key == "lobes[0].n";
  EXPECT_TRUE(lobe_n);
}

// The window labels a slider by its name within its nested object, under a tree node for that
// object: within every group of every model's defaults and of the nested presets the labels differ,
// and group + "." + label is the key (the full keys, cut by the label column, would read
// "directional_diff" five times for brushed-gold).
TEST(ViewSliders, NestedKeysHaveDistinctLabelsInTheirGroup) {
  std::vector<view::MaterialSlot> slots = {view::load_slot("brushed-gold"), view::load_slot("matte-steel")};
  // Every model's defaults, but for those that need a file (measured, rgl: no defaults to show).
  for (const ModelSpec* m : model_specs()) {
    try {
      slots.push_back(view::default_slot_for_model(std::string(m->name)));
    } catch (const InputError&) {}
  }
  EXPECT_GE(slots.size(), 8u);
  for (const view::MaterialSlot& slot : slots) {
    std::map<std::string, std::set<std::string>> labels;
    for (const view::SliderSpec& s : view::slider_specs(slot)) {
      EXPECT_EQ(s.group.empty() ? s.label : s.group + "." + s.label, s.key);
      EXPECT_EQ(s.label.find('.'), std::string::npos) << s.key;
      EXPECT_TRUE(labels[s.group].insert(s.label).second) << slot.source << ": " << s.key << " repeats its label in " << s.group;
    }
  }
  std::map<std::string, std::vector<std::string>> gold;
  for (const view::SliderSpec& s : view::slider_specs(view::load_slot("brushed-gold"))) gold[s.group].push_back(s.label);
  EXPECT_EQ(gold["directional_diffuse"], (std::vector<std::string>{"albedo", "cx", "cy", "cz", "n"}));
  EXPECT_EQ(gold["lobe"].front(), "model");
  std::set<std::string> lobes;
  for (const view::SliderSpec& s : view::slider_specs(view::load_slot("matte-steel"))) lobes.insert(s.group);
  EXPECT_EQ(lobes, (std::set<std::string>{"", "lobes[0]", "lobes[1]", "lobes[2]"}));
}

// The A/B captions' shortening: whole characters dropped from the end, "..." appended, never wider
// than asked (here one unit a byte, as a fixed-width font measures ASCII).
TEST(ViewText, EllipsizeFitsTheWidth) {
  const auto bytes = [](std::string_view t) { return float(t.size()); };
  EXPECT_EQ(view::ellipsize("A gold", 10.0f, bytes), "A gold");
  EXPECT_EQ(view::ellipsize("A brushed-gold (edited)", 10.0f, bytes), "A brush...");
  EXPECT_EQ(view::ellipsize("A brushed-gold (edited)", 3.0f, bytes), "...");
  EXPECT_EQ(view::ellipsize("A brushed-gold (edited)", 2.0f, bytes), "");
  // A two-byte character is dropped whole: "A caf\xc3\xa9 gris" cut after its 'f' or after the whole 'é', never inside it.
  for (float w = 3.0f; w < 14.0f; w += 1.0f) {
    const std::string t = view::ellipsize("A caf\xc3\xa9 gris", w, bytes);
    EXPECT_LE(float(t.size()), w);
    EXPECT_EQ(t.find("\xc3..."), std::string::npos) << t;
  }
}

// One frame-time figure for the window and the scripted run's stderr line: the first frames left
// out, the mean of all the others or of the last `window`.
TEST(ViewFrameTimes, MeanAfterTheFirstFrames) {
  view::FrameTimes all(2, 0);
  EXPECT_EQ(all.frames(), 0u);
  for (double ms : {500.0, 400.0, 10.0, 20.0, 30.0}) all.add(ms);
  EXPECT_EQ(all.frames(), 3u);
  EXPECT_DOUBLE_EQ(all.mean_ms(), 20.0);
  EXPECT_EQ(all.text(), "20.0 ms a frame, 50.0 fps (mean of 3 frames)");
  view::FrameTimes last(2, 2);
  for (double ms : {500.0, 400.0, 10.0, 20.0, 30.0}) last.add(ms);
  EXPECT_EQ(last.frames(), 2u);
  EXPECT_DOUBLE_EQ(last.mean_ms(), 25.0);
}

TEST(ViewSet, ChangesTheMaterialOrKeepsIt) {
  view::MaterialSlot s = view::load_slot(R"({"model": "ward", "alpha_x": 0.2, "alpha_y": 0.3})");
  view::apply_assignment(s, "alpha_x=0.05");
  EXPECT_DOUBLE_EQ(s.edit["alpha_x"].get<double>(), 0.05);
  {
    const MaterialT<double> ref = test::build<double>({{"model", "ward"}, {"alpha_x", 0.05}, {"alpha_y", 0.3}});
    const Vec3T<double> wi = dir(30.0, 10.0), wo = dir(25.0, 200.0);
    EXPECT_EQ(s.kernel.f(wi, wo).x, ref.f(wi, wo).x);  // the kernel is rebuilt from the edited JSON
  }
  view::apply_assignment(s, "form=angle");  // a bare word is a string
  EXPECT_EQ(s.edit["form"], "angle");
  const json before = s.edit;
  EXPECT_THROW(view::apply_assignment(s, "alpha_x=-1"), InputError);  // out of range
  EXPECT_THROW(view::apply_assignment(s, "no_such_key=1"), InputError);
  EXPECT_THROW(view::apply_assignment(s, "alpha_x"), InputError);  // no '='
  EXPECT_EQ(s.edit, before);
  view::MaterialSlot gold = view::load_slot("brushed-gold");
  view::apply_assignment(gold, "lobe.alpha_y=0.5");
  EXPECT_DOUBLE_EQ(gold.edit["lobe"]["alpha_y"].get<double>(), 0.5);
  view::apply_assignment(gold, "lobe.model=ggx");  // a new lobe model starts from its defaults
  EXPECT_EQ(gold.edit["lobe"]["model"], "ggx");
  view::MaterialSlot steel = view::load_slot("matte-steel");
  view::apply_assignment(steel, "lobes[0].n=40");
  EXPECT_DOUBLE_EQ(steel.edit["lobes"][0]["n"].get<double>(), 40.0);
  EXPECT_THROW(view::apply_assignment(steel, "lobes[3].n=40"), InputError);
}

class ViewFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("aniso-view-" + std::to_string(::getpid()) + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  fs::path dir_;
};

// A broken material, a corrupt tangent map or OBJ: an InputError naming the file, and the state
// as it was (the views keep drawing the last good scene).
TEST_F(ViewFiles, BadLoadsKeepTheLastGoodState) {
  view::Explorer ex;
  ex.a = view::load_slot("brushed-gold");
  ex.b = view::load_slot("gold");
  ex.refresh();
  const json a_before = ex.a.edit;
  const auto sphere_before = ex.sphere_base, object_before = ex.object_base;

  const std::string bad_json = write("bad.json", R"({"model": "ward", "alpha_x": 0.1)");
  try {
    ex.load_material_a(bad_json);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ex.a.edit, a_before);

  const std::string bad_png =
      write("bad.png", std::string("\x89PNG\r\n\x1a\n garbage"));  // 16 bytes (18 read past the literal: ASan)
  try {
    ex.load_tangent_map(bad_png);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(ex.tangent.map_path.empty());

  const std::string bad_obj = write("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  try {
    ex.load_obj(bad_obj);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(ex.obj_path.empty());
  EXPECT_EQ(ex.sphere_base, sphere_before);
  EXPECT_EQ(ex.object_base, object_before);

  // Good files load.
  ex.load_obj(std::string(ANISO_SOURCE_DIR) + "/examples/assets/ribbon.obj");
  EXPECT_FALSE(ex.object_base->objects.at(0).mesh->positions.empty());
  ex.load_tangent_map(std::string(ANISO_SOURCE_DIR) + "/examples/assets/checker_tangents.png");
  EXPECT_TRUE(ex.sphere_base->objects.at(0).tangent.map);
}

// The views' scene carries the hemisphere widget's light, the orbit camera, the tangent controls
// and the slot's kernel.
TEST(ViewScene, LinkedToTheControls) {
  view::Explorer ex;
  ex.a = view::load_slot("brushed-gold");
  ex.b = view::load_slot("gold");
  ex.light = {50.0, 120.0};
  ex.tangent.angle_deg = 30.0;
  ex.refresh();
  const auto s = ex.view_scene(view::ObjectKind::Sphere, ex.a);
  ASSERT_EQ(s->lights.size(), 1u);
  const Vec3T<double> l = ex.light.local();
  EXPECT_NEAR(s->lights[0].to_light.x, l.x, 1e-6);
  EXPECT_NEAR(s->lights[0].to_light.y, l.y, 1e-6);
  EXPECT_NEAR(s->lights[0].to_light.z, l.z, 1e-6);
  EXPECT_NEAR(s->objects[0].tangent.field.angle, 30.0 * kPi<float> / 180.0f, 1e-6);
  EXPECT_NEAR(s->camera.position.z, ex.camera.distance, 1e-5);
  const Vec3 wi(0.3f, 0.2f, 0.93f), wo(-0.2f, 0.1f, 0.97f);
  EXPECT_EQ(s->objects[0].material.f(wi, wo).x, ex.a.kernel_f.f(wi, wo).x);
}

// The tangent controls become the scene reader's field: each procedural field by name, its angle
// in radians, and an invalid parameter is an InputError.
TEST(ViewScene, TangentControlsAreTheScenesField) {
  view::Explorer ex;
  const std::pair<const char*, TangentFieldKind> kinds[] = {
      {"natural", TangentFieldKind::Natural},       {"projected", TangentFieldKind::Projected},
      {"concentric", TangentFieldKind::Concentric}, {"radial", TangentFieldKind::Radial},
      {"swirl", TangentFieldKind::Swirl},           {"noise", TangentFieldKind::Noise}};
  for (const auto& [name, kind] : kinds) {
    ex.tangent.field = name;
    ex.tangent.angle_deg = 90.0;
    const TangentFieldT<float> f = ex.tangent_field();
    EXPECT_EQ(f.kind, kind) << name;
    EXPECT_NEAR(f.angle, kPi<float> / 2.0f, 1e-6f) << name;
  }
  ex.tangent.field = "noise";
  ex.tangent.noise_strength = 3.0;  // the scene reader's range is [0, 1]
  EXPECT_THROW(ex.tangent_field(), InputError);
}

// --scene: the preview path-traces the file's scene with material A on its first object; a bad
// scene file is an InputError and changes nothing.
TEST_F(ViewFiles, SceneFileGoesToThePreview) {
  view::Explorer ex;
  ex.a = view::load_slot("clay");
  ex.b = ex.a;
  ex.refresh();
  EXPECT_THROW(ex.load_scene_file(write("bad.json", R"({"camera": {"position": [0, 0, 1]}, "objects": []})")), InputError);
  EXPECT_TRUE(ex.scene_file.is_null());
  ex.load_scene_file(std::string(ANISO_SOURCE_DIR) + "/examples/brushed-vase.json");
  const auto s = ex.preview_scene(view::ObjectKind::Object, 64, 48);
  EXPECT_EQ(s->film.width, 64);
  EXPECT_EQ(s->film.height, 48);
  const render::Scene file = render::load_scene(std::string(ANISO_SOURCE_DIR) + "/examples/brushed-vase.json");
  ASSERT_EQ(s->objects.size(), file.objects.size());
  EXPECT_EQ(s->camera.position, file.camera.position);  // the file's camera, not the orbit
  const Vec3 wi(0.3f, 0.2f, 0.93f), wo(-0.2f, 0.1f, 0.97f);
  EXPECT_EQ(s->objects[0].material.f(wi, wo).x, ex.a.kernel_f.f(wi, wo).x);
  ASSERT_EQ(s->objects.size(), 2u);
  EXPECT_EQ(s->objects[1].material.f(wi, wo).x, file.objects[1].material.f(wi, wo).x);  // the plate keeps its own
}

// A scene's film.noise_threshold and film.time_s apply to the preview's average (view/preview.h),
// not to each of its passes: with a loose threshold it stops soon after film.min_spp, far below its
// cap; with a short budget it stops near the budget (each pass applying it would instead reach
// the cap of 2^16 samples, pass by pass).
TEST(ViewPreview, NoiseThresholdAndTimeApplyToTheAverage) {
  view::Explorer ex;
  ex.a = view::load_slot("clay");
  ex.b = ex.a;
  ex.refresh();
  auto base = ex.view_scene(view::ObjectKind::Sphere, ex.a);
  auto scene = std::make_shared<render::Scene>(*base);
  scene->film.width = 24, scene->film.height = 16;
  scene->film.noise_threshold = 0.5f;
  scene->film.min_spp = 4;
  {
    view::ProgressivePreview preview(2, 1 << 16);
    preview.restart(scene);
    preview.wait_for(1 << 16);  // returns when the preview is idle
    EXPECT_GE(preview.spp(), 4);
    EXPECT_LE(preview.spp(), 16);
  }
  scene->film.noise_threshold = 0.0f;
  scene->film.time_s = 0.3f;
  {
    view::ProgressivePreview preview(2, 1 << 16);
    const auto t0 = std::chrono::steady_clock::now();
    preview.restart(scene);
    preview.wait_for(1 << 16);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_GE(preview.spp(), 1);
    EXPECT_LT(preview.spp(), 1 << 16);
    EXPECT_LT(seconds, 10.0);  // the budget, plus the last pass on a loaded machine
  }
}

// The progressive preview's average converges to the renderer's image of the same scene.
TEST(ViewPreview, ConvergesToTheRenderersImage) {
  view::Explorer ex;
  ex.a = view::load_slot("clay");
  ex.b = ex.a;
  ex.refresh();
  auto base = ex.view_scene(view::ObjectKind::Sphere, ex.a);
  auto scene = std::make_shared<render::Scene>(*base);
  scene->film.width = 48, scene->film.height = 32;
  view::ProgressivePreview preview(2, 16);
  preview.restart(scene);
  preview.wait_for(16);
  render::Image img;
  int spp = 0;
  uint64_t gen = 0;
  ASSERT_TRUE(preview.snapshot(&img, &spp, &gen));
  EXPECT_EQ(spp, 16);
  ASSERT_EQ(img.width, 48);
  render::RenderOptions opt;
  opt.spp = 64;
  opt.seed = 3;
  const render::Image ref = render::render(*scene, opt);
  double sum = 0.0, sum_ref = 0.0;
  for (size_t i = 0; i < img.rgb.size(); ++i) sum += img.rgb[i], sum_ref += ref.rgb[i];
  ASSERT_GT(sum_ref, 0.0);
  EXPECT_NEAR(sum / sum_ref, 1.0, 0.03);             // the image mean of 16 spp on 1536 pixels: well under 1 % noise
  EXPECT_FALSE(preview.snapshot(&img, &spp, &gen));  // nothing new since

  // A restart (the material changed) starts again from zero samples, at the new scene's size.
  auto other = std::make_shared<render::Scene>(*scene);
  other->film.width = 24, other->film.height = 16;
  other->objects[0].material = view::load_slot("gold").kernel_f;
  preview.restart(other);
  preview.wait_for(16);
  ASSERT_TRUE(preview.snapshot(&img, &spp, &gen));
  EXPECT_EQ(img.width, 24);
  EXPECT_EQ(spp, 16);
}

}  // namespace
}  // namespace aniso
