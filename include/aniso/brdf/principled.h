// aniso/brdf/principled.h: the Disney principled BRDF (Burley 2012, "Physically-Based Shading at
// Disney", SIGGRAPH course notes), as the reference implementation of Disney's BRDF Explorer,
// src/brdfs/disney.brdf (github.com/wdas/brdf; line numbers below are that file's). One
// difference: base_color is linear here (the .brdf file applies pow 2.2 to a display colour,
// mon2lin, lines 81-84 and 97).
//
//   f = ((1/pi) mix(Fd, ss, subsurface) C + Fsheen) (1 - metallic)        (lines 136-138)
//     + Gs Fs Ds                                                          anisotropic GTR2 specular
//     + 0.25 clearcoat Gr Fr Dr                                           GTR1 clearcoat
//
//   Fd   = (1 + (Fd90 - 1) FL)(1 + (Fd90 - 1) FV), Fd90 = 0.5 + 2 roughness (l.h)^2   (lines 106-108)
//   ss   = 1.25 (Fss (1 / (n.l + n.v) - 0.5) + 0.5), Fss as Fd with Fss90 = roughness (l.h)^2
//          (Hanrahan-Krueger subsurface approximation, lines 110-115)
//   Ds   = GTR2 anisotropic = D_GGX_Aniso with ax = max(0.001, roughness^2 / aspect),
//          ay = max(0.001, roughness^2 aspect), aspect = sqrt(1 - 0.9 anisotropic)   (lines 118-121)
//   Gs   = separable Smith GGX, G1(l) G1(v) / (4 (n.l)(n.v)) folded in (lines 76-79, 124-126)
//   Fs   = mix(Cspec0, 1, FH), Cspec0 = mix(0.08 specular mix(1, Ctint, specular_tint), C, metallic)
//   Fsheen = FH sheen mix(1, Ctint, sheen_tint); Ctint = C / lum(C), lum = .3 r + .6 g + .1 b
//   Dr   = GTR1(n.h, mix(0.1, 0.001, clearcoat_gloss)); Fr = mix(0.04, 1, FH);
//   Gr   = separable Smith GGX with alpha 0.25 (lines 131-134)
// FL, FV, FH are Schlick's weight (1 - cos)^5 of n.l, n.v, l.h (lines 42-47).
//
// Sampling: three lobes chosen by estimated weights (the pattern of core/lobe_mixture.h, with a
// third lobe): the specular by GGX visible normals (Heitz 2018, ggx.h) with (ax, ay), the clearcoat
// by GTR1's half-vector density D(h) cos(theta_h) (Burley 2012, Appendix B, Eq. 2), the diffuse
// and sheen by the cosine. The pdf is the mixture's, so weight = f cos / pdf stays exact.
// Energy: Burley's diffuse retro-reflection exceeds an albedo of 1 at grazing for rough
// dielectrics by design (docs/models/principled.md gives the measured albedos).
// The tangent frame's rotation (rotation_deg) is not a key of this model yet.
#pragma once

#include "aniso/brdf/ggx.h"

namespace aniso {

// GLSL's mix(a, b, t) = a (1 - t) + b t (the .brdf file's operator).
template <typename A, typename T> ANISO_INLINE A Principled_Mix(const A& a, const A& b, T t) { return a * (T(1) - t) + b * t; }

// SchlickFresnel(u) = (1 - u)^5 with 1 - u clamped to [0, 1] (lines 42-47).
template <typename T> ANISO_INLINE T Principled_SchlickWeight(T u) {
  const T m = clamp01(T(1) - u);
  const T m2 = m * m;
  return m2 * m2 * m;
}

// GTR1 (lines 49-55): (a^2 - 1) / (pi log(a^2) (1 + (a^2 - 1)(n.h)^2)), 1/pi for a >= 1;
// normalised, its integral of D cos(theta_h) over the hemisphere is 1. The denominator is written
// as Burley's GTR form a^2 cos^2(theta_h) + sin^2(theta_h) (Burley 2012, Sec. 5.4) with
// sin^2 = h.x^2 + h.y^2: the file's 1 + (a^2 - 1) cos^2 cancels in float near the peak (a = 0.001,
// cos(theta_h) = 0.999 loses 5e-5 of its relative precision), this form does not. h unit.
template <typename T> ANISO_INLINE T D_GTR1(const Vec3T<T>& h, T a) {
  using std::log;
  if (a >= T(1)) return kInvPi<T>;
  const T a2 = a * a;
  const T t = a2 * sqr(h.z) + (sqr(h.x) + sqr(h.y));
  return (a2 - T(1)) / (kPi<T> * log(a2) * t);
}

// smithG_GGX(n.v, alpha) = 1 / (n.v + sqrt(alpha^2 + (n.v)^2 - alpha^2 (n.v)^2)) (lines 69-74):
// Smith's G1 for GGX divided by 2 n.v.
template <typename T> ANISO_INLINE T Principled_SmithG_GGX(T NoV, T alpha) {
  using std::sqrt;
  const T a = alpha * alpha;
  const T b = NoV * NoV;
  return T(1) / (NoV + sqrt(a + b - a * b));
}

// smithG_GGX_aniso(n.v, v.x, v.y, ax, ay) = 1 / (n.v + sqrt((v.x ax)^2 + (v.y ay)^2 + (n.v)^2))
// (lines 76-79): the anisotropic G1 / (2 n.v).
template <typename T> ANISO_INLINE T Principled_SmithG_GGX_Aniso(const Vec3T<T>& w, T ax, T ay) {
  using std::sqrt;
  return T(1) / (w.z + sqrt(sqr(w.x * ax) + sqr(w.y * ay) + sqr(w.z)));
}

template <typename T> struct PrincipledT {
  RGBT<T> base_color{T(0.5)};  // linear
  T metallic = T(0);
  T subsurface = T(0);
  T specular = T(0.5);
  T roughness = T(0.5);
  T specular_tint = T(0);
  T anisotropic = T(0);
  T sheen = T(0);
  T sheen_tint = T(0.5);
  T clearcoat = T(0);
  T clearcoat_gloss = T(1);

  // The specular roughness (lines 118-120): 0.001 keeps the lobe inside the float range
  // (params.cpp, "Roughness alpha").
  ANISO_HD GGXLobeT<T> specular_lobe() const {
    using std::sqrt;
    const T aspect = sqrt(T(1) - anisotropic * T(0.9));
    const T ax = sqr(roughness) / aspect, ay = sqr(roughness) * aspect;
    GGXLobeT<T> l;
    l.alpha_x = ax > T(0.001) ? ax : T(0.001);
    l.alpha_y = ay > T(0.001) ? ay : T(0.001);
    return l;
  }
  ANISO_HD T clearcoat_alpha() const { return Principled_Mix(T(0.1), T(0.001), clearcoat_gloss); }
  // Ctint: the base colour with its luminance normalised away (line 100).
  ANISO_HD RGBT<T> tint() const {
    const T lum = T(0.3) * base_color.x + T(0.6) * base_color.y + T(0.1) * base_color.z;
    return lum > T(0) ? base_color / lum : RGBT<T>(T(1));
  }
  ANISO_HD RGBT<T> specular_f0() const {
    return Principled_Mix(specular * T(0.08) * Principled_Mix(RGBT<T>(T(1)), tint(), specular_tint), base_color, metallic);
  }

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    const Vec3T<T> h = glm::normalize(wi + wo);
    const T NoL = wi.z, NoV = wo.z, LoH = glm::dot(wi, h);
    const RGBT<T> Csheen = Principled_Mix(RGBT<T>(T(1)), tint(), sheen_tint);
    // Diffuse with retro-reflection (lines 104-108) and the subsurface approximation (110-115).
    const T FL = Principled_SchlickWeight(NoL), FV = Principled_SchlickWeight(NoV);
    const T Fd90 = T(0.5) + T(2) * LoH * LoH * roughness;
    const T Fd = Principled_Mix(T(1), Fd90, FL) * Principled_Mix(T(1), Fd90, FV);
    const T Fss90 = LoH * LoH * roughness;
    const T Fss = Principled_Mix(T(1), Fss90, FL) * Principled_Mix(T(1), Fss90, FV);
    const T ss = T(1.25) * (Fss * (T(1) / (NoL + NoV) - T(0.5)) + T(0.5));
    // Specular (lines 117-126).
    const GGXLobeT<T> lobe = specular_lobe();
    const T Ds = D_GGX_Aniso(h.x, h.y, h.z, lobe.alpha_x, lobe.alpha_y);
    const T FH = Principled_SchlickWeight(LoH);
    const RGBT<T> Fs = Principled_Mix(specular_f0(), RGBT<T>(T(1)), FH);
    const T Gs =
        Principled_SmithG_GGX_Aniso(wi, lobe.alpha_x, lobe.alpha_y) * Principled_SmithG_GGX_Aniso(wo, lobe.alpha_x, lobe.alpha_y);
    // Sheen (line 129) and clearcoat (lines 131-134).
    const RGBT<T> Fsheen = FH * sheen * Csheen;
    const T Dr = D_GTR1(h, clearcoat_alpha());
    const T Fr = Principled_Mix(T(0.04), T(1), FH);
    const T Gr = Principled_SmithG_GGX(NoL, T(0.25)) * Principled_SmithG_GGX(NoV, T(0.25));
    return (kInvPi<T> * Principled_Mix(Fd, ss, subsurface) * base_color + Fsheen) * (T(1) - metallic) + Gs * Fs * Ds +
           T(0.25) * clearcoat * Gr * Fr * Dr;
  }

  // Lobe weights for the choice (estimates; any positive choice is unbiased): the diffuse albedo
  // (1 - metallic) average(C), the specular Fresnel at the view angle, the clearcoat's
  // 0.25 clearcoat Fr at the view angle. Returns {p_specular, p_clearcoat}; the rest is diffuse.
  ANISO_HD Vec2T<T> lobe_probabilities(const Vec3T<T>& wo) const {
    const T Fv = Principled_SchlickWeight(wo.z);
    const T wd = (T(1) - metallic) * average(base_color);
    const T ws = average(Principled_Mix(specular_f0(), RGBT<T>(T(1)), Fv));
    const T wc = T(0.25) * clearcoat * Principled_Mix(T(0.04), T(1), Fv);
    const T total = wd + ws + wc;
    if (!(total > T(0))) return Vec2T<T>(T(0));
    return Vec2T<T>(ws / total, wc / total);
  }

  // The clearcoat's density of wi: D(h) cos(theta_h) / (4 wo.h) (Burley 2012, Appendix B).
  ANISO_HD T clearcoat_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    const T WoH = glm::dot(wo, h);
    if (!(WoH > T(0)) || !(h.z > T(0))) return T(0);
    return D_GTR1(h, clearcoat_alpha()) * h.z / (T(4) * WoH);
  }
  // cos^2(theta_h) = (1 - a^(2 (1 - u.x))) / (1 - a^2), phi_h = 2 pi u.y (Burley 2012, Appendix B,
  // Eq. 2, inverted CDF of D cos(theta_h)); wi = the reflection of wo about h.
  ANISO_HD Vec3T<T> clearcoat_sample(const Vec3T<T>& wo, const Vec2T<T>& u) const {
    using std::cos;
    using std::pow;
    using std::sin;
    const T a = clearcoat_alpha();
    const T a2 = a * a;
    const T cos2 = clamp01((T(1) - pow(a2, T(1) - u.x)) / (T(1) - a2));
    const T cos_t = safe_sqrt(cos2), sin_t = safe_sqrt(T(1) - cos2);
    const T phi = T(2) * kPi<T> * u.y;
    return reflect_about(wo, Vec3T<T>(sin_t * cos(phi), sin_t * sin(phi), cos_t));
  }

  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    const Vec2T<T> p = lobe_probabilities(wo);
    return (T(1) - p.x - p.y) * cosine_hemisphere_pdf(wi.z) + p.x * specular_lobe().pdf(wi, wo) + p.y * clearcoat_pdf(wi, wo);
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    const Vec2T<T> p = lobe_probabilities(wo);
    const Vec3T<T> wi =
        uc < p.x ? specular_lobe().sample(wo, u) : (uc < p.x + p.y ? clearcoat_sample(wo, u) : sample_cosine_hemisphere(u));
    if (!above_horizon(wi)) return {};
    return make_sample(wi, f(wi, wo), pdf(wi, wo));
  }

  // core/kernel.h. The specular alphas widen to (max(ax, alpha), max(ay, alpha)) through the two
  // keys that set them: lines 118-120 give ax ay = roughness^4 and ay / ax = aspect^2 (ay <= ax),
  // so roughness = (ax ay)^(1/4) and anisotropic = (1 - ay / ax) / 0.9 (never above its old value:
  // widening the narrower alpha only brings the two closer). Roughness also sets Burley's diffuse
  // retro-reflection (Fd90, lines 104-108), which changes with it. The clearcoat's GTR1 alpha
  // mix(0.1, 0.001, gloss) widens to alpha through a lower gloss, below 0 where alpha > 0.1 (GTR1
  // is defined for any alpha; the table's range is the host's). Nothing changes, bit for bit,
  // where both are as wide already.
  ANISO_HD void regularize(T alpha) {
    using std::sqrt;
    const GGXLobeT<T> l = specular_lobe();
    if (l.alpha_x < alpha || l.alpha_y < alpha) {
      T ax = l.alpha_x, ay = l.alpha_y;
      widen_alpha(ax, alpha);
      widen_alpha(ay, alpha);
      roughness = sqrt(sqrt(ax * ay));
      anisotropic = (T(1) - ay / ax) / T(0.9);
    }
    if (clearcoat_alpha() < alpha) clearcoat_gloss = (T(0.1) - alpha) / T(0.099);
  }
  // Metallic 1 without a clearcoat is a GGX alone (the diffuse and sheen terms carry 1 - metallic,
  // lines 136-138), with Schlick's F from specular_f0 and the separable G; without a clearcoat a
  // GGX lobe beside Burley's diffuse and the sheen; with one, a second glossy lobe (GTR1) that no
  // GGX describes.
  ANISO_HD GgxDistributionT<T> ggx_distribution() const {
    GgxDistributionT<T> d;
    if (clearcoat != T(0)) return d;
    const GGXLobeT<T> l = specular_lobe();
    d.part = metallic == T(1) ? GgxPart::Whole : GgxPart::Lobe;
    d.alpha_x = l.alpha_x, d.alpha_y = l.alpha_y;
    d.fresnel = GgxFresnel::Schlick;
    d.f0 = specular_f0();
    d.masking = GgxMasking::Separable;
    return d;
  }
};

}  // namespace aniso
