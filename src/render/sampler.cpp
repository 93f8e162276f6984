// render/sampler.cpp: Owen-scrambled, index-shuffled Sobol' points and PCG32 (see sampler.h; the
// per-request functions are inline there).
#include "aniso/render/sampler.h"

namespace aniso::render {

using namespace sampler_detail;

uint32_t Sampler::sobol(uint32_t index, int dim) {
  if (dim == 0) return reverse_bits(index);  // van der Corput (direction numbers 2^(31 - k))
  return kSobolDim1(index);
}

uint32_t Sampler::nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

Sampler::Sampler(uint64_t seed, uint64_t pixel, uint64_t sample, SamplerKind kind) : kind_(kind) {
  uint64_t x = seed;
  x ^= splitmix64(x) + pixel;
  if (kind == SamplerKind::Sobol) {
    key_ = splitmix64(x);
    index_reversed_ = reverse_bits(uint32_t(sample));
    return;
  }
  x ^= splitmix64(x) + sample;
  const uint64_t s = splitmix64(x);
  inc_ = (splitmix64(x) << 1u) | 1u;
  state_ = 0;
  next_u32_pcg();
  state_ += s;
  next_u32_pcg();
}

}  // namespace aniso::render
