// aniso/batch/batch.h: f, pdf and sample for N direction pairs at once.
//
// Structure of arrays in and out: each coordinate and each colour channel is its own contiguous
// array, so that the SIMD code loads 8 (AVX2) or 16 (AVX-512) lanes of one quantity at a time.
// Every model, form and normalisation goes through MaterialT (its converting constructors take any
// model struct: `batch::evaluate(MaterialT<float>(ward), ...)`), float or double.
//
// The numbers are the scalar kernels' (include/aniso/brdf) within 1e-5 relative (tests/test_batch.cpp):
// evaluate, pdf and sample run Google Highway twins of the scalar terms (src/batch/twins/,
// one binary, the instruction set chosen at run time: AVX2, AVX-512, ...); the sampler fed the
// same uniforms gives the scalar sampler's directions to ~1e-5 (other sin / cos / log code).
// A model whose registry row says Scalar (aniso/brdf/registry.h; the measured BRDF: table lookups)
// has no SIMD twin: evaluate, pdf and sample run its scalar kernel element by element, on the same
// blocks and threads.
// Threads::All splits the N elements into fixed blocks that oneTBB runs on all cores; every
// element's result depends only on its inputs, so the output is the same bit for bit whatever the
// thread count and the block order. docs/performance.md has the details and the measurements.
//
// Host-only (not under nvcc); implemented in src/batch/batch.cpp (library aniso_batch).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "aniso/brdf/material.h"

namespace aniso::batch {

enum class Threads : int { One = 0, All = 1 };

// Which code computes each element: the SIMD twins (default), or the scalar kernels themselves,
// element by element on the same blocks and threads, bit for bit what MaterialT::f / pdf return
// (for callers whose output must not depend on the input's size, such as `aniso eval`).
enum class Kernels : int { Simd = 0, Scalar = 1 };

// What evaluate and pdf return for an element with a NaN or infinite input value: what the kernels
// compute from it (AsComputed, the default), or NaN in every output of that element (NaN: the
// Python bindings' contract, docs/python.md), decided inside the kernel's loop, without a second
// pass over the data.
enum class NonFinite : int { AsComputed = 0, NaN = 1 };

// n unit directions in the local shading frame, one array per coordinate.
template <typename T> struct Directions {
  const T* x = nullptr;
  const T* y = nullptr;
  const T* z = nullptr;
};

// n RGB values, one array per channel.
template <typename T> struct Colors {
  T* r = nullptr;
  T* g = nullptr;
  T* b = nullptr;
};

// sample()'s output, the SoA form of BSDFSampleT: "no sample" is valid = 0 with every field 0.
template <typename T> struct Samples {
  T* wi_x = nullptr;
  T* wi_y = nullptr;
  T* wi_z = nullptr;
  T* weight_r = nullptr;
  T* weight_g = nullptr;
  T* weight_b = nullptr;
  T* pdf = nullptr;
  uint8_t* valid = nullptr;
};

// f[i] = m.f(wi[i], wo[i]) for i < n.
template <typename T> void evaluate(const MaterialT<T>& m, Directions<T> wi, Directions<T> wo, size_t n, Colors<T> f,
                                    Threads threads = Threads::All, Kernels kernels = Kernels::Simd,
                                    NonFinite non_finite = NonFinite::AsComputed);

// pdf[i] = m.pdf(wi[i], wo[i]).
template <typename T> void pdf(const MaterialT<T>& m, Directions<T> wi, Directions<T> wo, size_t n, T* pdf,
                               Threads threads = Threads::All, Kernels kernels = Kernels::Simd,
                               NonFinite non_finite = NonFinite::AsComputed);

// out[i] = m.sample(wo[i], uc[i], (u0[i], u1[i])).
template <typename T> void sample(const MaterialT<T>& m, Directions<T> wo, const T* uc, const T* u0, const T* u1, size_t n,
                                  Samples<T> out, Threads threads = Threads::All);

// Interleaved rows: n directions as (x, y, z) triples, the layout of a C-ordered (N, 3) array and
// of std::vector<Vec3T<T>>. stride 3: element i at xyz[3 i], xyz[3 i + 1], xyz[3 i + 2]; stride 0:
// the one direction xyz[0..2] for every element (a broadcast). No other stride.
template <typename T> struct Interleaved {
  const T* xyz = nullptr;
  size_t stride = 3;
};

// evaluate() on interleaved rows, f written interleaved: f_rgb[3 i + c] = m.f(wi[i], wo[i])[c]. The
// SIMD kernels load and store the rows themselves (Highway's LoadInterleaved3 / StoreInterleaved3),
// so this is the same arithmetic as evaluate() on the same elements, bit for bit (tests/test_batch.cpp),
// with no transposition pass before or after.
template <typename T> void evaluate_interleaved(const MaterialT<T>& m, Interleaved<T> wi, Interleaved<T> wo, size_t n, T* f_rgb,
                                                Threads threads = Threads::All, Kernels kernels = Kernels::Simd,
                                                NonFinite non_finite = NonFinite::AsComputed);

// pdf() on interleaved rows: pdf[i] = m.pdf(wi[i], wo[i]), pdf contiguous.
template <typename T> void pdf_interleaved(const MaterialT<T>& m, Interleaved<T> wi, Interleaved<T> wo, size_t n, T* pdf,
                                           Threads threads = Threads::All, Kernels kernels = Kernels::Simd,
                                           NonFinite non_finite = NonFinite::AsComputed);

// The Highway target the dispatcher picked on this machine ("AVX3", "AVX2", ...). The environment
// variable ANISO_SIMD (avx2, sse4, baseline) caps it, for measurements and tests; read at the
// first call.
const char* simd_target();
// Lanes of one float / double vector on that target.
size_t simd_lanes_float();
size_t simd_lanes_double();

// Owning SoA buffers for callers that start from arrays of Vec3 (the CLI, the albedo code, tests).
template <typename T> struct DirectionArray {
  std::vector<T> x, y, z;
  DirectionArray() = default;
  explicit DirectionArray(size_t n) : x(n), y(n), z(n) {}
  void resize(size_t n) { x.resize(n), y.resize(n), z.resize(n); }
  size_t size() const { return x.size(); }
  void set(size_t i, const Vec3T<T>& w) { x[i] = w.x, y[i] = w.y, z[i] = w.z; }
  Vec3T<T> get(size_t i) const { return Vec3T<T>(x[i], y[i], z[i]); }
  Directions<T> view() const { return {x.data(), y.data(), z.data()}; }
};

template <typename T> struct ColorArray {
  std::vector<T> r, g, b;
  ColorArray() = default;
  explicit ColorArray(size_t n) : r(n), g(n), b(n) {}
  void resize(size_t n) { r.resize(n), g.resize(n), b.resize(n); }
  RGBT<T> get(size_t i) const { return RGBT<T>(r[i], g[i], b[i]); }
  Colors<T> view() { return {r.data(), g.data(), b.data()}; }
};

template <typename T> struct SampleArray {
  DirectionArray<T> wi;
  ColorArray<T> weight;
  std::vector<T> pdf;
  std::vector<uint8_t> valid;
  SampleArray() = default;
  explicit SampleArray(size_t n) : wi(n), weight(n), pdf(n), valid(n) {}
  void resize(size_t n) { wi.resize(n), weight.resize(n), pdf.resize(n), valid.resize(n); }
  BSDFSampleT<T> get(size_t i) const {
    BSDFSampleT<T> s;
    s.wi = wi.get(i);
    s.weight = weight.get(i);
    s.pdf = pdf[i];
    s.valid = valid[i] != 0;
    return s;
  }
  Samples<T> view() {
    return {wi.x.data(), wi.y.data(), wi.z.data(), weight.r.data(), weight.g.data(), weight.b.data(), pdf.data(), valid.data()};
  }
};

}  // namespace aniso::batch
