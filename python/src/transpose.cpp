// python/src/transpose.cpp: see transpose.h.
#include "transpose.h"

#include <cmath>
#include <limits>

// One clone per instruction set, chosen by the loader (ifunc) on the running CPU. Not under clang
// (the sanitizer build): clang 14 compiles the always_inline bodies below for the first target into
// every clone, so the "default" clone of deinterleave(const float*, ..., double*) executed AVX-512
// mask compares (vcmpnleps into k0) and died of SIGILL on an AMD EPYC without AVX-512.
#if defined(__clang__)
#define ANISO_CLONES
#else
#define ANISO_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#endif

namespace aniso::python {
namespace {

template <typename S, typename T> [[gnu::always_inline]] inline void deinterleave_impl(const S* __restrict p, size_t len,
                                                                                       T* __restrict x, T* __restrict y,
                                                                                       T* __restrict z, uint8_t* __restrict bad) {
  constexpr S kMax = std::numeric_limits<S>::max();
  for (size_t i = 0; i < len; ++i) {
    const S a = p[3 * i], b = p[3 * i + 1], c = p[3 * i + 2];
    x[i] = T(a), y[i] = T(b), z[i] = T(c);
    // |v| <= max is false for NaN and for +-Inf; & (not &&) keeps the loop free of branches (on
    // ints: what bool & bool promotes to anyway, written out for clang's -Wbitwise-instead-of-logical).
    bad[i] |= uint8_t(!(int(std::fabs(a) <= kMax) & int(std::fabs(b) <= kMax) & int(std::fabs(c) <= kMax)));
  }
}

template <typename T> [[gnu::always_inline]] inline void interleave_impl(T* __restrict o, size_t len, const T* __restrict x,
                                                                         const T* __restrict y, const T* __restrict z,
                                                                         const uint8_t* __restrict bad) {
  for (size_t i = 0; i < len; ++i) {
    const T k = bad[i] ? std::numeric_limits<T>::quiet_NaN() : T(1);
    o[3 * i] = x[i] * k, o[3 * i + 1] = y[i] * k, o[3 * i + 2] = z[i] * k;
  }
}

template <typename T> [[gnu::always_inline]] inline void mark_nonfinite_impl(const T* __restrict x, const T* __restrict y,
                                                                             const T* __restrict z, size_t len,
                                                                             uint8_t* __restrict bad) {
  constexpr T kMax = std::numeric_limits<T>::max();
  for (size_t i = 0; i < len; ++i)
    bad[i] |= uint8_t(!(int(std::fabs(x[i]) <= kMax) & int(std::fabs(y[i]) <= kMax) & int(std::fabs(z[i]) <= kMax)));
}

template <typename T>
[[gnu::always_inline]] inline void mark_bad_impl(T* __restrict p, size_t len, const uint8_t* __restrict bad) {
  for (size_t i = 0; i < len; ++i) p[i] = bad[i] ? std::numeric_limits<T>::quiet_NaN() : p[i];
}

}  // namespace

ANISO_CLONES void deinterleave(const float* p, size_t len, float* x, float* y, float* z, uint8_t* bad) {
  deinterleave_impl(p, len, x, y, z, bad);
}
ANISO_CLONES void deinterleave(const float* p, size_t len, double* x, double* y, double* z, uint8_t* bad) {
  deinterleave_impl(p, len, x, y, z, bad);
}
ANISO_CLONES void deinterleave(const double* p, size_t len, double* x, double* y, double* z, uint8_t* bad) {
  deinterleave_impl(p, len, x, y, z, bad);
}
ANISO_CLONES void interleave(float* o, size_t len, const float* x, const float* y, const float* z, const uint8_t* bad) {
  interleave_impl(o, len, x, y, z, bad);
}
ANISO_CLONES void interleave(double* o, size_t len, const double* x, const double* y, const double* z, const uint8_t* bad) {
  interleave_impl(o, len, x, y, z, bad);
}
ANISO_CLONES void mark_nonfinite(const float* x, const float* y, const float* z, size_t len, uint8_t* bad) {
  mark_nonfinite_impl(x, y, z, len, bad);
}
ANISO_CLONES void mark_nonfinite(const double* x, const double* y, const double* z, size_t len, uint8_t* bad) {
  mark_nonfinite_impl(x, y, z, len, bad);
}
ANISO_CLONES void mark_bad(float* p, size_t len, const uint8_t* bad) { mark_bad_impl(p, len, bad); }
ANISO_CLONES void mark_bad(double* p, size_t len, const uint8_t* bad) { mark_bad_impl(p, len, bad); }

}  // namespace aniso::python
