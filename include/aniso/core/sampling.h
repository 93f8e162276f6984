// aniso/core/sampling.h: the sampling routines the models share, each with its density.
// u values are uniform in [0, 1).
#pragma once

#include "aniso/core/math.h"

namespace aniso {

// Result of BRDF::sample(wo, uc, u). weight = f(wi, wo) cos(theta_i) / pdf, per channel.
// valid == false is "no sample" (wi below the horizon, degenerate wo, zero pdf); all fields are 0.
template <typename T> struct BSDFSampleT {
  Vec3T<T> wi{T(0)};
  RGBT<T> weight{T(0)};
  T pdf = T(0);
  bool valid = false;
};

// Builds the sample record for a sampled wi from the model's own f and pdf; any wi the model
// cannot use becomes "no sample". Keeps weight == f cos / pdf true by construction.
template <typename T> ANISO_INLINE BSDFSampleT<T> make_sample(const Vec3T<T>& wi, const RGBT<T>& f, T pdf) {
  BSDFSampleT<T> s;
  if (!above_horizon(wi) || !(pdf > T(0))) return s;
  s.wi = wi;
  s.pdf = pdf;
  s.weight = f * (wi.z / pdf);
  s.valid = true;
  return s;
}

// The concentric disk map (Shirley & Chiu 1997) in polar form: the signed radius r (the dominant
// one of 2u - 1's coordinates; |r| = max(|2u - 1|), exact in float) and the angle theta, the point
// being r (cos theta, sin theta). At the centre, where the angle is undefined, r = theta = 0.
template <typename T> struct DiskPolarT { T r, theta; };
template <typename T> ANISO_INLINE DiskPolarT<T> concentric_disk_polar(const Vec2T<T>& u) {
  const T ox = T(2) * u.x - T(1), oy = T(2) * u.y - T(1);
  if (ox == T(0) && oy == T(0)) return {T(0), T(0)};
  if ((ox < T(0) ? -ox : ox) > (oy < T(0) ? -oy : oy)) return {ox, kPi<T> / T(4) * (oy / ox)};
  return {oy, kPiOver2<T> - kPi<T> / T(4) * (ox / oy)};
}

// A uniform point on the unit disk through the concentric map.
template <typename T> ANISO_INLINE Vec2T<T> sample_uniform_disk_concentric(const Vec2T<T>& u) {
  using std::cos;
  using std::sin;
  const DiskPolarT<T> p = concentric_disk_polar(u);
  return Vec2T<T>(p.r * cos(p.theta), p.r * sin(p.theta));
}

// Cosine-weighted hemisphere (Malley's method via the concentric disk map, Shirley & Chiu 1997).
template <typename T> ANISO_INLINE Vec3T<T> sample_cosine_hemisphere(const Vec2T<T>& u) {
  const Vec2T<T> d = sample_uniform_disk_concentric(u);
  return Vec3T<T>(d.x, d.y, safe_sqrt(T(1) - d.x * d.x - d.y * d.y));
}

template <typename T> ANISO_INLINE T cosine_hemisphere_pdf(T cos_theta) {
  return cos_theta > T(0) ? cos_theta * kInvPi<T> : T(0);
}

// Any unit vectors t, b completing the unit axis a to a right-handed frame (Duff et al. 2017).
template <typename T> ANISO_INLINE void orthonormal_basis(const Vec3T<T>& a, Vec3T<T>& t, Vec3T<T>& b) {
  using std::copysign;
  const T sign = copysign(T(1), a.z);
  const T k = T(-1) / (sign + a.z);
  const T m = a.x * a.y * k;
  t = Vec3T<T>(T(1) + sign * a.x * a.x * k, sign * m, -sign * a.x);
  b = Vec3T<T>(m, sign + a.y * a.y * k, -a.y);
}

// Cosine-power lobe about the unit axis a: density (n + 1) / (2 pi) (a . w)^n on the hemisphere
// around a (Phong / Lafortune lobes; Lafortune et al. 1997, Sec. 4; Lawrence's notes).
template <typename T> ANISO_INLINE Vec3T<T> sample_cosine_power(const Vec3T<T>& a, T n, const Vec2T<T>& u) {
  using std::cos;
  using std::pow;
  using std::sin;
  const T cos_t = pow(T(1) - u.x, T(1) / (n + T(1)));  // 1 - u in (0, 1]: avoids pow(0, .)
  const T sin_t = safe_sqrt(T(1) - cos_t * cos_t);
  const T phi = T(2) * kPi<T> * u.y;
  Vec3T<T> t, b;
  orthonormal_basis(a, t, b);
  return sin_t * cos(phi) * t + sin_t * sin(phi) * b + cos_t * a;
}

// (a . w)^n by multiplication where n is a small integer (pow_small_int: the metal's directional
// diffuse lobe, n = 3 or 4 in the presets), else by pow.
template <typename T> ANISO_INLINE T cosine_power_pdf(T cos_axis, T n) {
  using std::pow;
  if (!(cos_axis > T(0))) return T(0);
  const T p = pow_small_int(cos_axis, n);
  return (n + T(1)) * kInv2Pi<T> * (p >= T(0) ? p : pow(cos_axis, n));
}

}  // namespace aniso
