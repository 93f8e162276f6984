// python/src/transpose.h: (N, 3) rows <-> three arrays (the batch API's structure of arrays), for
// the bindings' chunks (arrays.h). The contiguous case is the common one (a C-ordered NumPy
// array) and costs as much as the cheapest models' evaluation when written as a scalar loop, so
// these loops are compiled once per instruction set (GCC target_clones: x86-64-v4 (AVX-512), v3 (AVX2) and the
// x86-64 baseline, picked when the module loads), where GCC vectorises the stride-3 accesses.
#pragma once

#include <cstddef>
#include <cstdint>

namespace aniso::python {

// x[i], y[i], z[i] = p[3i], p[3i + 1], p[3i + 2] for i < len; bad[i] |= 1 where one is NaN or
// infinite.
void deinterleave(const float* p, size_t len, float* x, float* y, float* z, uint8_t* bad);
void deinterleave(const float* p, size_t len, double* x, double* y, double* z, uint8_t* bad);
void deinterleave(const double* p, size_t len, double* x, double* y, double* z, uint8_t* bad);

// o[3i + c] = (x, y, z)[c][i], or NaN where bad[i].
void interleave(float* o, size_t len, const float* x, const float* y, const float* z, const uint8_t* bad);
void interleave(double* o, size_t len, const double* x, const double* y, const double* z, const uint8_t* bad);

// bad[i] |= 1 where x[i], y[i] or z[i] is NaN or infinite.
void mark_nonfinite(const float* x, const float* y, const float* z, size_t len, uint8_t* bad);
void mark_nonfinite(const double* x, const double* y, const double* z, size_t len, uint8_t* bad);

// p[i] = NaN where bad[i].
void mark_bad(float* p, size_t len, const uint8_t* bad);
void mark_bad(double* p, size_t len, const uint8_t* bad);

}  // namespace aniso::python
