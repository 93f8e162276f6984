// batch/simd_math-inl.h: Google Highway twins of include/aniso/core (math, sampling, lobe mixture)
// and brdf/fresnel.h, compiled once per SIMD target (src/batch/batch.cpp includes
// kernels-inl.h through hwy/foreach_target.h). The model twins are in src/batch/twins/.
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
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_SIMD_MATH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_SIMD_MATH_INL_H_
#undef ANISO_BATCH_SIMD_MATH_INL_H_
#else
#define ANISO_BATCH_SIMD_MATH_INL_H_
#endif

#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "aniso/brdf/material.h"
#include "batch/args.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D> using V = hn::Vec<D>;
template <class D> using M = hn::Mask<D>;

template <class D> struct V3 { V<D> x, y, z; };

template <class D> HWY_INLINE V<D> K(D d, hn::TFromD<D> c) { return hn::Set(d, c); }

// --- core/math.h twins -----------------------------------------------------------------------

template <class D> HWY_INLINE V<D> Sqr(V<D> x) { return hn::Mul(x, x); }
// Highway's Exp, Sin and Cos convert a multiple of their argument to int32 (range reduction); on
// the 1-lane SCALAR target that is a C++ float-to-int cast, undefined for NaN (UBSan reports it in
// batch_tests_baseline under make test-sanitize: Ward's exponent in a masked-off lane). NaN lanes go
// in as 0 and come out as the NaN they were: exp, sin and cos of NaN are NaN, so no result changes.
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
template <class D> HWY_INLINE V<D> Average(D d, V<D> r, V<D> g, V<D> b) { return hn::Div(hn::Add(hn::Add(r, g), b), K(d, 3)); }
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

// F_Schlick(f0, f90, c) = f0 + (f90 - f0)(1 - clamp01(c))^5 (fresnel.h); f90 = 1 is Schlick's.
template <class D> HWY_INLINE V<D> F_Schlick(D d, hn::TFromD<D> f0, hn::TFromD<D> f90, V<D> cos_theta) {
  const V<D> m = hn::Sub(K(d, 1), Clamp01(d, cos_theta));
  const V<D> m2 = hn::Mul(m, m);
  return hn::Add(K(d, f0), hn::Mul(K(d, f90 - f0), hn::Mul(hn::Mul(m2, m2), m)));
}
template <class D> HWY_INLINE V<D> F_Schlick(D d, hn::TFromD<D> f0, V<D> cos_theta) {
  return F_Schlick(d, f0, hn::TFromD<D>(1), cos_theta);
}

// F_Conductor(c, eta, k): the same real-arithmetic Fresnel equations, operation for operation.
template <class D> HWY_INLINE V<D> F_Conductor(D d, V<D> cos_theta, hn::TFromD<D> eta, hn::TFromD<D> k) {
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

template <class D> struct RGBV { V<D> c[3]; };

// LambertPlusLobeT: kd / pi + ks lobe, the lobe chosen with a constant probability.
template <typename T, typename LobeK> struct LambertPlusLobeK {
  T kd_pi[3], ks[3], p_spec;
  LobeK lobe;
  template <typename Lobe> explicit LambertPlusLobeK(const LambertPlusLobeT<T, Lobe>& m)
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

// SimdTwin<Model>::type: the Highway twin of a registry model whose row says Simd (registry.h),
// specialised beside each twin in src/batch/twins/; the dispatch (dispatch-inl.h) checks that every
// such row has one. Rows that say Scalar have none: the batch functions run the scalar kernel.
template <typename Model> struct SimdTwin;

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
