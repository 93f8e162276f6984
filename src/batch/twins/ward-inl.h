// batch/twins/ward-inl.h: the Highway twin of include/aniso/brdf/ward.h (Ward 1992); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_WARD_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_WARD_INL_H_
#undef ANISO_BATCH_TWINS_WARD_INL_H_
#else
#define ANISO_BATCH_TWINS_WARD_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- ward.h twins ------------------------------------------------------------------------------

// Ward_Exp: exp(x) with the underflow decided at the same bound as the scalar code.
template <class D> HWY_INLINE V<D> Ward_Exp(D d, V<D> x) {
  using T = hn::TFromD<D>;
  return hn::IfThenZeroElse(hn::Lt(x, K(d, T(sizeof(T) == sizeof(float) ? -104.0 : -746.0))), ExpNaN(d, x));
}
// E_Ward_Vector.
template <class D> HWY_INLINE V<D> E_Ward_Vector(D d, V<D> hx, V<D> hy, V<D> hz, V<D> ax, V<D> ay) {
  return Ward_Exp(d, hn::Div(hn::Neg(hn::Add(Sqr<D>(hn::Div(hx, ax)), Sqr<D>(hn::Div(hy, ay)))), Sqr<D>(hz)));
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
        e = Ward_Exp(d, hn::Mul(hn::Neg(Sqr<D>(tan_t)), hn::Add(Sqr<D>(hn::Div(cos_phi, vax)), Sqr<D>(hn::Div(sin_phi, vay)))));
        break;
      }
      case WardForm::Approx: {
        const V3<D> hn_ = Normalize(d, h);  // E_Ward_Approx
        e = Ward_Exp(d, hn::Div(hn::Mul(K(d, T(-2)), hn::Add(Sqr<D>(hn::Div(hn_.x, vax)), Sqr<D>(hn::Div(hn_.y, vay)))),
                                hn::Add(K(d, 1), hn_.z)));
        break;
      }
      default: e = E_Ward_Vector(d, h.x, h.y, h.z, vax, vay); break;
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
    const V<D> t2 =
        hn::Div(hn::Neg(hn::Log(d, hn::Sub(K(d, 1), u0))), hn::Add(Sqr<D>(hn::Div(c, K(d, ax))), Sqr<D>(hn::Div(s, K(d, ay)))));
    const V<D> inv = hn::Div(K(d, 1), hn::Sqrt(hn::Add(K(d, 1), t2)));
    const V<D> st = hn::Mul(hn::Sqrt(t2), inv);
    return ReflectAbout(d, wo, V3<D>{hn::Mul(st, c), hn::Mul(st, s), inv});
  }

  // WardLobeT::pdf with Ward_PdfHalf: the Gaussian of the unit h here, of the unnormalised h there
  // (E_Ward_Vector is scale-free: the same function, rounded apart).
  template <class D> HWY_INLINE V<D> Pdf(D d, const V3<D>& wi, const V3<D>& wo) const {
    const V3<D> h = Normalize(d, Add3(wi, wo));
    const V<D> woh = Dot(wo, h);
    const V<D> e = E_Ward_Vector(d, h.x, h.y, h.z, K(d, ax), K(d, ay));
    const V<D> ph = hn::Div(hn::Mul(e, K(d, kInvPi<T>)), hn::Mul(hn::Mul(hn::Mul(K(d, axay), h.z), h.z), h.z));
    const M<D> ok = hn::And(hn::Gt(woh, hn::Zero(d)), hn::Gt(h.z, hn::Zero(d)));
    return hn::IfThenElseZero(ok, hn::Div(ph, hn::Mul(K(d, T(4)), woh)));
  }
};

template <typename T> struct SimdTwin<WardT<T>> { using type = LambertPlusLobeK<T, WardLobeK<T>>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
