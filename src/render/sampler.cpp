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

namespace {
// The Sobol' sampler's key of (seed, pixel).
uint64_t pixel_key(uint64_t seed, uint64_t pixel) {
  uint64_t x = seed;
  x ^= splitmix64(x) + pixel;
  return splitmix64(x);
}
}  // namespace

Sampler::Sampler(uint64_t seed, uint64_t pixel, uint64_t sample, SamplerKind kind) : kind_(kind) {
  if (kind == SamplerKind::Sobol) {
    key_ = pixel_key(seed, pixel);
    index_reversed_ = reverse_bits(uint32_t(sample));
    return;
  }
  seed_pcg(seed, pixel, sample);
}

// PCG32 seeded from (seed, pixel, sample) through SplitMix64 (pcg32_srandom_r's order: state 0,
// a step, the initial state added, a step).
void Sampler::seed_pcg(uint64_t seed, uint64_t pixel, uint64_t sample) {
  uint64_t x = seed;
  x ^= splitmix64(x) + pixel;
  x ^= splitmix64(x) + sample;
  const uint64_t s = splitmix64(x);
  inc_ = (splitmix64(x) << 1u) | 1u;
  state_ = 0;
  next_u32_pcg();
  state_ += s;
  next_u32_pcg();
}

PixelSeeds::PixelSeeds(uint64_t seed, uint64_t pixel, SamplerKind kind)
    : seed_(seed), pixel_(pixel), key_(kind == SamplerKind::Sobol ? pixel_key(seed, pixel) : 0), kind_(kind) {}

}  // namespace aniso::render
