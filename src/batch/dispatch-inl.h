// batch/dispatch-inl.h: from a material to its SIMD twin, per target. Generated from the
// registry (aniso/brdf/registry.h): a row that says Simd runs SimdTwin<Type<T>>::type (its
// specialisation beside the twin, src/batch/twins/); a row that says Scalar has no twin and the
// functions here return false, so that the caller (batch.cpp) runs the scalar kernel. No model
// is ever run through another model's twin.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_DISPATCH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_DISPATCH_INL_H_
#undef ANISO_BATCH_DISPATCH_INL_H_
#else
#define ANISO_BATCH_DISPATCH_INL_H_
#endif

#include "batch/loops-inl.h"
#include "batch/simd_math-inl.h"
#include "batch/twins/ashikhmin_shirley-inl.h"
#include "batch/twins/ggx-inl.h"
#include "batch/twins/lafortune-inl.h"
#include "batch/twins/lambert-inl.h"
#include "batch/twins/metal-inl.h"
#include "batch/twins/phong-inl.h"
#include "batch/twins/ward-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Every row that says Simd has its twin, for float and double (a missing specialisation is an
// incomplete type: a compile error here, not a fall to another model at run time).
template <typename M> constexpr bool kHasTwin = requires { sizeof(typename SimdTwin<M>::type); };
#define ANISO_X(Tag, Type, member, name, path, glsl)                                                           \
  static_assert(registry_detail::path != BatchPath::Simd || (kHasTwin<Type<float>> && kHasTwin<Type<double>>), \
                #Tag ": the registry says Simd but SimdTwin<" #Type "<T>> is not specialised (src/batch/twins/)");
ANISO_MODELS(ANISO_X)
#undef ANISO_X

// Calls run(twin) with the SIMD twin of m and returns true, or returns false for a Scalar row.
template <typename T, typename Run> bool WithTwin(const MaterialT<T>& m, const Run& run) {
  return m.visit([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    if constexpr (kHasTwin<Model>) {
      run(typename SimdTwin<Model>::type(model));
      return true;
    } else {
      return false;
    }
  });
}

// Returns false for the models without a SIMD twin (the caller runs the scalar kernel).
template <typename T> bool RunMaterial(const MaterialT<T>& m, const EvalArgs<T>& a, size_t begin, size_t end, bool want_pdf) {
  const hn::ScalableTag<T> d;
  return WithTwin(m, [&](const auto& kernel) {
    if (a.non_finite == NonFinite::NaN)
      RunRange<true>(d, kernel, a, begin, end, want_pdf, m.rotation);
    else
      RunRange<false>(d, kernel, a, begin, end, want_pdf, m.rotation);
  });
}

template <typename T>
bool RunMaterialInterleaved(const MaterialT<T>& m, const InterleavedArgs<T>& a, size_t begin, size_t end, bool want_pdf) {
  const hn::ScalableTag<T> d;
  return WithTwin(m, [&](const auto& kernel) {
    if (a.non_finite == NonFinite::NaN)
      RunRangeInterleaved<true>(d, kernel, a, begin, end, want_pdf, m.rotation);
    else
      RunRangeInterleaved<false>(d, kernel, a, begin, end, want_pdf, m.rotation);
  });
}

template <typename T> bool SampleMaterial(const MaterialT<T>& m, const SampleArgs<T>& a, size_t begin, size_t end) {
  const hn::ScalableTag<T> d;
  return WithTwin(m, [&](const auto& kernel) { SampleRange(d, kernel, a, begin, end, m.rotation); });
}

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
