// aniso/core/math.h: vector types (glm, so the C++ reads like the GLSL mirror) and small scalar
// helpers. Scalar code calls the math functions unqualified after `using std::...` so that the
// same templates work on float, double and, for fitting, ceres::Jet (found by ADL).
#pragma once

#include <cmath>

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

template <typename T> ANISO_INLINE T clamp01(T x) { return x < T(0) ? T(0) : (x > T(1) ? T(1) : x); }

template <typename T> ANISO_INLINE T average(const Vec3T<T>& c) { return (c.x + c.y + c.z) / T(3); }

template <typename T> ANISO_INLINE T max_component(const Vec3T<T>& c) {
  T m = c.x > c.y ? c.x : c.y;
  return m > c.z ? m : c.z;
}

// Local shading frame (docs/conventions.md): z = n, x = t, y = b.
template <typename T> ANISO_INLINE T cos_theta(const Vec3T<T>& w) { return w.z; }

// Both directions strictly above the horizon: the BRDFs are defined there and nowhere else.
template <typename T> ANISO_INLINE bool same_upper_hemisphere(const Vec3T<T>& wi, const Vec3T<T>& wo) {
  return wi.z > T(0) && wo.z > T(0);
}

// Mirror of w about the unit vector h: 2 (w.h) h - w.
template <typename T> ANISO_INLINE Vec3T<T> reflect_about(const Vec3T<T>& w, const Vec3T<T>& h) {
  return T(2) * glm::dot(w, h) * h - w;
}

// Mirror about the normal in the local frame: the Householder matrix M = diag(-1, -1, 1).
template <typename T> ANISO_INLINE Vec3T<T> reflect_about_normal(const Vec3T<T>& w) {
  return Vec3T<T>(-w.x, -w.y, w.z);
}

}  // namespace aniso
