// tests/test_util.h: what the property tests share: a list of materials covering every model,
// form and normalisation (isotropic and anisotropic), and random directions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "stats/rng.h"

namespace aniso::test {

// The sample count of a statistical test, times ANISO_TEST_SCALE from the environment (default 1;
// the sanitize preset sets 0.25 so that the suite under ASan + UBSan fits in CI's time,
// docs/testing.md). Clamped to [0.01, 1]: the switch only ever makes tests smaller. Tests that use
// it derive their bounds from the count they run (standard errors, chi-square p-values), so a
// smaller count keeps the false-failure rate and loses only power.
inline int64_t scaled(int64_t n) {
  static const double scale = [] {
    const char* s = std::getenv("ANISO_TEST_SCALE");
    const double v = s && *s ? std::atof(s) : 1.0;
    return std::isfinite(v) ? std::clamp(v, 0.01, 1.0) : 1.0;
  }();
  return std::max<int64_t>(1, std::llround(double(n) * scale));
}

struct NamedMaterial {
  std::string name;
  nlohmann::json json;
};
// GoogleTest prints a parameter in the test's ctest name and in failure messages: the name, not
// the object's bytes.
inline void PrintTo(const NamedMaterial& m, std::ostream* os) { *os << m.name; }

// Every model, every Ward form x normalisation, isotropic and anisotropic, metals with each lobe.
inline std::vector<NamedMaterial> all_model_materials() {
  using nlohmann::json;
  std::vector<NamedMaterial> v;
  v.push_back({"lambert", {{"model", "lambert"}, {"kd", {0.8, 0.5, 0.2}}}});
  v.push_back({"phong", {{"model", "phong"}, {"kd", 0.2}, {"ks", 0.5}, {"exponent", 30.0}, {"normalized", true}}});
  v.push_back({"phong_plain", {{"model", "phong"}, {"kd", 0.1}, {"ks", 0.3}, {"exponent", 8.0}, {"normalized", false}}});
  for (const char* form : {"vector", "angle", "approx"})
    for (const char* norm : {"ward", "duer", "balanced"}) {
      v.push_back({std::string("ward_") + form + "_" + norm,
                   {{"model", "ward"},
                    {"kd", 0.1},
                    {"ks", 0.4},
                    {"alpha_x", 0.08},
                    {"alpha_y", 0.3},
                    {"form", form},
                    {"normalization", norm}}});
    }
  v.push_back({"ward_iso", {{"model", "ward"}, {"kd", 0.2}, {"ks", 0.3}, {"alpha_x", 0.15}, {"alpha_y", 0.15}}});
  v.push_back(
      {"as_aniso", {{"model", "ashikhmin-shirley"}, {"rd", {0.5, 0.3, 0.2}}, {"rs", 0.05}, {"n_u", 10.0}, {"n_v", 500.0}}});
  v.push_back({"as_iso", {{"model", "ashikhmin-shirley"}, {"rd", 0.4}, {"rs", 0.5}, {"n_u", 80.0}, {"n_v", 80.0}}});
  v.push_back({"lafortune_aniso",
               {{"model", "lafortune"},
                {"rho_d", 0.1},
                {"lobes", json::array({{{"cx", -0.9}, {"cy", -1.1}, {"cz", 0.95}, {"n", {20.0, 25.0, 30.0}}},
                                       {{"cxy", 0.6}, {"cz", 0.3}, {"n", 3.0}, {"scale", 0.5}}})}}});
  v.push_back(
      {"matte_steel", {{"model", "lafortune"}, {"lobes", json::array({{{"cxy", -1.11954}, {"cz", 1.01272}, {"n", 15.8708}}})}}});
  v.push_back({"ggx_aniso", {{"model", "ggx"}, {"kd", 0.2}, {"f0", {0.9, 0.6, 0.3}}, {"alpha_x", 0.05}, {"alpha_y", 0.4}}});
  // A flatter Fresnel than Schlick's (f90 below 1, per channel), as fits of films give.
  v.push_back(
      {"ggx_iso", {{"model", "ggx"}, {"kd", 0.0}, {"f0", 0.04}, {"f90", {0.3, 0.5, 0.8}}, {"alpha_x", 0.3}, {"alpha_y", 0.3}}});
  v.push_back({"metal_ward",
               {{"model", "metal"},
                {"metal", "gold"},
                {"lobe", {{"model", "ward"}, {"alpha_x", 0.1}, {"alpha_y", 0.35}, {"normalization", "balanced"}}},
                {"directional_diffuse", {{"albedo", 0.2}, {"n", 4.0}}}}});
  v.push_back(
      {"metal_as",
       {{"model", "metal"}, {"metal", "copper"}, {"lobe", {{"model", "ashikhmin-shirley"}, {"n_u", 20.0}, {"n_v", 300.0}}}}});
  v.push_back({"metal_ggx",
               {{"model", "metal"},
                {"eta", {0.2, 0.9, 1.1}},
                {"k", {3.9, 2.4, 2.2}},
                {"lobe", {{"model", "ggx"}, {"alpha_x", 0.3}, {"alpha_y", 0.1}}}}});
  v.push_back({"principled", {{"model", "principled"}, {"base_color", {0.8, 0.5, 0.2}}}});
  v.push_back({"principled_aniso_clearcoat",
               {{"model", "principled"},
                {"base_color", {0.2, 0.4, 0.7}},
                {"metallic", 0.3},
                {"subsurface", 0.5},
                {"roughness", 0.4},
                {"specular_tint", 0.5},
                {"anisotropic", 0.8},
                {"sheen", 0.5},
                {"clearcoat", 1.0},
                {"clearcoat_gloss", 0.5}}});
  // Roughness 0.4, anisotropic 0.9: alpha 0.37 x 0.07. At roughness 0.3 (alpha_y 0.039) the lobe
  // seen from 85 degrees is narrower in cos(theta) near the horizon than the chi-square's quadrature
  // (tests/chi2.h: 40 x 80 bins, 6 x 6 sub-cells) resolves: its pdf integral came out 0.98035
  // against 0.97910 from a 4000 x 4000 midpoint sum and an acceptance of 0.97908 in both float and
  // double, the same for plain GGX with those alphas, so the sampler is right and the quadrature not.
  v.push_back(
      {"principled_metal_aniso",
       {{"model", "principled"}, {"base_color", {0.9, 0.6, 0.3}}, {"metallic", 1.0}, {"roughness", 0.4}, {"anisotropic", 0.9}}});
  // The anisotropic models turned by their rotation_deg (material.h, FrameRotationT): the SIMD twins
  // (ward, ashikhmin-shirley, lafortune), the scalar batch path (principled) and every GLSL twin.
  v.push_back({"ward_rotated",
               {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.08}, {"alpha_y", 0.3}, {"rotation_deg", 30.0}}});
  v.push_back(
      {"as_rotated",
       {{"model", "ashikhmin-shirley"}, {"rd", 0.3}, {"rs", 0.1}, {"n_u", 180.0}, {"n_v", 25.0}, {"rotation_deg", 130.0}}});
  v.push_back({"lafortune_rotated",
               {{"model", "lafortune"},
                {"rho_d", 0.1},
                {"rotation_deg", -75.0},
                {"lobes", json::array({{{"cx", -0.8}, {"cy", -1.1}, {"cz", 0.95}, {"n", 20.0}}})}}});
  v.push_back({"principled_rotated",
               {{"model", "principled"},
                {"base_color", {0.9, 0.6, 0.3}},
                {"metallic", 1.0},
                {"roughness", 0.5},
                {"anisotropic", 0.8},
                {"rotation_deg", 200.0}}});
  return v;
}

// Test names for value-parameterised suites over NamedMaterial.
inline std::string material_name(const testing::TestParamInfo<NamedMaterial>& info) { return info.param.name; }

template <typename T> MaterialT<T> build(const nlohmann::json& j) {
  return build_material<T>(parse_material(j, "test material"));
}

// Uniform direction on the upper hemisphere (z > 0).
template <typename T> Vec3T<T> random_upper(Rng& rng) {
  const double z = 1.0 - rng.uniform();  // (0, 1]
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * M_PI * rng.uniform();
  return Vec3T<T>(T(r * std::cos(phi)), T(r * std::sin(phi)), T(z));
}

// Small grids for RGL files the tests write (colour 16 x 16, 8 theta_i, 9 phi_i, ndf 32 x 32): the
// tests' cost, not the defaults' accuracy (docs/rgl.md has those); an rgb file unless `spectral`.
inline rgl::ExportOptions small_rgl_options(bool spectral = false) {
  rgl::ExportOptions o;
  o.spectral = spectral;
  o.colour = 16;
  o.theta_i = 8;
  o.phi_i = 9;
  o.ndf = 32;
  return o;
}

inline Vec3d spherical(double theta_deg, double phi_deg) {
  const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

}  // namespace aniso::test
