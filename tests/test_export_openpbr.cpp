// Tests of `aniso export --to openpbr` (MaterialX open_pbr_surface; src/export, docs/export.md,
// "OpenPBR") and of a scene object's tangent angle in every export (`--scene FILE --object NAME`):
// the target model against OpenPBR's formulas, quoted here from MaterialX's open_pbr_surface.mtlx and
// GLSL and from the OpenPBR specification; the written document against the nodedef's input names
// and types; the composed rotation per target.
#include <cmath>
#include <map>
#include <regex>
#include <set>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/export/export.h"
#include "aniso/io/materials.h"
#include "cli_fixture.h"

namespace aniso {
namespace {

using namespace exporter;
using json = nlohmann::json;

Vec3d dir(double theta_deg, double phi_deg) {
  const double t = glm::radians(theta_deg), p = glm::radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

GgxSource ggx(double ax, double ay, double rot = 0.0) {
  GgxSource g;
  g.alpha_x = ax, g.alpha_y = ay, g.rotation_deg = rot;
  g.kd = glm::dvec3(0.2, 0.3, 0.1), g.f0 = glm::dvec3(0.04);
  return g;
}
GgxSource gold(double ax, double ay) {
  GgxSource g = ggx(ax, ay);
  g.conductor = true;
  g.eta = glm::dvec3(0.2, 0.5, 1.5), g.k = glm::dvec3(3.5, 2.3, 1.8);
  return g;
}

// OpenPBR specification (AcademySoftwareFoundation/OpenPBR @ f8d6d947, index.html:412-415):
//   alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)),  alpha_b = (1 - a) alpha_t
// and MaterialX's NG_open_pbr_anisotropy (open_pbr_surface.mtlx:618-654): invert(a) = 1 - a,
// fraction = 2 / (1 + invert^2), alpha_x = roughness^2 sqrt(fraction), alpha_y = invert alpha_x. A
// negative anisotropy (outside the ui range, not clamped by the graph) stretches along the bitangent.
TEST(ExportOpenPbr, AnisotropyFormulaBothSigns) {
  for (const double a : {0.6, -0.5, 0.0}) {
    const double r = 0.5, inv = 1.0 - a;
    const glm::dvec2 al = openpbr_alpha(r, a);
    EXPECT_NEAR(al.x, r * r * std::sqrt(2.0 / (1.0 + inv * inv)), 1e-15) << a;
    EXPECT_NEAR(al.y, inv * al.x, 1e-15) << a;
    EXPECT_NEAR(al.x * al.x + al.y * al.y, 2.0 * r * r * r * r, 1e-15) << "the spec's invariant, a = " << a;
    EXPECT_EQ(al.y > al.x, a < 0.0) << a;
  }
  // The BSDFs clamp each alpha to [M_FLOAT_EPS, 1] (mx_generalized_schlick_bsdf.glsl:30).
  EXPECT_EQ(openpbr_safe_alpha(openpbr_alpha(1.0, 0.9)).x, 1.0);
  EXPECT_EQ(openpbr_safe_alpha(openpbr_alpha(0.0, 0.0)).y, 1e-8);
}

// Both orientations of the source: the larger alpha along the written tangent (a in [0, 1]), turned
// by a quarter when the source's larger alpha is across dp/du; the model's alphas are the source's.
TEST(ExportOpenPbr, AlphasCarryOver) {
  for (const auto& [ax, ay] : {std::pair{0.3, 0.1}, std::pair{0.05, 0.2}, std::pair{0.2, 0.2}}) {
    json p;
    const TargetBrdf m = target_model(Target::OpenPbr, ggx(ax, ay), &p);
    const double a = p["specular_roughness_anisotropy"].get<double>();
    EXPECT_GE(a, 0.0);
    EXPECT_LE(a, 1.0);
    EXPECT_NEAR(m.lobe.alpha_x, std::max(ax, ay), 1e-12) << p.dump();
    EXPECT_NEAR(m.lobe.alpha_y, std::min(ax, ay), 1e-12) << p.dump();
    EXPECT_EQ(m.tangent_turn_deg, ax < ay ? 90.0 : 0.0);
    // The model in aniso's frame is the source's lobe: same D wherever the tangent was turned.
    const Vec3d wi = dir(30, 20), wo = dir(45, 210);
    TargetBrdf unturned = m;
    unturned.tangent_turn_deg = 0.0, unturned.lobe.alpha_x = ax, unturned.lobe.alpha_y = ay;
    const glm::dvec3 f = m.f(wi, wo), g = unturned.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], g[c], 1e-12 * std::max(1.0, g[c]));
  }
}

// MaterialX @ 4177b2cb, quoted:
//   mx_ggx_NDF (mx_microfacet_specular.glsl:34-39): He = H.xy / alpha; denom = dot(He, He) + H.z^2;
//     D = 1 / (pi alpha.x alpha.y denom^2)
//   mx_ggx_smith_G2 (82-88), at avgAlpha = sqrt(alpha.x alpha.y) (mx_generalized_schlick_bsdf.glsl:31, 46):
//     lambdaL = sqrt(a2 + (1 - a2) NdotL^2), lambdaV = sqrt(a2 + (1 - a2) NdotV^2),
//     G = 2 NdotL NdotV / (lambdaL NdotV + lambdaV NdotL)
//   mx_fresnel_hoffman_schlick (201-209): a = mix(F0, F90, (1 - 1/7)^5) (1 - F82) / (1/7 (1 - 1/7)^6);
//     F = mix(F0, F90, (1 - x)^5) - a x (1 - x)^6, F90 = 1 (generalized_schlick_bsdf's default)
//   response = D F G / (4 NdotV) with NdotL cancelled: as a BRDF, D F G / (4 NdotL NdotV).
// The metal: base_color = F0, specular_color = F82 (open_pbr_surface.mtlx:406-417).
TEST(ExportOpenPbr, MetalModelAtPinnedPoints) {
  json p;
  const GgxSource g = gold(0.25, 0.08);
  const TargetBrdf m = target_model(Target::OpenPbr, g, &p);
  EXPECT_EQ(p["base_metalness"].get<double>(), 1.0);
  const glm::dvec3 F0(p["base_color"][0].get<double>(), p["base_color"][1].get<double>(), p["base_color"][2].get<double>());
  const glm::dvec3 F82(p["specular_color"][0].get<double>(), p["specular_color"][1].get<double>(),
                       p["specular_color"][2].get<double>());
  const glm::dvec2 alpha = openpbr_alpha(p["specular_roughness"].get<double>(), p["specular_roughness_anisotropy"].get<double>());
  for (const auto& [wi, wo] :
       {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}, std::pair{dir(60, 0), dir(60, 180)}}) {
    const Vec3d H = glm::normalize(wi + wo);
    const glm::dvec2 He = glm::dvec2(H.x, H.y) / alpha;
    const double denom = glm::dot(He, He) + H.z * H.z;
    const double D = 1.0 / (kPi<double> * alpha.x * alpha.y * denom * denom);
    const double avg = std::sqrt(alpha.x * alpha.y), a2 = avg * avg, NdotL = wi.z, NdotV = wo.z;
    const double lL = std::sqrt(a2 + (1.0 - a2) * NdotL * NdotL), lV = std::sqrt(a2 + (1.0 - a2) * NdotV * NdotV);
    const double G = 2.0 * NdotL * NdotV / (lL * NdotV + lV * NdotL);
    const double cm = 1.0 / 7.0, x = glm::dot(wo, H);
    const glm::dvec3 a =
        (F0 + (glm::dvec3(1.0) - F0) * std::pow(1.0 - cm, 5.0)) * (glm::dvec3(1.0) - F82) / (cm * std::pow(1.0 - cm, 6.0));
    const glm::dvec3 F = F0 + (glm::dvec3(1.0) - F0) * std::pow(1.0 - x, 5.0) - a * x * std::pow(1.0 - x, 6.0);
    const glm::dvec3 want = D * F * G / (4.0 * NdotL * NdotV), got = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * std::max(1.0, want[c]));
  }
  // The F82 tint makes the curve pass through the conductor's reflectance at cos = 1/7.
  const glm::dvec3 want = F_Conductor(1.0 / 7.0, RGBT<double>(g.eta), RGBT<double>(g.k));
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(m.fresnel(1.0 / 7.0)[c], std::min(want[c], F0[c] + (1 - F0[c]) * std::pow(6.0 / 7.0, 5.0)), 1e-12);
}

// The dielectric base: dielectric_reflection (exact Fresnel at specular_ior, tint specular_color = 1)
// layered over the Lambertian diffuse (base_diffuse_roughness 0: mx_oren_nayar_compensated_diffuse is
// color, its multi-scatter term M_FLOAT_EPS-small): response_top + base_color / pi throughput(V),
// throughput = 1 - albedo(NdotV, avgAlpha, F0, 1) comp (mx_dielectric_bsdf.glsl:47-49,
// mx_layer_bsdf.glsl:5).
TEST(ExportOpenPbr, DielectricIsLayeredOverTheDiffuse) {
  json p;
  const GgxSource g = ggx(0.3, 0.12);
  const TargetBrdf m = target_model(Target::OpenPbr, g, &p);
  EXPECT_EQ(p["base_metalness"].get<double>(), 0.0);
  const double ior = p["specular_ior"].get<double>();
  EXPECT_NEAR(std::pow((ior - 1.0) / (ior + 1.0), 2.0), 0.04, 0.01);
  TargetBrdf lobe = m;
  lobe.diffuse = glm::dvec3(0.0);
  for (const auto& [wi, wo] : {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}}) {
    const double avg = std::sqrt(m.lobe.alpha_x * m.lobe.alpha_y);
    const glm::dvec3 want = lobe.f(wi, wo) + g.kd / kPi<double> * materialx_dielectric_throughput(wo.z, avg, ior);
    const glm::dvec3 got = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * std::max(1.0, want[c]));
  }
}

// A Schlick GGX without diffuse goes the exact way as a metal with tint 1 (plain Schlick): the target
// model is the source's lobe term for term once its masking (G2 at the mean alpha) is swapped for
// aniso's; with its own masking the report measures a small, non-zero error.
TEST(ExportOpenPbr, SchlickGgxIsExactUpToTheMasking) {
  const MaterialDesc d = load_material(R"({"model": "ggx", "kd": 0.0, "f0": [0.9, 0.6, 0.3], "alpha_x": 0.08, "alpha_y": 0.2})");
  const MaterialD src = build_material<double>(d);
  ExportOptions o;
  o.target = "openpbr", o.grid = 3, o.starts = 1;
  const ExportResult r = export_material(d, "ggx", o);
  EXPECT_TRUE(r.report.exact);
  EXPECT_EQ(r.report.parameters["specular_color"], json::array({1.0, 1.0, 1.0}));
  TargetBrdf same_masking = r.model;
  same_masking.lobe.masking = Masking::HeightCorrelated;
  for (const auto& [wi, wo] :
       {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}, std::pair{dir(20, 100), dir(25, 280)}}) {
    const RGBT<double> want = src.f(wi, wo);
    const glm::dvec3 got = same_masking.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9 * std::max(1.0, want[c]));
  }
  // The masking alone: measured 0.128 at grid 3 for this 0.08 x 0.2 lobe (standard_surface, the same
  // masking and the artistic IOR: 0.124; pbrt-v4, aniso's masking and an exact Fresnel: 0.058).
  EXPECT_GT(r.report.errors.relative_l2cos, 0.1);
  EXPECT_LT(r.report.errors.relative_l2cos, 0.14);
}

// The analytic albedo fit the layer uses (mx_ggx_dir_albedo_analytic) against the GGX lobe's
// directional albedo integrated here (Schlick F0 = 1: the lobe's own energy, height-correlated G2):
// a fit, within 0.03 where it is used.
TEST(ExportOpenPbr, AnalyticAlbedoFitIsTheLobesAlbedo) {
  for (const double alpha : {0.1, 0.3, 0.6})
    for (const double theta : {0.0, 40.0, 70.0}) {
      const Vec3d wo = dir(theta, 0.0);
      double e = 0.0;
      constexpr int n = 400;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double u = (i + 0.5) / n, th = u * u * kPi<double> / 2.0, dth = 2.0 * u / n * kPi<double> / 2.0;
          const double ph = (j + 0.5) * 2.0 * kPi<double> / n;
          const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
          const double oh = glm::dot(wo, h);
          if (!(oh > 0.0)) continue;
          const Vec3d wi = 2.0 * oh * h - wo;
          if (!(wi.z > 0.0)) continue;
          const double D = D_GGX_Aniso(h.x, h.y, h.z, alpha, alpha);
          const double G = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, alpha, alpha), Lambda_GGX_Aniso(wo, alpha, alpha));
          e += D * G / (4.0 * wo.z) * 4.0 * oh * std::sin(th) * dth * (2.0 * kPi<double> / n);
        }
      EXPECT_NEAR(materialx_ggx_dir_albedo(wo.z, alpha, 1.0, 1.0), e, 0.03) << alpha << " " << theta;
    }
}

// open_pbr_surface's nodedef (MaterialX @ 4177b2cb, libraries/bxdf/open_pbr_surface.mtlx:8-25, 86):
// the inputs the exporter writes, with their types.
const std::map<std::string, std::string> kOpenPbrInputs = {
    {"base_weight", "float"},        {"base_color", "color3"},     {"base_diffuse_roughness", "float"},
    {"base_metalness", "float"},     {"specular_weight", "float"}, {"specular_color", "color3"},
    {"specular_roughness", "float"}, {"specular_ior", "float"},    {"specular_roughness_anisotropy", "float"},
    {"geometry_tangent", "vector3"},
};

using ExportOpenPbrCli = Cli;

// Every element a known MaterialX node, every open_pbr_surface input a name of its nodedef with the
// nodedef's type; a turned tangent as the stdlib's tangent / normal (space world) into rotate3d
// (in, amount, axis: stdlib_defs.mtlx:3012-3017) and normalize, into geometry_tangent.
TEST_F(ExportOpenPbrCli, WritesTheNodedefsNamesAndTypes) {
  const std::string rotated = R"({"model": "ggx", "kd": 0.2, "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.1, "rotation_deg": 30})";
  for (const std::string& material : {std::string("gold"), std::string("clay"), rotated}) {
    const std::string out = (dir_ / "m.mtlx").string();
    const Result r = run({"export", "--to", "openpbr", "--material", material, "-o", out, "--starts", "1", "--grid", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string x = read_file(out);
    EXPECT_TRUE(contains(x, "<materialx version=\"1.39\">")) << x;
    static const std::regex element(R"re(<([A-Za-z_][\w]*)\s+name="([^"]*)"(\s+type="([^"]*)")?)re");
    std::string parent;
    int shaders = 0;
    for (auto it = std::sregex_iterator(x.begin(), x.end(), element); it != std::sregex_iterator(); ++it) {
      const std::string el = (*it)[1], name = (*it)[2], type = (*it)[4];
      // MaterialX's valid names (source/MaterialXCore/Util.cpp:25-28): letters, digits, '_', ':'.
      EXPECT_TRUE(std::regex_match(name, std::regex("[A-Za-z0-9_:]+"))) << name;
      static const std::set<std::string> known = {"open_pbr_surface", "surfacematerial", "input",    "tangent",
                                                  "normal",           "rotate3d",        "normalize"};
      EXPECT_TRUE(known.count(el)) << el;
      if (el != "input") {
        parent = el;
        shaders += el == "open_pbr_surface";
        continue;
      }
      if (parent == "open_pbr_surface") {
        ASSERT_TRUE(kOpenPbrInputs.count(name)) << name;
        EXPECT_EQ(type, kOpenPbrInputs.at(name)) << name;
      }
    }
    EXPECT_EQ(shaders, 1);
    if (material == rotated) {
      EXPECT_TRUE(contains(x, "name=\"amount\" type=\"float\" value=\"330\"")) << x;
      EXPECT_TRUE(contains(x, "name=\"geometry_tangent\" type=\"vector3\" nodename=")) << x;
    }
  }
}

// Both MaterialX targets: every element name valid (source/MaterialXCore/Util.cpp:25-28, letters,
// digits, '_', ':'), for a material name with a '-' in it.
TEST_F(ExportOpenPbrCli, MaterialXNamesAreValid) {
  for (const char* to : {"materialx", "openpbr"}) {
    const std::string out = (dir_ / "m.mtlx").string();
    const Result r = run({"export", "--to", to, "--material", "gold", "--name", "brushed-gold 2", "-o", out});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string x = read_file(out);
    static const std::regex name_attr(R"re(\sname="([^"]*)")re");
    int names = 0;
    for (auto it = std::sregex_iterator(x.begin(), x.end(), name_attr); it != std::sregex_iterator(); ++it, ++names)
      EXPECT_TRUE(std::regex_match((*it)[1].str(), std::regex("[A-Za-z0-9_:]+"))) << (*it)[1];
    EXPECT_GE(names, 3) << x;
    EXPECT_TRUE(contains(x, "name=\"brushed_gold_2\"")) << x;
  }
}

// ---- a scene object's tangent angle -------------------------------------------------------------

// Each target's rotation input (or note) for the composed angle A: Blender Anisotropic Rotation
// A / 360; standard_surface specular_rotation -A / 360 (a turn); OpenPBR rotate3d -A degrees; glTF
// anisotropyRotation A in radians; Mitsuba 3 and pbrt-v4 have none (the note gives A).
void expect_rotation(Target t, const ExportReport& r, double A) {
  const json& p = r.parameters;
  const auto turn = [](double x) { return x - std::floor(x); };
  switch (t) {
    case Target::Blender: EXPECT_NEAR(p["Anisotropic Rotation"].get<double>(), turn(A / 360.0), 1e-12); break;
    case Target::MaterialX: EXPECT_NEAR(p["specular_rotation"].get<double>(), turn(-A / 360.0), 1e-12); break;
    case Target::OpenPbr: EXPECT_NEAR(p["geometry_tangent_rotate3d_deg"].get<double>(), 360.0 * turn(-A / 360.0), 1e-9); break;
    case Target::Gltf: EXPECT_NEAR(p["anisotropyRotation"].get<double>(), glm::radians(A), 1e-12); break;
    case Target::Mitsuba3:
    case Target::PbrtV4: {
      bool says = false;
      for (const std::string& n : r.notes) says |= contains(n, fmt::format("by {:.9g} degrees", A));
      EXPECT_TRUE(says) << r.text();
      break;
    }
  }
}

TEST(ExportScene, TangentAngleComposesWithRotationDegPerTarget) {
  MaterialDesc d = load_material(R"({"model": "ggx", "kd": 0.1, "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.1})");
  d.params.values["rotation_deg"] = 10.0;
  for (const TargetInfo& info : targets()) {
    ExportOptions o;
    o.target = std::string(info.name), o.grid = 2, o.starts = 1;
    o.tangent_angle_deg = 25.0;
    const ExportResult r = export_material(d, "ggx", o, "x.bin");
    SCOPED_TRACE(info.name);
    expect_rotation(info.target, r.report, 35.0);
  }
}

TEST_F(ExportOpenPbrCli, SceneObjectByNameAndIndex) {
  const std::string scene = write("scene.json", R"({
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
    "objects": [
      {"shape": "sphere", "center": [0, 0, 0], "radius": 1, "name": "knob", "tangent": {"angle_deg": 25},
       "material": {"model": "ggx", "kd": 0.1, "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.1, "rotation_deg": 10}},
      {"shape": "sphere", "center": [3, 0, 0], "radius": 1, "material": "clay"}
    ]})");
  const std::string out = (dir_ / "k.gltf").string();
  for (const std::string& which : {std::string("knob"), std::string("0")}) {
    const Result r = run({"export", "--to", "gltf", "--scene", scene, "--object", which, "-o", out});
    ASSERT_EQ(r.code, 0) << r.err;
    const json doc = json::parse(read_file(out));
    const json& m = doc["materials"][0];
    EXPECT_NEAR(m["extensions"]["KHR_materials_anisotropy"]["anisotropyRotation"].get<double>(), glm::radians(35.0), 1e-12);
    EXPECT_EQ(m["name"], "knob");
    EXPECT_TRUE(contains(r.out, "composed")) << r.out;
  }
  Result r = run({"export", "--to", "gltf", "--scene", scene, "--object", "lid", "-o", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--object lid")) << r.err;
  EXPECT_TRUE(contains(r.err, "\"knob\"")) << r.err;
  r = run({"export", "--to", "gltf", "--scene", scene, "--object", "2", "-o", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "indices 0 to 1")) << r.err;
  r = run({"export", "--to", "gltf", "--scene", scene, "--material", "gold", "--object", "0", "-o", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--scene and --material")) << r.err;
}

}  // namespace
}  // namespace aniso
