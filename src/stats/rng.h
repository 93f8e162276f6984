// stats/rng.h: the random numbers host tools and tests draw: std::mt19937_64, mapped to [0, 1)
// by taking its top 53 (double) or 24 (float) bits, which is exact and never returns 1.
#pragma once

#include <cstdint>
#include <random>

namespace aniso {

class Rng {
 public:
  explicit Rng(uint64_t seed = 1) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  template <typename T> T uniform_as() {
    if constexpr (sizeof(T) == sizeof(float))
      return static_cast<float>(engine_() >> 40) * 0x1.0p-24f;
    else
      return static_cast<T>(uniform());
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace aniso
