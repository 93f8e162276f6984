// batch/kernels-inl.h: Google Highway twins of the scalar kernels in include/aniso/brdf, compiled
// once per SIMD target (src/batch/batch.cpp includes this through hwy/foreach_target.h).
//
// Every function here names its scalar twin and repeats its arithmetic in the same order (same
// operations, same association, no fused multiply-adds the scalar code does not have), so that the
// two differ only where a function of the C library is replaced by its Highway version:
//   exp, log, acos, atan, sin, cos   hwy/contrib/math (1 to 4 ulp by Highway's documentation)
//   pow(x, y), x > 0                 exp(y log x): the error of log x is multiplied by |y log x|
//   tan                              sin / cos (Highway 1.0 has no Tan)
//   atan2 and sin / cos of atan      algebra (Ward's sampler, WardLobeK::Sample)
// (CMakeLists.txt compiles this with -ffp-contract=off so that the compiler does not fuse a * b + c
// either; batch.cpp flushes subnormals while it runs.)
// Branches become masks: both sides are computed for every lane and the mask picks one. Lanes
// whose inputs are outside a term's domain (below the horizon) compute garbage, NaN included, that
// the caller's mask discards; no floating-point exception is observed, so that is harmless.
//
// The argument block every target's loop takes (one type for all targets: the dispatch table
// holds one function pointer type).
#ifndef ANISO_BATCH_KERNELS_ARGS_H_
#define ANISO_BATCH_KERNELS_ARGS_H_
#include <algorithm>
#include <limits>
#include "aniso/batch/batch.h"
namespace aniso::batch {
template <typename T> struct EvalArgs {
  Directions<T> wi, wo;
  Colors<T> f;
  T* pdf;
  NonFinite non_finite = NonFinite::AsComputed;
};
template <typename T> struct InterleavedArgs {
  Interleaved<T> wi, wo;
  T* f_rgb;  // evaluate: interleaved RGB rows
  T* pdf;    // pdf
  NonFinite non_finite;
};
template <typename T> struct SampleArgs {
  Directions<T> wo;
  const T *uc, *u0, *u1;
  Samples<T> out;
};
}  // namespace aniso::batch
#endif

// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_KERNELS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_KERNELS_INL_H_
#undef ANISO_BATCH_KERNELS_INL_H_
#else
#define ANISO_BATCH_KERNELS_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "aniso/brdf/material.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D> using V = hn::Vec<D>;
template <class D> using M = hn::Mask<D>;

template <class D> struct V3 {
  V<D> x, y, z;
};

template <class D> HWY_INLINE V<D> K(D d, hn::TFromD<D> c) { return hn::Set(d, c); }

// --- core/math.h twins -----------------------------------------------------------------------

template <class D> HWY_INLINE V<D> Sqr(V<D> x) { return hn::Mul(x, x); }
// Highway's Exp, Sin and Cos convert a multiple of their argument to int32 (range reduction); on
// the 1-lane SCALAR target that is a C++ float-to-int cast, undefined for NaN (found by UBSan in
// make test-sanitize, batch_tests_baseline: Ward's exponent in a masked-off lane). NaN lanes go in
// as 0 and come out as the NaN they were: exp, sin and cos of NaN are NaN, so no result changes.
template <class D, class Op> HWY_INLINE V<D> NaNPassing(D d, V<D> x, Op op) {
  const M<D> nan = hn::IsNaN(x);
  return hn::IfThenElse(nan, x, op(d, hn::IfThenZeroElse(nan, x)));
}
template <class D> HWY_INLINE V<D> ExpNaN(D d, V<D> x) {
  return NaNPassing(d, x, [](D dd, V<D> v) { return hn::Exp(dd, v); });
}
template <class D> HWY_INLINE V<D> SinNaN(D d, V<D> x) {
  return NaNPassing(d, x, [](D dd, V<D> v) { return hn::Sin(dd, v); });
}
template <class D> HWY_INLINE V<D> CosNaN(D d, V<D> x) {
  return NaNPassing(d, x, [](D dd, V<D> v) { return hn::Cos(dd, v); });
}
// glm::dot: (a.x b.x + a.y b.y) + a.z b.z.
template <class D> HWY_INLINE V<D> Dot(const V3<D>& a, const V3<D>& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
template <class D> HWY_INLINE V3<D> Add3(const V3<D>& a, const V3<D>& b) {
  return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
}
// glm::normalize: v * (1 / sqrt(v . v)) (glm's inversesqrt is 1 / sqrt).
template <class D> HWY_INLINE V3<D> Normalize(D d, const V3<D>& v) {
  const V<D> inv = hn::Div(K(d, 1), hn::Sqrt(Dot(v, v)));
  return {hn::Mul(v.x, inv), hn::Mul(v.y, inv), hn::Mul(v.z, inv)};
}
// safe_sqrt: sqrt(max(x, 0)) (the max as in math.h: a NaN argument becomes 0 there and here).
template <class D> HWY_INLINE V<D> SafeSqrt(D d, V<D> x) { return hn::Sqrt(hn::IfThenElseZero(hn::Gt(x, hn::Zero(d)), x)); }
// clamp01.
template <class D> HWY_INLINE V<D> Clamp01(D d, V<D> x) { return hn::Min(hn::Max(x, hn::Zero(d)), K(d, 1)); }
// above_horizon: cos(theta) > horizon_cos<T>() (math.h, "The horizon").
template <class D> HWY_INLINE M<D> AboveHorizon(D d, V<D> cos_theta) {
  return hn::Gt(cos_theta, K(d, horizon_cos<hn::TFromD<D>>()));
}
// same_upper_hemisphere.
template <class D> HWY_INLINE M<D> UpperBoth(D d, const V3<D>& wi, const V3<D>& wo) {
  return hn::And(AboveHorizon(d, wi.z), AboveHorizon(d, wo.z));
}
// average(c) = (c.x + c.y + c.z) / 3.
template <class D> HWY_INLINE V<D> Average(D d, V<D> r, V<D> g, V<D> b) {
  return hn::Div(hn::Add(hn::Add(r, g), b), K(d, 3));
}
// pow(x, y) for x > 0 as exp(y log x). Own SIMD version: Highway has exp and log, not pow.
// The error of log x is multiplied by |y log x|; Highway's log (musl's algorithm) is accurate
// relative to its result near x = 1 as well, so for the exponents of the fitted materials
// (Ashikhmin-Shirley n up to 10^4, Lafortune n up to 200) the float result stays within 2e-6 of
// powf wherever the value is above 1e-12 of the lobe's peak (test_batch.cpp measures it).
template <class D> HWY_INLINE V<D> PowPositive(D d, V<D> x, V<D> y) { return ExpNaN(d, hn::Mul(y, hn::Log(d, x))); }

// --- core/sampling.h twins -------------------------------------------------------------------

// cosine_hemisphere_pdf.
template <class D> HWY_INLINE V<D> CosineHemispherePdf(D d, V<D> c) {
  return hn::IfThenElseZero(hn::Gt(c, hn::Zero(d)), hn::Mul(c, K(d, kInvPi<hn::TFromD<D>>)));
}
// cosine_power_pdf: (n + 1) / (2 pi) c^n for c > 0.
template <class D> HWY_INLINE V<D> CosinePowerPdf(D d, V<D> c, V<D> n) {
  using T = hn::TFromD<D>;
  const M<D> pos = hn::Gt(c, hn::Zero(d));
  const V<D> safe_c = hn::IfThenElse(pos, c, K(d, 1));
  return hn::IfThenElseZero(pos, hn::Mul(hn::Mul(hn::Add(n, K(d, 1)), K(d, kInv2Pi<T>)), PowPositive(d, safe_c, n)));
}

// sample_uniform_disk_concentric (Shirley & Chiu 1997): the branch on |ox| > |oy| becomes a mask.
template <class D> HWY_INLINE void ConcentricDisk(D d, V<D> u0, V<D> u1, V<D>& dx, V<D>& dy) {
  using T = hn::TFromD<D>;
  const V<D> ox = hn::Sub(hn::Mul(K(d, T(2)), u0), K(d, 1)), oy = hn::Sub(hn::Mul(K(d, T(2)), u1), K(d, 1));
  const M<D> centre = hn::And(hn::Eq(ox, hn::Zero(d)), hn::Eq(oy, hn::Zero(d)));
  const M<D> x_major = hn::Gt(hn::Abs(ox), hn::Abs(oy));
  const V<D> r = hn::IfThenElse(x_major, ox, oy);
  const V<D> quarter_pi = K(d, kPi<T> / T(4));
  const V<D> theta = hn::IfThenElse(x_major, hn::Mul(quarter_pi, hn::Div(oy, ox)),
                                    hn::Sub(K(d, kPiOver2<T>), hn::Mul(quarter_pi, hn::Div(ox, oy))));
  dx = hn::IfThenZeroElse(centre, hn::Mul(r, CosNaN(d, theta)));
  dy = hn::IfThenZeroElse(centre, hn::Mul(r, SinNaN(d, theta)));
}
// sample_cosine_hemisphere.
template <class D> HWY_INLINE V3<D> CosineHemisphere(D d, V<D> u0, V<D> u1) {
  V<D> dx, dy;
  ConcentricDisk(d, u0, u1, dx, dy);
  return {dx, dy, SafeSqrt(d, hn::Sub(hn::Sub(K(d, 1), hn::Mul(dx, dx)), hn::Mul(dy, dy)))};
}
// reflect_about(w, h) = 2 (w.h) h - w.
template <class D> HWY_INLINE V3<D> ReflectAbout(D d, const V3<D>& w, const V3<D>& h) {
  const V<D> k = hn::Mul(K(d, 2), Dot(w, h));
  return {hn::Sub(hn::Mul(k, h.x), w.x), hn::Sub(hn::Mul(k, h.y), w.y), hn::Sub(hn::Mul(k, h.z), w.z)};
}
// sample_cosine_power about the unit axis a, with orthonormal_basis (Duff et al. 2017).
template <class D> HWY_INLINE V3<D> CosinePowerSample(D d, const V3<D>& a, V<D> n, V<D> u0, V<D> u1) {
  using T = hn::TFromD<D>;
  const V<D> one = K(d, 1);
  const V<D> cos_t = PowPositive(d, hn::Sub(one, u0), hn::Div(one, hn::Add(n, one)));
  const V<D> sin_t = SafeSqrt(d, hn::Sub(one, hn::Mul(cos_t, cos_t)));
  const V<D> phi = hn::Mul(K(d, T(2) * kPi<T>), u1);
  const V<D> sign = hn::CopySign(one, a.z);
  const V<D> k = hn::Div(K(d, -1), hn::Add(sign, a.z));
  const V<D> m = hn::Mul(hn::Mul(a.x, a.y), k);
  const V3<D> t{hn::Add(one, hn::Mul(hn::Mul(hn::Mul(sign, a.x), a.x), k)), hn::Mul(sign, m), hn::Neg(hn::Mul(sign, a.x))};
  const V3<D> b{m, hn::Add(sign, hn::Mul(hn::Mul(a.y, a.y), k)), hn::Neg(a.y)};
  const V<D> ct = hn::Mul(sin_t, CosNaN(d, phi)), st = hn::Mul(sin_t, SinNaN(d, phi));
  return {hn::Add(hn::Add(hn::Mul(ct, t.x), hn::Mul(st, b.x)), hn::Mul(cos_t, a.x)),
          hn::Add(hn::Add(hn::Mul(ct, t.y), hn::Mul(st, b.y)), hn::Mul(cos_t, a.y)),
          hn::Add(hn::Add(hn::Mul(ct, t.z), hn::Mul(st, b.z)), hn::Mul(cos_t, a.z))};
}

// --- brdf/fresnel.h twins --------------------------------------------------------------------

// F_Schlick(f0, c) = f0 + (1 - f0)(1 - clamp01(c))^5.
template <class D> HWY_INLINE V<D> FSchlick(D d, hn::TFromD<D> f0, V<D> cos_theta) {
  const V<D> m = hn::Sub(K(d, 1), Clamp01(d, cos_theta));
  const V<D> m2 = hn::Mul(m, m);
  return hn::Add(K(d, f0), hn::Mul(K(d, hn::TFromD<D>(1) - f0), hn::Mul(hn::Mul(m2, m2), m)));
}

// F_Conductor(c, eta, k): the same real-arithmetic Fresnel equations, operation for operation.
template <class D> HWY_INLINE V<D> FConductor(D d, V<D> cos_theta, hn::TFromD<D> eta, hn::TFromD<D> k) {
  using T = hn::TFromD<D>;
  const V<D> c = Clamp01(d, cos_theta);
  const V<D> cos2 = hn::Mul(c, c);
  const V<D> sin2 = hn::Sub(K(d, 1), cos2);
  const T eta2 = eta * eta, k2 = k * k;
  const V<D> t0 = hn::Sub(K(d, eta2 - k2), sin2);
  const V<D> a2_plus_b2 = hn::Sqrt(hn::Add(hn::Mul(t0, t0), K(d, T(4) * eta2 * k2)));
  const V<D> t1 = hn::Add(a2_plus_b2, cos2);
  const V<D> a = SafeSqrt(d, hn::Mul(K(d, T(0.5)), hn::Add(a2_plus_b2, t0)));
  const V<D> t2 = hn::Mul(hn::Mul(K(d, T(2)), c), a);
  const V<D> rs = hn::Div(hn::Sub(t1, t2), hn::Add(t1, t2));
  const V<D> t3 = hn::Add(hn::Mul(cos2, a2_plus_b2), hn::Mul(sin2, sin2));
  const V<D> t4 = hn::Mul(t2, sin2);
  const V<D> rp = hn::Div(hn::Mul(rs, hn::Sub(t3, t4)), hn::Add(t3, t4));
  const V<D> f = hn::Mul(K(d, T(0.5)), hn::Add(rp, rs));
  return hn::IfThenElseZero(hn::Gt(f, hn::Zero(d)), f);  // clamped at 0, as the scalar code
}

// --- lobe_mixture.h twins --------------------------------------------------------------------

// specular_share(dw, sw) = sw / (dw + sw), 0 when nothing weighs.
template <class D> HWY_INLINE V<D> SpecularShare(D d, V<D> dw, V<D> sw) {
  const V<D> total = hn::Add(dw, sw);
  return hn::IfThenElseZero(hn::Gt(total, hn::Zero(d)), hn::Div(sw, total));
}
// pdf_diffuse_specular inside the upper hemisphere: (1 - p) cos_pdf(wi.z) + p lobe_pdf.
template <class D> HWY_INLINE V<D> MixturePdf(D d, V<D> p_spec, V<D> wi_z, V<D> lobe_pdf) {
  return hn::Add(hn::Mul(hn::Sub(K(d, 1), p_spec), CosineHemispherePdf(d, wi_z)), hn::Mul(p_spec, lobe_pdf));
}

template <class D> struct RGBV {
  V<D> c[3];
};

// --- ward.h twins ------------------------------------------------------------------------------

// Ward_Exp: exp(x) with the underflow decided at the same bound as the scalar code.
template <class D> HWY_INLINE V<D> WardExp(D d, V<D> x) {
  using T = hn::TFromD<D>;
  return hn::IfThenZeroElse(hn::Lt(x, K(d, T(sizeof(T) == sizeof(float) ? -104.0 : -746.0))), ExpNaN(d, x));
}
// E_Ward_Vector.
template <class D> HWY_INLINE V<D> EWardVector(D d, V<D> hx, V<D> hy, V<D> hz, V<D> ax, V<D> ay) {
  return WardExp(d, hn::Div(hn::Neg(hn::Add(Sqr<D>(hn::Div(hx, ax)), Sqr<D>(hn::Div(hy, ay)))), Sqr<D>(hz)));
}

template <typename T> struct WardLobeK {
  T ax, ay, axay;
  WardForm form;
  WardNormalization normalization;
  explicit WardLobeK(const WardLobeT<T>& l)
      : ax(l.alpha_x), ay(l.alpha_y), axay(l.alpha_x * l.alpha_y), form(l.form), normalization(l.normalization) {}

  // WardLobeT::eval (lanes with both directions above the horizon are meaningful).
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> vax = K(d, ax), vay = K(d, ay);
    const V3<D> h = Add3(wi, wo);
    V<D> e;
    switch (form) {
      case WardForm::Angle: {
        // Ward_HalfAngles + E_Ward_Angle; tan(theta) as sin / cos (own SIMD version: no Tan).
        const V3<D> hn_ = Normalize(d, h);
        const V<D> theta = hn::Acos(d, Clamp01(d, hn_.z));
        const V<D> proj_len = hn::Sqrt(hn::Add(Sqr<D>(hn_.x), Sqr<D>(hn_.y)));
        const M<D> has_dir = hn::Gt(proj_len, hn::Zero(d));
        const V<D> cos_phi = hn::IfThenElse(has_dir, hn::Div(hn_.x, proj_len), K(d, 1));
        const V<D> sin_phi = hn::IfThenElseZero(has_dir, hn::Div(hn_.y, proj_len));
        const V<D> tan_t = hn::Div(SinNaN(d, theta), CosNaN(d, theta));
        e = WardExp(d, hn::Mul(hn::Neg(Sqr<D>(tan_t)),
                               hn::Add(Sqr<D>(hn::Div(cos_phi, vax)), Sqr<D>(hn::Div(sin_phi, vay)))));
        break;
      }
      case WardForm::Approx: {
        const V3<D> hn_ = Normalize(d, h);  // E_Ward_Approx
        e = WardExp(d, hn::Div(hn::Mul(K(d, T(-2)), hn::Add(Sqr<D>(hn::Div(hn_.x, vax)), Sqr<D>(hn::Div(hn_.y, vay)))),
                               hn::Add(K(d, 1), hn_.z)));
        break;
      }
      default:
        e = EWardVector(d, h.x, h.y, h.z, vax, vay);
        break;
    }
    V<D> norm;
    switch (normalization) {
      case WardNormalization::Duer:  // N_Duer
        norm = hn::Div(K(d, kInv4Pi<T>), hn::Mul(hn::Mul(K(d, axay), wi.z), wo.z));
        break;
      case WardNormalization::Balanced:  // N_Balanced
        norm = hn::Div(hn::Mul(Dot(h, h), K(d, kInvPi<T>)), hn::Mul(K(d, axay), Sqr<D>(Sqr<D>(h.z))));
        break;
      default:  // N_Ward1992
        norm = hn::Div(K(d, kInv4Pi<T>), hn::Mul(K(d, axay), hn::Sqrt(hn::Mul(wi.z, wo.z))));
        break;
    }
    // The Gaussian underflowed: 0, never 0 * inf.
    return hn::IfThenElseZero(hn::Gt(e, hn::Zero(d)), hn::Mul(e, norm));
  }

  // WardLobeT::sample with Ward_SampleHalf (Walter 2005 Eqs. 8-9). Own SIMD version of the angles:
  // Highway 1.0 has no atan2, so (cos phi, sin phi) = (ax cos 2 pi u, ay sin 2 pi u) / length, which
  // is what atan2 followed by cos and sin computes, and sin / cos of theta = atan(t) are
  // t / sqrt(1 + t^2) and 1 / sqrt(1 + t^2).
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    const V<D> two_pi_u = hn::Mul(K(d, T(2) * kPi<T>), u1);
    const V<D> px = hn::Mul(K(d, ax), CosNaN(d, two_pi_u)), py = hn::Mul(K(d, ay), SinNaN(d, two_pi_u));
    const V<D> len = hn::Sqrt(hn::Add(hn::Mul(px, px), hn::Mul(py, py)));
    const V<D> c = hn::Div(px, len), s = hn::Div(py, len);
    const V<D> t2 = hn::Div(hn::Neg(hn::Log(d, hn::Sub(K(d, 1), u0))),
                            hn::Add(Sqr<D>(hn::Div(c, K(d, ax))), Sqr<D>(hn::Div(s, K(d, ay)))));
    const V<D> inv = hn::Div(K(d, 1), hn::Sqrt(hn::Add(K(d, 1), t2)));
    const V<D> st = hn::Mul(hn::Sqrt(t2), inv);
    return ReflectAbout(d, wo, V3<D>{hn::Mul(st, c), hn::Mul(st, s), inv});
  }

  // WardLobeT::pdf with Ward_PdfHalf.
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh = Dot(wo, h);
    const V<D> e = EWardVector(d, h.x, h.y, h.z, K(d, ax), K(d, ay));
    const V<D> ph = hn::Div(hn::Mul(e, K(d, kInvPi<T>)), hn::Mul(hn::Mul(hn::Mul(K(d, axay), h.z), h.z), h.z));
    const M<D> ok = hn::And(hn::Gt(woh, hn::Zero(d)), hn::Gt(h.z, hn::Zero(d)));
    return hn::IfThenElseZero(ok, hn::Div(ph, hn::Mul(K(d, T(4)), woh)));
  }
};

// --- phong.h twins -----------------------------------------------------------------------------

template <typename T> struct PhongLobeK {
  T exponent, normalization;
  bool normalized;
  explicit PhongLobeK(const PhongLobeT<T>& l)
      : exponent(l.exponent), normalization(Phong_Normalization(l.exponent)), normalized(l.normalized) {}
  // (M wi) . wo with M = diag(-1, -1, 1).
  template <class D> HWY_INLINE static V<D> MirrorDot(const V3<D>& a, const V3<D>& b) {
    return hn::Add(hn::Add(hn::Mul(hn::Neg(a.x), b.x), hn::Mul(hn::Neg(a.y), b.y)), hn::Mul(a.z, b.z));
  }
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> rov = MirrorDot(wi, wo);
    const M<D> pos = hn::Gt(rov, hn::Zero(d));  // Phong_Lobe
    const V<D> lobe = hn::IfThenElseZero(pos, PowPositive(d, hn::IfThenElse(pos, rov, K(d, 1)), K(d, exponent)));
    return normalized ? hn::Mul(lobe, K(d, normalization)) : lobe;
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    return CosinePowerPdf(d, MirrorDot(wo, wi), K(d, exponent));
  }
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    return CosinePowerSample(d, V3<D>{hn::Neg(wo.x), hn::Neg(wo.y), wo.z}, K(d, exponent), u0, u1);
  }
};

// LambertPlusLobeT: kd / pi + ks lobe, the lobe chosen with a constant probability.
template <typename T, typename LobeK> struct LambertPlusLobeK {
  T kd_pi[3], ks[3], p_spec;
  LobeK lobe;
  template <typename Lobe>
  explicit LambertPlusLobeK(const LambertPlusLobeT<T, Lobe>& m)
      : kd_pi{m.kd.x * kInvPi<T>, m.kd.y * kInvPi<T>, m.kd.z * kInvPi<T>},
        ks{m.ks.x, m.ks.y, m.ks.z},
        p_spec(m.specular_probability(Vec3T<T>(T(0), T(0), T(1)))),
        lobe(m.lobe) {}
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V<D> l = lobe.Eval(d, wi, wo);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) out.c[c] = hn::IfThenElseZero(upper, hn::Add(K(d, kd_pi[c]), hn::Mul(K(d, ks[c]), l)));
    return out;
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), MixturePdf(d, K(d, p_spec), wi.z, lobe.Pdf(d, wi, wo)));
  }
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>&) const { return K(d, p_spec); }
};

// --- lambert.h twin ----------------------------------------------------------------------------

template <typename T> struct LambertK {
  T kd_pi[3];
  explicit LambertK(const LambertT<T>& m) : kd_pi{m.kd.x * Fd_Lambert<T>(), m.kd.y * Fd_Lambert<T>(), m.kd.z * Fd_Lambert<T>()} {}
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) out.c[c] = hn::IfThenElseZero(upper, K(d, kd_pi[c]));
    return out;
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), CosineHemispherePdf(d, wi.z));
  }
};

// --- ashikhmin_shirley.h twins -----------------------------------------------------------------

template <typename T> struct ASLobeK {
  T nu, nv, spec_norm, half_norm;
  explicit ASLobeK(const AshikhminShirleyLobeT<T>& l)
      : nu(l.n_u),
        nv(l.n_v),
        spec_norm(std::sqrt((l.n_u + T(1)) * (l.n_v + T(1))) / (T(8) * kPi<T>)),
        half_norm(std::sqrt((l.n_u + T(1)) * (l.n_v + T(1))) * kInv2Pi<T>) {}
  // AS_Exponent.
  template <class D> HWY_INLINE V<D> Exponent(D d, V<D> hot, V<D> hob) const {
    const V<D> s2 = hn::Add(hn::Mul(hot, hot), hn::Mul(hob, hob));
    const V<D> e = hn::Div(hn::Add(hn::Mul(hn::Mul(K(d, nu), hot), hot), hn::Mul(hn::Mul(K(d, nv), hob), hob)), s2);
    return hn::IfThenElse(hn::Gt(s2, hn::Zero(d)), e, K(d, nu));
  }
  // AS_Specular for a unit h (h.z > 0 above the horizon), 0 unless h.wi > 0.
  template <class D> HWY_INLINE V<D> Specular(D d, const V3<D>& h, V<D> hol, V<D> nol, V<D> nov) const {
    const V<D> p = PowPositive(d, h.z, Exponent(d, h.x, h.y));
    return hn::IfThenElseZero(hn::Gt(hol, hn::Zero(d)), hn::Div(hn::Mul(K(d, spec_norm), p), hn::Mul(hol, hn::Max(nol, nov))));
  }
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    return Specular(d, h, Dot(h, wi), wi.z, wo.z);
  }
  // AshikhminShirleyLobeT::sample with AS_SampleHalf (Eqs. 9-10): the four quarters of u.x become
  // masks over one atan; tan(x) as sin / cos (own SIMD version: Highway 1.0 has no Tan).
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    const V<D> one = K(d, 1), two = K(d, 2);
    const V<D> ratio = K(d, std::sqrt((nu + T(1)) / (nv + T(1))));
    const V<D> q = hn::Mul(K(d, T(4)), u0);
    const M<D> q1 = hn::Lt(q, one), q2 = hn::Lt(q, two), q3 = hn::Lt(q, K(d, 3));
    // The argument of tan(pi / 2 x) in each quarter: q, 2 - q, q - 2, 4 - q.
    const V<D> x = hn::IfThenElse(q1, q, hn::IfThenElse(q2, hn::Sub(two, q), hn::IfThenElse(q3, hn::Sub(q, two), hn::Sub(K(d, 4), q))));
    const V<D> arg = hn::Mul(K(d, kPiOver2<T>), x);
    const V<D> base = hn::Atan(d, hn::Mul(ratio, hn::Div(SinNaN(d, arg), CosNaN(d, arg))));
    const V<D> phi = hn::IfThenElse(
        q1, base,
        hn::IfThenElse(q2, hn::Sub(K(d, kPi<T>), base),
                       hn::IfThenElse(q3, hn::Add(K(d, kPi<T>), base), hn::Sub(K(d, T(2) * kPi<T>), base))));
    const V<D> c = CosNaN(d, phi), s = SinNaN(d, phi);
    const V<D> e = hn::Add(hn::Mul(hn::Mul(K(d, nu), c), c), hn::Mul(hn::Mul(K(d, nv), s), s));
    const V<D> cos_t = PowPositive(d, hn::Sub(one, u1), hn::Div(one, hn::Add(e, one)));
    const V<D> sin_t = SafeSqrt(d, hn::Sub(one, hn::Mul(cos_t, cos_t)));
    return ReflectAbout(d, wo, V3<D>{hn::Mul(sin_t, c), hn::Mul(sin_t, s), cos_t});
  }
  // AshikhminShirleyLobeT::pdf with AS_PdfHalf.
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh = Dot(wo, h);
    const M<D> hz_pos = hn::Gt(h.z, hn::Zero(d));
    const V<D> ph = hn::IfThenElseZero(
        hz_pos, hn::Mul(K(d, half_norm), PowPositive(d, hn::IfThenElse(hz_pos, h.z, K(d, 1)), Exponent(d, h.x, h.y))));
    return hn::IfThenElseZero(hn::Gt(woh, hn::Zero(d)), hn::Div(ph, hn::Mul(K(d, T(4)), woh)));
  }
};

// AS_Diffuse.
template <class D> HWY_INLINE V<D> ASDiffuse(D d, V<D> nol, V<D> nov) {
  using T = hn::TFromD<D>;
  const V<D> a = hn::Sub(K(d, 1), hn::Mul(nol, K(d, T(0.5)))), b = hn::Sub(K(d, 1), hn::Mul(nov, K(d, T(0.5))));
  const V<D> a5 = hn::Mul(hn::Mul(hn::Mul(hn::Mul(a, a), a), a), a);
  const V<D> b5 = hn::Mul(hn::Mul(hn::Mul(hn::Mul(b, b), b), b), b);
  return hn::Mul(hn::Mul(K(d, T(28) / (T(23) * kPi<T>)), hn::Sub(K(d, 1), a5)), hn::Sub(K(d, 1), b5));
}

template <typename T> struct AshikhminShirleyK {
  T rs[3], ks[3], diffuse[3], kd_pi[3], diffuse_weight;
  ASLobeK<T> lobe;
  explicit AshikhminShirleyK(const AshikhminShirleyT<T>& m) : lobe(m.lobe) {
    for (int c = 0; c < 3; ++c) {
      rs[c] = m.rs[c];
      ks[c] = m.ks_scale[c];
      diffuse[c] = m.rd[c] * (T(1) - m.rs[c]);
      kd_pi[c] = m.kd[c] * kInvPi<T>;
    }
    diffuse_weight = average(m.rd * (RGBT<T>(T(1)) - m.rs)) + average(m.kd);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh_i = Dot(wi, h);
    const V<D> spec = lobe.Specular(d, h, Dot(h, wi), wi.z, wo.z);
    const V<D> diff = ASDiffuse(d, wi.z, wo.z);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      const V<D> f = hn::Add(hn::Add(hn::Mul(hn::Mul(K(d, ks[c]), FSchlick(d, rs[c], woh_i)), spec),
                                     hn::Mul(K(d, diffuse[c]), diff)),
                             K(d, kd_pi[c]));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  // specular_probability(wo): Schlick at wo.z, averaged over the channels.
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo) const {
    const V<D> sw = Average(d, hn::Mul(K(d, ks[0]), FSchlick(d, rs[0], wo.z)), hn::Mul(K(d, ks[1]), FSchlick(d, rs[1], wo.z)),
                            hn::Mul(K(d, ks[2]), FSchlick(d, rs[2], wo.z)));
    return SpecularShare(d, K(d, diffuse_weight), sw);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> p_spec = SpecularProbability(d, wo);
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), MixturePdf(d, p_spec, wi.z, lobe.Pdf(d, wi, wo)));
  }
};

// --- ggx.h twins -------------------------------------------------------------------------------

template <typename T> struct GGXLobeK {
  T ax, ay, axay;
  explicit GGXLobeK(const GGXLobeT<T>& l) : ax(l.alpha_x), ay(l.alpha_y), axay(l.alpha_x * l.alpha_y) {}
  // D_GGX_Aniso.
  template <class D> HWY_INLINE V<D> Dist(D d, const V3<D>& h) const {
    const V<D> s = hn::Add(hn::Add(Sqr<D>(hn::Div(h.x, K(d, ax))), Sqr<D>(hn::Div(h.y, K(d, ay)))), Sqr<D>(h.z));
    return hn::Div(K(d, kInvPi<T>), hn::Mul(hn::Mul(K(d, axay), s), s));
  }
  // Lambda_GGX_Aniso.
  template <class D> HWY_INLINE V<D> Lambda(D d, const V3<D>& w) const {
    const V<D> tan2 = hn::Div(hn::Add(Sqr<D>(hn::Mul(K(d, ax), w.x)), Sqr<D>(hn::Mul(K(d, ay), w.y))), Sqr<D>(w.z));
    return hn::Mul(hn::Sub(hn::Sqrt(hn::Add(K(d, 1), tan2)), K(d, 1)), K(d, T(0.5)));
  }
  template <class D> HWY_INLINE V<D> EvalH(D d, const V3<D>& h, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> g2 = hn::Div(K(d, 1), hn::Add(hn::Add(K(d, 1), Lambda(d, wi)), Lambda(d, wo)));
    return hn::Div(hn::Mul(Dist(d, h), g2), hn::Mul(hn::Mul(K(d, T(4)), wi.z), wo.z));
  }
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& wi, const V3<D>& wo) const {
    return EvalH(d, Normalize(d, Add3(wi, wo)), wi, wo);
  }
  // GGXLobeT::sample with GGX_SampleVisibleNormal (Heitz 2018, Listing 1), step for step.
  template <class D> HWY_INLINE V3<D> Sample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    const V<D> one = K(d, 1);
    const V3<D> vh = Normalize(d, V3<D>{hn::Mul(K(d, ax), wo.x), hn::Mul(K(d, ay), wo.y), wo.z});
    const V<D> lensq = hn::Add(hn::Mul(vh.x, vh.x), hn::Mul(vh.y, vh.y));
    const M<D> has_len = hn::Gt(lensq, hn::Zero(d));
    const V<D> root = hn::Sqrt(hn::IfThenElse(has_len, lensq, one));
    const V3<D> t1{hn::IfThenElse(has_len, hn::Div(hn::Neg(vh.y), root), one), hn::IfThenElseZero(has_len, hn::Div(vh.x, root)),
                   hn::Zero(d)};
    // glm::cross(vh, t1)
    const V3<D> t2{hn::Sub(hn::Mul(vh.y, t1.z), hn::Mul(t1.y, vh.z)), hn::Sub(hn::Mul(vh.z, t1.x), hn::Mul(t1.z, vh.x)),
                   hn::Sub(hn::Mul(vh.x, t1.y), hn::Mul(t1.x, vh.y))};
    const V<D> r = hn::Sqrt(u0);
    const V<D> phi = hn::Mul(K(d, T(2) * kPi<T>), u1);
    const V<D> p1 = hn::Mul(r, CosNaN(d, phi));
    V<D> p2 = hn::Mul(r, SinNaN(d, phi));
    const V<D> s = hn::Mul(K(d, T(0.5)), hn::Add(one, vh.z));
    p2 = hn::Add(hn::Mul(hn::Sub(one, s), SafeSqrt(d, hn::Sub(one, hn::Mul(p1, p1)))), hn::Mul(s, p2));
    const V<D> q = SafeSqrt(d, hn::Sub(hn::Sub(one, hn::Mul(p1, p1)), hn::Mul(p2, p2)));
    const V3<D> nh{hn::Add(hn::Add(hn::Mul(p1, t1.x), hn::Mul(p2, t2.x)), hn::Mul(q, vh.x)),
                   hn::Add(hn::Add(hn::Mul(p1, t1.y), hn::Mul(p2, t2.y)), hn::Mul(q, vh.y)),
                   hn::Add(hn::Add(hn::Mul(p1, t1.z), hn::Mul(p2, t2.z)), hn::Mul(q, vh.z))};
    const V3<D> h = Normalize(d, V3<D>{hn::Mul(K(d, ax), nh.x), hn::Mul(K(d, ay), nh.y),
                                       hn::IfThenElseZero(hn::Gt(nh.z, hn::Zero(d)), nh.z)});
    return ReflectAbout(d, wo, h);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const M<D> ok = hn::And(hn::Gt(Dot(wo, h), hn::Zero(d)), hn::Gt(h.z, hn::Zero(d)));
    const V<D> g1 = hn::Div(K(d, 1), hn::Add(K(d, 1), Lambda(d, wo)));
    return hn::IfThenElseZero(ok, hn::Div(hn::Mul(g1, Dist(d, h)), hn::Mul(K(d, T(4)), wo.z)));
  }
};

template <typename T> struct GGXK {
  T f0[3], kd_pi[3], diffuse_weight;
  GGXLobeK<T> lobe;
  explicit GGXK(const GGXT<T>& m) : lobe(m.lobe) {
    for (int c = 0; c < 3; ++c) f0[c] = m.f0[c], kd_pi[c] = m.kd[c] * kInvPi<T>;
    diffuse_weight = average(m.kd);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> l = lobe.EvalH(d, h, wi, wo);
    const V<D> cos_ih = Dot(wi, h);
    RGBV<D> out;
    for (int c = 0; c < 3; ++c)
      out.c[c] = hn::IfThenElseZero(upper, hn::Add(hn::Mul(FSchlick(d, f0[c], cos_ih), l), K(d, kd_pi[c])));
    return out;
  }
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo) const {
    const V<D> sw = Average(d, FSchlick(d, f0[0], wo.z), FSchlick(d, f0[1], wo.z), FSchlick(d, f0[2], wo.z));
    return SpecularShare(d, K(d, diffuse_weight), sw);
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V<D> p_spec = SpecularProbability(d, wo);
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), MixturePdf(d, p_spec, wi.z, lobe.Pdf(d, wi, wo)));
  }
};

// --- lafortune.h twins -------------------------------------------------------------------------

template <typename T> struct LafortuneLobeK {
  T cx[3], cy[3], cz[3], n[3], scale[3], log_scale[3];
  LafortuneLobeK() = default;
  explicit LafortuneLobeK(const LafortuneLobeT<T>& l) {
    using std::log;
    for (int c = 0; c < 3; ++c) {
      cx[c] = l.cx[c], cy[c] = l.cy[c], cz[c] = l.cz[c], n[c] = l.n[c], scale[c] = l.scale[c];
      log_scale[c] = l.scale[c] > T(0) ? log(l.scale[c]) : T(0);
    }
  }
  // Lafortune_Lobe(base, n, scale) = exp(n log(base) + log(scale)) for base > 0 and scale > 0.
  template <class D> HWY_INLINE V<D> Lobe(D d, V<D> base, int c) const {
    if (!(scale[c] > T(0))) return hn::Zero(d);
    const M<D> pos = hn::Gt(base, hn::Zero(d));
    const V<D> safe = hn::IfThenElse(pos, base, K(d, 1));
    return hn::IfThenElseZero(pos, ExpNaN(d, hn::Add(hn::Mul(K(d, n[c]), hn::Log(d, safe)), K(d, log_scale[c]))));
  }
  // LafortuneLobeT::eval, channel c, p = wi * wo.
  template <class D> HWY_INLINE V<D> Eval(D d, const V3<D>& p, int c) const {
    const V<D> base = hn::Add(hn::Add(hn::Mul(K(d, cx[c]), p.x), hn::Mul(K(d, cy[c]), p.y)), hn::Mul(K(d, cz[c]), p.z));
    return Lobe(d, base, c);
  }
  template <class D> HWY_INLINE V3<D> Axis(D d, const V3<D>& wo, int c) const {
    return {hn::Mul(K(d, cx[c]), wo.x), hn::Mul(K(d, cy[c]), wo.y), hn::Mul(K(d, cz[c]), wo.z)};
  }
  // channel_weight.
  template <class D> HWY_INLINE V<D> ChannelWeight(D d, const V3<D>& wo, int c) const {
    if (!(scale[c] > T(0))) return hn::Zero(d);
    const V3<D> a = Axis(d, wo, c);
    const V<D> len = hn::Sqrt(Dot(a, a));
    const M<D> ok = hn::And(hn::Gt(len, hn::Zero(d)), hn::Gt(a.z, hn::Zero(d)));
    const V<D> safe_len = hn::IfThenElse(ok, len, K(d, 1));
    const V<D> w = hn::Div(hn::Mul(hn::Mul(hn::Mul(Lobe(d, safe_len, c), hn::Div(a.z, safe_len)), K(d, T(2))), K(d, kPi<T>)),
                           K(d, (n[c] + T(1)) * T(3)));
    return hn::IfThenElseZero(ok, w);
  }
  // channel_pdf.
  template <class D> HWY_INLINE V<D> ChannelPdf(D d, const V3<D>& wi, const V3<D>& wo, int c) const {
    const V3<D> a = Axis(d, wo, c);
    const V<D> len2 = Dot(a, a);
    const M<D> ok = hn::Gt(len2, hn::Zero(d));
    const V<D> cos_axis = hn::Div(Dot(a, wi), hn::Sqrt(hn::IfThenElse(ok, len2, K(d, 1))));
    return hn::IfThenElseZero(ok, CosinePowerPdf(d, cos_axis, K(d, n[c])));
  }
};

template <typename T> struct LafortuneK {
  T rho_pi[3], rho_avg;
  int lobe_count;
  LafortuneLobeK<T> lobes[kLafortuneMaxLobes];
  explicit LafortuneK(const LafortuneT<T>& m) : lobe_count(m.lobe_count) {
    for (int c = 0; c < 3; ++c) rho_pi[c] = m.rho_d[c] * kInvPi<T>;
    rho_avg = average(m.rho_d);
    for (int i = 0; i < lobe_count; ++i) lobes[i] = LafortuneLobeK<T>(m.lobes[i]);
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> p{hn::Mul(wi.x, wo.x), hn::Mul(wi.y, wo.y), hn::Mul(wi.z, wo.z)};
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      V<D> f = K(d, rho_pi[c]);
      for (int i = 0; i < lobe_count; ++i) f = hn::Add(f, lobes[i].Eval(d, p, c));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  // LafortuneT::sample's direction: walk the cumulative weights with uc (cosine first, then each
  // (lobe, channel) of positive weight while the target is not negative), per lane with masks.
  template <class D>
  HWY_INLINE V3<D> SampleDirection(D d, const V3<D>& wo, V<D> uc, V<D> u0, V<D> u1, M<D>& /*ok*/) const {
    V<D> w[kLafortuneMaxLobes][3];
    V<D> total = hn::Zero(d);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) total = hn::Add(total, w[i][c] = lobes[i].ChannelWeight(d, wo, c));
    const V<D> cos_w = hn::Add(K(d, rho_avg), hn::Mul(K(d, T(LafortuneT<T>::kDefensiveShare)), total));
    const V<D> cosine =
        hn::IfThenElse(hn::Or(hn::Gt(cos_w, hn::Zero(d)), hn::Gt(total, hn::Zero(d))), cos_w, K(d, 1));
    V<D> target = hn::Sub(hn::Mul(uc, hn::Add(cosine, total)), cosine);
    M<D> chosen = hn::Lt(K(d, 1), hn::Zero(d));  // all false
    V3<D> axis{hn::Zero(d), hn::Zero(d), K(d, 1)};
    V<D> n = K(d, 1);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) {
        const M<D> take = hn::AndNot(hn::Lt(target, hn::Zero(d)), hn::Gt(w[i][c], hn::Zero(d)));
        const V3<D> a = lobes[i].Axis(d, wo, c);
        axis = {hn::IfThenElse(take, a.x, axis.x), hn::IfThenElse(take, a.y, axis.y), hn::IfThenElse(take, a.z, axis.z)};
        n = hn::IfThenElse(take, K(d, lobes[i].n[c]), n);
        chosen = hn::Or(chosen, take);
        target = hn::IfThenElse(take, hn::Sub(target, w[i][c]), target);
      }
    const V<D> len = hn::Sqrt(Dot(axis, axis));
    const V3<D> a_unit{hn::Div(axis.x, len), hn::Div(axis.y, len), hn::Div(axis.z, len)};
    const V3<D> wl = CosinePowerSample(d, a_unit, n, u0, u1);
    const V3<D> wc = CosineHemisphere(d, u0, u1);
    return {hn::IfThenElse(chosen, wl.x, wc.x), hn::IfThenElse(chosen, wl.y, wc.y), hn::IfThenElse(chosen, wl.z, wc.z)};
  }
  // pdf(sampling_weights(wo), wi, wo).
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    V<D> w[kLafortuneMaxLobes][3];
    V<D> total = hn::Zero(d);
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c) total = hn::Add(total, w[i][c] = lobes[i].ChannelWeight(d, wo, c));
    const V<D> cos_w = hn::Add(K(d, rho_avg), hn::Mul(K(d, T(LafortuneT<T>::kDefensiveShare)), total));
    const V<D> cosine =
        hn::IfThenElse(hn::Or(hn::Gt(cos_w, hn::Zero(d)), hn::Gt(total, hn::Zero(d))), cos_w, K(d, 1));
    V<D> p = hn::Mul(cosine, CosineHemispherePdf(d, wi.z));
    for (int i = 0; i < lobe_count; ++i)
      for (int c = 0; c < 3; ++c)
        p = hn::Add(p, hn::IfThenElseZero(hn::Gt(w[i][c], hn::Zero(d)), hn::Mul(w[i][c], lobes[i].ChannelPdf(d, wi, wo, c))));
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), hn::Div(p, hn::Add(cosine, total)));
  }
};

// --- metal.h twins -----------------------------------------------------------------------------

template <typename T> struct MetalK {
  T eta[3], k[3], specular_weight[3];
  SpecularLobeKind kind;
  WardLobeK<T> ward;
  ASLobeK<T> as;
  GGXLobeK<T> ggx;
  bool has_dd;
  LafortuneLobeK<T> dd;
  explicit MetalK(const MetalT<T>& m)
      : kind(m.lobe_kind), ward(m.ward), as(m.ashikhmin_shirley), ggx(m.ggx), has_dd(m.has_directional_diffuse),
        dd(m.directional_diffuse) {
    for (int c = 0; c < 3; ++c) eta[c] = m.eta[c], k[c] = m.k[c], specular_weight[c] = m.specular_weight[c];
  }
  template <class D> HWY_INLINE V<D> Specular(D d, const V3<D>& wi, const V3<D>& wo) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Eval(d, wi, wo);
      case SpecularLobeKind::AshikhminShirley: return as.Eval(d, wi, wo);
      default: return ggx.Eval(d, wi, wo);
    }
  }
  template <class D> HWY_INLINE V<D> SpecularPdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Pdf(d, wi, wo);
      case SpecularLobeKind::AshikhminShirley: return as.Pdf(d, wi, wo);
      default: return ggx.Pdf(d, wi, wo);
    }
  }
  template <class D> HWY_INLINE V3<D> SpecularSample(D d, const V3<D>& wo, V<D> u0, V<D> u1) const {
    switch (kind) {
      case SpecularLobeKind::Ward: return ward.Sample(d, wo, u0, u1);
      case SpecularLobeKind::AshikhminShirley: return as.Sample(d, wo, u0, u1);
      default: return ggx.Sample(d, wo, u0, u1);
    }
  }
  // specular_probability(wo).
  template <class D> HWY_INLINE V<D> SpecularProbability(D d, const V3<D>& wo, V<D> ws[3]) const {
    V<D> fw[3];
    for (int c = 0; c < 3; ++c) fw[c] = hn::Mul(K(d, specular_weight[c]), FConductor(d, wo.z, eta[c], k[c]));
    const V<D> s = Average(d, fw[0], fw[1], fw[2]);
    V<D> dsum = hn::Zero(d);
    for (int c = 0; c < 3; ++c) ws[c] = hn::Zero(d);
    if (has_dd)
      for (int c = 0; c < 3; ++c) dsum = hn::Add(dsum, ws[c] = dd.ChannelWeight(d, wo, c));
    const V<D> sd = hn::Add(s, dsum);
    return hn::IfThenElse(hn::Gt(sd, hn::Zero(d)), hn::Div(s, sd), K(d, 1));
  }
  // MetalT::sample's direction: the specular lobe with probability ps, else a channel of the
  // directional-diffuse lobe picked by weight with uc rescaled (first c with target < ws[c], else
  // the last positive one); no weight at all is "no sample".
  template <class D>
  HWY_INLINE V3<D> SampleDirection(D d, const V3<D>& wo, V<D> uc, V<D> u0, V<D> u1, M<D>& ok) const {
    V<D> ws[3];
    const V<D> ps = SpecularProbability(d, wo, ws);
    const M<D> spec = hn::Lt(uc, ps);
    const V3<D> w_spec = SpecularSample(d, wo, u0, u1);
    if (!has_dd) {
      ok = hn::And(ok, spec);  // ps = 1 here unless every weight is 0
      return w_spec;
    }
    const V<D> wsum = hn::Add(hn::Add(ws[0], ws[1]), ws[2]);
    V<D> target = hn::Mul(hn::Div(hn::Sub(uc, ps), hn::Sub(K(d, 1), ps)), wsum);
    M<D> found = hn::Lt(K(d, 1), hn::Zero(d));  // all false
    V<D> chosen = K(d, 2);
    for (int c = 0; c < 3; ++c) {
      const M<D> hit = hn::AndNot(found, hn::And(hn::Gt(ws[c], hn::Zero(d)), hn::Lt(target, ws[c])));
      chosen = hn::IfThenElse(hit, K(d, T(c)), chosen);
      found = hn::Or(found, hit);
      target = hn::IfThenElse(found, target, hn::Sub(target, ws[c]));
    }
    // while (chosen > 0 && !(ws[chosen] > 0)) --chosen, for the lanes that found nothing.
    const V<D> last_positive = hn::IfThenElse(hn::Gt(ws[2], hn::Zero(d)), K(d, 2),
                                              hn::IfThenElse(hn::Gt(ws[1], hn::Zero(d)), K(d, 1), hn::Zero(d)));
    chosen = hn::IfThenElse(found, chosen, last_positive);
    V3<D> axis{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
    V<D> n = hn::Zero(d);
    for (int c = 0; c < 3; ++c) {
      const M<D> is_c = hn::Eq(chosen, K(d, T(c)));
      const V3<D> a = dd.Axis(d, wo, c);
      axis = {hn::IfThenElse(is_c, a.x, axis.x), hn::IfThenElse(is_c, a.y, axis.y), hn::IfThenElse(is_c, a.z, axis.z)};
      n = hn::IfThenElse(is_c, K(d, dd.n[c]), n);
    }
    const V<D> len = hn::Sqrt(Dot(axis, axis));
    const V3<D> w_dd = CosinePowerSample(d, V3<D>{hn::Div(axis.x, len), hn::Div(axis.y, len), hn::Div(axis.z, len)}, n, u0, u1);
    ok = hn::And(ok, hn::Or(spec, hn::Gt(wsum, hn::Zero(d))));
    return {hn::IfThenElse(spec, w_spec.x, w_dd.x), hn::IfThenElse(spec, w_spec.y, w_dd.y),
            hn::IfThenElse(spec, w_spec.z, w_dd.z)};
  }
  template <class D> HWY_INLINE RGBV<D> F(D d, const V3<D>& wi, const V3<D>& wo) const {
    const M<D> upper = UpperBoth(d, wi, wo);
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> cos_ih = Dot(wi, h);
    const V<D> s = Specular(d, wi, wo);
    const V3<D> p{hn::Mul(wi.x, wo.x), hn::Mul(wi.y, wo.y), hn::Mul(wi.z, wo.z)};
    RGBV<D> out;
    for (int c = 0; c < 3; ++c) {
      V<D> f = hn::Mul(hn::Mul(K(d, specular_weight[c]), FConductor(d, cos_ih, eta[c], k[c])), s);
      if (has_dd) f = hn::Add(f, dd.Eval(d, p, c));
      out.c[c] = hn::IfThenElseZero(upper, f);
    }
    return out;
  }
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    // specular_probability(wo)
    V<D> fw[3];
    for (int c = 0; c < 3; ++c) fw[c] = hn::Mul(K(d, specular_weight[c]), FConductor(d, wo.z, eta[c], k[c]));
    const V<D> s = Average(d, fw[0], fw[1], fw[2]);
    V<D> dsum = hn::Zero(d), ws[3];
    if (has_dd)
      for (int c = 0; c < 3; ++c) dsum = hn::Add(dsum, ws[c] = dd.ChannelWeight(d, wo, c));
    const V<D> sd = hn::Add(s, dsum);
    const V<D> ps = hn::IfThenElse(hn::Gt(sd, hn::Zero(d)), hn::Div(s, sd), K(d, 1));
    V<D> p = hn::Mul(ps, SpecularPdf(d, wi, wo));
    if (has_dd) {
      // directional_diffuse_pdf
      V<D> wsum = hn::Zero(d), pd = hn::Zero(d);
      for (int c = 0; c < 3; ++c) {
        const M<D> pos = hn::Gt(ws[c], hn::Zero(d));
        wsum = hn::Add(wsum, hn::IfThenElseZero(pos, ws[c]));
        pd = hn::Add(pd, hn::IfThenElseZero(pos, hn::Mul(ws[c], dd.ChannelPdf(d, wi, wo, c))));
      }
      const M<D> wpos = hn::Gt(wsum, hn::Zero(d));
      const V<D> ddp = hn::IfThenElseZero(wpos, hn::Div(pd, hn::IfThenElse(wpos, wsum, K(d, 1))));
      p = hn::Add(p, hn::IfThenElseZero(hn::Lt(ps, K(d, 1)), hn::Mul(hn::Sub(K(d, 1), ps), ddp)));
    }
    return hn::IfThenElseZero(UpperBoth(d, wi, wo), p);
  }
};

// --- The loops ---------------------------------------------------------------------------------

// The lanes where one of the six input values is NaN or infinite (IsFinite is false for both).
template <class D> HWY_INLINE M<D> NonFiniteLanes(const V3<D>& wi, const V3<D>& wo) {
  const M<D> fi = hn::And(hn::And(hn::IsFinite(wi.x), hn::IsFinite(wi.y)), hn::IsFinite(wi.z));
  const M<D> fo = hn::And(hn::And(hn::IsFinite(wo.x), hn::IsFinite(wo.y)), hn::IsFinite(wo.z));
  return hn::Not(hn::And(fi, fo));
}

// One vector at a time over [begin, end); the last partial vector goes through a padded copy
// (padding: wi = wo = n, a valid input, so no lane of the padding computes anything odd).
// kNanRows (NonFinite::NaN) is a template parameter: without it the loop is exactly the plain one,
// and a kernel that reads only some coordinates (Lambert: the two z) loads only those.
template <bool kNanRows, class D, class Kernel, typename T>
HWY_INLINE void RunRange(D d, const Kernel& k, const EvalArgs<T>& a, size_t begin, size_t end, bool want_pdf) {
  const size_t N = hn::Lanes(d);
  constexpr bool nan_rows = kNanRows;
  const V<D> nan = hn::Set(d, std::numeric_limits<T>::quiet_NaN());
  const auto one = [&](const T* wix, const T* wiy, const T* wiz, const T* wox, const T* woy, const T* woz, T* r, T* g,
                       T* b, T* p) {
    const V3<D> wi{hn::LoadU(d, wix), hn::LoadU(d, wiy), hn::LoadU(d, wiz)};
    const V3<D> wo{hn::LoadU(d, wox), hn::LoadU(d, woy), hn::LoadU(d, woz)};
    // NonFinite::NaN: NaN in every output of a lane with a NaN or infinite input (batch.h).
    if constexpr (nan_rows) {
      const M<D> bad = NonFiniteLanes(wi, wo);
      if (want_pdf) {
        hn::StoreU(hn::IfThenElse(bad, nan, k.Pdf(d, wi, wo)), d, p);
      } else {
        const RGBV<D> f = k.F(d, wi, wo);
        hn::StoreU(hn::IfThenElse(bad, nan, f.c[0]), d, r);
        hn::StoreU(hn::IfThenElse(bad, nan, f.c[1]), d, g);
        hn::StoreU(hn::IfThenElse(bad, nan, f.c[2]), d, b);
      }
    } else {
      (void)nan;
      if (want_pdf) {
        hn::StoreU(k.Pdf(d, wi, wo), d, p);
      } else {
        const RGBV<D> f = k.F(d, wi, wo);
        hn::StoreU(f.c[0], d, r);
        hn::StoreU(f.c[1], d, g);
        hn::StoreU(f.c[2], d, b);
      }
    }
  };
  size_t i = begin;
  for (; i + N <= end; i += N) {
    one(a.wi.x + i, a.wi.y + i, a.wi.z + i, a.wo.x + i, a.wo.y + i, a.wo.z + i, want_pdf ? nullptr : a.f.r + i,
        want_pdf ? nullptr : a.f.g + i, want_pdf ? nullptr : a.f.b + i, want_pdf ? a.pdf + i : nullptr);
  }
  if (i < end) {
    constexpr size_t kMax = hn::MaxLanes(D());
    HWY_ALIGN T buf[10][kMax];
    for (size_t j = 0; j < kMax; ++j) {
      for (int q = 0; q < 6; ++q) buf[q][j] = (q == 2 || q == 5) ? T(1) : T(0);
    }
    const size_t rest = end - i;
    for (size_t j = 0; j < rest; ++j) {
      buf[0][j] = a.wi.x[i + j], buf[1][j] = a.wi.y[i + j], buf[2][j] = a.wi.z[i + j];
      buf[3][j] = a.wo.x[i + j], buf[4][j] = a.wo.y[i + j], buf[5][j] = a.wo.z[i + j];
    }
    one(buf[0], buf[1], buf[2], buf[3], buf[4], buf[5], buf[6], buf[7], buf[8], buf[9]);
    for (size_t j = 0; j < rest; ++j) {
      if (want_pdf) {
        a.pdf[i + j] = buf[9][j];
      } else {
        a.f.r[i + j] = buf[6][j], a.f.g[i + j] = buf[7][j], a.f.b[i + j] = buf[8][j];
      }
    }
  }
}

template <typename T> void RunMaterial(const MaterialT<T>& m, const EvalArgs<T>& a, size_t begin, size_t end, bool want_pdf) {
  const hn::ScalableTag<T> d;
  const auto run = [&](const auto& kernel) {
    if (a.non_finite == NonFinite::NaN) RunRange<true>(d, kernel, a, begin, end, want_pdf);
    else RunRange<false>(d, kernel, a, begin, end, want_pdf);
  };
  switch (m.kind) {
    case ModelKind::Phong: return run(LambertPlusLobeK<T, PhongLobeK<T>>(m.phong));
    case ModelKind::Ward: return run(LambertPlusLobeK<T, WardLobeK<T>>(m.ward));
    case ModelKind::AshikhminShirley: return run(AshikhminShirleyK<T>(m.ashikhmin_shirley));
    case ModelKind::Lafortune: return run(LafortuneK<T>(m.lafortune));
    case ModelKind::GGX: return run(GGXK<T>(m.ggx));
    case ModelKind::Metal: return run(MetalK<T>(m.metal));
    default: return run(LambertK<T>(m.lambert));
  }
}

// The same loop on interleaved rows (batch.h, evaluate_interleaved / pdf_interleaved): each vector's
// rows are loaded and de-interleaved in registers (LoadInterleaved3: three loads and shuffles), the
// kernel runs on the vectors exactly as in RunRange, and f is re-interleaved in registers
// (StoreInterleaved3). A broadcast input (stride 0) is one vector per coordinate for the whole
// range. With NonFinite::NaN (kNanRows, as in RunRange) a lane whose six input values are not all
// finite gets NaN in every output.
template <bool kNanRows, class D, class Kernel, typename T>
HWY_INLINE void RunRangeInterleaved(D d, const Kernel& k, const InterleavedArgs<T>& a, size_t begin, size_t end,
                                    bool want_pdf) {
  const size_t N = hn::Lanes(d);
  const V<D> nan = hn::Set(d, std::numeric_limits<T>::quiet_NaN());
  (void)nan;  // used with kNanRows only
  const auto broadcast = [&](const Interleaved<T>& w) {
    return w.stride == 0 ? V3<D>{hn::Set(d, w.xyz[0]), hn::Set(d, w.xyz[1]), hn::Set(d, w.xyz[2])} : V3<D>{};
  };
  const V3<D> wi_all = broadcast(a.wi), wo_all = broadcast(a.wo);
  const bool wi_rows = a.wi.stride != 0, wo_rows = a.wo.stride != 0;
  // wi and wo: the rows at pi / po (3 N values each), or the broadcast vectors; f: 3 N values at
  // pf, or N at pp.
  const auto one = [&](const T* pi, const T* po, T* pf, T* pp) {
    V3<D> wi = wi_all, wo = wo_all;
    if (wi_rows) hn::LoadInterleaved3(d, pi, wi.x, wi.y, wi.z);
    if (wo_rows) hn::LoadInterleaved3(d, po, wo.x, wo.y, wo.z);
    if (want_pdf) {
      V<D> p = k.Pdf(d, wi, wo);
      if constexpr (kNanRows) p = hn::IfThenElse(NonFiniteLanes(wi, wo), nan, p);
      hn::StoreU(p, d, pp);
    } else {
      RGBV<D> f = k.F(d, wi, wo);
      if constexpr (kNanRows) {
        const M<D> bad = NonFiniteLanes(wi, wo);
        for (int c = 0; c < 3; ++c) f.c[c] = hn::IfThenElse(bad, nan, f.c[c]);
      }
      hn::StoreInterleaved3(f.c[0], f.c[1], f.c[2], d, pf);
    }
  };
  const auto at = [](const Interleaved<T>& w, size_t i) { return w.xyz + w.stride * i; };
  size_t i = begin;
  for (; i + N <= end; i += N) one(at(a.wi, i), at(a.wo, i), want_pdf ? nullptr : a.f_rgb + 3 * i, want_pdf ? a.pdf + i : nullptr);
  if (i < end) {
    // The last, partial vector through padded copies (padding rows wi = wo = n, as RunRange).
    constexpr size_t kMax = hn::MaxLanes(D());
    HWY_ALIGN T bi[3 * kMax], bo[3 * kMax], bf[3 * kMax], bp[kMax];
    for (size_t j = 0; j < kMax; ++j)
      for (int c = 0; c < 3; ++c) bi[3 * j + c] = bo[3 * j + c] = c == 2 ? T(1) : T(0);
    const size_t rest = end - i;
    if (wi_rows) std::copy_n(at(a.wi, i), 3 * rest, bi);
    if (wo_rows) std::copy_n(at(a.wo, i), 3 * rest, bo);
    one(bi, bo, bf, bp);
    if (want_pdf) std::copy_n(bp, rest, a.pdf + i);
    else std::copy_n(bf, 3 * rest, a.f_rgb + 3 * i);
  }
}

template <typename T>
void RunMaterialInterleaved(const MaterialT<T>& m, const InterleavedArgs<T>& a, size_t begin, size_t end, bool want_pdf) {
  const hn::ScalableTag<T> d;
  const auto run = [&](const auto& kernel) {
    if (a.non_finite == NonFinite::NaN) RunRangeInterleaved<true>(d, kernel, a, begin, end, want_pdf);
    else RunRangeInterleaved<false>(d, kernel, a, begin, end, want_pdf);
  };
  switch (m.kind) {
    case ModelKind::Phong: return run(LambertPlusLobeK<T, PhongLobeK<T>>(m.phong));
    case ModelKind::Ward: return run(LambertPlusLobeK<T, WardLobeK<T>>(m.ward));
    case ModelKind::AshikhminShirley: return run(AshikhminShirleyK<T>(m.ashikhmin_shirley));
    case ModelKind::Lafortune: return run(LafortuneK<T>(m.lafortune));
    case ModelKind::GGX: return run(GGXK<T>(m.ggx));
    case ModelKind::Metal: return run(MetalK<T>(m.metal));
    default: return run(LambertK<T>(m.lambert));
  }
}

// --- Sampling: sample_diffuse_specular + make_sample -------------------------------------------

// sample_diffuse_specular (Phong, Ward, Ashikhmin-Shirley, GGX), Lambert's cosine sampling, and the
// models with their own lobe choice (Lafortune, metal: SampleDirection), then make_sample.
template <class D, class Kernel> HWY_INLINE void SampleVec(D d, const Kernel& k, const V3<D>& wo, V<D> uc, V<D> u0, V<D> u1,
                                                          V3<D>& wi, RGBV<D>& weight, V<D>& pdf, M<D>& valid) {
  M<D> direction_ok = AboveHorizon(d, wo.z);
  if constexpr (requires { k.SampleDirection(d, wo, uc, u0, u1, direction_ok); }) {
    wi = k.SampleDirection(d, wo, uc, u0, u1, direction_ok);
  } else if constexpr (requires { k.SpecularProbability(d, wo); }) {
    const M<D> spec = hn::Lt(uc, k.SpecularProbability(d, wo));
    const V3<D> ws = k.lobe.Sample(d, wo, u0, u1);
    const V3<D> wd = CosineHemisphere(d, u0, u1);
    wi = {hn::IfThenElse(spec, ws.x, wd.x), hn::IfThenElse(spec, ws.y, wd.y), hn::IfThenElse(spec, ws.z, wd.z)};
  } else {
    wi = CosineHemisphere(d, u0, u1);
  }
  // make_sample, with the checks of sample_diffuse_specular: wo and wi above the horizon, pdf > 0.
  const V<D> p = k.Pdf(d, wi, wo);
  const RGBV<D> f = k.F(d, wi, wo);
  valid = hn::And(hn::And(direction_ok, AboveHorizon(d, wi.z)), hn::Gt(p, hn::Zero(d)));
  const V<D> scale = hn::Div(wi.z, hn::IfThenElse(valid, p, K(d, 1)));
  for (int c = 0; c < 3; ++c) weight.c[c] = hn::IfThenElseZero(valid, hn::Mul(f.c[c], scale));
  wi = {hn::IfThenElseZero(valid, wi.x), hn::IfThenElseZero(valid, wi.y), hn::IfThenElseZero(valid, wi.z)};
  pdf = hn::IfThenElseZero(valid, p);
}

template <class D, class Kernel, typename T>
HWY_INLINE void SampleRange(D d, const Kernel& k, const SampleArgs<T>& a, size_t begin, size_t end) {
  const size_t N = hn::Lanes(d);
  constexpr size_t kMax = hn::MaxLanes(D());
  HWY_ALIGN T buf[14][kMax];
  for (size_t i = begin; i < end; i += N) {
    const size_t count = std::min(N, end - i);
    const T* src[6] = {a.wo.x + i, a.wo.y + i, a.wo.z + i, a.uc + i, a.u0 + i, a.u1 + i};
    if (count < N) {  // the last, partial vector: padded copies (wo = n, u = 0.5)
      for (int q = 0; q < 6; ++q) {
        for (size_t j = 0; j < N; ++j) buf[q][j] = j < count ? src[q][j] : (q == 2 ? T(1) : q >= 3 ? T(0.5) : T(0));
        src[q] = buf[q];
      }
    }
    const V3<D> wo{hn::LoadU(d, src[0]), hn::LoadU(d, src[1]), hn::LoadU(d, src[2])};
    V3<D> wi;
    RGBV<D> w;
    V<D> p;
    M<D> valid;
    SampleVec(d, k, wo, hn::LoadU(d, src[3]), hn::LoadU(d, src[4]), hn::LoadU(d, src[5]), wi, w, p, valid);
    T* dst[7] = {a.out.wi_x + i, a.out.wi_y + i, a.out.wi_z + i, a.out.weight_r + i, a.out.weight_g + i, a.out.weight_b + i,
                 a.out.pdf + i};
    const V<D> vals[7] = {wi.x, wi.y, wi.z, w.c[0], w.c[1], w.c[2], p};
    const V<D> valid_v = hn::IfThenElseZero(valid, K(d, 1));
    if (count == N) {
      for (int q = 0; q < 7; ++q) hn::StoreU(vals[q], d, dst[q]);
    } else {
      for (int q = 0; q < 7; ++q) {
        hn::Store(vals[q], d, buf[6 + q]);
        std::copy_n(buf[6 + q], count, dst[q]);
      }
    }
    hn::Store(valid_v, d, buf[13]);
    for (size_t j = 0; j < count; ++j) a.out.valid[i + j] = buf[13][j] != T(0) ? 1 : 0;
  }
}

// Returns false for the models without a SIMD sampler (the caller runs the scalar one).
template <typename T> bool SampleMaterial(const MaterialT<T>& m, const SampleArgs<T>& a, size_t begin, size_t end) {
  const hn::ScalableTag<T> d;
  switch (m.kind) {
    case ModelKind::Phong: SampleRange(d, LambertPlusLobeK<T, PhongLobeK<T>>(m.phong), a, begin, end); return true;
    case ModelKind::Ward: SampleRange(d, LambertPlusLobeK<T, WardLobeK<T>>(m.ward), a, begin, end); return true;
    case ModelKind::AshikhminShirley: SampleRange(d, AshikhminShirleyK<T>(m.ashikhmin_shirley), a, begin, end); return true;
    case ModelKind::GGX: SampleRange(d, GGXK<T>(m.ggx), a, begin, end); return true;
    case ModelKind::Lafortune: SampleRange(d, LafortuneK<T>(m.lafortune), a, begin, end); return true;
    case ModelKind::Metal: SampleRange(d, MetalK<T>(m.metal), a, begin, end); return true;
    case ModelKind::Measured: return false;  // table lookups: the scalar kernel (batch.cpp)
    default: SampleRange(d, LambertK<T>(m.lambert), a, begin, end); return true;
  }
}

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
