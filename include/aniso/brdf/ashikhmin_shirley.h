// aniso/brdf/ashikhmin_shirley.h: Ashikhmin & Shirley 2000, "An Anisotropic Phong BRDF Model",
// JGT 5(2), 25-32: Eq. 4 (specular), Eq. 5 (diffuse), Sec. 5 / Eqs. 9-10 (sampling).
//
//   f = ks_scale * f_s + f_d + kd / pi
//   f_s = sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e / ((h.wi) max(n.wi, n.wo)) F(wi.h)
//   e   = nu cos^2 phi_h + nv sin^2 phi_h = (nu (h.t)^2 + nv (h.b)^2) / (1 - (h.n)^2)
//   F   = Rs + (1 - Rs)(1 - wi.h)^5 (Schlick)
//   f_d = 28 Rd / (23 pi) (1 - Rs) (1 - (1 - n.wi / 2)^5) (1 - (1 - n.wo / 2)^5)
// `kd` (an extra Lambertian term) and `ks_scale` are zero and one in the paper's model; they exist
// to express Ngan et al. 2005's fits (Lambertian + scaled AS specular without f_d).
// Note: pbrt-v2's "Anisotropic" distribution uses sqrt((ex + 2)(ey + 2)) / (2 pi): a different
// normalisation. Do not mix the two.
#pragma once

#include "aniso/brdf/fresnel.h"
#include "aniso/core/lobe_mixture.h"

namespace aniso {

// The anisotropic exponent e = (nu (h.t)^2 + nv (h.b)^2) / (1 - (h.n)^2). For a unit h the
// denominator equals (h.t)^2 + (h.b)^2, which is what is used: it is exact where 1 - (h.n)^2 loses
// all its digits to cancellation (h near n), and e stays a weighted mean of nu and nv. At h = n,
// (n.h)^e = 1 for every e: any value in [nu, nv] will do.
template <typename T> ANISO_INLINE T AS_Exponent(T HoT, T HoB, T nu, T nv) {
  const T s2 = HoT * HoT + HoB * HoB;
  return s2 > T(0) ? (nu * HoT * HoT + nv * HoB * HoB) / s2 : nu;
}

// The specular term without Fresnel (Eq. 4 with F = 1). h.wi = |wi + wo| / 2 > 0 for any two
// directions above the horizon, but computed as dot(h, wi) it is rounding alone when wi and wo are
// nearly opposite and grazing (wi + wo cancels to a few ulp): there it came out negative, and so
// did f (-1.3e17 for a double pair at cos 3e-10). As the pdfs do with h.wo (p_h / (4 h.wo) is 0
// unless h.wo > 0), the term is 0 unless h.wi > 0.
template <typename T> ANISO_INLINE T AS_Specular(T HoT, T HoB, T HoN, T HoL, T NoL, T NoV, T nu, T nv) {
  using std::pow;
  using std::sqrt;
  if (!(HoL > T(0))) return T(0);
  const T e = AS_Exponent(HoT, HoB, nu, nv);
  return sqrt((nu + T(1)) * (nv + T(1))) / (T(8) * kPi<T>)*pow(HoN, e) / (HoL * (NoL > NoV ? NoL : NoV));
}

// Eq. 5 without the colour: 28 / (23 pi) (1 - (1 - n.wi / 2)^5) (1 - (1 - n.wo / 2)^5).
template <typename T> ANISO_INLINE T AS_Diffuse(T NoL, T NoV) {
  const T a = T(1) - NoL * T(0.5), b = T(1) - NoV * T(0.5);
  const T a5 = a * a * a * a * a, b5 = b * b * b * b * b;
  return T(28) / (T(23) * kPi<T>)*(T(1) - a5) * (T(1) - b5);
}

// Density of the unit half vector (Sec. 5): sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^e.
template <typename T> ANISO_INLINE T AS_PdfHalf(const Vec3T<T>& h, T nu, T nv) {
  using std::pow;
  using std::sqrt;
  if (!(h.z > T(0))) return T(0);
  return sqrt((nu + T(1)) * (nv + T(1))) * kInv2Pi<T> * pow(h.z, AS_Exponent(h.x, h.y, nu, nv));
}

// Eq. 9: phi = atan(sqrt((nu + 1) / (nv + 1)) tan(pi xi / 2)) in the first quadrant, mapped to the
// four quadrants by splitting u.x into quarters; Eq. 10: cos theta_h = xi2^(1 / (e + 1)).
template <typename T> ANISO_INLINE Vec3T<T> AS_SampleHalf(const Vec2T<T>& u, T nu, T nv) {
  using std::atan;
  using std::cos;
  using std::pow;
  using std::sin;
  using std::sqrt;
  using std::tan;
  const T ratio = sqrt((nu + T(1)) / (nv + T(1)));
  const T q = T(4) * u.x;  // which quarter, and where in it
  T phi;
  if (q < T(1)) {
    phi = atan(ratio * tan(kPiOver2<T> * q));
  } else if (q < T(2)) {
    phi = kPi<T> - atan(ratio * tan(kPiOver2<T> * (T(2) - q)));
  } else if (q < T(3)) {
    phi = kPi<T> + atan(ratio * tan(kPiOver2<T> * (q - T(2))));
  } else {
    phi = T(2) * kPi<T> - atan(ratio * tan(kPiOver2<T> * (T(4) - q)));
  }
  const T c = cos(phi), s = sin(phi);
  const T e = nu * c * c + nv * s * s;
  const T cos_t = pow(T(1) - u.y, T(1) / (e + T(1)));  // 1 - u in (0, 1]
  const T sin_t = safe_sqrt(T(1) - cos_t * cos_t);
  return Vec3T<T>(sin_t * c, sin_t * s, cos_t);
}

// The colourless, Fresnel-less specular lobe, shared with the metal material.
template <typename T> struct AshikhminShirleyLobeT {
  T n_u = T(100);
  T n_v = T(100);

  // Requires both directions above the horizon. Returns f_s / F.
  ANISO_HD T eval(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    return AS_Specular(h.x, h.y, h.z, glm::dot(h, wi), wi.z, wo.z, n_u, n_v);
  }
  // pdf(wi) = p_h(h) / (4 (wo.h)).
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> h = glm::normalize(wi + wo);
    const T WoH = glm::dot(wo, h);
    if (!(WoH > T(0))) return T(0);
    return AS_PdfHalf(h, n_u, n_v) / (T(4) * WoH);
  }
  ANISO_HD Vec3T<T> sample(const Vec3T<T>& wo, const Vec2T<T>& u) const { return reflect_about(wo, AS_SampleHalf(u, n_u, n_v)); }
  // Roughened to at least alpha (core/kernel.h): both exponents narrow to n(alpha).
  ANISO_HD void regularize(T alpha) {
    const T n = exponent_for_roughness(alpha);
    narrow_exponent(n_u, n);
    narrow_exponent(n_v, n);
  }
};

template <typename T> struct AshikhminShirleyT {
  RGBT<T> rd{T(0.3)};
  RGBT<T> rs{T(0.05)};
  RGBT<T> kd{T(0)};
  RGBT<T> ks_scale{T(1)};
  AshikhminShirleyLobeT<T> lobe;

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    const Vec3T<T> h = glm::normalize(wi + wo);
    const RGBT<T> F = F_Schlick(rs, glm::dot(wi, h));
    const T spec = AS_Specular(h.x, h.y, h.z, glm::dot(h, wi), wi.z, wo.z, lobe.n_u, lobe.n_v);
    return ks_scale * F * spec + rd * (RGBT<T>(T(1)) - rs) * AS_Diffuse(wi.z, wo.z) + kd * kInvPi<T>;
  }
  // Lobe choice: the specular weight is its Fresnel reflectance seen from wo (Schlick at wo.n, an
  // estimate of the lobe's albedo that grows towards grazing as f_s does), the diffuse weight its
  // colour. Any positive weights are unbiased; these keep the variance low.
  ANISO_HD T specular_probability(const Vec3T<T>& wo) const {
    return specular_share(average(rd * (RGBT<T>(T(1)) - rs)) + average(kd), average(ks_scale * F_Schlick(rs, wo.z)));
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return pdf_diffuse_specular(specular_probability(wo), lobe, wi, wo);
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    return sample_diffuse_specular(*this, lobe, specular_probability(wo), wo, uc, u);
  }
  ANISO_HD void regularize(T alpha) { lobe.regularize(alpha); }
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }  // an anisotropic Phong lobe
};

}  // namespace aniso
