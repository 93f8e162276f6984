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

// The hashes and tables of Sampler's inline requests (sampler.h: the hot path of every path
// vertex, inlined into the integrator), exposed only for Sampler and its tests.
namespace sampler_detail {

constexpr uint64_t splitmix64(uint64_t& x) {
  uint64_t z = (x += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// The bytes reversed by one instruction (bswap), then the bits within each byte by three swaps.
constexpr uint32_t reverse_bits(uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
}
static_assert(reverse_bits(1u) == 0x80000000u && reverse_bits(0x12345678u) == 0x1e6a2c48u);

// Two 32-bit reversals for the price of one 64-bit one: reversing the 64 bits of (a << 32 | b)
// gives reverse_bits(b) in the high half and reverse_bits(a) in the low half.
struct ReversedPair {
  uint32_t a, b;  // reverse_bits of the inputs a and b
};
constexpr ReversedPair reverse_bits_pair(uint32_t a, uint32_t b) {
  uint64_t x = __builtin_bswap64((uint64_t(a) << 32) | b);
  x = ((x >> 1) & 0x5555555555555555ull) | ((x & 0x5555555555555555ull) << 1);
  x = ((x >> 2) & 0x3333333333333333ull) | ((x & 0x3333333333333333ull) << 2);
  x = ((x >> 4) & 0x0f0f0f0f0f0f0f0full) | ((x & 0x0f0f0f0f0f0f0f0full) << 4);
  return {uint32_t(x), uint32_t(x >> 32)};
}
static_assert(reverse_bits_pair(0x12345678u, 1u).a == reverse_bits(0x12345678u) &&
              reverse_bits_pair(0x12345678u, 1u).b == reverse_bits(1u));

// Burley 2020, Listing 2: a hash that, applied to the bit-reversed value, is a nested uniform
// (Owen) scramble: each output bit is flipped or not depending only on the bits above it. The
// constants are Burley's (after Laine & Karras 2011, "Stratified sampling for stochastic
// transparency").
constexpr uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// The second Sobol' dimension's direction numbers (primitive polynomial x + 1, m_1 = 1):
// v_0 = 2^31, v_k = v_{k-1} ^ (v_{k-1} >> 1) (Pascal's triangle mod 2; Joe & Kuo's table, dimension 2).
// The generator matrix is applied a byte at a time: table[b][x] is the XOR of v[8 b + j] over the
// set bits j of x (the shuffled index is a full 32-bit number, so a bit loop would take ~32 steps).
// With `reversed` every entry is bit-reversed: reversal distributes over XOR, so the lookup gives
// reverse_bits of the point, which is what the scramble takes (one reversal fewer per sample).
struct SobolDim1 {
  uint32_t v[32];
  uint32_t table[4][256];
  constexpr explicit SobolDim1(bool reversed) : v{}, table{} {
    v[0] = 0x80000000u;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    for (int b = 0; b < 4; ++b)
      for (int x = 0; x < 256; ++x) {
        for (int j = 0; j < 8; ++j)
          if (x & (1 << j)) table[b][x] ^= v[8 * b + j];
        if (reversed) table[b][x] = reverse_bits(table[b][x]);
      }
  }
  constexpr uint32_t operator()(uint32_t i) const {
    return table[0][i & 255u] ^ table[1][(i >> 8) & 255u] ^ table[2][(i >> 16) & 255u] ^ table[3][i >> 24];
  }
};
inline constexpr SobolDim1 kSobolDim1{false}, kSobolDim1Reversed{true};
static_assert(kSobolDim1.v[1] == 0xc0000000u && kSobolDim1.v[2] == 0xa0000000u && kSobolDim1.v[4] == 0x88000000u);
static_assert(kSobolDim1(3u) == (0x80000000u ^ 0xc0000000u));
static_assert(kSobolDim1Reversed(0x9abcdef1u) == reverse_bits(kSobolDim1(0x9abcdef1u)));

// What a request needs of the shuffled index i, read from its reversal j = reverse_bits(i) (the
// shuffle's output): i itself and kSobolDim1Reversed(i), both linear over GF(2) in the bits of j,
// so one table a byte of j gives both (i in the low half, the reversed Sobol' coordinate in the
// high half): four 64-bit lookups in place of a bit reversal and four 32-bit lookups.
struct UnreversedIndex {
  uint64_t table[4][256];
  constexpr UnreversedIndex() : table{} {
    for (int b = 0; b < 4; ++b)
      for (uint32_t x = 0; x < 256; ++x) {
        const uint32_t i = reverse_bits(x << (8 * b));
        table[b][x] = uint64_t(i) | (uint64_t(kSobolDim1Reversed(i)) << 32);
      }
  }
  constexpr uint64_t operator()(uint32_t j) const {
    return table[0][j & 255u] ^ table[1][(j >> 8) & 255u] ^ table[2][(j >> 16) & 255u] ^ table[3][j >> 24];
  }
};
inline constexpr UnreversedIndex kUnreversedIndex{};
static_assert(uint32_t(kUnreversedIndex(0x9abcdef1u)) == reverse_bits(0x9abcdef1u) &&
              uint32_t(kUnreversedIndex(0x9abcdef1u) >> 32) == kSobolDim1Reversed(reverse_bits(0x9abcdef1u)));

// The three 32-bit seeds of one request (a "dimension" d of Burley 2020, Listing 4): the index
// shuffle's and each coordinate's scramble, hashed from the (seed, pixel) key and d alone.
struct DimensionSeeds {
  uint32_t shuffle, x, y;
};
inline DimensionSeeds dimension_seeds(uint64_t key, uint32_t d) {
  uint64_t x = key + uint64_t(d) * 0xd1b54a32d192ed03ull;
  const uint64_t a = splitmix64(x), b = splitmix64(x);
  return {uint32_t(a), uint32_t(a >> 32), uint32_t(b)};
}

}  // namespace sampler_detail

enum class SamplerKind { Sobol, Independent };

// What the samples of one pixel share: the key hashed from (seed, pixel), and the seeds of each
// request d, which depend on (key, d) alone and so are the same for every sample of the pixel
// (sampler_detail::dimension_seeds: two SplitMix64 a request). The first sample to make request d
// stores its seeds; later samples of the pixel read them. The numbers are those of a Sampler
// without it, bit for bit. One per pixel and thread (not shared between threads: it is written).
class PixelSeeds {
 public:
  PixelSeeds(uint64_t seed, uint64_t pixel, SamplerKind kind = SamplerKind::Sobol);

 private:
  friend class Sampler;
  // Requests kept: a path of the default depth (8) with two lights and the sky sampled at every
  // vertex makes 6 a vertex, 49 in all; later ones are hashed each time.
  static constexpr uint32_t kKept = 64;
  uint64_t seed_, pixel_, key_;
  SamplerKind kind_;
  uint32_t kept_ = 0;  // seeds_[0, kept_) are filled
  sampler_detail::DimensionSeeds seeds_[kKept];
};

class Sampler {
 public:
  Sampler(uint64_t seed, uint64_t pixel, uint64_t sample, SamplerKind kind = SamplerKind::Sobol);
  // The same numbers as Sampler(seed, pixel, sample, kind) of `pixel`'s arguments, the per-pixel
  // hashes read from (and added to) `pixel`, which must outlive the sampler.
  Sampler(PixelSeeds& pixel, uint64_t sample);
  float uniform();  // [0, 1), 24 bits: never 1
  Vec2 uniform2();  // [0, 1)^2
  // Passes over the request uniform2() would make: every later request gets the numbers it gets
  // after uniform2() (a caller that knows it would discard them saves their hashing).
  void skip2();

  // The building blocks, exposed for tests (Burley 2020, Listings 1-3).
  static uint32_t sobol(uint32_t index, int dim);  // dim 0 (van der Corput) or 1, unscrambled
  static uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed);

 private:
  uint32_t next_u32_pcg();
  void seed_pcg(uint64_t seed, uint64_t pixel, uint64_t sample);
  // The seeds of the next request (advances the request counter).
  sampler_detail::DimensionSeeds dimension_seeds();
  static float to_unit(uint32_t x) { return float(x >> 8) * 0x1.0p-24f; }

  SamplerKind kind_;
  uint64_t key_ = 0;                   // hash of (seed, pixel)
  uint32_t index_reversed_ = 0;        // the sample index within the pixel, bits reversed
  uint32_t dimension_ = 0;             // requests made so far
  uint64_t state_ = 0, inc_ = 1;       // PCG32 (independent)
  PixelSeeds* pixel_seeds_ = nullptr;  // the pixel's kept seeds, if any
};

inline Sampler::Sampler(PixelSeeds& pixel, uint64_t sample) : kind_(pixel.kind_) {
  if (kind_ == SamplerKind::Independent) {
    seed_pcg(pixel.seed_, pixel.pixel_, sample);
    return;
  }
  key_ = pixel.key_;
  index_reversed_ = sampler_detail::reverse_bits(uint32_t(sample));
  pixel_seeds_ = &pixel;
}

inline uint32_t Sampler::next_u32_pcg() {
  const uint64_t old = state_;
  state_ = old * 6364136223846793005ull + inc_;
  const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = uint32_t(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

inline sampler_detail::DimensionSeeds Sampler::dimension_seeds() {
  const uint32_t d = dimension_++;
  if (pixel_seeds_ && d < PixelSeeds::kKept) {
    PixelSeeds& p = *pixel_seeds_;
    if (d < p.kept_) return p.seeds_[d];
    const sampler_detail::DimensionSeeds s = sampler_detail::dimension_seeds(key_, d);
    // Requests come in order (d = 0, 1, ...), so the first sample past the kept ones extends them.
    if (d == p.kept_) p.seeds_[p.kept_++] = s;
    return s;
  }
  return sampler_detail::dimension_seeds(key_, d);
}

inline float Sampler::uniform() {
  using namespace sampler_detail;
  if (kind_ == SamplerKind::Independent) return to_unit(next_u32_pcg());
  // Burley 2020, Listing 4 in one dimension: shuffle the index, then scramble its van der Corput
  // point, each with a seed of its own.
  // Written out with fewer bit reversals: the shuffled index's van der Corput point sobol(i, 0) =
  // reverse(i) is LK(reverse(index)), and its scramble reverse(LK(reverse(.))) = reverse(LK(i)).
  const sampler_detail::DimensionSeeds s = dimension_seeds();
  const uint32_t i = uint32_t(kUnreversedIndex(laine_karras_permutation(index_reversed_, s.shuffle)));  // shuffled index
  return to_unit(reverse_bits(laine_karras_permutation(i, s.x)));
}

inline void Sampler::skip2() {
  if (kind_ == SamplerKind::Independent) {
    next_u32_pcg();
    next_u32_pcg();
    return;
  }
  dimension_seeds();  // advances the request counter (and keeps the pixel's seeds in order)
}

inline Vec2 Sampler::uniform2() {
  using namespace sampler_detail;
  if (kind_ == SamplerKind::Independent) {
    const float a = to_unit(next_u32_pcg());
    return Vec2(a, to_unit(next_u32_pcg()));
  }
  // Listing 4 in two dimensions: one shuffled index, its two Sobol' coordinates scrambled apart.
  // (The first coordinate as in uniform(); the second through the table of sobol(., 1).)
  const sampler_detail::DimensionSeeds s = dimension_seeds();
  // The shuffled index i and reverse_bits(sobol(i, 1)) from one lookup on i's reversal.
  const uint64_t t = kUnreversedIndex(laine_karras_permutation(index_reversed_, s.shuffle));
  const uint32_t i = uint32_t(t), sobol1_reversed = uint32_t(t >> 32);
  // The second: nested_uniform_scramble(sobol(i, 1), s.y), its first reversal taken by the table.
  // The two last reversals in one.
  const ReversedPair r = reverse_bits_pair(laine_karras_permutation(i, s.x), laine_karras_permutation(sobol1_reversed, s.y));
  return Vec2(to_unit(r.a), to_unit(r.b));
}

}  // namespace aniso::render
