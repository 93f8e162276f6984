// aniso/brdf/phong.h: Phong's lobe about the mirror direction, as a BRDF (Phong 1975), plain and
// energy-normalised ("modified Phong", Lewis 1994, "Making Shaders More Physically Plausible").
//   plain:       f = kd / pi + ks (r . wo)^s,                  r = 2 (n . wi) n - wi = M wi
//   normalised:  f = kd / pi + ks (s + 2) / (2 pi) (r . wo)^s,  M = diag(-1, -1, 1)
// (r . wo) = (M wi) . wo is symmetric in wi and wo, so both are reciprocal.
#pragma once

#include "aniso/core/sampling.h"

namespace aniso {

// (r . wo)^s, 0 when the lobe base is not positive.
template <typename T> ANISO_INLINE T Phong_Lobe(T RoV, T exponent) {
  using std::pow;
  return RoV > T(0) ? pow(RoV, exponent) : T(0);
}

// Lewis 1994: (s + 2) / (2 pi) makes the lobe's cosine-weighted integral 1 at normal incidence.
template <typename T> ANISO_INLINE T Phong_Normalization(T exponent) { return (exponent + T(2)) * kInv2Pi<T>; }

template <typename T> struct PhongT {
  RGBT<T> kd{T(0.5)};
  RGBT<T> ks{T(0.5)};
  T exponent = T(20);
  bool normalized = true;

  ANISO_HD T specular(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const T lobe = Phong_Lobe(glm::dot(reflect_about_normal(wi), wo), exponent);
    return normalized ? lobe * Phong_Normalization(exponent) : lobe;
  }
  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    return kd * kInvPi<T> + ks * specular(wi, wo);
  }
  // Lobe choice by average colour; the specular lobe is sampled as the cosine power about r(wo).
  ANISO_HD T specular_probability() const {
    const T d = average(kd), s = average(ks);
    return d + s > T(0) ? s / (d + s) : T(0);
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    const T ps = specular_probability();
    return (T(1) - ps) * cosine_hemisphere_pdf(wi.z) +
           ps * cosine_power_pdf(glm::dot(reflect_about_normal(wo), wi), exponent);
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!(wo.z > T(0))) return {};
    const Vec3T<T> wi = uc < specular_probability()
                            ? sample_cosine_power(reflect_about_normal(wo), exponent, u)
                            : sample_cosine_hemisphere(u);
    return make_sample(wi, f(wi, wo), pdf(wi, wo));
  }
};

}  // namespace aniso
