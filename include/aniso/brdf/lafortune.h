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
// below the horizon, and mix lobes, channels, the diffuse term and a defensive cosine share by
// weight (docs/models/lafortune.md).
#pragma once

#include "aniso/core/kernel.h"
#include "aniso/core/sampling.h"

namespace aniso {

// Kernels allocate nothing, so the lobe count has a fixed ceiling. Published fits use 1 to 3 lobes.
inline constexpr int kLafortuneMaxLobes = 8;

// One lobe's value for one channel: scale max(Cx wi.x wo.x + Cy wi.y wo.y + Cz wi.z wo.z, 0)^n,
// computed as exp(n log(base) + log(scale)). The product is what the reader bounds
// (scale max|C|^n <= 1e30, src/io/materials.cpp), but its factors alone need not be finite:
// C_z = 100, n = 160 gives base^n = inf in double, and a scale of 1e-300 then made inf * 1e-300 or
// 0 * inf = NaN. In log space the exponent is at most ln(1e30) = 69, so the result is finite for
// every material the reader accepts, in float and double. A scale of 0 (or one that rounds to 0 in
// float) switches the lobe off.
// A small integer n (a metal's directional diffuse lobe: n = 3 or 4 in the presets) takes
// base^n by multiplication (pow_small_int) where that power is a normal, finite number: then
// base^n scale is the bounded product above, finite, and within rounding of the exp-log form.
// The power is computed once for channels that share base and n (Lafortune_LobeOfPower).
template <typename T> struct LafortunePowerT {
  T power;       // base^n by multiplication, or -1: use n_log_base
  T n_log_base;  // n log(base), where power is -1
};
template <typename T> ANISO_INLINE LafortunePowerT<T> Lafortune_Power(T base, T n) {
  using std::log;
  const T p = pow_small_int(base, n);
  return {p, p >= T(0) ? T(0) : n * log(base)};
}
// The lobe of a base > 0 whose power is given; the same value bit for bit as Lafortune_Lobe of
// that base.
template <typename T> ANISO_INLINE T Lafortune_LobeOfPower(const LafortunePowerT<T>& p, T scale) {
  using std::exp;
  using std::log;
  if (!(scale > T(0))) return T(0);
  return p.power >= T(0) ? p.power * scale : exp(p.n_log_base + log(scale));
}
template <typename T> ANISO_INLINE T Lafortune_Lobe(T base, T n, T scale) {
  return base > T(0) && scale > T(0) ? Lafortune_LobeOfPower(Lafortune_Power(base, n), scale) : T(0);
}

template <typename T> struct LafortuneLobeT {
  RGBT<T> cx{T(-1)};
  RGBT<T> cy{T(-1)};
  RGBT<T> cz{T(1)};
  RGBT<T> n{T(10)};
  RGBT<T> scale{T(1)};

  // Whether the three channels share the lobe's shape (cx, cy, cz and n), as a metal's directional
  // diffuse lobe does (only its scale is coloured): then channel_pdf() is the same for every channel.
  ANISO_HD bool channels_share_shape() const {
    return cx.x == cx.y && cx.y == cx.z && cy.x == cy.y && cy.y == cy.z && cz.x == cz.y && cz.y == cz.z && n.x == n.y &&
           n.y == n.z;
  }

  ANISO_HD RGBT<T> eval(const Vec3T<T>& wi, const Vec3T<T>& wo) const { return eval(wi, wo, channels_share_shape()); }
  // eval() with share_shape == channels_share_shape() given (a caller that evaluates the lobe many
  // times at one shading point asks once: eight comparisons an evaluation otherwise).
  ANISO_HD RGBT<T> eval(const Vec3T<T>& wi, const Vec3T<T>& wo, bool share_shape) const {
    const Vec3T<T> p = wi * wo;  // component-wise: the diagonal matrix acts on wi.x wo.x, ...
    RGBT<T> out;
    if (share_shape) {
      // One base and one power of it for the three channels (each channel's base is this one).
      const T base = cx.x * p.x + cy.x * p.y + cz.x * p.z;
      if (!(base > T(0))) return RGBT<T>(T(0));
      const LafortunePowerT<T> power = Lafortune_Power(base, n.x);
      for (int c = 0; c < 3; ++c) out[c] = Lafortune_LobeOfPower(power, scale[c]);
      return out;
    }
    for (int c = 0; c < 3; ++c) {
      out[c] = Lafortune_Lobe(cx[c] * p.x + cy[c] * p.y + cz[c] * p.z, n[c], scale[c]);
    }
    return out;
  }

  // The lobe axis for channel c: a = M wo.
  ANISO_HD Vec3T<T> axis(const Vec3T<T>& wo, int c) const { return Vec3T<T>(cx[c] * wo.x, cy[c] * wo.y, cz[c] * wo.z); }

  // Sampling weight of channel c: an estimate of the lobe's albedo, scale |a|^n 2 pi / (n + 1)
  // times the axis' elevation a_hat.z (a lobe about an axis below the horizon reflects little into
  // the upper hemisphere; without this factor, fits like pbrt-v1's clay with C_z < 0 waste almost
  // every sample), divided by 3 so that a grey lobe weighs as much as its three channels together.
  ANISO_HD T channel_weight(const Vec3T<T>& wo, int c) const {
    using std::sqrt;
    const Vec3T<T> a = axis(wo, c);
    const T len = sqrt(glm::dot(a, a));
    if (!(len > T(0)) || !(a.z > T(0))) return T(0);
    // scale |a|^n through Lafortune_Lobe: |a| <= max|C|, so the same bound keeps it finite.
    return Lafortune_Lobe(len, n[c], scale[c]) * (a.z / len) * T(2) * kPi<T> / ((n[c] + T(1)) * T(3));
  }

  // channel_weight(wo, c) for the three channels, with one power of |a| where they share the shape
  // (then |a|, a.z and n are the same for each): the same values bit for bit.
  ANISO_HD void channel_weights(const Vec3T<T>& wo, T out[3]) const { channel_weights(wo, out, channels_share_shape()); }
  ANISO_HD void channel_weights(const Vec3T<T>& wo, T out[3], bool share_shape) const {
    using std::sqrt;
    if (!share_shape) {
      for (int c = 0; c < 3; ++c) out[c] = channel_weight(wo, c);
      return;
    }
    const Vec3T<T> a = axis(wo, 0);
    const T len = sqrt(glm::dot(a, a));
    if (!(len > T(0)) || !(a.z > T(0))) {
      out[0] = out[1] = out[2] = T(0);
      return;
    }
    const LafortunePowerT<T> power = Lafortune_Power(len, n.x);
    const T cos_axis = a.z / len, denom = (n.x + T(1)) * T(3);
    for (int c = 0; c < 3; ++c) out[c] = Lafortune_LobeOfPower(power, scale[c]) * cos_axis * T(2) * kPi<T> / denom;
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

  // Defensive share of cosine sampling (Hesterberg 1995, "Weighted average importance sampling and
  // defensive mixture distributions"): the lobe weights are estimates, and where they miss (a lobe
  // whose axis is below the horizon but whose tail is not) cosine samples keep the variance bounded.
  static constexpr float kDefensiveShare = 0.1f;

  // The mixture's weights for one wo, computed once and shared by sample() and its pdf (each
  // channel weight costs a pow).
  struct SamplingWeights {
    T lobe[kLafortuneMaxLobes][3];
    T lobes_total;
    T cosine;  // the diffuse albedo plus the defensive share; all of it when nothing else weighs
  };
  ANISO_HD SamplingWeights sampling_weights(const Vec3T<T>& wo) const {
    SamplingWeights w;
    w.lobes_total = T(0);
    for (int i = 0; i < lobe_count; ++i) {
      lobes[i].channel_weights(wo, w.lobe[i]);
      for (int c = 0; c < 3; ++c) w.lobes_total += w.lobe[i][c];
    }
    const T cos_w = average(rho_d) + T(kDefensiveShare) * w.lobes_total;
    w.cosine = cos_w > T(0) || w.lobes_total > T(0) ? cos_w : T(1);
    return w;
  }

  ANISO_HD T pdf(const SamplingWeights& w, const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    T p = w.cosine * cosine_hemisphere_pdf(wi.z);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c)
        if (w.lobe[i][c] > T(0)) p += w.lobe[i][c] * lobes[i].channel_pdf(wi, wo, c);
    return p / (w.cosine + w.lobes_total);
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    return pdf(sampling_weights(wo), wi, wo);
  }

  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    return sample(sampling_weights(wo), wo, uc, u);
  }
  // sample() with the weights of this wo already computed (w == sampling_weights(wo)).
  ANISO_HD BSDFSampleT<T> sample(const SamplingWeights& w, const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    // Walk the cumulative weights with uc: cosine first, then each (lobe, channel). Rounding that
    // leaves target >= 0 after the last lobe picks the last positive-weight candidate.
    T target = uc * (w.cosine + w.lobes_total) - w.cosine;
    int lobe = -1, channel = 0;
    for (int i = 0; i < lobe_count && !(target < T(0)); ++i)
      for (int c = 0; c < 3 && !(target < T(0)); ++c) {
        if (!(w.lobe[i][c] > T(0))) continue;
        lobe = i;
        channel = c;
        target -= w.lobe[i][c];
      }
    Vec3T<T> wi;
    if (lobe < 0) {
      wi = sample_cosine_hemisphere(u);
    } else {
      const Vec3T<T> a = lobes[lobe].axis(wo, channel);
      wi = sample_cosine_power(a / std::sqrt(glm::dot(a, a)), lobes[lobe].n[channel], u);
    }
    if (!above_horizon(wi)) return {};
    return make_sample(wi, f(wi, wo), pdf(w, wi, wo));
  }
  // core/kernel.h: left as fitted. A lobe's exponent n is not its width alone: the lobe's value
  // is |C|^n (a_hat . wi)^n (Lafortune et al. 1997, Eq. 6), so a smaller n without a new C would
  // change the lobe's energy by the factor |C|^(n' - n), not only its width. No GGX.
  ANISO_HD void regularize(T /*alpha*/) {}
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }
};

}  // namespace aniso
