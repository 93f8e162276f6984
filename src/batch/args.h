// batch/args.h: the argument blocks every target's loops take (one type for all targets: the
// dispatch table holds one function pointer type).
#pragma once

#include <algorithm>
#include <limits>

#include "aniso/batch/batch.h"
namespace aniso::batch {
template <typename T> struct EvalArgs {
  Directions<T> wi, wo;
  Colors<T> f;
  T* pdf;
  NonFinite non_finite = NonFinite::AsComputed;
};
template <typename T> struct InterleavedArgs {
  Interleaved<T> wi, wo;
  T* f_rgb;  // evaluate: interleaved RGB rows
  T* pdf;    // pdf
  NonFinite non_finite;
};
template <typename T> struct SampleArgs {
  Directions<T> wo;
  const T *uc, *u0, *u1;
  Samples<T> out;
};
}  // namespace aniso::batch
