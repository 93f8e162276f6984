// batch/twins/lambert-inl.h: the Highway twin of include/aniso/brdf/lambert.h (Lambert); the
// rules every twin follows are in src/batch/simd_math-inl.h.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_TWINS_LAMBERT_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_TWINS_LAMBERT_INL_H_
#undef ANISO_BATCH_TWINS_LAMBERT_INL_H_
#else
#define ANISO_BATCH_TWINS_LAMBERT_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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

template <typename T> struct SimdTwin<LambertT<T>> { using type = LambertK<T>; };

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
