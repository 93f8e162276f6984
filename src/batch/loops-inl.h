// batch/loops-inl.h: the loops over rows that run a SIMD twin (src/batch/twins/) one vector at a
// time: evaluate / pdf on separate or interleaved arrays, and sampling.
// Per-target include guard, the pattern Highway documents for -inl.h files.
#if defined(ANISO_BATCH_LOOPS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef ANISO_BATCH_LOOPS_INL_H_
#undef ANISO_BATCH_LOOPS_INL_H_
#else
#define ANISO_BATCH_LOOPS_INL_H_
#endif

#include "batch/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// --- The loops ---------------------------------------------------------------------------------

// The material's orientation (FrameRotationT, aniso/brdf/material.h): directions into the turned
// frame the model lives in (ToModel) and sampled ones back (FromModel), lane by lane the scalar
// arithmetic. The loops skip both for the identity, which is then bit for bit the plain loop.
template <class D, typename T> HWY_INLINE V3<D> ToModel(D d, const FrameRotationT<T>& r, const V3<D>& w) {
  const V<D> c = hn::Set(d, r.c), s = hn::Set(d, r.s);
  return {hn::MulAdd(s, w.y, hn::Mul(c, w.x)), hn::NegMulAdd(s, w.x, hn::Mul(c, w.y)), w.z};
}
template <class D, typename T> HWY_INLINE V3<D> FromModel(D d, const FrameRotationT<T>& r, const V3<D>& w) {
  const V<D> c = hn::Set(d, r.c), s = hn::Set(d, r.s);
  return {hn::NegMulAdd(s, w.y, hn::Mul(c, w.x)), hn::MulAdd(c, w.y, hn::Mul(s, w.x)), w.z};
}

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
template <bool kNanRows, class D, class Kernel, typename T> HWY_INLINE void RunRange(D d, const Kernel& k, const EvalArgs<T>& a,
                                                                                     size_t begin, size_t end, bool want_pdf,
                                                                                     const FrameRotationT<T>& rot) {
  const size_t N = hn::Lanes(d);
  constexpr bool nan_rows = kNanRows;
  const V<D> nan = hn::Set(d, std::numeric_limits<T>::quiet_NaN());
  const auto one = [&](const T* wix, const T* wiy, const T* wiz, const T* wox, const T* woy, const T* woz, T* r, T* g, T* b,
                       T* p) {
    V3<D> wi{hn::LoadU(d, wix), hn::LoadU(d, wiy), hn::LoadU(d, wiz)};
    V3<D> wo{hn::LoadU(d, wox), hn::LoadU(d, woy), hn::LoadU(d, woz)};
    if (!rot.identity()) wi = ToModel(d, rot, wi), wo = ToModel(d, rot, wo);
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

// The same loop on interleaved rows (batch.h, evaluate_interleaved / pdf_interleaved): each vector's
// rows are loaded and de-interleaved in registers (LoadInterleaved3: three loads and shuffles), the
// kernel runs on the vectors exactly as in RunRange, and f is re-interleaved in registers
// (StoreInterleaved3). A broadcast input (stride 0) is one vector per coordinate for the whole
// range. With NonFinite::NaN (kNanRows, as in RunRange) a lane whose six input values are not all
// finite gets NaN in every output.
template <bool kNanRows, class D, class Kernel, typename T>
HWY_INLINE void RunRangeInterleaved(D d, const Kernel& k, const InterleavedArgs<T>& a, size_t begin, size_t end, bool want_pdf,
                                    const FrameRotationT<T>& rot) {
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
    if (!rot.identity()) wi = ToModel(d, rot, wi), wo = ToModel(d, rot, wo);
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
  for (; i + N <= end; i += N)
    one(at(a.wi, i), at(a.wo, i), want_pdf ? nullptr : a.f_rgb + 3 * i, want_pdf ? a.pdf + i : nullptr);
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
    if (want_pdf)
      std::copy_n(bp, rest, a.pdf + i);
    else
      std::copy_n(bf, 3 * rest, a.f_rgb + 3 * i);
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

template <class D, class Kernel, typename T> HWY_INLINE void SampleRange(D d, const Kernel& k, const SampleArgs<T>& a,
                                                                         size_t begin, size_t end, const FrameRotationT<T>& rot) {
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
    V3<D> wo{hn::LoadU(d, src[0]), hn::LoadU(d, src[1]), hn::LoadU(d, src[2])};
    if (!rot.identity()) wo = ToModel(d, rot, wo);
    V3<D> wi;
    RGBV<D> w;
    V<D> p;
    M<D> valid;
    SampleVec(d, k, wo, hn::LoadU(d, src[3]), hn::LoadU(d, src[4]), hn::LoadU(d, src[5]), wi, w, p, valid);
    if (!rot.identity()) wi = FromModel(d, rot, wi);  // an invalid lane's wi is 0 and stays 0
    T* dst[7] = {a.out.wi_x + i,     a.out.wi_y + i,     a.out.wi_z + i, a.out.weight_r + i,
                 a.out.weight_g + i, a.out.weight_b + i, a.out.pdf + i};
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

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
