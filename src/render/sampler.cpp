// render/sampler.cpp: Owen-scrambled, index-shuffled Sobol' points and PCG32 (see sampler.h).
#include "aniso/render/sampler.h"

namespace aniso::render {
namespace {

uint64_t splitmix64(uint64_t& x) {
  uint64_t z = (x += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Burley 2020, Listing 2: a hash that, applied to the bit-reversed value, is a nested uniform
// (Owen) scramble: each output bit is flipped or not depending only on the bits above it. The
// constants are Burley's (after Laine & Karras 2011, "Stratified sampling for stochastic
// transparency").
uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
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
struct SobolDim1 {
  uint32_t v[32];
  uint32_t table[4][256];
  constexpr SobolDim1() : v{}, table{} {
    v[0] = 0x80000000u;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    for (int b = 0; b < 4; ++b)
      for (int x = 0; x < 256; ++x)
        for (int j = 0; j < 8; ++j)
          if (x & (1 << j)) table[b][x] ^= v[8 * b + j];
  }
  constexpr uint32_t operator()(uint32_t i) const {
    return table[0][i & 255u] ^ table[1][(i >> 8) & 255u] ^ table[2][(i >> 16) & 255u] ^ table[3][i >> 24];
  }
};
constexpr SobolDim1 kSobolDim1{};
static_assert(kSobolDim1.v[1] == 0xc0000000u && kSobolDim1.v[2] == 0xa0000000u && kSobolDim1.v[4] == 0x88000000u);
static_assert(kSobolDim1(3u) == (0x80000000u ^ 0xc0000000u));

}  // namespace

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

uint32_t Sampler::next_u32_pcg() {
  const uint64_t old = state_;
  state_ = old * 6364136223846793005ull + inc_;
  const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = uint32_t(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

Sampler::DimensionSeeds Sampler::dimension_seeds() {
  uint64_t x = key_ + uint64_t(dimension_++) * 0xd1b54a32d192ed03ull;
  const uint64_t a = splitmix64(x), b = splitmix64(x);
  return {uint32_t(a), uint32_t(a >> 32), uint32_t(b)};
}

float Sampler::uniform() {
  if (kind_ == SamplerKind::Independent) return to_unit(next_u32_pcg());
  // Burley 2020, Listing 4 in one dimension: shuffle the index, then scramble its van der Corput
  // point, each with a seed of its own.
  // Written out with fewer bit reversals: the shuffled index's van der Corput point sobol(i, 0) =
  // reverse(i) is LK(reverse(index)), and its scramble reverse(LK(reverse(.))) = reverse(LK(i)).
  const DimensionSeeds s = dimension_seeds();
  const uint32_t i = reverse_bits(laine_karras_permutation(index_reversed_, s.shuffle));  // shuffled index
  return to_unit(reverse_bits(laine_karras_permutation(i, s.x)));
}

Vec2 Sampler::uniform2() {
  if (kind_ == SamplerKind::Independent) {
    const float a = to_unit(next_u32_pcg());
    return Vec2(a, to_unit(next_u32_pcg()));
  }
  // Listing 4 in two dimensions: one shuffled index, its two Sobol' coordinates scrambled apart.
  // (The first coordinate as in uniform(); the second through the table of sobol(., 1).)
  const DimensionSeeds s = dimension_seeds();
  const uint32_t i = reverse_bits(laine_karras_permutation(index_reversed_, s.shuffle));
  return Vec2(to_unit(reverse_bits(laine_karras_permutation(i, s.x))), to_unit(nested_uniform_scramble(kSobolDim1(i), s.y)));
}

}  // namespace aniso::render
