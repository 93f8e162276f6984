// Tests of `aniso export --to TARGET` (src/export, docs/export.md): each target model against the
// target's formulas, quoted here from the renderer's source at pinned points; the exact path's
// round trip; the fitted path's errors for the standard materials, pinned; the written files'
// grammar; bad input.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/export/export.h"
#include "aniso/io/materials.h"
#include "aniso/measured/merl.h"
#include "aniso/version.h"
#include "cli_fixture.h"
#include "test_util.h"

namespace aniso {
namespace {

using namespace exporter;
using json = nlohmann::json;

Vec3d dir(double theta_deg, double phi_deg) {
  const double t = glm::radians(theta_deg), p = glm::radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// ---- target formulas, quoted ------------------------------------------------------------------------

// Cycles, closure.h (Principled BSDF):
//   float alpha_x = sqr(roughness), alpha_y = sqr(roughness);
//   if (anisotropic > 0.0f) { float aspect = sqrtf(1.0f - anisotropic * 0.9f); alpha_x /= aspect; alpha_y *= aspect; }
TEST(ExportTargets, CyclesPrincipledAlpha) {
  const double aspect = std::sqrt(1.0 - 0.8 * 0.9);
  glm::dvec2 a = cycles_principled_alpha(0.5, 0.8);
  EXPECT_NEAR(a.x, 0.25 / aspect, 1e-12);
  EXPECT_NEAR(a.y, 0.25 * aspect, 1e-12);
  EXPECT_NEAR(a.x, 0.472455591261534, 1e-12);
  a = cycles_principled_alpha(0.5, 0.0);
  EXPECT_EQ(a, glm::dvec2(0.25));
  a = cycles_principled_alpha(0.5, -0.5);  // saturatef(anisotropic): a negative value is 0
  EXPECT_EQ(a, glm::dvec2(0.25));
  a = cycles_principled_alpha(0.3, 1.0);  // the largest ratio: 1 / 0.1
  EXPECT_NEAR(a.x / a.y, 10.0, 1e-12);
}

// Cycles, closure.h (Glossy BSDF): anisotropy = clamp(param2, -0.99f, 0.99f);
//   if (anisotropy < 0.0f) { alpha_x = roughness / (1.0f + anisotropy); alpha_y = roughness * (1.0f + anisotropy); }
//   else { alpha_x = roughness * (1.0f - anisotropy); alpha_y = roughness / (1.0f - anisotropy); }
TEST(ExportTargets, CyclesGlossyAlphaBothSigns) {
  glm::dvec2 a = cycles_glossy_alpha(0.5, 0.5);
  EXPECT_NEAR(a.x, 0.125, 1e-12);
  EXPECT_NEAR(a.y, 0.5, 1e-12);
  a = cycles_glossy_alpha(0.5, -0.5);
  EXPECT_NEAR(a.x, 0.5, 1e-12);
  EXPECT_NEAR(a.y, 0.125, 1e-12);
  a = cycles_glossy_alpha(0.5, 0.999);  // clamped to 0.99
  EXPECT_NEAR(a.x, 0.25 * 0.01, 1e-12);
  EXPECT_NEAR(a.y, 0.25 / 0.01, 1e-9);
  EXPECT_EQ(cycles_glossy_alpha(0.5, 5e-5), glm::dvec2(0.25));  // |anisotropy| <= 1e-4: isotropic
}

// Cycles, bsdf_util.h: fresnel_f82tint_B: F_schlick(6/7) * (7 / (f^5 f)) * (1 - tint);
// fresnel_f82(cosi) = saturate(F_schlick(cosi) - B * cosi * (1 - cosi)^6): F(1/7) = Schlick(1/7) tint.
TEST(ExportTargets, CyclesF82Tint) {
  const glm::dvec3 f0(0.9, 0.6, 0.3), tint(0.8, 0.9, 1.0);
  const glm::dvec3 b = cycles_f82tint_b(f0, tint);
  const double c = 1.0 / 7.0, s5 = std::pow(1.0 - c, 5.0);
  const glm::dvec3 schlick = f0 + (glm::dvec3(1.0) - f0) * s5;
  const glm::dvec3 f = cycles_f82(c, f0, b);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[k], schlick[k] * tint[k], 1e-12);
  EXPECT_EQ(b.z, 0.0);  // tint 1: plain Schlick
  EXPECT_NEAR(cycles_f82(1.0, f0, b).x, 0.9, 1e-12);
  // The tint the exporter chooses reproduces a target value at 82 degrees.
  const glm::dvec3 want(0.7, 0.55, 0.4);
  const glm::dvec3 t2 = cycles_tint_for(f0, want);
  const glm::dvec3 f2 = cycles_f82(c, f0, cycles_f82tint_b(f0, t2));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f2[k], want[k], 1e-12);
}

// Mitsuba 3, principledhelpers.h, calc_dist_params: aspect = sqrt(1 - 0.9 anisotropic),
// { max(0.001, roughness_2 / aspect), max(0.001, roughness_2 * aspect) }: aniso's principled alphas.
TEST(ExportTargets, MitsubaPrincipledAlphaIsAnisosPrincipled) {
  for (const auto& [r, a] : {std::pair{0.5, 0.8}, std::pair{0.02, 0.3}, std::pair{0.9, 1.0}, std::pair{0.3, 0.0}}) {
    const glm::dvec2 m = mitsuba_principled_alpha(r, a, true);
    PrincipledT<double> p;
    p.roughness = r, p.anisotropic = a;
    const GGXLobeT<double> l = p.specular_lobe();
    EXPECT_NEAR(m.x, l.alpha_x, 1e-15) << r << " " << a;
    EXPECT_NEAR(m.y, l.alpha_y, 1e-15) << r << " " << a;
  }
  EXPECT_EQ(mitsuba_principled_alpha(0.01, 0.0, false), glm::dvec2(0.001));
}

// MaterialX, mx_roughness_anisotropy.glsl:
//   float roughness_sqr = clamp(roughness*roughness, M_FLOAT_EPS, 1.0);
//   if (anisotropy > 0.0) { float aspect = sqrt(1.0 - clamp(anisotropy, 0.0, 0.98));
//       result.x = min(roughness_sqr / aspect, 1.0); result.y = roughness_sqr * aspect; }
TEST(ExportTargets, MaterialXRoughnessAnisotropy) {
  glm::dvec2 a = materialx_alpha(0.5, 0.5);
  EXPECT_NEAR(a.x, 0.25 / std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(a.y, 0.25 * std::sqrt(0.5), 1e-12);
  a = materialx_alpha(0.5, 0.99);  // anisotropy clamped to 0.98, alpha_x to 1
  EXPECT_EQ(a.x, 1.0);
  EXPECT_NEAR(a.y, 0.25 * std::sqrt(0.02), 1e-12);
  EXPECT_EQ(materialx_alpha(0.5, -0.3), glm::dvec2(0.25));  // anisotropy <= 0: isotropic
}

// MaterialX, mx_artistic_ior.glsl (Gulbrandsen 2014): the inverse the exporter uses round-trips.
TEST(ExportTargets, MaterialXArtisticIorRoundTrip) {
  const glm::dvec3 eta(0.2067, 0.4892, 1.4885), k(3.2, 2.27, 1.76);
  glm::dvec3 r, g, n2, k2;
  materialx_artistic_from_ior(eta, k, r, g);
  materialx_artistic_ior(r, g, n2, k2);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(F_Conductor(1.0, n2[c], k2[c]), r[c], 1e-9);
    EXPECT_NEAR(n2[c], eta[c], 1e-9) << "edge colour inside [0, 1] reproduces n";
    EXPECT_NEAR(k2[c], k[c], 1e-9);
  }
}

// glTF KHR_materials_anisotropy README: at = mix(alphaRoughness, 1.0, anisotropy * anisotropy); ab = alphaRoughness.
TEST(ExportTargets, GltfAlpha) {
  const glm::dvec2 a = gltf_alpha(0.5, 0.6);
  EXPECT_NEAR(a.x, 0.25 * (1.0 - 0.36) + 0.36, 1e-12);
  EXPECT_NEAR(a.y, 0.25, 1e-12);
  EXPECT_EQ(gltf_alpha(0.5, 0.0), glm::dvec2(0.25));
}

// glTF README's BRDF_specularAnisotropicGGX = F V D with
//   D = a2 w2^2 / pi, a2 = at ab, f = (ab TdotH, at BdotH, a2 NdotH), w2 = a2 / dot(f, f)
//   V = 0.5 / (NdotL |(at TdotV, ab BdotV, NdotV)| + NdotV |(at TdotL, ab BdotL, NdotL)|)
// equals the target model's height-correlated lobe.
TEST(ExportTargets, GltfLobeMatchesTheReadmeFormula) {
  TargetBrdf t;
  t.lobe.alpha_x = 0.4, t.lobe.alpha_y = 0.1;
  t.lobe.masking = Masking::HeightCorrelated;
  t.lobe.fresnel = FresnelModel::Schlick;
  t.lobe.f0 = glm::dvec3(0.9);
  for (const auto& [wi, wo] :
       {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}, std::pair{dir(55, 0), dir(55, 180)}}) {
    const Vec3d h = glm::normalize(wi + wo);
    const double at = 0.4, ab = 0.1, a2 = at * ab;
    const glm::dvec3 f(ab * h.x, at * h.y, a2 * h.z);
    const double w2 = a2 / glm::dot(f, f), D = a2 * w2 * w2 / kPi<double>;
    const double V = 0.5 / (wi.z * glm::length(glm::dvec3(at * wo.x, ab * wo.y, wo.z)) +
                            wo.z * glm::length(glm::dvec3(at * wi.x, ab * wi.y, wi.z)));
    const double F = 0.9 + 0.1 * std::pow(1.0 - glm::dot(wo, h), 5.0);
    EXPECT_NEAR(t.f(wi, wo).x, F * V * D, 1e-9 * F * V * D);
  }
}

// Mitsuba 3, microfacet.h: G = smith_g1(wi, m) * smith_g1(wo, m), smith_g1 = 2 / (1 + sqrt(1 + tan^2 alpha^2))
// with alpha^2 = (alpha_u v.x)^2 + (alpha_v v.y)^2 over sin^2; pbrt-v4, scattering.h:
// G = 1 / (1 + Lambda(wo) + Lambda(wi)).
TEST(ExportTargets, MaskingSeparableAndHeightCorrelated) {
  const Vec3d wi = dir(60, 30), wo = dir(45, 250);
  const double au = 0.3, av = 0.08;
  const auto lambda = [&](const Vec3d& v) {
    const double xy = sqr(au * v.x) + sqr(av * v.y);
    return (std::sqrt(1.0 + xy / sqr(v.z)) - 1.0) / 2.0;
  };
  const auto g1 = [&](const Vec3d& v) { return 2.0 / (1.0 + std::sqrt(1.0 + (sqr(au * v.x) + sqr(av * v.y)) / sqr(v.z))); };
  TargetBrdf sep, hc;
  sep.lobe = hc.lobe =
      TargetLobe{.alpha_x = au, .alpha_y = av, .fresnel = FresnelModel::Conductor, .eta = glm::dvec3(1.0), .k = glm::dvec3(3.0)};
  sep.lobe.masking = Masking::Separable;
  hc.lobe.masking = Masking::HeightCorrelated;
  const double ratio = sep.f(wi, wo).x / hc.f(wi, wo).x;
  EXPECT_NEAR(ratio, g1(wi) * g1(wo) * (1.0 + lambda(wi) + lambda(wo)), 1e-12);
}

// Mitsuba 3, principled.cpp:230: m_eta = 2 / (1 - sqrt(0.08 specular)) - 1, and
// principledhelpers.h:179-182, schlick_R0_eta = ((eta - 1) / (eta + 1))^2: R0 = 0.08 specular.
// principled.cpp:643-680: f_diff = (1 - 0.5 Fi)(1 - 0.5 Fo), Rr = 2 roughness cos_d^2,
// f_retro = Rr (Fo + Fi + Fo Fi (Rr - 1)): Burley's Fd = (1 + (Fd90 - 1) Fi)(1 + (Fd90 - 1) Fo),
// Fd90 = 0.5 + Rr, expanded. So for aniso's principled source the target differs from the source
// only by the dielectric Fresnel (exact there, Schlick here): mitsuba - aniso = (F_exact - Schlick)
// D G / (4 cos cos), and nothing at metallic 1.
TEST(ExportTargets, MitsubaPrincipledAgainstAnisosPrincipled) {
  const double eta = mitsuba_principled_eta(0.5);
  EXPECT_NEAR(sqr((eta - 1.0) / (eta + 1.0)), 0.04, 1e-15);
  for (const double metallic : {0.0, 0.3, 1.0}) {
    const nlohmann::json j = {{"model", "principled"}, {"base_color", {0.6, 0.3, 0.1}},
                              {"metallic", metallic},  {"roughness", 0.4},
                              {"anisotropic", 0.6},    {"subsurface", 0.3},
                              {"specular", 0.7},       {"sheen", 0.4},
                              {"sheen_tint", 0.0}};
    const MaterialD src = build_material<double>(parse_material(j, "test"));
    const PrincipledT<double>& s = src.principled;
    MitsubaPrincipled mp;
    mp.base_color = glm::dvec3(0.6, 0.3, 0.1), mp.metallic = metallic, mp.roughness = 0.4, mp.anisotropic = 0.6;
    mp.flatness = 0.3, mp.specular = 0.7, mp.sheen = 0.4;
    const glm::dvec2 a = mitsuba_principled_alpha(0.4, 0.6, true);
    EXPECT_NEAR(a.x, s.specular_lobe().alpha_x, 1e-15);
    EXPECT_NEAR(a.y, s.specular_lobe().alpha_y, 1e-15);
    for (const auto& [wi, wo] :
         {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}, std::pair{dir(55, 0), dir(60, 170)}}) {
      const Vec3d h = glm::normalize(wi + wo);
      const double c = glm::dot(wi, h), w5 = std::pow(1.0 - c, 5.0), f0 = 0.08 * 0.7;
      const double DG = D_GGX_Aniso(h.x, h.y, h.z, a.x, a.y) * G1_SmithGGX(Lambda_GGX_Aniso(wi, a.x, a.y)) *
                        G1_SmithGGX(Lambda_GGX_Aniso(wo, a.x, a.y)) / (4.0 * wi.z * wo.z);
      const double fresnel_difference =
          (1.0 - metallic) * (F_Conductor(c, mitsuba_principled_eta(0.7), 0.0) - (f0 + (1.0 - f0) * w5));
      const glm::dvec3 mf = mitsuba_principled_f(mp, wi, wo), af = glm::dvec3(src.f(wi, wo));
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(mf[ch] - af[ch], fresnel_difference * DG, 1e-12 * std::max(1.0, af[ch]));
    }
  }
}

// ---- exact path ---------------------------------------------------------------------------------------

GgxSource ggx(double ax, double ay, double rotation = 0.0) {
  GgxSource g;
  g.alpha_x = ax, g.alpha_y = ay, g.rotation_deg = rotation;
  g.conductor = true;
  g.eta = glm::dvec3(0.2, 0.5, 1.5), g.k = glm::dvec3(3.5, 2.3, 1.8);
  return g;
}

// Blender 3.4.1's Principled BSDF v1, quoted from intern/cycles/kernel (the source Blender 3.4.1
// installs under scripts/addons/cycles/source/kernel):
//   svm/closure.h:317      bsdf->ior = (2.0f / (1.0f - safe_sqrtf(0.08f * specular))) - 1.0f;
//   svm/closure.h:327-334  m_cdlum = 0.3 R + 0.6 G + 0.1 B; m_ctint = base_color / m_cdlum;
//                          tmp_col = (1 - specular_tint) + m_ctint specular_tint;
//                          cspec0 = (specular 0.08 tmp_col)(1 - metallic) + base_color metallic
//   bsdf_util.h:94-105     FH = (fresnel_dielectric_cos(dot(L, H), ior) - F0) / (1 - F0);
//                          return cspec0 (1 - FH) + FH     (F0 = fresnel_dielectric_cos(1, ior))
//   bsdf_microfacet.h:431-454  G1 = 2 / (1 + sqrt(1 + alpha_v^2 tan^2)), alpha_v^2 = cos^2 phi
//                          alpha_x^2 + sin^2 phi alpha_y^2; out = F G1o G1i D 0.25 / cosNO (times cosNI)
//   bsdf_principled_diffuse.h:60-82  (1 - 0.5 FV)(1 - 0.5 FL) + RR (FL + FV + FL FV (RR - 1)),
//                          RR = roughness (L.V + 1), value = NdotL f / pi
TEST(ExportTargets, CyclesPrincipledV1) {
  // The ior's F0 is 0.08 specular, so a dielectric with specular_tint 0 has the exact Fresnel.
  for (double spec : {0.1, 0.5, 1.0}) {
    const double ior = cycles_v1_ior(spec);
    EXPECT_NEAR(sqr((ior - 1.0) / (ior + 1.0)), 0.08 * spec, 1e-12);
    const glm::dvec3 cspec0 = cycles_v1_cspec0(glm::dvec3(0.5, 0.2, 0.1), 0.0, spec, 0.0);
    EXPECT_NEAR(cspec0.y, 0.08 * spec, 1e-12);
    for (double c : {0.05, 0.3, 0.9}) EXPECT_NEAR(cycles_v1_fresnel(c, cspec0, ior).x, F_Conductor(c, ior, 0.0), 1e-12);
  }
  // Metallic: cspec0 = base_color; F(1) = base_color, F(0) = 1, and the tint's luminance is 0.3, 0.6, 0.1.
  const glm::dvec3 base(0.9, 0.6, 0.3);
  EXPECT_NEAR(cycles_v1_cspec0(base, 1.0, 0.5, 0.0).z, 0.3, 1e-12);
  EXPECT_NEAR(cycles_v1_fresnel(1.0, base, cycles_v1_ior(0.5)).y, 0.6, 1e-12);
  EXPECT_NEAR(cycles_v1_fresnel(0.0, base, cycles_v1_ior(0.5)).y, 1.0, 1e-12);
  const double lum = 0.3 * 0.9 + 0.6 * 0.6 + 0.1 * 0.3;
  EXPECT_NEAR(cycles_v1_cspec0(base, 0.0, 0.5, 1.0).x, 0.04 * 0.9 / lum, 1e-12);
  // The exported 3.4 model against the quoted formulas, term for term.
  GgxSource g;
  g.alpha_x = 0.3, g.alpha_y = 0.1, g.kd = glm::dvec3(0.4, 0.3, 0.2), g.f0 = glm::dvec3(0.05);
  json p;
  const TargetBrdf m = target_model(Target::Blender, g, &p, nullptr, 3.4);
  EXPECT_EQ(m.lobe.masking, Masking::Separable);
  const double spec = p["Specular"].get<double>(), rough = p["Roughness"].get<double>();
  EXPECT_NEAR(spec, 0.05 / 0.08, 1e-12);
  const glm::dvec2 a = cycles_principled_alpha(rough, p["Anisotropic"].get<double>());
  for (const auto& [wi, wo] : {std::pair{dir(60, 30), dir(45, 250)}, std::pair{dir(20, 0), dir(70, 90)}}) {
    const Vec3d h = glm::normalize(wi + wo);
    const double sx = -h.x / (h.z * a.x), sy = -h.y / (h.z * a.y), sl = 1 + sx * sx + sy * sy;
    const double D = 1.0 / (sl * sl * kPi<double> * a.x * a.y * sqr(sqr(h.z)));
    const auto g1 = [&](const Vec3d& v) {
      const double t2 = (1 - v.z * v.z) / (v.z * v.z), c2 = v.x * v.x / (v.x * v.x + v.y * v.y);
      return 2.0 / (1.0 + std::sqrt(1.0 + (c2 * a.x * a.x + (1 - c2) * a.y * a.y) * t2));
    };
    const double ior = 2.0 / (1.0 - std::sqrt(0.08 * spec)) - 1.0, F0 = F_Conductor(1.0, ior, 0.0);
    const double FH = (F_Conductor(glm::dot(wi, h), ior, 0.0) - F0) / (1.0 - F0);
    const double F = 0.08 * spec * (1.0 - FH) + FH;
    const double FL = std::pow(1.0 - wi.z, 5.0), FV = std::pow(1.0 - wo.z, 5.0), RR = rough * (glm::dot(wi, wo) + 1.0);
    const double fd = ((1 - 0.5 * FV) * (1 - 0.5 * FL) + RR * (FL + FV + FL * FV * (RR - 1))) / kPi<double>;
    const glm::dvec3 want = F * g1(wi) * g1(wo) * D * 0.25 / (wo.z * wi.z) + g.kd * fd;
    const glm::dvec3 got = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * want[c]) << c;
  }
  // A metal: Base Color = F0, Specular chosen for the curve's shape; the model's F(1) is F0.
  GgxSource metal = ggx(0.2, 0.08);
  const TargetBrdf mm = target_model(Target::Blender, metal, &p, nullptr, 3.4);
  EXPECT_EQ(mm.lobe.fresnel, FresnelModel::CyclesV1);
  EXPECT_GE(p["Specular"].get<double>(), 0.0);
  EXPECT_LE(p["Specular"].get<double>(), 1.0);
  EXPECT_NEAR(mm.fresnel(1.0).x, F_Conductor(1.0, 0.2, 3.5), 1e-12);
}

// Blender 3.4's dielectric specular (cycles_v1_dielectric_specular): cspec0 = 0.08 Specular
// ((1 - Specular Tint) + Specular Tint m_ctint), m_ctint = Base Color / (0.3 R + 0.6 G + 0.1 B)
// (svm/closure.h:327-334, quoted above), with Specular above 1 where F0 is above 0.08.
TEST(ExportTargets, CyclesV1DielectricSpecularIsTheClosestCspec0) {
  const auto cspec0 = [](const glm::dvec3& base, double specular, double tint) {
    const double lum = 0.3 * base.x + 0.6 * base.y + 0.1 * base.z;
    return 0.08 * specular * ((1.0 - tint) * glm::dvec3(1.0) + tint * base / lum);
  };
  const glm::dvec3 yellow(0.13, 0.12, 0.07), blue(0.03, 0.03, 0.15);
  // A grey F0 over a coloured diffuse: no tint, Specular = F0 / 0.08, above 1 where F0 > 0.08.
  for (double f0 : {0.02, 0.08, 0.3}) {
    const CyclesV1Specular s = cycles_v1_dielectric_specular(glm::dvec3(f0), yellow);
    EXPECT_NEAR(s.specular, f0 / 0.08, 1e-12);
    EXPECT_NEAR(s.tint, 0.0, 1e-12);
  }
  // Any F0 in the cone of white and the Base Color's hue comes back exactly.
  for (const auto& [spec, tint] : {std::pair{0.5, 0.3}, std::pair{4.0, 0.7}, std::pair{1.2, 1.0}}) {
    const CyclesV1Specular s = cycles_v1_dielectric_specular(cspec0(blue, spec, tint), blue);
    EXPECT_NEAR(s.specular, spec, 1e-9);
    EXPECT_NEAR(s.tint, tint, 1e-9);
  }
  // A hue outside the cone (the light blue film's blue F0 over its yellow diffuse): the least-squares
  // projection, no worse than any (Specular, Specular Tint) on a fine grid.
  const glm::dvec3 film_f0(0.113, 0.319, 0.541);
  const CyclesV1Specular s = cycles_v1_dielectric_specular(film_f0, yellow);
  const auto err = [&](double spec, double tint) {
    const glm::dvec3 d = cspec0(yellow, spec, tint) - film_f0;
    return glm::dot(d, d);
  };
  EXPECT_NEAR(s.tint, 0.0, 1e-12);
  EXPECT_NEAR(s.specular, (0.113 + 0.319 + 0.541) / 3.0 / 0.08, 1e-9);
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 20; ++j) EXPECT_GE(err(0.08 * i, j / 20.0), err(s.specular, s.tint) - 1e-15);
  // Capped where the ior stays finite (0.08 Specular < 1).
  EXPECT_EQ(cycles_v1_dielectric_specular(glm::dvec3(0.99), yellow).specular, kCyclesV1SpecularMax);
  // The 3.4 export writes them, and its model's F0 is that cspec0 (no clamp at Specular 1).
  GgxSource g;
  g.alpha_x = g.alpha_y = 0.05, g.kd = yellow, g.f0 = film_f0;
  json p;
  const TargetBrdf m = target_model(Target::Blender, g, &p, nullptr, 3.4);
  EXPECT_NEAR(p["Specular"].get<double>(), s.specular, 1e-12);
  EXPECT_NEAR(p["Specular Tint (3.4)"].get<double>(), s.tint, 1e-12);
  const glm::dvec3 want = cspec0(yellow, s.specular, s.tint);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.fresnel(1.0)[c], want[c], 1e-12);
  EXPECT_NEAR(m.lobe.eta.x, 2.0 / (1.0 - std::sqrt(0.08 * s.specular)) - 1.0, 1e-12);
}

TEST(ExportExact, AlphasCarryOverToEveryTarget) {
  for (Target t : {Target::Blender, Target::Mitsuba3, Target::PbrtV4, Target::MaterialX, Target::Gltf}) {
    for (const auto& [ax, ay] : {std::pair{0.3, 0.1}, std::pair{0.05, 0.2}}) {
      json p;
      const TargetBrdf m = target_model(t, ggx(ax, ay), &p);
      // Targets with the major axis along the tangent turn the tangent by 90 degrees instead of
      // swapping: the model's own (alpha along its tangent, across) is then (max, min).
      const bool swaps = (t == Target::Blender || t == Target::MaterialX || t == Target::Gltf) && ax < ay;
      EXPECT_NEAR(m.lobe.alpha_x, swaps ? ay : ax, 1e-9) << p.dump();
      EXPECT_NEAR(m.lobe.alpha_y, swaps ? ax : ay, 1e-9) << p.dump();
    }
  }
}

// KHR_materials_specular README.md:144-157, quoted:
//   dielectric_f0 = min(0.04 * specularColor, float3(1.0)) * specular; dielectric_f90 = specular
//   dielectric_fresnel = mix(dielectric_f0, dielectric_f90, fresnel_w)
//   dielectric_brdf = dielectric_fresnel * specular_brdf + (1 - max_value(dielectric_fresnel)) * diffuse_brdf
// A Schlick source with an F0 other than 0.04 is written with the extension, and its specular lobe
// is then the source's exactly; F0 = 0.04 is written without it.
TEST(ExportExact, GltfSpecularCarriesTheSourcesF0) {
  GgxSource g;
  g.alpha_x = 0.2, g.alpha_y = 0.1;
  g.kd = glm::dvec3(0.3, 0.2, 0.1), g.f0 = glm::dvec3(0.9, 0.6, 0.02);
  json p;
  std::vector<std::string> notes;
  const TargetBrdf m = target_model(Target::Gltf, g, &p, &notes);
  ASSERT_TRUE(p.contains("specularFactor")) << p.dump();
  const double specular = p["specularFactor"].get<double>();
  const glm::dvec3 color(p["specularColorFactor"][0].get<double>(), p["specularColorFactor"][1].get<double>(),
                         p["specularColorFactor"][2].get<double>());
  // F0 0.9 needs KHR_materials_ior (gltf_specular_for): every factor within [0, 1].
  ASSERT_TRUE(p.contains("ior")) << p.dump();
  const double ior = p["ior"].get<double>(), f0_ior = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(color[c] >= 0.0 && color[c] <= 1.0) << p.dump();
  for (const auto& [wi, wo] : {std::pair{dir(30, 10), dir(40, 200)}, std::pair{dir(70, 80), dir(10, 250)}}) {
    const Vec3d h = glm::normalize(wi + wo);
    const double w = std::pow(1.0 - std::abs(glm::dot(wo, h)), 5.0);
    const glm::dvec3 f0 = glm::min(f0_ior * color, glm::dvec3(1.0)) * specular;
    const glm::dvec3 F = f0 * (1.0 - w) + glm::dvec3(specular) * w;
    // The source's Schlick with F0 = g.f0 and f90 = 1: the same curve.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(F[c], g.f0[c] + (1.0 - g.f0[c]) * w, 1e-12);
    const double fmax = std::max({F.x, F.y, F.z});
    TargetBrdf lobe_only = m;
    lobe_only.diffuse = glm::dvec3(0.0);
    const glm::dvec3 want = lobe_only.f(wi, wo) + (1.0 - fmax) * g.kd / kPi<double>;
    const glm::dvec3 got = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * std::max(1.0, want[c]));
    // The lobe against aniso's GGX with the same F0: equal (no diffuse).
    TargetBrdf src = lobe_only;
    src.lobe.f0 = g.f0;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(lobe_only.f(wi, wo)[c], src.f(wi, wo)[c], 1e-12 * std::max(1.0, src.f(wi, wo)[c]));
  }
  g.f0 = glm::dvec3(0.04);
  target_model(Target::Gltf, g, &p);
  EXPECT_FALSE(p.contains("specularFactor")) << p.dump();
}

TEST(ExportExact, RotationGoesToEachTargetsInputWithItsSign) {
  json p;
  target_model(Target::Blender, ggx(0.3, 0.1, 30.0), &p);
  EXPECT_NEAR(p["Anisotropic Rotation"].get<double>(), 30.0 / 360.0, 1e-12);  // counter-clockwise, x 2 pi
  target_model(Target::Blender, ggx(0.1, 0.3, 30.0), &p);
  EXPECT_NEAR(p["Anisotropic Rotation"].get<double>(), 120.0 / 360.0, 1e-12);
  target_model(Target::MaterialX, ggx(0.3, 0.1, 30.0), &p);
  EXPECT_NEAR(p["specular_rotation"].get<double>(), 1.0 - 30.0 / 360.0, 1e-12);  // rotate3d turns clockwise
  target_model(Target::Gltf, ggx(0.1, 0.3, 30.0), &p);
  EXPECT_NEAR(p["anisotropyRotation"].get<double>(), glm::radians(120.0), 1e-12);
  std::vector<std::string> notes;
  target_model(Target::Mitsuba3, ggx(0.3, 0.1, 30.0), &p, &notes);
  bool says = false;
  for (const std::string& n : notes) says |= n.find("no rotation input") != std::string::npos;
  EXPECT_TRUE(says);
}

ExportOptions quick(const std::string& target) {
  ExportOptions o;
  o.target = target;
  o.grid = 3;
  o.starts = 2;
  return o;
}

// rotation_deg (not in the parameter tables yet: the exporter reads it when it is there, default 0)
// reaches the targets' inputs through the exact path.
TEST(ExportExact, RotationDegOfTheMaterialIsRead) {
  MaterialDesc d = load_material(R"({"model": "ggx", "kd": 0.1, "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.1})");
  d.params.values["rotation_deg"] = 30.0;
  ExportOptions o = quick("blender");
  const ExportResult r = export_material(d, "ggx", o);
  EXPECT_NEAR(r.report.parameters["Anisotropic Rotation"].get<double>(), 30.0 / 360.0, 1e-12);
  // The source is compared unrotated against the target model in the target's own frame.
  EXPECT_LT(r.report.errors.relative_l2cos, 0.2);
}

// A GGX with f90 below 1 (ggx.h): no target writes F90, so the exported GGX keeps the source's
// alphas and kd with the Schlick F0' closest to its F over theta_d in [0, 80] degrees (uniform in
// the angle, least squares), and is refined as a fit is. The expected F0' here is found by
// minimising that squared difference directly (golden-section search over F0', Simpson's rule on
// 2000 intervals), not by the exporter's closed form, and read back from the report's origin.
TEST(ExportFit, AFlatFresnelBecomesTheClosestSchlickF0) {
  const MaterialDesc d =
      load_material(R"({"model": "ggx", "kd": 0.1, "f0": [0.3, 0.5, 0.05], "f90": [0.4, 0.5, 1.0], "alpha": 0.3})");
  const auto closest_f0 = [](double f0, double f90) {
    const auto cost = [&](double f0p) {
      constexpr int n = 2000;
      const double h = 80.0 * M_PI / 180.0 / n;
      double sum = 0.0;
      for (int i = 0; i <= n; ++i) {
        const double w = std::pow(1.0 - std::cos(i * h), 5.0);
        const double diff = (f0 + (f90 - f0) * w) - (f0p + (1.0 - f0p) * w);
        sum += (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * diff * diff;
      }
      return sum * h / 3.0;
    };
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = 0.0, b = 1.0;
    while (b - a > 1e-9) {
      const double x1 = b - g * (b - a), x2 = a + g * (b - a);
      if (cost(x1) < cost(x2))
        b = x2;
      else
        a = x1;
    }
    return 0.5 * (a + b);
  };
  const ExportResult r = export_material(d, "flat", quick("mitsuba3"));
  EXPECT_FALSE(r.report.exact);
  EXPECT_NE(r.report.origin.find("closest to its Fresnel with f90 0.4, 0.5, 1"), std::string::npos) << r.report.origin;
  const std::string key = "Schlick F0 ";
  const size_t at = r.report.origin.find(key);
  ASSERT_NE(at, std::string::npos) << r.report.origin;
  double written[3];
  ASSERT_EQ(std::sscanf(r.report.origin.c_str() + at + key.size(), "%lf, %lf, %lf", &written[0], &written[1], &written[2]), 3)
      << r.report.origin;
  // %.4g in the origin: 5e-5 of rounding at these values; 1e-4 leaves room for the quadratures.
  EXPECT_NEAR(written[0], closest_f0(0.3, 0.4), 1e-4);
  EXPECT_NEAR(written[1], closest_f0(0.5, 0.5), 1e-4);
  EXPECT_NEAR(written[2], 0.05, 1e-12);  // f90 1: Schlick's own F
  EXPECT_GT(0.3 - written[0], 0.01);     // the flat F is not left as F0
  EXPECT_LT(r.report.errors.relative_l2cos, 0.2);
}

TEST(ExportExact, NamedSpectraWhenTheMetalMatches) {
  GgxSource g = ggx(0.1, 0.1);
  g.metal = "gold", g.symbol = "Au";
  json p;
  target_model(Target::PbrtV4, g, &p);
  EXPECT_EQ(p["eta"], "metal-Au-eta");
  EXPECT_EQ(p["remaproughness"], false);
  target_model(Target::Mitsuba3, g, &p);
  EXPECT_EQ(p["material"], "Au");
  g.metal = "nickel", g.symbol = "Ni";  // not among either renderer's names: values
  target_model(Target::PbrtV4, g, &p);
  EXPECT_TRUE(p["eta"].is_array());
}

// An <rgb> eta / k above 1 is clipped by Mitsuba 3's spectral variants (the bounded rgb2spec
// upsampling; measured by bench/mitsuba3/compare.py: nickel at 0.41 of its brightness under
// scalar_spectral, right under scalar_rgb): the export says to render it with an RGB variant. A
// named conductor (Mitsuba's own spectra) and pbrt-v4's rgb eta / k (RGBUnboundedSpectrum) do not
// need the note.
TEST(ExportExact, MitsubaRgbEtaKSaysRenderWithAnRgbVariant) {
  const auto says = [](const ExportResult& r) {
    for (const std::string& n : r.report.notes)
      if (n.find("render with an RGB variant") != std::string::npos) return true;
    return false;
  };
  const char* nickel = R"({"model": "metal", "metal": "nickel", "lobe": {"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3}})";
  const char* gold = R"({"model": "metal", "metal": "gold", "lobe": {"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3}})";
  const ExportResult mi_nickel = export_material(load_material(nickel), "nickel", quick("mitsuba3"));
  EXPECT_TRUE(mi_nickel.report.parameters["eta"].is_array());
  EXPECT_TRUE(says(mi_nickel)) << mi_nickel.report.text();
  EXPECT_FALSE(says(export_material(load_material(gold), "gold", quick("mitsuba3"))));
  EXPECT_FALSE(says(export_material(load_material(nickel), "nickel", quick("pbrt-v4"))));
}

TEST(ExportExact, GgxSourceToPbrtIsExactUpToItsMaskingAndFresnel) {
  const MaterialDesc d =
      load_material(R"({"model": "metal", "metal": "gold", "lobe": {"model": "ggx", "alpha_x": 0.2, "alpha_y": 0.08}})");
  const ExportResult r = export_material(d, "gold", quick("pbrt-v4"));
  EXPECT_TRUE(r.report.exact);
  // pbrt-v4's conductor is aniso's metal with a GGX lobe, term for term.
  EXPECT_LT(r.report.errors.relative_l2cos, 1e-9);
  EXPECT_LT(r.report.max_albedo_difference, 1e-9);
  const ExportResult m = export_material(d, "gold", quick("mitsuba3"));
  EXPECT_GT(m.report.errors.relative_l2cos, 1e-4);  // separable masking differs
  EXPECT_LT(m.report.errors.relative_l2cos, 0.1);
}

// ---- fitted path: the standard materials' errors per target, pinned -------------------------------

// Each row: the error of the written target model against the source samples (relative l2cos and
// log), measured at grid 3, 2 starts and the refinement on 1500 samples (docs/export.md gives the default grid's); a regression
// of more than 10 % (plus 0.005) fails.
struct Pinned {
  const char* material;
  const char* target;
  double relative_l2cos, log;
};

constexpr const char* kWard =
    R"({"model": "ward", "kd": 0.05, "ks": 0.4, "alpha_x": 0.05, "alpha_y": 0.3, "normalization": "balanced"})";
constexpr const char* kAS = R"({"model": "ashikhmin-shirley", "rd": 0.3, "rs": 0.05, "n_u": 100, "n_v": 10})";

TEST(ExportFit, StandardMaterialsPerTarget) {
  const std::vector<Pinned> pinned = {
#include "export_pinned.inc"
#include "export_pinned_openpbr.inc"
  };
  const bool print = std::getenv("ANISO_EXPORT_PRINT") != nullptr;
  // Scale (ANISO_TEST_SCALE, test_util.h): the release suite (scale 1) fits all four materials; the
  // sanitizer suite (0.25) the first two, a metal and a Lafortune source, through every target's
  // path (the source fit, the refinement, the target model), each against its pinned row: 93 CPU s
  // under ASan instead of 155.
  const std::vector<const char*> materials = {"brushed-gold", "matte-steel", kWard, kAS};
  const size_t count = size_t(std::max<int64_t>(2, test::scaled(int64_t(materials.size()))));
  for (size_t i = 0; i < count; ++i) {
    const char* material = materials[i];
    const MaterialDesc d = load_material(material);
    const MaterialD m = build_material<double>(d);
    const SampleSet samples = sample_source(m, 3);
    ExportOptions o;
    o.grid = 3, o.starts = 2, o.refine_samples = 1500;
    const GgxSource g = ggx_source(d, samples, o);
    EXPECT_FALSE(g.exact);
    // Every target, and Blender's again as 3.4's Principled BSDF v1 ("blender-3.4").
    std::vector<std::pair<Target, std::string>> rows;
    for (const TargetInfo& t : targets()) rows.emplace_back(t.target, std::string(t.name));
    rows.emplace_back(Target::Blender, "blender-3.4");
    for (const auto& [target, name] : rows) {
      o.blender_version = name == "blender-3.4" ? 3.4 : 4.3;
      const TargetBrdf tm = target_model(target, refine_for_target(target, g, samples, o), nullptr, nullptr, o.blender_version);
      const FitErrors e = target_errors(tm, samples);
      const std::string label = std::string(material).substr(0, 20);
      if (print)
        std::printf("    {%s, \"%s\", %.4f, %.4f},\n",
                    d.model == "lafortune" ? "\"matte-steel\""
                    : d.model == "metal"   ? "\"brushed-gold\""
                    : d.model == "ward"    ? "kWard"
                                           : "kAS",
                    name.c_str(), e.relative_l2cos, e.log_all);
      int found = 0;
      for (const Pinned& p : pinned) {
        if (std::string(p.target) != name || std::string(p.material) != material) continue;
        ++found;
        EXPECT_LE(e.relative_l2cos, 1.1 * p.relative_l2cos + 0.005) << label << " " << name;
        EXPECT_LE(e.log_all, 1.1 * p.log + 0.005) << label << " " << name;
      }
      EXPECT_EQ(found, 1) << label << " " << name << ": no pinned row";
    }
  }
}

// ---- the written files -----------------------------------------------------------------------------

using ExportCli = Cli;

// A tiny XML well-formedness check: tags nest and close, attributes are quoted; returns the element
// names with their attribute "name" values (MaterialX inputs).
bool xml_well_formed(const std::string& s, std::vector<std::pair<std::string, std::string>>* elements, std::string* why) {
  std::vector<std::string> stack;
  size_t i = 0;
  while ((i = s.find('<', i)) != std::string::npos) {
    if (s.compare(i, 4, "<!--") == 0) {
      const size_t e = s.find("-->", i + 4);
      if (e == std::string::npos) return *why = "unclosed comment", false;
      if (s.substr(i + 4, e - i - 4).find("--") != std::string::npos) return *why = "-- inside a comment", false;
      i = e + 3;
      continue;
    }
    if (s.compare(i, 2, "<?") == 0) {
      i = s.find("?>", i) + 2;
      continue;
    }
    const size_t e = s.find('>', i);
    if (e == std::string::npos) return *why = "unclosed tag", false;
    std::string tag = s.substr(i + 1, e - i - 1);
    i = e + 1;
    if (tag[0] == '/') {
      if (stack.empty() || stack.back() != tag.substr(1)) return *why = "mismatched </" + tag.substr(1) + ">", false;
      stack.pop_back();
      continue;
    }
    const bool empty = tag.back() == '/';
    if (empty) tag.pop_back();
    static const std::regex head(R"re(^([A-Za-z_][\w.-]*)((\s+[A-Za-z_][\w.-]*="[^"<&]*")*)\s*$)re");
    std::smatch m;
    if (!std::regex_match(tag, m, head)) return *why = "malformed tag <" + tag + ">", false;
    std::smatch nm;
    static const std::regex name_attr(R"re(\bname="([^"]*)")re");
    const std::string attrs = m[2].str();
    elements->push_back({m[1].str(), std::regex_search(attrs, nm, name_attr) ? nm[1].str() : ""});
    if (!empty) stack.push_back(m[1].str());
  }
  if (!stack.empty()) return *why = "unclosed <" + stack.back() + ">", false;
  return true;
}

TEST_F(ExportCli, MitsubaXmlParses) {
  for (const char* material : {"gold", "clay"}) {
    const Result r = run(
        {"export", "--to", "mitsuba3", "--material", material, "-o", (dir_ / "m.xml").string(), "--starts", "1", "--grid", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string x = read_file(dir_ / "m.xml");
    std::vector<std::pair<std::string, std::string>> el;
    std::string why;
    ASSERT_TRUE(xml_well_formed(x, &el, &why)) << why << "\n" << x;
    ASSERT_FALSE(el.empty());
    EXPECT_EQ(el[0].first, "scene");
    std::set<std::string> bsdf_types;
    for (size_t i = 0; i < el.size(); ++i)
      EXPECT_TRUE(el[i].first == "scene" || el[i].first == "bsdf" || el[i].first == "float" || el[i].first == "rgb" ||
                  el[i].first == "string")
          << el[i].first;
    EXPECT_TRUE(contains(x, "type=\"roughconductor\"")) << x;
    EXPECT_TRUE(contains(x, "<string name=\"distribution\" value=\"ggx\"/>")) << x;
    EXPECT_TRUE(contains(x, "Exported by aniso " ANISO_VERSION " from")) << x;
  }
}

// pbrt-v4's scene grammar for the statements written: MakeNamedMaterial "name" followed by
// "type name" value pairs, a value being a quoted string, a number, true / false or a bracketed list.
TEST_F(ExportCli, PbrtStatementsParse) {
  for (const char* material : {"gold", "clay", "brushed-copper"}) {
    const Result r = run(
        {"export", "--to", "pbrt-v4", "--material", material, "-o", (dir_ / "m.pbrt").string(), "--starts", "1", "--grid", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    std::string text;
    std::istringstream in(read_file(dir_ / "m.pbrt"));
    for (std::string line; std::getline(in, line);) text += line.substr(0, line.find('#')) + "\n";
    static const std::regex token(R"re(\s*("[^"]*"|\[[^\]]*\]|[A-Za-z]+|[-+0-9.eE]+))re");
    std::vector<std::string> toks;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), token); it != std::sregex_iterator(); ++it)
      toks.push_back((*it)[1]);
    size_t i = 0, statements = 0;
    static const std::set<std::string> types = {"string", "float", "rgb", "spectrum", "bool"};
    while (i < toks.size()) {
      ASSERT_EQ(toks[i], "MakeNamedMaterial") << "token " << i;
      ASSERT_LT(i + 1, toks.size());
      ASSERT_EQ(toks[i + 1].front(), '"');
      i += 2, ++statements;
      while (i < toks.size() && toks[i].front() == '"') {
        const std::string decl = toks[i].substr(1, toks[i].size() - 2);
        const std::string type = decl.substr(0, decl.find(' '));
        EXPECT_TRUE(types.count(type)) << decl;
        ASSERT_LT(i + 1, toks.size());
        const std::string& v = toks[i + 1];
        if (type == "string" || type == "spectrum") {
          EXPECT_TRUE(v.front() == '"' || v.front() == '[') << decl << " " << v;
        }
        if (type == "bool") {
          EXPECT_TRUE(v == "false" || v == "true") << decl;
        }
        if (type == "rgb") {
          EXPECT_EQ(v.front(), '[') << decl;
        }
        i += 2;
      }
    }
    EXPECT_GE(statements, 1u);
  }
}

// MaterialX: element and input names of libraries/bxdf/standard_surface.mtlx (its nodedef inputs)
// and the stdlib's surfacematerial.
TEST_F(ExportCli, MaterialXUsesTheSchemasNames) {
  static const std::set<std::string> inputs = {
      "base",         "base_color",          "metalness",         "specular",     "specular_color", "specular_roughness",
      "specular_IOR", "specular_anisotropy", "specular_rotation", "surfaceshader"};
  for (const char* material : {"gold", "clay"}) {
    const Result r = run({"export", "--to", "materialx", "--material", material, "-o", (dir_ / "m.mtlx").string(), "--starts",
                          "1", "--grid", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string x = read_file(dir_ / "m.mtlx");
    std::vector<std::pair<std::string, std::string>> el;
    std::string why;
    ASSERT_TRUE(xml_well_formed(x, &el, &why)) << why << "\n" << x;
    EXPECT_EQ(el[0].first, "materialx");
    for (const auto& [e, name] : el) {
      EXPECT_TRUE(e == "materialx" || e == "standard_surface" || e == "surfacematerial" || e == "input") << e;
      if (e == "input") {
        EXPECT_TRUE(inputs.count(name)) << name;
      }
    }
  }
}

// glTF 2.0's required fields (the Khronos JSON schema: asset.version; buffer.byteLength;
// bufferView.buffer, byteLength; accessor.componentType, count, type; mesh.primitives[].attributes),
// the buffer's length, and the extension declared in extensionsUsed.
TEST_F(ExportCli, GltfWritesKhrMaterialsSpecularForAnF0Other0p04) {
  const std::string mat = (dir_ / "plastic.json").string();
  std::FILE* f = std::fopen(mat.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(R"({"model": "ggx", "kd": [0.3, 0.2, 0.1], "f0": [0.9, 0.6, 0.02], "alpha_x": 0.2, "alpha_y": 0.1})", f);
  std::fclose(f);
  const std::string out = (dir_ / "plastic.gltf").string();
  const Result r = run({"export", "--to", "gltf", "--material", mat, "-o", out});
  ASSERT_EQ(r.code, 0) << r.err;
  const json doc = json::parse(read_file(out));
  const json& ext = doc["materials"][0]["extensions"]["KHR_materials_specular"];
  EXPECT_EQ(ext["specularFactor"].get<double>(), 1.0);
  // F0 0.9 is above 0.04: KHR_materials_ior carries the largest F0, specularColorFactor the rest,
  // every factor in [0, 1] (no 22.5).
  EXPECT_NEAR(ext["specularColorFactor"][0].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(ext["specularColorFactor"][2].get<double>(), 0.02 / 0.9, 1e-9);
  const double ior = doc["materials"][0]["extensions"]["KHR_materials_ior"]["ior"].get<double>();
  EXPECT_NEAR(std::pow((ior - 1.0) / (ior + 1.0), 2.0), 0.9, 1e-9);
  EXPECT_NE(doc["extensionsUsed"].dump().find("KHR_materials_specular"), std::string::npos) << doc["extensionsUsed"].dump();
  EXPECT_NE(doc["extensionsUsed"].dump().find("KHR_materials_ior"), std::string::npos) << doc["extensionsUsed"].dump();
}

// Mitsuba 3's principled: written for an aniso principled source (the file's parameters are the
// source's), and for a source with a diffuse part where it is closer to the source than the
// blendbsdf (the report says which and both errors).
TEST_F(ExportCli, MitsubaPrincipledForPrincipledAndDiffuseSources) {
  const std::string out = (dir_ / "p.xml").string();
  const Result r =
      run({"export", "--to", "mitsuba3", "--material", "principled/red-plastic", "-o", out, "--starts", "1", "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string x = read_file(out);
  std::vector<std::pair<std::string, std::string>> elements;
  std::string why;
  ASSERT_TRUE(xml_well_formed(x, &elements, &why)) << why << "\n" << x;
  EXPECT_NE(x.find("<bsdf type=\"principled\""), std::string::npos) << x;
  std::set<std::string> names;
  for (const auto& [element, name] : elements) names.insert(name);
  for (const char* key : {"base_color", "roughness", "anisotropic", "metallic", "specular", "spec_tint", "sheen", "sheen_tint",
                          "flatness", "clearcoat", "clearcoat_gloss"})
    EXPECT_TRUE(names.count(key)) << key << "\n" << x;
  EXPECT_NE(x.find("name=\"roughness\" value=\"0.3\""), std::string::npos) << x;  // red-plastic's roughness, carried over

  const MaterialDesc as = load_material(kAS);  // rd 0.3: the fitted GGX has a diffuse part
  ExportOptions o;
  o.target = "mitsuba3", o.grid = 3, o.starts = 2, o.refine_samples = 1500;
  const ExportResult e = export_material(as, kAS, o);
  std::string said;
  for (const std::string& n : e.report.notes)
    if (n.find("written: it is closer") != std::string::npos) said = n;
  EXPECT_FALSE(said.empty()) << e.report.text();
  std::printf("%s: %s\n", e.report.target_model.c_str(), said.c_str());
}

TEST_F(ExportCli, GltfHasTheSchemasRequiredFieldsAndTangents) {
  const std::string out = (dir_ / "gold.gltf").string();
  const Result r = run({"export", "--to", "gltf", "--material", "brushed-gold", "-o", out, "--starts", "1", "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json g = json::parse(read_file(out));
  EXPECT_EQ(g["asset"]["version"], "2.0");
  ASSERT_EQ(g["buffers"].size(), 1u);
  const std::string bin = read_file(dir_ / g["buffers"][0]["uri"].get<std::string>());
  EXPECT_EQ(bin.size(), g["buffers"][0]["byteLength"].get<size_t>());
  for (const json& v : g["bufferViews"]) {
    ASSERT_TRUE(v.contains("buffer") && v.contains("byteLength"));
    EXPECT_LE(v.value("byteOffset", 0) + v["byteLength"].get<size_t>(), bin.size());
  }
  for (const json& a : g["accessors"]) ASSERT_TRUE(a.contains("componentType") && a.contains("count") && a.contains("type"));
  const json& attrs = g["meshes"][0]["primitives"][0]["attributes"];
  EXPECT_TRUE(attrs.contains("POSITION") && attrs.contains("NORMAL") && attrs.contains("TANGENT"));
  EXPECT_EQ(g["accessors"][attrs["TANGENT"].get<int>()]["type"], "VEC4");
  EXPECT_EQ(g["extensionsUsed"][0], "KHR_materials_anisotropy");
  const json& ext = g["materials"][0]["extensions"]["KHR_materials_anisotropy"];
  EXPECT_GT(ext["anisotropyStrength"].get<double>(), 0.0);
  EXPECT_TRUE(g["asset"]["extras"].contains("aniso_export"));
}

TEST(ExportSphere, TangentsAreUnitAndPerpendicularToTheNormals) {
  const SphereMesh m = uv_sphere(8, 16);
  for (size_t v = 0; v < m.positions.size() / 3; ++v) {
    const glm::dvec3 n(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    const glm::dvec3 t(m.tangents[4 * v], m.tangents[4 * v + 1], m.tangents[4 * v + 2]);
    EXPECT_NEAR(glm::length(t), 1.0, 1e-6);
    EXPECT_NEAR(glm::dot(n, t), 0.0, 1e-6);
    EXPECT_EQ(m.tangents[4 * v + 3], 1.0f);
  }
  for (uint16_t i : m.indices) EXPECT_LT(i, m.positions.size() / 3);
}

// Blender: the script runs headless (skipped without blender, with the reason).
TEST_F(ExportCli, BlenderScriptRunsInBlender) {
  const std::string script = (dir_ / "m.py").string();
  const Result r = run({"export", "--to", "blender", "--material", "brushed-gold", "-o", script, "--starts", "1", "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string py = read_file(script);
  EXPECT_TRUE(contains(py, "bpy.app.version")) << py;
  EXPECT_TRUE(contains(py, "ShaderNodeBsdfPrincipled")) << py;
  // The inputs it sets are the Principled BSDF's sockets (node_shader_bsdf_principled.cc,
  // node_declare): 3.x "Specular" (float), 4.x "Specular IOR Level" and a colour "Specular Tint".
  static const std::set<std::string> sockets = {
      "Base Color",         "Metallic",      "Roughness", "Anisotropic", "Anisotropic Rotation", "IOR",     "Specular",
      "Specular IOR Level", "Specular Tint", "Tangent",   "Extinction",  "Anisotropy",           "Rotation"};
  static const std::regex put(R"re(put\("([^"]+)")re");
  int puts = 0;
  for (auto it = std::sregex_iterator(py.begin(), py.end(), put); it != std::sregex_iterator(); ++it, ++puts)
    EXPECT_TRUE(sockets.count((*it)[1])) << (*it)[1];
  EXPECT_GE(puts, 6);
  // Valid Python (the syntax, without Blender).
  if (std::system("command -v python3 > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("python3 -c 'import ast, sys; ast.parse(open(sys.argv[1]).read())' " + shell_quote(script)).c_str()),
              0);
  }
  if (std::system("command -v blender > /dev/null 2>&1") != 0) GTEST_SKIP() << "blender is not installed: the script was not run";
  // A script that makes an object (with a UV map), then execs the export: the material lands on it.
  const std::string out = blender_on_a_uv_sphere(dir_ / "driver.py", script,
                                                 "assert obj.data.materials[0].name == NAME, obj.data.materials[0].name\n"
                                                 "nodes = obj.data.materials[0].node_tree.nodes\n"
                                                 "assert any(n.bl_idname == 'ShaderNodeTangent' for n in nodes)\n");
  EXPECT_TRUE(contains(out, "ANISO_OK")) << out;
}

// Where Blender is absent: the script run by Python against a stand-in for bpy with the Principled
// BSDF's 3.4 and 4.x sockets (tests/export_bpy_stub/bpy.py), with and without a UV map, for a metal
// and a dielectric: every input it sets exists with its type, the node is single-scattering GGX,
// the material lands on the active object, the Tangent node comes with the UV map.
TEST_F(ExportCli, BlenderScriptRunsOnABpyStub) {
  if (std::system("command -v python3 > /dev/null 2>&1") != 0) GTEST_SKIP() << "python3 is not installed";
  for (const char* material : {"gold", R"({"model": "ggx", "kd": 0.3, "f0": 0.04, "alpha_x": 0.1, "alpha_y": 0.3})"}) {
    const std::string script = (dir_ / "m.py").string();
    const Result r = run({"export", "--to", "blender", "--material", material, "-o", script, "--grid", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string check =
        write("check.py",
              "import bpy\n"
              "MATERIAL = '" +
                  std::string(material[0] == '{' ? "ggx" : material) +
                  "'\n"
                  "exec(open(r'" +
                  script +
                  "').read())\n"
                  "obj = bpy.context.view_layer.objects.active\n"
                  "assert obj.data.materials[0] is mat\n"
                  "assert bsdf.distribution == 'GGX'\n"
                  "assert bsdf in nodes and (bsdf.outputs['BSDF'], out.inputs['Surface']) in links\n"
                  "want = 'ShaderNodeBsdfMetallic' if bpy.app.version >= (4, 3, 0) and MATERIAL == 'gold' "
                  "else 'ShaderNodeBsdfPrincipled'\n"
                  "assert bsdf.bl_idname == want, bsdf.bl_idname\n"
                  "assert bsdf.bl_idname != 'ShaderNodeBsdfMetallic' or bsdf.fresnel_type == 'PHYSICAL_CONDUCTOR'\n"
                  "has_tangent = any(n.bl_idname == 'ShaderNodeTangent' for n in nodes)\n"
                  "assert has_tangent == (obj.data.uv_layers.active is not None), has_tangent\n"
                  "print('ANISO_OK')\n");
    for (const char* version : {"3.4", "4.2", "4.3"})
      for (const char* uv : {"0", "1"}) {
        const std::string cmd = "PYTHONPATH=" + shell_quote(std::string(ANISO_SOURCE_DIR) + "/tests/export_bpy_stub") +
                                " ANISO_BPY_VERSION=" + version + " ANISO_BPY_UV=" + uv + " python3 " + shell_quote(check) +
                                " 2>&1";
        const std::string out = command_output(cmd);
        EXPECT_TRUE(contains(out, "ANISO_OK")) << material << " Blender " << version << " uv " << uv << ":\n" << out;
      }
  }
}

// Measured data (a MERL table, here aniso's tabulation of a Ward material): pbrt-v4's own measured
// material with the spectral tensor file beside the scene by default; --analytic takes the fitted
// path (an isotropic GGX: a MERL table is isotropic by construction).
TEST_F(ExportCli, MeasuredMerlTableIsFitted) {
  const std::string merl = (dir_ / "ward.binary").string();
  write_merl(merl,
             tabulate_merl(build_material<double>(load_material(
                 R"({"model": "ward", "kd": 0.1, "ks": 0.2, "alpha_x": 0.1, "alpha_y": 0.25, "normalization": "balanced"})"))));
  const std::string out = (dir_ / "m.pbrt").string();
  const Result r =
      run({"export", "--to", "pbrt-v4", "--material", merl, "-o", out, "--grid", "2", "--starts", "1", "--analytic"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "fitted: aniso's isotropic GGX")) << r.out;
  EXPECT_TRUE(contains(read_file(out), "MakeNamedMaterial")) << read_file(out);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "m_spec.bsdf"));
}

// ---- bad input: exit 2, nothing written ---------------------------------------------------------

TEST_F(ExportCli, UnknownTarget) {
  const std::string out = (dir_ / "x.out").string();
  const Result r = run({"export", "--to", "renderman", "--material", "gold", "-o", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "unknown target \"renderman\"")) << r.err;
  EXPECT_TRUE(contains(r.err, "\"pbrt-v4\"")) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ExportCli, ABlackMaterialCannotBeRepresented) {
  const std::string out = (dir_ / "x.xml").string();
  const Result r = run({"export", "--to", "mitsuba3", "--material", R"({"model": "lambert", "kd": 0})", "-o", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "black")) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ExportCli, UnwritableOutputLeavesNothing) {
  const std::string out = (dir_ / "missing" / "x.gltf").string();
  const Result r = run({"export", "--to", "gltf", "--material", "gold", "-o", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "cannot open for writing")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  // The .bin is written before the .gltf: a .gltf that cannot be written takes the .bin with it.
  fs::create_directory(dir_ / "x.gltf");
  const Result d = run({"export", "--to", "gltf", "--material", "gold", "-o", (dir_ / "x.gltf").string()});
  EXPECT_EQ(d.code, 2) << d.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.bin"));
}

TEST_F(ExportCli, PreviewWritesAPng) {
  const std::string png = (dir_ / "p.png").string();
  const Result r =
      run({"export", "--to", "pbrt-v4", "--material", "gold", "-o", (dir_ / "g.pbrt").string(), "--preview", png, "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_file(png).substr(1, 3), "PNG");
  const Result bad =
      run({"export", "--to", "pbrt-v4", "--material", "gold", "-o", (dir_ / "h.pbrt").string(), "--preview", "x.jpg"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_FALSE(fs::exists(dir_ / "h.pbrt"));
}

TEST_F(ExportCli, ListAndHelpTargets) {
  const Result r = run({"export", "--list-targets"});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* t : {"blender", "mitsuba3", "pbrt-v4", "materialx", "gltf"}) EXPECT_TRUE(contains(r.out, t)) << r.out;
  const Result h = run({"export", "--help-target", "pbrt-v4"});
  ASSERT_EQ(h.code, 0) << h.err;
  EXPECT_TRUE(contains(h.out, "remaproughness false")) << h.out;
}

}  // namespace
}  // namespace aniso
