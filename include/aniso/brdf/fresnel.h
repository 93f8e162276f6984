// aniso/brdf/fresnel.h: Fresnel reflectance of conductors (exact, from n + ik) and Schlick's
// approximation. Unpolarised light, incident from air (n = 1).
#pragma once

#include "aniso/core/math.h"

#if defined(__SSE2__) && !defined(__CUDACC__)
#include <immintrin.h>
#endif

namespace aniso {

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", Eq. 15:
// F(c) = F0 + (1 - F0)(1 - c)^5, c = cos of the angle between the light and the half vector.
template <typename T> ANISO_INLINE T F_Schlick(T f0, T cos_theta) {
  const T m = T(1) - clamp01(cos_theta);
  const T m2 = m * m;
  return f0 + (T(1) - f0) * (m2 * m2 * m);
}

// Schlick's form with a free reflectance at grazing incidence F90 (Schlick 1994 Eq. 15 with 1
// replaced by F90; Filament's F_Schlick(f0, f90, VoH), Karis 2013's specular model):
// F(c) = F0 + (F90 - F0)(1 - c)^5. Below 1 the Fresnel stays flatter towards grazing, as films
// and paints measure (docs/models/ggx.md).
template <typename T> ANISO_INLINE RGBT<T> F_Schlick(const RGBT<T>& f0, const RGBT<T>& f90, T cos_theta) {
  const T m = T(1) - clamp01(cos_theta);
  const T m2 = m * m;
  return f0 + (f90 - f0) * (m2 * m2 * m);
}
template <typename T> ANISO_INLINE RGBT<T> F_Schlick(const RGBT<T>& f0, T cos_theta) {
  return F_Schlick(f0, RGBT<T>(T(1)), cos_theta);
}

// Exact unpolarised reflectance of a conductor with complex index eta + i k, from air.
// Real-arithmetic form of the Fresnel equations (Born & Wolf, Principles of Optics, Sec. 14.2;
// the a^2 + b^2 formulation as in pbrt-v3's FrConductor):
//   a^2 + b^2 = sqrt((eta^2 - k^2 - sin^2)^2 + 4 eta^2 k^2),  a = sqrt((a^2 + b^2 + eta^2 - k^2 - sin^2)/2)
//   R_s = (a^2 + b^2 + cos^2 - 2 a cos) / (a^2 + b^2 + cos^2 + 2 a cos)
//   R_p = R_s (cos^2 (a^2 + b^2) + sin^4 - 2 a cos sin^2) / (cos^2 (a^2 + b^2) + sin^4 + 2 a cos sin^2)
// F = (R_s + R_p) / 2. At cos = 0 both are 1 (grazing incidence reflects everything).
// The terms of F_Conductor that depend on the angle alone, shared by the three channels of an RGB
// call (the same values as each channel computing its own).
template <typename T> struct FresnelAngleT { T c, cos2, sin2; };
template <typename T> ANISO_INLINE FresnelAngleT<T> Fresnel_Angle(T cos_theta) {
  const T c = clamp01(cos_theta);
  const T cos2 = c * c;
  return {c, cos2, T(1) - cos2};
}
template <typename T> ANISO_INLINE T F_Conductor(const FresnelAngleT<T>& angle, T eta, T k) {
  using std::sqrt;
  const T c = angle.c, cos2 = angle.cos2, sin2 = angle.sin2;
  const T eta2 = eta * eta, k2 = k * k;
  const T t0 = eta2 - k2 - sin2;
  const T a2_plus_b2 = sqrt(t0 * t0 + T(4) * eta2 * k2);
  const T t1 = a2_plus_b2 + cos2;
  const T a = safe_sqrt(T(0.5) * (a2_plus_b2 + t0));
  const T t2 = T(2) * c * a;
  const T rs = (t1 - t2) / (t1 + t2);
  const T t3 = cos2 * a2_plus_b2 + sin2 * sin2;
  const T t4 = t2 * sin2;
  const T rp = rs * (t3 - t4) / (t3 + t4);
  // Clamp at 0: for an index matched to air (eta = 1, k = 0) the true reflectance is 0, and the
  // differences t1 - t2 and t3 - t4 cancel to a rounding-size value of either sign (-1e-12 seen).
  const T f = T(0.5) * (rp + rs);
  return f > T(0) ? f : T(0);
}

template <typename T> ANISO_INLINE T F_Conductor(T cos_theta, T eta, T k) {
  return F_Conductor(Fresnel_Angle(cos_theta), eta, k);
}

template <typename T> ANISO_INLINE RGBT<T> F_Conductor(T cos_theta, const RGBT<T>& eta, const RGBT<T>& k) {
  const FresnelAngleT<T> angle = Fresnel_Angle(cos_theta);
  return RGBT<T>(F_Conductor(angle, eta.x, k.x), F_Conductor(angle, eta.y, k.y), F_Conductor(angle, eta.z, k.z));
}

#if defined(__SSE2__) && !defined(__CUDACC__)
// The three channels of a float call at once, one per lane of an SSE register (the fourth lane
// repeats the third and is dropped): every lane does the scalar F_Conductor's IEEE operations in
// its order (sqrt, add, multiply and divide are correctly rounded in SSE as in scalar code, and
// max(x, 0) is x > 0 ? x : 0, NaN included, as maxps returns its second operand on NaN), so the
// result is the scalar one bit for bit (tests/test_reference.cpp,
// ReferenceFresnel.FloatChannelsAtOnceAreTheScalarOnesBitForBit). The metal's hot path evaluates
// it twice a vertex; written out because the compiler keeps the channels apart.
template <> inline RGBT<float> F_Conductor<float>(float cos_theta, const RGBT<float>& eta, const RGBT<float>& k) {
  const FresnelAngleT<float> angle = Fresnel_Angle(cos_theta);
  const __m128 zero = _mm_setzero_ps(), half = _mm_set1_ps(0.5f);
  const __m128 c = _mm_set1_ps(angle.c), cos2 = _mm_set1_ps(angle.cos2), sin2 = _mm_set1_ps(angle.sin2);
  const __m128 e = _mm_setr_ps(eta.x, eta.y, eta.z, eta.z), kk = _mm_setr_ps(k.x, k.y, k.z, k.z);
  const __m128 eta2 = _mm_mul_ps(e, e), k2 = _mm_mul_ps(kk, kk);
  const __m128 t0 = _mm_sub_ps(_mm_sub_ps(eta2, k2), sin2);
  const __m128 a2_plus_b2 = _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(t0, t0), _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(4.0f), eta2), k2)));
  const __m128 t1 = _mm_add_ps(a2_plus_b2, cos2);
  const __m128 a = _mm_sqrt_ps(_mm_max_ps(_mm_mul_ps(half, _mm_add_ps(a2_plus_b2, t0)), zero));
  const __m128 t2 = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(2.0f), c), a);
  const __m128 rs = _mm_div_ps(_mm_sub_ps(t1, t2), _mm_add_ps(t1, t2));
  const __m128 t3 = _mm_add_ps(_mm_mul_ps(cos2, a2_plus_b2), _mm_mul_ps(sin2, sin2));
  const __m128 t4 = _mm_mul_ps(t2, sin2);
  const __m128 rp = _mm_div_ps(_mm_mul_ps(rs, _mm_sub_ps(t3, t4)), _mm_add_ps(t3, t4));
  const __m128 f = _mm_max_ps(_mm_mul_ps(half, _mm_add_ps(rp, rs)), zero);
  alignas(16) float out[4];
  _mm_store_ps(out, f);
  return RGBT<float>(out[0], out[1], out[2]);
}
#endif

}  // namespace aniso
