// aniso/export/targets.h: the BRDFs of the renderers aniso exports to ("target models"), each
// transcribed from that renderer's own source and cited by file and line (docs/export.md has the
// same table). A target model is the specular lobe the renderer evaluates for the parameters the
// exporter writes, plus the diffuse term it adds, so that the exporter can say how far the export
// is from the source (export.h) before anybody renders it.
//
// Sources read (the commit each line number refers to):
//   Blender     blender/blender, intern/cycles/kernel/svm/closure.h @ 02e6985c (4.x/5.x: the
//               Principled BSDF and the Glossy BSDF cases of svm_node_closure_bsdf),
//               intern/cycles/kernel/closure/bsdf_microfacet.h @ 014f6e43 (bsdf_aniso_D,
//               bsdf_aniso_lambda, the height-correlated G in bsdf_microfacet_eval),
//               intern/cycles/kernel/closure/bsdf_util.h (fresnel_f82tint_B, fresnel_f82).
//   Blender 3.4 the kernel source Blender 3.4.1 ships for run-time GPU compiles (Debian 12's
//               blender 3.4.1+dfsg-2: /usr/share/blender/scripts/addons/cycles/source/kernel/ =
//               intern/cycles/kernel/ @ v3.4.1): svm/closure.h (Principled v1), closure/
//               bsdf_microfacet.h, bsdf_util.h, bsdf_principled_diffuse.h, bsdf_microfacet_multi.h.
//   Mitsuba 3   mitsuba-renderer/mitsuba3 @ b45b0a93: src/bsdfs/roughconductor.cpp,
//               include/mitsuba/render/microfacet.h.
//   pbrt-v4     mmp/pbrt-v4 @ 5f7a6068: src/pbrt/util/scattering.h (TrowbridgeReitzDistribution),
//               src/pbrt/bxdfs.h (ConductorBxDF::f), src/pbrt/materials.{h,cpp}.
//   MaterialX   AcademySoftwareFoundation/MaterialX @ 4177b2cb: libraries/pbrlib/genglsl/
//               mx_roughness_anisotropy.glsl, mx_conductor_bsdf.glsl, mx_artistic_ior.glsl,
//               mx_dielectric_bsdf.glsl, mx_layer_bsdf.glsl, lib/mx_microfacet_specular.glsl;
//               libraries/pbrlib/pbrlib_defs.mtlx (ND_dielectric_bsdf); libraries/bxdf/standard_surface.mtlx;
//               documents/Specification/MaterialX.PBRSpec.md (dielectric_bsdf's tint).
//   OpenPBR     AcademySoftwareFoundation/MaterialX @ 4177b2cb: libraries/bxdf/open_pbr_surface.mtlx,
//               libraries/pbrlib/genglsl/mx_generalized_schlick_bsdf.glsl, mx_dielectric_bsdf.glsl,
//               mx_layer_bsdf.glsl, lib/mx_microfacet_specular.glsl; AcademySoftwareFoundation/OpenPBR
//               @ f8d6d947: index.html (the specification).
//   glTF        KhronosGroup/glTF @ 77b44be7: extensions/2.0/Khronos/KHR_materials_anisotropy/README.md,
//               KHR_materials_specular/README.md.
//
// Frames: aniso's local frame (docs/conventions.md): z the normal, x the tangent, y = z x x.
// Every renderer here uses the same right-handed tangent frame (Cycles' make_orthonormals_tangent
// takes Y = N x T; glTF's bitangent is cross(normal, tangent.xyz) tangent.w with w = +1; Mitsuba 3
// and pbrt-v4 shade in (dp/du, n x dp/du, n)).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "aniso/brdf/fresnel.h"
#include "aniso/brdf/ggx.h"

namespace aniso::exporter {

// The Smith masking-shadowing each target multiplies D by.
enum class Masking {
  HeightCorrelated,  // 1 / (1 + L(wi) + L(wo)): Cycles >= 3.5, pbrt-v4, glTF (Heitz 2014 Eq. 99)
  Separable,         // G1(wi) G1(wo): Mitsuba 3 (microfacet.h:329-331), Cycles 3.4 (bsdf_microfacet.h:444)
  // MaterialX: the isotropic height-correlated G2 at the mean alpha sqrt(ax ay)
  // (mx_conductor_bsdf.glsl:23, 38; mx_microfacet_specular.glsl:82-88, 177-180)
  HeightCorrelatedMeanAlpha,
};

// The Fresnel factor of the specular lobe.
enum class FresnelModel {
  Schlick,     // f0 + (1 - f0)(1 - cos)^5 (glTF; Cycles' F82-tint with tint 1)
  Conductor,   // the exact unpolarised conductor Fresnel with eta, k (Mitsuba 3, pbrt-v4, MaterialX)
  Dielectric,  // the exact dielectric Fresnel at the index ior (conductor Fresnel with k = 0)
  F82Tint,     // Cycles 4.x metallic: Schlick(f0) - b cos (1 - cos)^6, clamped to [0, 1]
  // Cycles 3.4 Principled v1: cspec0 (1 - FH) + FH, FH the dielectric Fresnel at ior normalised to
  // [F0(ior), 1] (cycles_v1_fresnel); cspec0 in f0, ior in eta.x.
  CyclesV1,
  // Cycles 4.x Principled dielectric: the same with FH clamped to [0, 1] (cycles_dielectric_tint_fresnel);
  // F0(ior) Specular Tint in f0, ior in eta.x.
  CyclesDielectricTint,
};

struct TargetLobe {
  double alpha_x = 0.1, alpha_y = 0.1;  // GGX roughness along the tangent and the bitangent
  Masking masking = Masking::HeightCorrelated;
  FresnelModel fresnel = FresnelModel::Schlick;
  glm::dvec3 f0{0.04};          // Schlick, F82Tint
  glm::dvec3 f82_b{0.0};        // F82Tint's b (cycles_f82tint_b)
  glm::dvec3 eta{1.5}, k{0.0};  // Conductor; Dielectric uses eta.x
  glm::dvec3 weight{1.0};       // a colour or mix weight the lobe is multiplied by
};

// The parameters of <bsdf type="principled"> the exporter writes (principled.cpp:20-105; no
// spec_trans: reflection only).
struct MitsubaPrincipled {
  glm::dvec3 base_color{0.5};
  double roughness = 0.5, anisotropic = 0.0, metallic = 0.0, specular = 0.5, spec_tint = 0.0;
  double sheen = 0.0, sheen_tint = 0.0, flatness = 0.0, clearcoat = 0.0, clearcoat_gloss = 0.0;
};

// The target's BRDF for the written parameters: weight F D G / (4 cos_i cos_o) + diffuse / pi,
// where glTF's dielectric weights its diffuse term by 1 - F(v.h) (diffuse_times_one_minus_f), and
// with KHR_materials_specular by 1 - max(F) (diffuse_times_one_minus_max_f, README.md:152-157).
struct TargetBrdf {
  std::string name;  // "Cycles 4.x Principled BSDF (metallic)"
  TargetLobe lobe;
  glm::dvec3 diffuse{0.0};
  bool diffuse_times_one_minus_f = false;
  bool diffuse_times_one_minus_max_f = false;
  // MaterialX's dielectric_bsdf layered over the diffuse (a `layer`, mx_layer_bsdf.glsl:5: OpenPBR's
  // dielectric base, open_pbr_surface.mtlx:400-403; standard_surface's specular_layer,
  // standard_surface.mtlx:300-303): the diffuse times the specular's throughput at the view direction,
  // materialx_dielectric_throughput(wo.z, sqrt(alpha_x alpha_y), lobe.eta.x).
  bool diffuse_times_dielectric_throughput = false;
  // >= 0: the diffuse term is Cycles 3.4's Principled diffuse (Burley's, with retro-reflection, at
  // this roughness: cycles_v1_principled_diffuse) instead of Lambert's.
  double burley_roughness = -1.0;
  // The target's tangent, turned from aniso's x axis towards y by this angle (the targets that want
  // the larger alpha along the tangent turn it by 90 degrees instead of swapping the alphas); f()
  // takes directions in aniso's frame.
  double tangent_turn_deg = 0.0;
  // Mitsuba 3's principled BSDF (mitsuba_principled_f) in place of the lobe and the diffuse term.
  bool is_mitsuba_principled = false;
  MitsubaPrincipled principled;
  // The renderers' own measured BSDF (Mitsuba 3 `measured`, pbrt-v4 `measured`): f of the tensor
  // file written beside the scene, read back (pbrt-v4's MeasuredBxDF::f, aniso/brdf/rgl.h), in
  // place of everything above.
  std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)> measured;

  glm::dvec3 fresnel(double cos_theta) const;
  glm::dvec3 f(const Vec3d& wi, const Vec3d& wo) const;
};
inline glm::dvec3 mitsuba_principled_f(const MitsubaPrincipled& p, const Vec3d& wi, const Vec3d& wo);

// --- Blender Cycles -----------------------------------------------------------------------------

// Principled BSDF, closure.h @ 02e6985c, svm_node_closure_bsdf, CLOSURE_BSDF_PRINCIPLED_ID:
//   float alpha_x = sqr(roughness), alpha_y = sqr(roughness);
//   if (anisotropic > 0.0f) { float aspect = sqrtf(1.0f - anisotropic * 0.9f);
//                             alpha_x /= aspect; alpha_y *= aspect; ... }
// roughness and anisotropic are saturatef()'d first. Cycles 3.4 computes the same alphas without
// the `if` (aspect = safe_sqrtf(1 - anisotropic 0.9), alpha_x = r^2 / aspect, alpha_y = r^2 aspect).
inline glm::dvec2 cycles_principled_alpha(double roughness, double anisotropic) {
  const double r = std::clamp(roughness, 0.0, 1.0), a = std::clamp(anisotropic, 0.0, 1.0);
  glm::dvec2 alpha(r * r);
  if (a > 0.0) {
    const double aspect = std::sqrt(1.0 - a * 0.9);
    alpha.x /= aspect, alpha.y *= aspect;
  }
  return alpha;
}

// Glossy (Anisotropic in 3.x) BSDF, closure.h @ 02e6985c, CLOSURE_BSDF_MICROFACET_GGX_ID:
//   float roughness = sqr(saturatef(param1)); float anisotropy = clamp(param2, -0.99f, 0.99f);
//   if (anisotropy < 0.0f) { alpha_x = roughness / (1.0f + anisotropy); alpha_y = roughness * (1.0f + anisotropy); }
//   else { alpha_x = roughness * (1.0f - anisotropy); alpha_y = roughness / (1.0f - anisotropy); }
// (isotropic when |anisotropy| <= 1e-4 or no tangent is connected). Note the sign: a positive
// anisotropy stretches the highlight along the bitangent (alpha_y > alpha_x), the Principled
// BSDF's along the tangent.
inline glm::dvec2 cycles_glossy_alpha(double roughness, double anisotropy) {
  const double r = std::clamp(roughness, 0.0, 1.0), r2 = r * r;
  const double a = std::clamp(anisotropy, -0.99, 0.99);
  if (std::abs(a) <= 1e-4) return glm::dvec2(r2);
  if (a < 0.0) return {r2 / (1.0 + a), r2 * (1.0 + a)};
  return {r2 * (1.0 - a), r2 / (1.0 - a)};
}

// F82-tint (bsdf_util.h, fresnel_f82tint_B and fresnel_f82): with f = 6/7,
//   B = mix(F0, 1, f^5) * (7 / (f^5 f)) * (1 - tint),
//   F(cos) = saturate(mix(F0, 1, (1 - cos)^5) - B cos (1 - cos)^6),
// so that F(1/7) = Schlick(F0, 1/7) * tint. The Principled BSDF passes f82 = min(Specular Tint, 1)
// (closure.h, the metallic component) and F0 = min(Base Color, 1).
inline glm::dvec3 cycles_f82tint_b(const glm::dvec3& f0, const glm::dvec3& tint) {
  const double f = 6.0 / 7.0, f5 = f * f * f * f * f;
  const glm::dvec3 schlick = f0 + (glm::dvec3(1.0) - f0) * f5;
  return schlick * (7.0 / (f5 * f)) * (glm::dvec3(1.0) - tint);
}
inline glm::dvec3 cycles_f82(double cos_theta, const glm::dvec3& f0, const glm::dvec3& b) {
  const double s = std::clamp(1.0 - cos_theta, 0.0, 1.0), s5 = s * s * s * s * s;
  const glm::dvec3 schlick = f0 + (glm::dvec3(1.0) - f0) * s5;
  return glm::clamp(schlick - b * (cos_theta * s5 * s), 0.0, 1.0);
}

// The Specular Tint that makes F82-tint pass through the source's reflectance at cos = 1/7
// (about 82 degrees): tint = F_source(1/7) / Schlick(F0, 1/7), clamped to [0, 1] as Cycles does.
inline glm::dvec3 cycles_tint_for(const glm::dvec3& f0, const glm::dvec3& f_at_82) {
  const double s = 6.0 / 7.0, s5 = s * s * s * s * s;
  const glm::dvec3 schlick = f0 + (glm::dvec3(1.0) - f0) * s5;
  return glm::clamp(f_at_82 / schlick, 0.0, 1.0);
}

// --- Blender 3.4: the Principled BSDF v1 --------------------------------------------------------
// Blender 3.4.1, intern/cycles/kernel/svm/closure.h, case CLOSURE_BSDF_PRINCIPLED_ID (lines 114-488):
//   diffuse_weight = (1 - metallic)(1 - transmission)                                 (line 169)
//   diffuse: weight base_color diffuse_weight, bsdf_principled_diffuse_setup(FULL)     (lines 226-239)
//   specular (lines 300-348): ior = 2 / (1 - safe_sqrtf(0.08 specular)) - 1  (the IOR input is
//     for transmission only); aspect = safe_sqrtf(1 - 0.9 anisotropic), alpha_x = r^2 / aspect,
//     alpha_y = r^2 aspect; m_cdlum = 0.3 R + 0.6 G + 0.1 B, m_ctint = base_color / m_cdlum;
//     cspec0 = specular 0.08 mix(1, m_ctint, specular_tint) (1 - metallic) + base_color metallic;
//     distribution GGX (or roughness <= 0.075): bsdf_microfacet_ggx_fresnel_setup, else the
//     multiscatter GGX (bsdf_microfacet_multi_ggx_fresnel_setup). The lobe's weight is 1 (no
//     transmission) and the diffuse is added to it, not layered under it.
// closure/bsdf_microfacet.h: bsdf_microfacet_ggx_fresnel_setup (lines 310-323) saturates cspec0 and
//   both alphas; bsdf_microfacet_ggx_eval_reflect (lines 360-465) returns F G D / (4 cosNO) (the
//   BRDF times cosNI) with G = G1o G1i, the separable Smith G1 of the anisotropic GGX
//   (alphaO2 = cos^2 phi alpha_x^2 + sin^2 phi alpha_y^2, lines 422-441), and F = reflection_color
//   (lines 236-250) = interpolate_fresnel_color(L, H, ior, fresnel_dielectric_cos(1, ior), cspec0).
// closure/bsdf_util.h:94-105, interpolate_fresnel_color: FH = (fresnel_dielectric_cos(L.H, ior) -
//   F0) / (1 - F0); cspec0 (1 - FH) + FH. For a dielectric with specular_tint 0, cspec0 = 0.08
//   specular = F0(ior) and F is the exact dielectric Fresnel; for a metal (cspec0 = base_color) the
//   curve rises from base_color to 1 with the dielectric's shape at the Specular input's ior.
inline double cycles_v1_ior(double specular) { return 2.0 / (1.0 - std::sqrt(std::max(0.08 * specular, 0.0))) - 1.0; }
inline glm::dvec3 cycles_v1_cspec0(const glm::dvec3& base_color, double metallic, double specular, double specular_tint) {
  const double lum = 0.3 * base_color.x + 0.6 * base_color.y + 0.1 * base_color.z;
  const glm::dvec3 ctint = lum > 0.0 ? base_color / lum : glm::dvec3(1.0);
  const glm::dvec3 tmp = glm::dvec3(1.0 - specular_tint) + ctint * specular_tint;
  return glm::clamp(specular * 0.08 * tmp * (1.0 - metallic) + base_color * metallic, 0.0, 1.0);
}
inline glm::dvec3 cycles_v1_fresnel(double cos_lh, const glm::dvec3& cspec0, double ior) {
  const double F0 = F_Conductor(1.0, ior, 0.0);
  const double FH = (F_Conductor(cos_lh, ior, 0.0) - F0) / (1.0 - F0);
  return cspec0 * (1.0 - FH) + glm::dvec3(FH);
}
// Cycles 4.x's Principled dielectric (closure.h @ 02e6985c, "Apply IOR adjustment" and the Specular
// component: fresnel->f0 = F0_from_ior(eta) specular_tint, f90 = 1, exponent = -eta) evaluates the
// generalized Schlick Fresnel with a negative exponent as the real Fresnel curve's interpolation
// (bsdf_microfacet.h, fresnel_generalized_schlick / microfacet_fresnel, GENERALIZED_SCHLICK, exponent
// < 0): s = saturatef(inverse_lerp(F0_real, 1, F_real)), F = mix(f0, f90, s). This is 3.4's
// interpolated Fresnel with cspec0 = F0(ior) tint, and with a white tint the exact dielectric
// Fresnel, except where the dielectric curve dips below its F0 (unpolarised light, ior above about
// 2.4): there s is clamped at 0 (a stored earlier 4.x version, "Used by Principled v1", has no
// saturatef; 3.4's interpolate_fresnel_color none either), so that a tinted channel never goes negative.
inline glm::dvec3 cycles_dielectric_tint_fresnel(double cos_lh, const glm::dvec3& f0, double ior) {
  const double F0 = F_Conductor(1.0, ior, 0.0);
  const double s = std::clamp((F_Conductor(cos_lh, ior, 0.0) - F0) / (1.0 - F0), 0.0, 1.0);
  return f0 * (1.0 - s) + glm::dvec3(s);
}
// A dielectric's Specular and Specular Tint (metallic 0) for a Schlick F0 over the diffuse colour
// base_color. cspec0 = 0.08 Specular ((1 - Specular Tint) + Specular Tint m_ctint) lies in the cone of
// white and m_ctint = base_color / m_cdlum (closure.h:327-334): F0 / 0.08 = a white + b m_ctint,
// a, b >= 0, by non-negative least squares over the channels; Specular = a + b, Specular Tint =
// b / (a + b). A hue outside the cone (a blue F0 over a yellow diffuse) cannot be written: its
// projection is. Specular is not capped at 1: the socket's declared 0..1 (node_shader_bsdf_principled.cc,
// node_declare) is only its soft range (rna_nodetree.c, rna_NodeSocketStandard_float_range: hard
// range -FLT_MAX..FLT_MAX), and Cycles reads it unclamped (closure.h:141, 317, 333). At most
// kCyclesV1SpecularMax, where 0.08 Specular = 0.96 and the ior (98) is still finite.
inline constexpr double kCyclesV1SpecularMax = 12.0;
struct CyclesV1Specular {
  double specular = 0.0, tint = 0.0;
};
inline CyclesV1Specular cycles_v1_dielectric_specular(const glm::dvec3& f0, const glm::dvec3& base_color) {
  const glm::dvec3 y = glm::max(f0, 0.0) / 0.08, w(1.0);
  const double lum = 0.3 * base_color.x + 0.6 * base_color.y + 0.1 * base_color.z;
  const glm::dvec3 c = lum > 0.0 ? base_color / lum : w;
  const auto residual = [&](double a, double b) {
    const glm::dvec3 r = a * w + b * c - y;
    return glm::dot(r, r);
  };
  // The candidates of the active-set enumeration: white alone, the tint alone, both.
  double a = std::max(0.0, glm::dot(y, w) / 3.0), b = 0.0;
  if (const double bc = std::max(0.0, glm::dot(y, c) / glm::dot(c, c)); residual(0.0, bc) < residual(a, b)) a = 0.0, b = bc;
  const double ww = 3.0, wc = glm::dot(w, c), cc = glm::dot(c, c), det = ww * cc - wc * wc;
  if (det > 1e-12 * ww * cc) {
    const double a2 = (cc * glm::dot(w, y) - wc * glm::dot(c, y)) / det, b2 = (ww * glm::dot(c, y) - wc * glm::dot(w, y)) / det;
    if (a2 >= 0.0 && b2 >= 0.0 && residual(a2, b2) < residual(a, b)) a = a2, b = b2;
  }
  CyclesV1Specular s;
  s.specular = a + b;
  s.tint = s.specular > 0.0 ? b / s.specular : 0.0;
  s.specular = std::min(s.specular, kCyclesV1SpecularMax);
  return s;
}
// closure/bsdf_principled_diffuse.h:45-86 (PRINCIPLED_DIFFUSE_FULL), as a BRDF times pi:
//   FV, FL = (1 - cos)^5; (1 - FV / 2)(1 - FL / 2) + RR (FL + FV + FL FV (RR - 1)), RR = roughness
//   (L.V + 1): Burley's 2012 diffuse with retro-reflection (2 cos_d^2 = L.V + 1).
inline double cycles_v1_principled_diffuse(double roughness, const Vec3d& wi, const Vec3d& wo) {
  const auto w5 = [](double c) {
    const double m = std::clamp(1.0 - c, 0.0, 1.0);
    return m * m * m * m * m;
  };
  const double FL = w5(wi.z), FV = w5(wo.z), RR = roughness * (glm::dot(wi, wo) + 1.0);
  return (1.0 - 0.5 * FV) * (1.0 - 0.5 * FL) + RR * (FL + FV + FL * FV * (RR - 1.0));
}

// --- Mitsuba 3 principled ------------------------------------------------------------------------

// src/bsdfs/principledhelpers.h:320-331, calc_dist_params: roughness_2 = roughness^2;
//   isotropic: a = max(0.001, roughness_2); else aspect = sqrt(1 - 0.9 anisotropic),
//   { max(0.001, roughness_2 / aspect), max(0.001, roughness_2 * aspect) }.
// The same mapping as aniso's principled (principled.h) and Blender's Principled BSDF, with
// aniso's 0.001 clamp.
inline glm::dvec2 mitsuba_principled_alpha(double roughness, double anisotropic, bool has_anisotropic) {
  const double r2 = roughness * roughness;
  if (!has_anisotropic) return glm::dvec2(std::max(0.001, r2));
  const double aspect = std::sqrt(1.0 - 0.9 * anisotropic);
  return {std::max(0.001, r2 / aspect), std::max(0.001, r2 * aspect)};
}

// principled.cpp:227-230: without "eta", m_eta = 2 / (1 - sqrt(0.08 specular)) - 1, so that
// schlick_R0_eta(eta) = ((eta - 1) / (eta + 1))^2 = 0.08 specular (principledhelpers.h:179-182).
inline double mitsuba_principled_eta(double specular) { return 2.0 / (1.0 - std::sqrt(0.08 * specular)) - 1.0; }

// Mitsuba's luminance of an RGB (include/mitsuba/core/spectrum.h:439-442), which its c_tint divides by.
inline double mitsuba_luminance(const glm::dvec3& c) { return c.x * 0.212671 + c.y * 0.715160 + c.z * 0.072169; }

// Its reflection, principled.cpp:493-708 (eval) for wi, wo above the surface, spec_trans 0, as a
// BRDF (eval returns f cos(theta_o)):
//   specular   F_principled D G / (4 cos_i cos_o), D the anisotropic GGX with calc_dist_params'
//              alphas, G = smith_g1(wi) smith_g1(wo) (microfacet.h:329-331: separable);
//   F_principled (principledhelpers.h:239-275) = (1 - metallic)(1 - spec_tint) F_dielectric(wi.h; eta)
//              + metallic Schlick(base_color) + (1 - metallic) spec_tint Schlick(c_tint 0.08 specular),
//              F_dielectric the exact dielectric Fresnel (fresnel.h), Schlick(R0) = R0 + (1 - R0)(1 - wi.h)^5
//              (calc_schlick, principledhelpers.h:157-170, eta > 1), c_tint = base_color / luminance;
//   diffuse    (1 - metallic) base_color / pi mix(f_diff + f_retro, f_ss, flatness) (lines 643-680):
//              f_diff = (1 - Fi / 2)(1 - Fo / 2), Rr = 2 roughness (wh.wo)^2,
//              f_retro = Rr (Fo + Fi + Fo Fi (Rr - 1)), f_ss = 1.25 (Fss (1 / (cos_o + cos_i) - 1/2) + 1/2),
//              Fss = mix(1, Rr / 2, Fo) mix(1, Rr / 2, Fi), Fi, Fo = (1 - cos)^5 (schlick_weight);
//   sheen      (1 - metallic) sheen (1 - wh.wo)^5 mix(1, c_tint, sheen_tint) (lines 681-706);
//   clearcoat  0.25 clearcoat Schlick(0.04) D_GTR1(mix(0.1, 0.001, gloss)) G1(wi) G1(wo) with
//              smith_ggx1 at alpha 0.25 (lines 619-641, principledhelpers.h:21-40, 77-111): the
//              product has no 1 / (4 cos_i cos_o), which Burley's (and aniso's) clearcoat has.
// Directions in the lobe's frame (x its tangent).
inline glm::dvec3 mitsuba_principled_f(const MitsubaPrincipled& p, const Vec3d& wi, const Vec3d& wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return glm::dvec3(0.0);
  const Vec3d h = glm::normalize(wi + wo);
  const double ci = wi.z, co = wo.z, hi = glm::dot(wi, h), ho = glm::dot(wo, h);
  const auto weight = [](double c) {
    const double m = std::clamp(1.0 - c, 0.0, 1.0);
    return m * m * m * m * m;
  };
  const auto schlick = [&](const glm::dvec3& r0) { return r0 + (glm::dvec3(1.0) - r0) * weight(hi); };
  const glm::dvec2 a = mitsuba_principled_alpha(p.roughness, p.anisotropic, true);
  const double D = D_GGX_Aniso(h.x, h.y, h.z, a.x, a.y);
  const double G = G1_SmithGGX(Lambda_GGX_Aniso(wi, a.x, a.y)) * G1_SmithGGX(Lambda_GGX_Aniso(wo, a.x, a.y));
  const double lum = mitsuba_luminance(p.base_color);
  const glm::dvec3 c_tint = lum > 0.0 ? p.base_color / lum : glm::dvec3(1.0);
  const double eta = mitsuba_principled_eta(p.specular);
  const glm::dvec3 F = (1.0 - p.metallic) * (1.0 - p.spec_tint) * glm::dvec3(F_Conductor(hi, eta, 0.0)) +
                       p.metallic * schlick(p.base_color) +
                       (1.0 - p.metallic) * p.spec_tint * schlick(c_tint * (0.08 * p.specular));
  glm::dvec3 out = F * (D * G / (4.0 * ci * co));
  const double Fi = weight(ci), Fo = weight(co), Rr = 2.0 * p.roughness * ho * ho;
  const double f_diff = (1.0 - 0.5 * Fi) * (1.0 - 0.5 * Fo), f_retro = Rr * (Fo + Fi + Fo * Fi * (Rr - 1.0));
  const double Fss = (1.0 + (Rr / 2.0 - 1.0) * Fo) * (1.0 + (Rr / 2.0 - 1.0) * Fi);
  const double f_ss = 1.25 * (Fss * (1.0 / (co + ci) - 0.5) + 0.5);
  out += (1.0 - p.metallic) * p.base_color * kInvPi<double> * ((f_diff + f_retro) * (1.0 - p.flatness) + f_ss * p.flatness);
  out += (1.0 - p.metallic) * p.sheen * weight(ho) * (glm::dvec3(1.0) * (1.0 - p.sheen_tint) + c_tint * p.sheen_tint);
  if (p.clearcoat > 0.0) {
    const double g = 0.1 * (1.0 - p.clearcoat_gloss) + 0.001 * p.clearcoat_gloss, g2 = g * g;
    const double Dcc = (g2 - 1.0) / (kPi<double> * std::log(g2) * (1.0 + (g2 - 1.0) * h.z * h.z));
    const auto g1 = [](const Vec3d& v) {
      const double c2 = v.z * v.z, t2 = (1.0 - c2) / c2;
      return 2.0 / (1.0 + std::sqrt(1.0 + 0.0625 * t2));
    };
    out += glm::dvec3(0.25 * p.clearcoat * (0.04 + 0.96 * weight(hi)) * Dcc * g1(wi) * g1(wo));
  }
  return out;
}

// --- MaterialX ---------------------------------------------------------------------------------

// mx_roughness_anisotropy.glsl:1-15:
//   float roughness_sqr = clamp(roughness*roughness, M_FLOAT_EPS, 1.0);
//   if (anisotropy > 0.0) { float aspect = sqrt(1.0 - clamp(anisotropy, 0.0, 0.98));
//       result.x = min(roughness_sqr / aspect, 1.0); result.y = roughness_sqr * aspect; }
//   else { result.x = roughness_sqr; result.y = roughness_sqr; }
// M_FLOAT_EPS is 1e-8 in MaterialX's GLSL (mx_math.glsl).
inline glm::dvec2 materialx_alpha(double roughness, double anisotropy) {
  const double r2 = std::clamp(roughness * roughness, 1e-8, 1.0);
  if (anisotropy > 0.0) {
    const double aspect = std::sqrt(1.0 - std::clamp(anisotropy, 0.0, 0.98));
    return {std::min(r2 / aspect, 1.0), r2 * aspect};
  }
  return glm::dvec2(r2);
}

// mx_artistic_ior.glsl:1-17 (Gulbrandsen 2014): reflectivity r and edge colour g to n, k.
//   r = clamp(reflectivity, 0, 0.99); n_min = (1 - r) / (1 + r); n_max = (1 + sqrt r) / (1 - sqrt r);
//   n = mix(n_max, n_min, g); k^2 = ((n + 1)^2 r - (n - 1)^2) / (1 - r), k = sqrt(max(k^2, 0)).
inline void materialx_artistic_ior(const glm::dvec3& reflectivity, const glm::dvec3& edge, glm::dvec3& n, glm::dvec3& k) {
  const glm::dvec3 r = glm::clamp(reflectivity, 0.0, 0.99), rs = glm::sqrt(r);
  const glm::dvec3 n_min = (glm::dvec3(1.0) - r) / (glm::dvec3(1.0) + r);
  const glm::dvec3 n_max = (glm::dvec3(1.0) + rs) / (glm::dvec3(1.0) - rs);
  n = n_max * (glm::dvec3(1.0) - edge) + n_min * edge;
  const glm::dvec3 np1 = n + 1.0, nm1 = n - 1.0;
  k = glm::sqrt(glm::max((np1 * np1 * r - nm1 * nm1) / (glm::dvec3(1.0) - r), 0.0));
}
// Its inverse (Gulbrandsen 2014, Eq. 10): g = (n_max - n) / (n_max - n_min), r = F(0; n, k),
// clamped to [0, 1] (an n outside [n_min, n_max] has no edge colour in this model).
inline void materialx_artistic_from_ior(const glm::dvec3& n, const glm::dvec3& k, glm::dvec3& reflectivity, glm::dvec3& edge) {
  reflectivity = glm::clamp(((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k), 0.0, 0.99);
  const glm::dvec3 r = reflectivity, rs = glm::sqrt(r);
  const glm::dvec3 n_min = (glm::dvec3(1.0) - r) / (glm::dvec3(1.0) + r);
  const glm::dvec3 n_max = (glm::dvec3(1.0) + rs) / (glm::dvec3(1.0) - rs);
  edge = glm::clamp((n_max - n) / glm::max(n_max - n_min, 1e-12), 0.0, 1.0);
}

// --- OpenPBR (MaterialX open_pbr_surface) -------------------------------------------------------

// open_pbr_surface.mtlx:608-654 (NG_open_pbr_anisotropy: invert, square, add 1, divide 2 by it,
// sqrt, times roughness^2; alpha_y = (1 - anisotropy) alpha_x), the OpenPBR specification's
// Eq. openpbr-anisotropy-formula (index.html:412-415):
//   alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)),  alpha_b = (1 - a) alpha_t,
// so alpha_t^2 + alpha_b^2 = 2 r^4 whatever a. The node clamps nothing (a is [0, 1] by its ui range
// only; a < 0 stretches along the bitangent); the BSDFs clamp each alpha to [M_FLOAT_EPS, 1]
// (mx_generalized_schlick_bsdf.glsl:30, mx_dielectric_bsdf.glsl:28), which openpbr_safe_alpha does.
inline glm::dvec2 openpbr_alpha(double roughness, double anisotropy) {
  const double inv = 1.0 - anisotropy, at = roughness * roughness * std::sqrt(2.0 / (1.0 + inv * inv));
  return {at, inv * at};
}
inline glm::dvec2 openpbr_safe_alpha(const glm::dvec2& a) { return glm::clamp(a, 1e-8, 1.0); }

// mx_microfacet_specular.glsl:91-108, mx_ggx_dir_albedo_analytic (the GLSL generator's default,
// DIRECTIONAL_ALBEDO_ANALYTIC, MaterialXGenShader/GenOptions.h:89): a rational fit of the GGX lobe's
// directional albedo, F0 A + F90 B.
inline double materialx_ggx_dir_albedo(double NdotV, double alpha, double F0, double F90) {
  const double x = NdotV, y = alpha, x2 = x * x, y2 = y * y;
  const auto r = [&](double c0, double c1, double c2, double c3, double c4, double c5, double c6, double c7, double c8) {
    return c0 + c1 * x + c2 * y + c3 * x * y + c4 * x2 + c5 * y2 + c6 * x2 * y + c7 * x * y2 + c8 * x2 * y2;
  };
  const double rx = r(0.1003, -0.6303, 9.748, -2.038, 29.34, -8.245, -26.44, 19.99, -5.448);
  const double ry = r(0.9345, -2.323, 2.229, -3.748, 1.424, -0.7684, 1.436, 0.2913, 0.6286);
  const double rz = r(1.0, -1.765, 8.263, 11.53, 28.96, -7.507, -36.11, 15.86, 33.37);
  const double rw = r(1.0, 0.2281, 15.94, -55.83, 13.08, 41.26, 54.9, 300.2, -285.1);
  const double A = std::clamp(rx / rz, 0.0, 1.0), B = std::clamp(ry / rw, 0.0, 1.0);
  return F0 * A + F90 * B;
}

// The throughput of MaterialX's dielectric_bsdf in reflection (mx_dielectric_bsdf.glsl:23-49; the
// specular of open_pbr_surface and of standard_surface, each at weight 1): with
// NdotV = clamp(wo.z, M_FLOAT_EPS, 1) and F0 = mx_ior_to_f0(ior) = ((ior - 1) / (ior + 1))^2,
//   comp = 1 + Fss (1 - Ess) / Ess, Fss = F0 + (1 - F0) / 21, Ess = albedo(NdotV, alpha, 1, 1)
//          (mx_ggx_energy_compensation and mx_fresnel_average, mx_microfacet_specular.glsl:503-521),
//   throughput = 1 - albedo(NdotV, alpha, F0, 1) comp   (weight 1),
// which the `layer` multiplies the diffuse base by (mx_layer_bsdf.glsl:5).
inline double materialx_dielectric_throughput(double cos_o, double avg_alpha, double ior) {
  const double NdotV = std::clamp(cos_o, 1e-8, 1.0), f0 = ((ior - 1.0) / (ior + 1.0)) * ((ior - 1.0) / (ior + 1.0));
  const double ess = materialx_ggx_dir_albedo(NdotV, avg_alpha, 1.0, 1.0), fss = f0 + (1.0 - f0) / 21.0;
  const double comp = 1.0 + fss * (1.0 - ess) / ess;
  return 1.0 - materialx_ggx_dir_albedo(NdotV, avg_alpha, f0, 1.0) * comp;
}

// The metal's Fresnel, F82-tint (OpenPBR index.html:541-558; mx_fresnel_hoffman_schlick,
// mx_microfacet_specular.glsl:201-209, with color90 1 and exponent 5, the generalized_schlick_bsdf
// defaults, pbrlib_defs.mtlx:103-104):
//   a = mix(F0, 1, (1 - 1/7)^5) (1 - F82) / (1/7 (1 - 1/7)^6),  F = mix(F0, 1, (1 - x)^5) - a x (1 - x)^6,
// F0 = base_weight base_color, F82 = specular_color. a is Cycles' B (cycles_f82tint_b) term for
// term, so the target model uses cycles_f82tint_b and cycles_f82; cycles_f82 clamps F to [0, 1],
// MaterialX does not (the exporter notes when the written curve leaves [0, 1]).

// --- glTF (KHR_materials_anisotropy) ------------------------------------------------------------

// README.md:88-100, 156-157: alpha = roughness^2 (the material's alphaRoughness);
//   at = mix(alphaRoughness, 1.0, anisotropy * anisotropy); ab = alphaRoughness;
// along the anisotropy direction (the tangent rotated by anisotropyRotation, counter-clockwise
// towards the bitangent, README.md:68) and across it.
inline glm::dvec2 gltf_alpha(double roughness, double strength) {
  const double a = roughness * roughness, s2 = strength * strength;
  return {a * (1.0 - s2) + s2, a};
}

// KHR_materials_specular (KhronosGroup/glTF @ 77b44be7, extensions/2.0/Khronos/
// KHR_materials_specular/README.md:144-157):
//   dielectric_f0 = min(0.04 * specularColor, float3(1.0)) * specular; dielectric_f90 = specular;
//   dielectric_fresnel = mix(dielectric_f0, dielectric_f90, fresnel_w)   (fresnel_w = (1 - |v.h|)^5)
//   dielectric_brdf = dielectric_fresnel * specular_brdf + (1 - max_value(dielectric_fresnel)) * diffuse_brdf
// So a Schlick F0 (f90 = 1) is specular = 1, specularColor = F0 / 0.04 when max(F0) <= 0.04. A
// larger F0 would need a factor above 1 (the extension allows it, README.md:125, and clamps the
// product; an F0 of 0.46 gave 11.6): instead the 0.04 is raised with KHR_materials_ior, whose ior
// replaces it by ((ior - 1) / (ior + 1))^2 (MaterialX's glTF PBR graph, gltf_pbr.mtlx:
// dielectric_f0_from_ior, dielectric_f0_from_ior_specular_color = that times specular_color,
// clamped to 1): ior from max(F0) and specularColor = F0 / max(F0), every factor in [0, 1].
// Returns {specularFactor, specularColorFactor, ior} (ior 1.5, glTF's default, when not needed).
struct GltfSpecular {
  double specular;
  glm::dvec3 color;
  double ior;
};
inline double gltf_f0_of_ior(double ior) { return sqr((ior - 1.0) / (ior + 1.0)); }
inline GltfSpecular gltf_specular_for(const glm::dvec3& f0_in) {
  const glm::dvec3 f0 = glm::clamp(f0_in, 0.0, 0.999);
  const double m = std::max({f0.x, f0.y, f0.z});
  if (m <= 0.04) return {1.0, f0 / 0.04, 1.5};
  const double r = std::sqrt(m);
  return {1.0, f0 / m, (1.0 + r) / (1.0 - r)};
}
inline glm::dvec3 gltf_dielectric_f0(double specular, const glm::dvec3& specular_color, double ior = 1.5) {
  return glm::min(gltf_f0_of_ior(ior) * specular_color, glm::dvec3(1.0)) * specular;
}

// --- the shared evaluation ----------------------------------------------------------------------

inline glm::dvec3 TargetBrdf::fresnel(double c) const {
  switch (lobe.fresnel) {
    case FresnelModel::Schlick: return F_Schlick(RGBT<double>(lobe.f0), c);
    case FresnelModel::Conductor: return F_Conductor(c, RGBT<double>(lobe.eta), RGBT<double>(lobe.k));
    case FresnelModel::Dielectric: return glm::dvec3(F_Conductor(c, lobe.eta.x, 0.0));
    case FresnelModel::F82Tint: return cycles_f82(c, lobe.f0, lobe.f82_b);
    case FresnelModel::CyclesV1: return cycles_v1_fresnel(c, lobe.f0, lobe.eta.x);
    case FresnelModel::CyclesDielectricTint: return cycles_dielectric_tint_fresnel(c, lobe.f0, lobe.eta.x);
  }
  return glm::dvec3(1.0);
}

inline glm::dvec3 TargetBrdf::f(const Vec3d& wi_in, const Vec3d& wo_in) const {
  if (!(wi_in.z > 0.0) || !(wo_in.z > 0.0)) return glm::dvec3(0.0);
  if (measured) return measured(wi_in, wo_in);
  Vec3d wi = wi_in, wo = wo_in;
  if (tangent_turn_deg != 0.0) {
    // Components along the turned tangent t' = cos a x + sin a y and b' = -sin a x + cos a y.
    const double a = tangent_turn_deg * kPi<double> / 180.0, c = std::cos(a), s = std::sin(a);
    wi = Vec3d(c * wi_in.x + s * wi_in.y, -s * wi_in.x + c * wi_in.y, wi_in.z);
    wo = Vec3d(c * wo_in.x + s * wo_in.y, -s * wo_in.x + c * wo_in.y, wo_in.z);
  }
  if (is_mitsuba_principled) return mitsuba_principled_f(principled, wi, wo);
  const Vec3d h = glm::normalize(wi + wo);
  const double ax = lobe.alpha_x, ay = lobe.alpha_y;
  const double D = D_GGX_Aniso(h.x, h.y, h.z, ax, ay);
  double G = 0.0;
  switch (lobe.masking) {
    case Masking::HeightCorrelated:
      G = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, ax, ay), Lambda_GGX_Aniso(wo, ax, ay));
      break;
    case Masking::Separable: G = G1_SmithGGX(Lambda_GGX_Aniso(wi, ax, ay)) * G1_SmithGGX(Lambda_GGX_Aniso(wo, ax, ay)); break;
    case Masking::HeightCorrelatedMeanAlpha: {
      const double a = std::sqrt(ax * ay);
      G = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, a, a), Lambda_GGX_Aniso(wo, a, a));
      break;
    }
  }
  const glm::dvec3 F = fresnel(glm::dot(wi, h));
  glm::dvec3 out = lobe.weight * F * (D * G / (4.0 * wi.z * wo.z));
  glm::dvec3 d = diffuse * kInvPi<double>;
  if (burley_roughness >= 0.0) d *= cycles_v1_principled_diffuse(burley_roughness, wi, wo);
  if (diffuse_times_one_minus_f) d *= glm::dvec3(1.0) - F;
  if (diffuse_times_one_minus_max_f) d *= 1.0 - std::max({F.x, F.y, F.z});
  if (diffuse_times_dielectric_throughput) d *= materialx_dielectric_throughput(wo.z, std::sqrt(ax * ay), lobe.eta.x);
  return out + d;
}

}  // namespace aniso::exporter
