// batch/batch.cpp: the batch API (include/aniso/batch/batch.h). Highway compiles kernels-inl.h once
// per x86 target (SSE4, AVX2, AVX-512, ...; hwy/foreach_target.h) and HWY_DYNAMIC_DISPATCH picks
// the best one the running CPU has, once, at the first call. oneTBB spreads fixed blocks of
// elements over the cores.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch/batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "batch/kernels-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aniso::batch::HWY_NAMESPACE {

void EvalFloat(const MaterialT<float>& m, const EvalArgs<float>& a, size_t begin, size_t end, bool want_pdf) {
  (void)RunMaterial(m, a, begin, end, want_pdf);
}
void EvalDouble(const MaterialT<double>& m, const EvalArgs<double>& a, size_t begin, size_t end, bool want_pdf) {
  (void)RunMaterial(m, a, begin, end, want_pdf);
}
void EvalInterleavedFloat(const MaterialT<float>& m, const InterleavedArgs<float>& a, size_t begin, size_t end, bool want_pdf) {
  (void)RunMaterialInterleaved(m, a, begin, end, want_pdf);
}
void EvalInterleavedDouble(const MaterialT<double>& m, const InterleavedArgs<double>& a, size_t begin, size_t end,
                           bool want_pdf) {
  (void)RunMaterialInterleaved(m, a, begin, end, want_pdf);
}
bool SampleFloat(const MaterialT<float>& m, const SampleArgs<float>& a, size_t begin, size_t end) {
  return SampleMaterial(m, a, begin, end);
}
bool SampleDouble(const MaterialT<double>& m, const SampleArgs<double>& a, size_t begin, size_t end) {
  return SampleMaterial(m, a, begin, end);
}
size_t LanesFloat() { return hn::Lanes(hn::ScalableTag<float>()); }
size_t LanesDouble() { return hn::Lanes(hn::ScalableTag<double>()); }
const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace aniso::batch::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

#if HWY_ARCH_X86
#include <xmmintrin.h>
#endif

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include <hwy/targets.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aniso/batch/batch.h"

namespace aniso::batch {

HWY_EXPORT(EvalFloat);
HWY_EXPORT(EvalDouble);
HWY_EXPORT(EvalInterleavedFloat);
HWY_EXPORT(EvalInterleavedDouble);
HWY_EXPORT(SampleFloat);
HWY_EXPORT(SampleDouble);
HWY_EXPORT(LanesFloat);
HWY_EXPORT(LanesDouble);
HWY_EXPORT(TargetName);

namespace {

// Elements per task: large enough that a task (tens of microseconds for the cheapest model)
// outweighs TBB's scheduling, small enough that 2 to 64 cores all get work for N ~ 1e5. A multiple
// of every vector length, so that only the last block has a partial vector.
constexpr size_t kBlock = 4096;

// Calls fn(begin, end) over [0, n) in blocks of kBlock: in order on this thread, or on all cores.
// The blocks are fixed (simple_partitioner, grain 1 block), so each element is computed by the
// same code whatever the scheduling: the results do not depend on the thread count.
// Subnormal floats cost a microcode assist per SIMD instruction that touches one (x86: ~100 cycles):
// a narrow Ward or Phong lobe puts exp(-90) (float) in whole vectors of random pairs, and masked-off
// lanes compute such values too. While the SIMD kernels run, MXCSR flushes subnormal results to 0
// and reads subnormal inputs as 0 (FTZ | DAZ), and is restored after each block, on the thread that
// ran it. Only values below 1.2e-38 (float; 2.2e-308 double) change: they become 0.
class FlushSubnormals {
 public:
  FlushSubnormals() {
#if HWY_ARCH_X86
    saved_ = _mm_getcsr();
    _mm_setcsr(saved_ | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
#endif
  }
  ~FlushSubnormals() {
#if HWY_ARCH_X86
    _mm_setcsr(saved_);
#endif
  }
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;

 private:
  unsigned saved_ = 0;
};

// ANISO_SIMD in the environment caps the dispatcher (to measure and test, on an AVX-512 machine,
// the code other machines run): "avx2" (8 float lanes, the CI machine's), "sse4" (4 lanes),
// "baseline" (the compiled-in minimum, SSE2 on x86-64). Read once, before the first dispatch.
void apply_simd_limit_from_environment() {
  static const bool applied = [] {
    const char* limit = std::getenv("ANISO_SIMD");
    if (limit == nullptr) return true;
    int64_t avx512 = HWY_AVX3 | HWY_AVX3_DL;
#ifdef HWY_AVX3_ZEN4
    avx512 |= HWY_AVX3_ZEN4;
#endif
#ifdef HWY_AVX3_SPR
    avx512 |= HWY_AVX3_SPR;
#endif
    if (std::strcmp(limit, "avx2") == 0)
      hwy::DisableTargets(avx512);
    else if (std::strcmp(limit, "sse4") == 0)
      hwy::DisableTargets(avx512 | HWY_AVX2);
    else if (std::strcmp(limit, "baseline") == 0)
      hwy::DisableTargets(~int64_t(0));  // the baseline stays
    return true;
  }();
  (void)applied;
}

template <typename Fn> void for_blocks(size_t n, Threads threads, Fn&& fn) {
  apply_simd_limit_from_environment();
  const size_t blocks = (n + kBlock - 1) / kBlock;
  const auto run = [&](size_t b) { fn(b * kBlock, std::min(n, (b + 1) * kBlock)); };
  if (threads == Threads::One || blocks <= 1) {
    for (size_t b = 0; b < blocks; ++b) run(b);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, blocks, 1),
      [&](const tbb::blocked_range<size_t>& r) {
        for (size_t b = r.begin(); b != r.end(); ++b) run(b);
      },
      tbb::simple_partitioner());
}

template <typename T> void dispatch(const MaterialT<T>& m, const EvalArgs<T>& a, size_t b, size_t e, bool want_pdf) {
  if constexpr (sizeof(T) == sizeof(float)) {
    HWY_DYNAMIC_DISPATCH(EvalFloat)(m, a, b, e, want_pdf);
  } else {
    HWY_DYNAMIC_DISPATCH(EvalDouble)(m, a, b, e, want_pdf);
  }
}

template <typename T> void dispatch(const MaterialT<T>& m, const InterleavedArgs<T>& a, size_t b, size_t e, bool want_pdf) {
  if constexpr (sizeof(T) == sizeof(float)) {
    HWY_DYNAMIC_DISPATCH(EvalInterleavedFloat)(m, a, b, e, want_pdf);
  } else {
    HWY_DYNAMIC_DISPATCH(EvalInterleavedDouble)(m, a, b, e, want_pdf);
  }
}

// Element i of interleaved rows, for the scalar kernels.
template <typename T> Vec3T<T> row(const Interleaved<T>& w, size_t i) {
  const T* p = w.xyz + w.stride * i;
  return Vec3T<T>(p[0], p[1], p[2]);
}
template <typename T> bool finite(const Vec3T<T>& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Row i of the arguments, split or interleaved: its {wi, wo}, and where its f goes.
template <typename T> std::pair<Vec3T<T>, Vec3T<T>> directions(const EvalArgs<T>& a, size_t i) {
  return {Vec3T<T>(a.wi.x[i], a.wi.y[i], a.wi.z[i]), Vec3T<T>(a.wo.x[i], a.wo.y[i], a.wo.z[i])};
}
template <typename T> std::pair<Vec3T<T>, Vec3T<T>> directions(const InterleavedArgs<T>& a, size_t i) {
  return {row(a.wi, i), row(a.wo, i)};
}
template <typename T> void put_f(const EvalArgs<T>& a, size_t i, const RGBT<T>& c) {
  a.f.r[i] = c.x, a.f.g[i] = c.y, a.f.b[i] = c.z;
}
template <typename T> void put_f(const InterleavedArgs<T>& a, size_t i, const RGBT<T>& c) {
  a.f_rgb[3 * i] = c.x, a.f_rgb[3 * i + 1] = c.y, a.f_rgb[3 * i + 2] = c.z;
}

// The four evaluations (f or pdf, of split or interleaved rows) on the blocks of for_blocks: the
// SIMD twin, or the scalar kernel per row where asked for or where the model's registry row says
// Scalar (no SIMD twin: the measured BRDF, table lookups and gathers from 35 MB), on the same
// blocks and threads.
template <bool kPdf, typename T, typename Args>
void evaluate_blocks(const MaterialT<T>& m, const Args& a, size_t n, Threads threads, Kernels kernels) {
  if (model_info(m.kind).batch == BatchPath::Scalar) kernels = Kernels::Scalar;
  const bool nan_rows = a.non_finite == NonFinite::NaN;
  for_blocks(n, threads, [&](size_t b, size_t e) {
    if (kernels == Kernels::Scalar) {
      const FrameRotationT<T>& r = m.rotation;
      m.visit([&](const auto& model) {
        for (size_t i = b; i < e; ++i) {
          // In the model's own frame (material.h, FrameRotationT: the identity unless rotation_deg).
          const auto [wi, wo] = directions(a, i);
          const Vec3T<T> u = r.to_model(wi), v = r.to_model(wo);
          const bool nan_row = nan_rows && !(finite(u) && finite(v));
          if constexpr (kPdf)
            a.pdf[i] = nan_row ? std::numeric_limits<T>::quiet_NaN() : model.pdf(u, v);
          else
            put_f(a, i, nan_row ? RGBT<T>(std::numeric_limits<T>::quiet_NaN()) : model.f(u, v));
        }
      });
      return;
    }
    const FlushSubnormals ftz;
    dispatch(m, a, b, e, kPdf);
  });
}

}  // namespace

template <typename T> void evaluate(const MaterialT<T>& m, Directions<T> wi, Directions<T> wo, size_t n, Colors<T> f,
                                    Threads threads, Kernels kernels, NonFinite non_finite) {
  evaluate_blocks<false>(m, EvalArgs<T>{wi, wo, f, nullptr, non_finite}, n, threads, kernels);
}

template <typename T> void pdf(const MaterialT<T>& m, Directions<T> wi, Directions<T> wo, size_t n, T* out, Threads threads,
                               Kernels kernels, NonFinite non_finite) {
  evaluate_blocks<true>(m, EvalArgs<T>{wi, wo, {}, out, non_finite}, n, threads, kernels);
}

template <typename T> void evaluate_interleaved(const MaterialT<T>& m, Interleaved<T> wi, Interleaved<T> wo, size_t n, T* f_rgb,
                                                Threads threads, Kernels kernels, NonFinite non_finite) {
  evaluate_blocks<false>(m, InterleavedArgs<T>{wi, wo, f_rgb, nullptr, non_finite}, n, threads, kernels);
}

template <typename T> void pdf_interleaved(const MaterialT<T>& m, Interleaved<T> wi, Interleaved<T> wo, size_t n, T* out,
                                           Threads threads, Kernels kernels, NonFinite non_finite) {
  evaluate_blocks<true>(m, InterleavedArgs<T>{wi, wo, nullptr, out, non_finite}, n, threads, kernels);
}

// The SIMD samplers (src/batch/twins/) for every model whose registry row says Simd; the scalar
// loop below for the others (the measured BRDF: table lookups).
template <typename T> void sample(const MaterialT<T>& m, Directions<T> wo, const T* uc, const T* u0, const T* u1, size_t n,
                                  Samples<T> out, Threads threads) {
  const SampleArgs<T> a{wo, uc, u0, u1, out};
  for_blocks(n, threads, [&](size_t b, size_t e) {
    {
      const FlushSubnormals ftz;
      bool done;
      if constexpr (sizeof(T) == sizeof(float)) {
        done = HWY_DYNAMIC_DISPATCH(SampleFloat)(m, a, b, e);
      } else {
        done = HWY_DYNAMIC_DISPATCH(SampleDouble)(m, a, b, e);
      }
      if (done) return;
    }
    const FrameRotationT<T>& r = m.rotation;
    m.visit([&](const auto& model) {
      for (size_t i = b; i < e; ++i) {
        BSDFSampleT<T> s = model.sample(r.to_model(Vec3T<T>(wo.x[i], wo.y[i], wo.z[i])), uc[i], Vec2T<T>(u0[i], u1[i]));
        s.wi = r.from_model(s.wi);
        out.wi_x[i] = s.wi.x, out.wi_y[i] = s.wi.y, out.wi_z[i] = s.wi.z;
        out.weight_r[i] = s.weight.x, out.weight_g[i] = s.weight.y, out.weight_b[i] = s.weight.z;
        out.pdf[i] = s.pdf;
        out.valid[i] = s.valid ? 1 : 0;
      }
    });
  });
}

const char* simd_target() {
  apply_simd_limit_from_environment();
  return HWY_DYNAMIC_DISPATCH(TargetName)();
}
size_t simd_lanes_float() {
  apply_simd_limit_from_environment();
  return HWY_DYNAMIC_DISPATCH(LanesFloat)();
}
size_t simd_lanes_double() {
  apply_simd_limit_from_environment();
  return HWY_DYNAMIC_DISPATCH(LanesDouble)();
}

template void evaluate<float>(const MaterialT<float>&, Directions<float>, Directions<float>, size_t, Colors<float>, Threads,
                              Kernels, NonFinite);
template void evaluate<double>(const MaterialT<double>&, Directions<double>, Directions<double>, size_t, Colors<double>, Threads,
                               Kernels, NonFinite);
template void pdf<float>(const MaterialT<float>&, Directions<float>, Directions<float>, size_t, float*, Threads, Kernels,
                         NonFinite);
template void pdf<double>(const MaterialT<double>&, Directions<double>, Directions<double>, size_t, double*, Threads, Kernels,
                          NonFinite);
template void evaluate_interleaved<float>(const MaterialT<float>&, Interleaved<float>, Interleaved<float>, size_t, float*,
                                          Threads, Kernels, NonFinite);
template void evaluate_interleaved<double>(const MaterialT<double>&, Interleaved<double>, Interleaved<double>, size_t, double*,
                                           Threads, Kernels, NonFinite);
template void pdf_interleaved<float>(const MaterialT<float>&, Interleaved<float>, Interleaved<float>, size_t, float*, Threads,
                                     Kernels, NonFinite);
template void pdf_interleaved<double>(const MaterialT<double>&, Interleaved<double>, Interleaved<double>, size_t, double*,
                                      Threads, Kernels, NonFinite);
template void sample<float>(const MaterialT<float>&, Directions<float>, const float*, const float*, const float*, size_t,
                            Samples<float>, Threads);
template void sample<double>(const MaterialT<double>&, Directions<double>, const double*, const double*, const double*, size_t,
                             Samples<double>, Threads);

}  // namespace aniso::batch

#endif  // HWY_ONCE
