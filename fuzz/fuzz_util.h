// fuzz/fuzz_util.h: what every fuzz target shares (docs/testing.md, "Fuzz targets").
//
// A target is one function, LLVMFuzzerTestOneInput(data, size), linked either with clang's
// libFuzzer (-fsanitize=fuzzer: coverage-guided search) or with replay_main.cpp (any compiler:
// runs the seed corpus and the regression inputs once). A finding is anything that ends the
// process abnormally: a crash, a sanitizer report, an exception other than aniso::InputError (the
// readers' one way to reject input), a hang (libFuzzer's -timeout), or FUZZ_CHECK failing on
// non-finite or out-of-range output.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "aniso/brdf/material.h"

// Aborts with the condition and the place: libFuzzer saves the input as crash-<sha1>.
#define FUZZ_CHECK(cond)                                                                  \
  do {                                                                                    \
    if (!(cond)) {                                                                        \
      std::fprintf(stderr, "fuzz check failed: %s (%s:%d)\n", #cond, __FILE__, __LINE__); \
      std::abort();                                                                       \
    }                                                                                     \
  } while (0)

namespace aniso::fuzz {

inline std::string_view as_text(const uint8_t* data, size_t size) { return {reinterpret_cast<const char*>(data), size}; }

// Called where a target's reader rejected the input (an InputError): prints the message when
// ANISO_FUZZ_VERBOSE is set (to see which seeds get past the reader), otherwise nothing.
void rejected(const std::exception& e);

// A per-process scratch directory (readers that take a path get the input as a file there).
// Created once under $TMPDIR (default /tmp), removed at exit.
const std::string& scratch_dir();

// Writes bytes to scratch_dir()/name and returns the path.
std::string write_scratch_file(const std::string& name, const uint8_t* data, size_t size);

// Direction pairs that exercise every branch of the kernels: normal incidence, mirror and
// retro-reflection, grazing pairs down to the smallest normal and subnormal cosines, pairs across
// the horizon cosine of each precision (1e-6 float, 1e-12 double: docs/conventions.md), and
// below-horizon pairs.
struct FuzzPair {
  double wi[3], wo[3];
};
extern const FuzzPair kPairs[];
extern const size_t kPairCount;

// Evaluates f, pdf and sample() of a material over kPairs and a grid of random numbers, in its
// precision T, and FUZZ_CHECKs the kernel contract (aniso/brdf/material.h): f and pdf finite and
// >= 0; a valid sample has a unit wi above the horizon, finite weight >= 0 and finite pdf > 0.
template <typename T> void check_material(const MaterialT<T>& m);
extern template void check_material<float>(const MaterialT<float>&);
extern template void check_material<double>(const MaterialT<double>&);

}  // namespace aniso::fuzz
