// aniso/brdf/phong.h: Phong's lobe about the mirror direction, as a BRDF (Phong 1975), plain and
// energy-normalised ("modified Phong", Lewis 1994, "Making Shaders More Physically Plausible").
//   plain:       f = kd / pi + ks (r . wo)^s,                  r = 2 (n . wi) n - wi = M wi
//   normalised:  f = kd / pi + ks (s + 2) / (2 pi) (r . wo)^s,  M = diag(-1, -1, 1)
// (r . wo) = (M wi) . wo is symmetric in wi and wo, so both are reciprocal.
#pragma once

#include "aniso/core/lobe_mixture.h"

namespace aniso {

// (r . wo)^s, 0 when the lobe base is not positive.
template <typename T> ANISO_INLINE T Phong_Lobe(T RoV, T exponent) {
  using std::pow;
  return RoV > T(0) ? pow(RoV, exponent) : T(0);
}

// Lewis 1994: (s + 2) / (2 pi) makes the lobe's cosine-weighted integral 1 at normal incidence.
template <typename T> ANISO_INLINE T Phong_Normalization(T exponent) { return (exponent + T(2)) * kInv2Pi<T>; }

// The specular lobe without its colour; sampled as the cosine power about r(wo), which is the same
// lobe because (M wi) . wo = wi . (M wo).
template <typename T> struct PhongLobeT {
  T exponent = T(20);
  bool normalized = true;

  ANISO_HD T eval(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const T lobe = Phong_Lobe(glm::dot(reflect_about_normal(wi), wo), exponent);
    return normalized ? lobe * Phong_Normalization(exponent) : lobe;
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return cosine_power_pdf(glm::dot(reflect_about_normal(wo), wi), exponent);
  }
  ANISO_HD Vec3T<T> sample(const Vec3T<T>& wo, const Vec2T<T>& u) const {
    return sample_cosine_power(reflect_about_normal(wo), exponent, u);
  }
  // Roughened to at least alpha (core/kernel.h): the exponent narrows to n(alpha).
  ANISO_HD void regularize(T alpha) { narrow_exponent(exponent, exponent_for_roughness(alpha)); }
};

template <typename T> using PhongT = LambertPlusLobeT<T, PhongLobeT<T>>;

}  // namespace aniso
