// aniso/core/math.h: vector types (glm, so the C++ reads like the GLSL mirror) and small scalar
// helpers. Scalar code calls the math functions unqualified after `using std::...` so that the
// same templates work on float, double and, for fitting, ceres::Jet (found by ADL).
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

#include <glm/glm.hpp>

#include "aniso/core/platform.h"

namespace aniso {

template <typename T> using Vec2T = glm::vec<2, T, glm::defaultp>;
template <typename T> using Vec3T = glm::vec<3, T, glm::defaultp>;
using Vec2 = Vec2T<float>;
using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;
// Linear RGB, Rec.709 primaries (docs/conventions.md).
template <typename T> using RGBT = Vec3T<T>;
using RGB = RGBT<float>;

template <typename T> ANISO_INLINE T sqr(T x) { return x * x; }

// max(x, 0) before sqrt: rounding can push a mathematically non-negative argument below zero.
template <typename T> ANISO_INLINE T safe_sqrt(T x) {
  using std::sqrt;
  return sqrt(x > T(0) ? x : T(0));
}

// x^n for x > 0 by repeated squaring where n is an integer in [1, 16] and the result a normal,
// finite number: at most 7 multiplications in place of a pow (or an exp and a log), each rounding
// once, so within about n ulps of the exact power (each squaring doubles its factor's relative
// error). -1 where that does not hold (another n; a power that overflows, or falls below the normal
// range where the squares lose precision): the caller then takes pow. Floating-point T only: a
// derivative type (the fitter's ceres::Jet) always gets -1, which keeps its derivative in n.
template <typename T> ANISO_INLINE T pow_small_int(T x, T n) {
  if constexpr (std::is_floating_point_v<T>) {
    if (n >= T(1) && n <= T(16) && n == T(int(n))) {
      int k = int(n);
      T r = T(1), b = x;
      for (;;) {
        if (k & 1) r *= b;
        k >>= 1;
        if (k == 0) break;
        b *= b;
      }
      if (r >= std::numeric_limits<T>::min() && r <= std::numeric_limits<T>::max()) return r;
    }
  }
  return T(-1);
}

template <typename T> ANISO_INLINE T clamp01(T x) { return x < T(0) ? T(0) : (x > T(1) ? T(1) : x); }

template <typename T> ANISO_INLINE T average(const Vec3T<T>& c) { return (c.x + c.y + c.z) / T(3); }

template <typename T> ANISO_INLINE T max_component(const Vec3T<T>& c) {
  T m = c.x > c.y ? c.x : c.y;
  return m > c.z ? m : c.z;
}

// Local shading frame (docs/conventions.md): z = n, x = t, y = b.
template <typename T> ANISO_INLINE T cos_theta(const Vec3T<T>& w) { return w.z; }

// The horizon (docs/conventions.md, "The horizon"): a unit direction whose cos(theta) is at or
// below HorizonCos is treated as on the horizon, where every BRDF is 0, every pdf 0 and sample()
// gives no sample. Why not 0: the normalisations grow like 1 / cos (Ward 1992, Duer), 1 / (h.n)^4
// (balanced Ward) or 1 / cos^3 (Walter's half-vector pdf); for cosines a few hundred orders of
// magnitude below 1 in double, or ~1e-15 in float, those terms overflow or become 0 / 0, and
// wi + wo of two such directions loses its length to underflow. The thresholds:
//  - float 1e-6 (theta = 89.99994 deg): the rounding of a float unit vector's z is ~6e-8, so below
//    1e-6 the cosine is mostly rounding; with alpha >= 1e-3 (params.cpp) every normalisation then
//    stays below ~1e25, far inside float's 3.4e38.
//  - double 1e-12: the same margin in double's range (Duer's 1 / (4 pi ax ay cos_i cos_o) <= 1e31).
// The solid angle lost is about 2 pi HorizonCos sr (6e-6 sr in float), an energy change far below
// any test's tolerance. tests/test_horizon.cpp sweeps every model and preset down to the smallest
// subnormal cosine.
template <typename T> struct HorizonCos { static constexpr double value = 1e-12; };
template <> struct HorizonCos<float> { static constexpr double value = 1e-6; };
template <typename T> ANISO_INLINE T horizon_cos() { return T(HorizonCos<T>::value); }

// w strictly above the horizon (see HorizonCos).
template <typename T> ANISO_INLINE bool above_horizon(const Vec3T<T>& w) { return w.z > horizon_cos<T>(); }

// Both directions above the horizon: the BRDFs are defined there and nowhere else.
template <typename T> ANISO_INLINE bool same_upper_hemisphere(const Vec3T<T>& wi, const Vec3T<T>& wo) {
  return above_horizon(wi) && above_horizon(wo);
}

// Mirror of w about the unit vector h: 2 (w.h) h - w.
template <typename T> ANISO_INLINE Vec3T<T> reflect_about(const Vec3T<T>& w, const Vec3T<T>& h) {
  return T(2) * glm::dot(w, h) * h - w;
}

// Mirror about the normal in the local frame: the Householder matrix M = diag(-1, -1, 1).
template <typename T> ANISO_INLINE Vec3T<T> reflect_about_normal(const Vec3T<T>& w) { return Vec3T<T>(-w.x, -w.y, w.z); }

}  // namespace aniso
