// aniso/brdf/lafortune.h: Lafortune, Foo, Torrance & Greenberg 1997, "Non-Linear Approximation of
// Reflectance Functions", SIGGRAPH, Eq. 5-6: generalised cosine lobes.
//
//   f = rho_d / pi + sum_i scale_i [Cx_i wi.x wo.x + Cy_i wi.y wo.y + Cz_i wi.z wo.z]^(n_i)
// per RGB channel; a lobe whose base is <= 0 contributes 0. Phong's mirror matrix
// M = diag(-1, -1, 1) becomes M = diag(Cx, Cy, Cz): symmetric, so reciprocal. Cx = Cy is isotropic;
// |Cz| < |Cx| moves the lobe towards grazing; Cx > 0 reflects back towards the light.
// `scale` is the lecture's optional per-lobe k_s (1 in the fitted tables, where the scale lives in
// the magnitude of C).
//
// Sampling: lobe i, channel c is the cosine-power lobe |a|^n (a_hat . wi)^n about the axis
// a = (Cx wo.x, Cy wo.y, Cz wo.z); sample wi with density (n + 1) / (2 pi) (a_hat . wi)^n, reject
// below the horizon, and mix lobes, channels and the diffuse term by weight (docs/models/lafortune.md).
#pragma once

#include "aniso/core/sampling.h"

namespace aniso {

// Kernels allocate nothing, so the lobe count has a fixed ceiling. Published fits use 1 to 3 lobes.
inline constexpr int kLafortuneMaxLobes = 8;

// One lobe's value for one channel: max(Cx wi.x wo.x + Cy wi.y wo.y + Cz wi.z wo.z, 0)^n.
template <typename T> ANISO_INLINE T Lafortune_Lobe(T base, T n) {
  using std::pow;
  return base > T(0) ? pow(base, n) : T(0);
}

template <typename T> struct LafortuneLobeT {
  RGBT<T> cx{T(-1)};
  RGBT<T> cy{T(-1)};
  RGBT<T> cz{T(1)};
  RGBT<T> n{T(10)};
  RGBT<T> scale{T(1)};

  ANISO_HD RGBT<T> eval(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> p = wi * wo;  // component-wise: the diagonal matrix acts on wi.x wo.x, ...
    RGBT<T> out;
    for (int c = 0; c < 3; ++c) {
      out[c] = scale[c] * Lafortune_Lobe(cx[c] * p.x + cy[c] * p.y + cz[c] * p.z, n[c]);
    }
    return out;
  }

  // The lobe axis for channel c: a = M wo.
  ANISO_HD Vec3T<T> axis(const Vec3T<T>& wo, int c) const { return Vec3T<T>(cx[c] * wo.x, cy[c] * wo.y, cz[c] * wo.z); }

  // Sampling weight of channel c: an upper bound of the lobe's albedo, scale |a|^n 2 pi / (n + 1),
  // divided by 3 so that a grey lobe weighs as much as its three channels together.
  ANISO_HD T channel_weight(const Vec3T<T>& wo, int c) const {
    using std::pow;
    using std::sqrt;
    const Vec3T<T> a = axis(wo, c);
    const T len = sqrt(glm::dot(a, a));
    if (!(len > T(0)) || !(scale[c] > T(0))) return T(0);
    return scale[c] * pow(len, n[c]) * T(2) * kPi<T> / ((n[c] + T(1)) * T(3));
  }

  ANISO_HD T channel_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, int c) const {
    const Vec3T<T> a = axis(wo, c);
    const T len2 = glm::dot(a, a);
    if (!(len2 > T(0))) return T(0);
    return cosine_power_pdf(glm::dot(a, wi) / std::sqrt(len2), n[c]);
  }
};

template <typename T> struct LafortuneT {
  RGBT<T> rho_d{T(0)};
  int lobe_count = 0;
  LafortuneLobeT<T> lobes[kLafortuneMaxLobes];

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    RGBT<T> out = rho_d * kInvPi<T>;
    for (int i = 0; i < lobe_count; ++i) out += lobes[i].eval(wi, wo);
    return out;
  }

  ANISO_HD T diffuse_weight() const { return average(rho_d); }

  ANISO_HD T total_weight(const Vec3T<T>& wo) const {
    T w = diffuse_weight();
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) w += lobes[i].channel_weight(wo, c);
    return w;
  }

  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    const T total = total_weight(wo);
    if (!(total > T(0))) return T(0);
    T p = diffuse_weight() * cosine_hemisphere_pdf(wi.z);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) {
        const T w = lobes[i].channel_weight(wo, c);
        if (w > T(0)) p += w * lobes[i].channel_pdf(wi, wo, c);
      }
    return p / total;
  }

  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!(wo.z > T(0))) return {};
    const T total = total_weight(wo);
    if (!(total > T(0))) return {};
    // Walk the cumulative weights with uc; the last positive-weight candidate absorbs rounding.
    T target = uc * total;
    Vec3T<T> wi(T(0));
    bool chosen = false;
    target -= diffuse_weight();
    if (target < T(0) && diffuse_weight() > T(0)) {
      wi = sample_cosine_hemisphere(u);
      chosen = true;
    }
    int last_i = -1, last_c = 0;
    for (int i = 0; i < lobe_count && !chosen; ++i)
      for (int c = 0; c < 3 && !chosen; ++c) {
        const T w = lobes[i].channel_weight(wo, c);
        if (!(w > T(0))) continue;
        last_i = i;
        last_c = c;
        target -= w;
        if (target < T(0)) {
          const Vec3T<T> a = lobes[i].axis(wo, c);
          wi = sample_cosine_power(a / std::sqrt(glm::dot(a, a)), lobes[i].n[c], u);
          chosen = true;
        }
      }
    if (!chosen) {
      if (last_i < 0) {
        wi = sample_cosine_hemisphere(u);
      } else {
        const Vec3T<T> a = lobes[last_i].axis(wo, last_c);
        wi = sample_cosine_power(a / std::sqrt(glm::dot(a, a)), lobes[last_i].n[last_c], u);
      }
    }
    if (!(wi.z > T(0))) return {};
    return make_sample(wi, f(wi, wo), pdf(wi, wo));
  }
};

}  // namespace aniso
