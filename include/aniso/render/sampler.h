// aniso/render/sampler.h: the random numbers of one pixel sample.
//
// Two kinds, chosen by the scene's integrator.sampler (docs/scenes.md):
//
// - sobol (default): Owen-scrambled Sobol' points, padded dimension by dimension with independent
//   index shuffles (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), Sec. 3-5: the
//   "shuffled scrambled Sobol'" of its Listing 4, in 1D and 2D). Every request of the path (the
//   sub-pixel position, each light choice, light sample, lobe choice, BRDF sample, roulette draw)
//   is a new "dimension" d with its own 32-bit seed hashed from (seed, pixel, d). The sample index
//   is first shuffled by a nested uniform scramble keyed by that seed, then the first one (1D) or
//   two (2D) Sobol' dimensions of the shuffled index are Owen-scrambled (nested uniform scramble,
//   Laine-Karras style hash permutation of the reversed bits; Burley's Listing 2 and 3). A
//   pixel's n samples are then, in each 2D request, a scrambled (0, 2)-sequence: stratified in
//   every elementary interval of area 1/n when n is a power of two, still well spread otherwise.
//   Owen scrambling keeps each point uniformly distributed over [0, 1)^2 (Owen 1995), so every
//   estimate stays unbiased; the pixels' scrambles are independent, so the error is white noise
//   across pixels (no blue-noise ordering is attempted).
// - independent: the same requests answered by PCG32 (O'Neill 2014, pcg32 XSH-RR), seeded from
//   (seed, pixel, sample) by SplitMix64 (Steele et al. 2014). Kept for comparisons (the benchmark's
//   equal-spp RMSE table) and for tests that want plain Monte Carlo.
//
// Both depend on (seed, pixel, sample index, request number) alone, so the image is the same for
// any thread count or tile order.
#pragma once

#include <cstdint>

#include "aniso/core/math.h"

namespace aniso::render {

enum class SamplerKind { Sobol, Independent };

class Sampler {
 public:
  Sampler(uint64_t seed, uint64_t pixel, uint64_t sample, SamplerKind kind = SamplerKind::Sobol);
  float uniform();  // [0, 1), 24 bits: never 1
  Vec2 uniform2();  // [0, 1)^2

  // The building blocks, exposed for tests (Burley 2020, Listings 1-3).
  static uint32_t sobol(uint32_t index, int dim);  // dim 0 (van der Corput) or 1, unscrambled
  static uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed);

 private:
  uint32_t next_u32_pcg();
  struct DimensionSeeds {
    uint32_t shuffle, x, y;
  };
  DimensionSeeds dimension_seeds();  // the seeds of the next request (advances the request counter)
  static float to_unit(uint32_t x) { return float(x >> 8) * 0x1.0p-24f; }

  SamplerKind kind_;
  uint64_t key_ = 0;              // hash of (seed, pixel)
  uint32_t index_reversed_ = 0;   // the sample index within the pixel, bits reversed
  uint32_t dimension_ = 0;        // requests made so far
  uint64_t state_ = 0, inc_ = 1;  // PCG32 (independent)
};

}  // namespace aniso::render
