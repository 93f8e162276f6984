// aniso/brdf/ggx.h: anisotropic GGX / Trowbridge-Reitz microfacets with height-correlated Smith
// masking-shadowing and visible-normal sampling. Not in the lecture: the modern reference that
// pbrt-v4, Mitsuba 3 and Filament use, so the classic models can be compared against it.
//
// Trowbridge & Reitz 1975; Walter et al. 2007, "Microfacet Models for Refraction", Eq. 20, 33;
// Heitz 2014, "Understanding the Masking-Shadowing Function", Eq. 86 (anisotropic Lambda), Eq. 99
// (height-correlated G2); Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4).
//
//   f = kd / pi + F(wi.h) D(h) G2(wi, wo) / (4 cos_i cos_o),   F = Schlick with f0 and f90
// (f90 = 1: Schlick 1994; below 1 a flatter Fresnel, fresnel.h).
// The diffuse and specular terms are simply added (no energy coupling): docs/models/ggx.md.
#pragma once

#include "aniso/brdf/fresnel.h"
#include "aniso/core/lobe_mixture.h"

namespace aniso {

// D(h) = 1 / (pi ax ay ((h.t / ax)^2 + (h.b / ay)^2 + (h.n)^2)^2), h unit.
template <typename T> ANISO_INLINE T D_GGX_Aniso(T HoT, T HoB, T HoN, T ax, T ay) {
  const T d = sqr(HoT / ax) + sqr(HoB / ay) + sqr(HoN);
  return kInvPi<T> / (ax * ay * d * d);
}

// Lambda(w) = (-1 + sqrt(1 + (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2)) / 2 (Heitz 2014 Eq. 86).
template <typename T> ANISO_INLINE T Lambda_GGX_Aniso(const Vec3T<T>& w, T ax, T ay) {
  using std::sqrt;
  const T tan2_alpha2 = (sqr(ax * w.x) + sqr(ay * w.y)) / sqr(w.z);
  return (sqrt(T(1) + tan2_alpha2) - T(1)) * T(0.5);
}

// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wi) + Lambda(wo)) (Heitz 2014 Eq. 99).
template <typename T> ANISO_INLINE T G2_SmithGGX_HeightCorrelated(T lambda_i, T lambda_o) {
  return T(1) / (T(1) + lambda_i + lambda_o);
}

template <typename T> ANISO_INLINE T G1_SmithGGX(T lambda) { return T(1) / (T(1) + lambda); }

// Heitz 2018, Listing 1: sample a visible normal for the view direction wo (upper hemisphere).
template <typename T> ANISO_INLINE Vec3T<T> GGX_SampleVisibleNormal(const Vec3T<T>& wo, const Vec2T<T>& u, T ax, T ay) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  // Stretch the view vector to the hemisphere configuration (alpha = 1).
  const Vec3T<T> vh = glm::normalize(Vec3T<T>(ax * wo.x, ay * wo.y, wo.z));
  // Orthonormal basis around vh (vh.z > 0, so lensq = 0 only at normal view).
  const T lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3T<T> t1 = lensq > T(0) ? Vec3T<T>(-vh.y, vh.x, T(0)) / sqrt(lensq) : Vec3T<T>(T(1), T(0), T(0));
  const Vec3T<T> t2 = glm::cross(vh, t1);
  // Uniform point on the disk, warped towards the visible half (Section 4.2).
  const T r = sqrt(u.x);
  const T phi = T(2) * kPi<T> * u.y;
  const T p1 = r * cos(phi);
  T p2 = r * sin(phi);
  const T s = T(0.5) * (T(1) + vh.z);
  p2 = (T(1) - s) * safe_sqrt(T(1) - p1 * p1) + s * p2;
  const Vec3T<T> nh = p1 * t1 + p2 * t2 + safe_sqrt(T(1) - p1 * p1 - p2 * p2) * vh;
  // Unstretch; nh.z >= 0, and the max() keeps the normal strictly above the horizon (Listing 1).
  return glm::normalize(Vec3T<T>(ax * nh.x, ay * nh.y, nh.z > T(0) ? nh.z : T(0)));
}

// The colourless, Fresnel-less specular lobe D G2 / (4 cos_i cos_o), shared with the metal.
template <typename T> struct GGXLobeT {
  T alpha_x = T(0.2);
  T alpha_y = T(0.2);

  ANISO_HD T eval(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    const T D = D_GGX_Aniso(h.x, h.y, h.z, alpha_x, alpha_y);
    const T G2 = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, alpha_x, alpha_y), Lambda_GGX_Aniso(wo, alpha_x, alpha_y));
    return D * G2 / (T(4) * wi.z * wo.z);
  }
  // Visible-normal density: D_wo(h) = G1(wo) max(wo.h, 0) D(h) / wo.z; pdf(wi) = D_wo(h) / (4 wo.h)
  // = G1(wo) D(h) / (4 wo.z).
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    if (!(glm::dot(wo, h) > T(0)) || !(h.z > T(0))) return T(0);
    const T D = D_GGX_Aniso(h.x, h.y, h.z, alpha_x, alpha_y);
    return G1_SmithGGX(Lambda_GGX_Aniso(wo, alpha_x, alpha_y)) * D / (T(4) * wo.z);
  }
  // eval() and pdf() together, each bit for bit: the half vector, D and Lambda(wo) computed once.
  ANISO_HD T eval_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf_out) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    const T D = D_GGX_Aniso(h.x, h.y, h.z, alpha_x, alpha_y);
    const T lambda_o = Lambda_GGX_Aniso(wo, alpha_x, alpha_y);
    *pdf_out = !(glm::dot(wo, h) > T(0)) || !(h.z > T(0)) ? T(0) : G1_SmithGGX(lambda_o) * D / (T(4) * wo.z);
    const T G2 = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, alpha_x, alpha_y), lambda_o);
    return D * G2 / (T(4) * wi.z * wo.z);
  }
  ANISO_HD Vec3T<T> sample(const Vec3T<T>& wo, const Vec2T<T>& u) const {
    return reflect_about(wo, GGX_SampleVisibleNormal(wo, u, alpha_x, alpha_y));
  }
  // Roughened to at least alpha (core/kernel.h): both alphas widen.
  ANISO_HD void regularize(T alpha) {
    widen_alpha(alpha_x, alpha);
    widen_alpha(alpha_y, alpha);
  }
};

template <typename T> struct GGXT {
  RGBT<T> kd{T(0)};
  RGBT<T> f0{T(0.04)};
  RGBT<T> f90{T(1)};
  GGXLobeT<T> lobe;

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    const Vec3T<T> h = glm::normalize(wi + wo);
    return F_Schlick(f0, f90, glm::dot(wi, h)) * lobe.eval(wi, wo) + kd * kInvPi<T>;
  }
  // Specular weight: Schlick's Fresnel at the view angle (the lobe's albedo is <= that).
  ANISO_HD T specular_probability(const Vec3T<T>& wo) const {
    return specular_share(average(kd), average(F_Schlick(f0, f90, wo.z)));
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return pdf_diffuse_specular(specular_probability(wo), lobe, wi, wo);
  }
  // f() and pdf() together (model_f_pdf), bit for bit.
  ANISO_HD RGBT<T> f_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf_out) const {
    if (!same_upper_hemisphere(wi, wo)) {
      *pdf_out = T(0);
      return RGBT<T>(T(0));
    }
    const Vec3T<T> h = glm::normalize(wi + wo);
    T lobe_pdf;
    const T spec = lobe_eval_pdf(lobe, wi, wo, &lobe_pdf);
    *pdf_out = mix_diffuse_specular_pdf(specular_probability(wo), lobe_pdf, wi);
    return F_Schlick(f0, f90, glm::dot(wi, h)) * spec + kd * kInvPi<T>;
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    return sample_diffuse_specular(*this, lobe, specular_probability(wo), wo, uc, u);
  }
  ANISO_HD void regularize(T alpha) { lobe.regularize(alpha); }
  // The whole model is a GGX: Schlick's F (with its f90), height-correlated G2, a Lambertian kd.
  ANISO_HD GgxDistributionT<T> ggx_distribution() const {
    GgxDistributionT<T> d;
    d.part = GgxPart::Whole;
    d.alpha_x = lobe.alpha_x, d.alpha_y = lobe.alpha_y;
    d.fresnel = GgxFresnel::Schlick;
    d.f0 = f0;
    d.f90 = f90;
    d.kd = kd;
    return d;
  }
};

}  // namespace aniso
