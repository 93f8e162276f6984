// batch/twins/phong-inl.h: the Highway twin of include/aniso/brdf/phong.h (Phong); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_PHONG_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_PHONG_INL_H_
#undef ANISO_BATCH_TWINS_PHONG_INL_H_
#else
#define ANISO_BATCH_TWINS_PHONG_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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

template <typename T> struct SimdTwin<PhongT<T>> { using type = LambertPlusLobeK<T, PhongLobeK<T>>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
