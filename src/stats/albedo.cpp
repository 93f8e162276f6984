#include "aniso/stats/albedo.h"

#include <cmath>
#include <vector>

#include "aniso/batch/batch.h"

#include "stats/rng.h"

namespace aniso {
namespace {

struct Accumulator {
  glm::dvec3 sum{0.0}, sum2{0.0};
  int64_t n = 0;
  void add(const glm::dvec3& x) {
    sum += x;
    sum2 += x * x;
    ++n;
  }
  AlbedoEstimate result() const {
    AlbedoEstimate e;
    if (n == 0) return e;
    e.mean = sum / double(n);
    const glm::dvec3 var = glm::max(sum2 / double(n) - e.mean * e.mean, glm::dvec3(0.0));
    e.std_error = glm::sqrt(var / double(n));
    return e;
  }
};

// Stratified 2D points: a k x k grid, jittered, where k = floor(sqrt(samples)); the rest plain random.
template <typename T, typename Fn> void for_each_stratified(int64_t samples, uint64_t seed, Fn&& fn) {
  Rng rng(seed);
  const auto k = static_cast<int64_t>(std::floor(std::sqrt(double(samples))));
  for (int64_t i = 0; i < samples; ++i) {
    Vec2T<T> u;
    if (i < k * k) {
      const double ux = (double(i % k) + rng.uniform()) / double(k);
      const double uy = (double(i / k) + rng.uniform()) / double(k);
      // Rounding in the division can reach 1 for the last stratum: keep u in [0, 1).
      u = Vec2T<T>(T(std::min(ux, 0x1.fffffep-1)), T(std::min(uy, 0x1.fffffep-1)));
    } else {
      u = Vec2T<T>(rng.uniform_as<T>(), rng.uniform_as<T>());
    }
    fn(rng.uniform_as<T>(), u);
  }
}

}  // namespace

// Both estimators draw their uniforms in the order for_each_stratified gives them, a chunk at a
// time, hand the chunk to the batch path (include/aniso/batch: all cores, SIMD for f) and add the
// results up in the same order: the estimate does not depend on the chunk size or the thread count.
constexpr size_t kChunk = 1 << 16;

template <typename T>
AlbedoEstimate albedo_importance(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed) {
  Accumulator acc;
  batch::DirectionArray<T> wos;
  std::vector<T> uc, u0, u1;
  batch::SampleArray<T> out;
  const auto flush = [&] {
    const size_t n = uc.size();
    wos.resize(n);
    for (size_t i = 0; i < n; ++i) wos.set(i, wo);
    out.resize(n);
    batch::sample(m, wos.view(), uc.data(), u0.data(), u1.data(), n, out.view());
    for (size_t i = 0; i < n; ++i)
      acc.add(out.valid[i] ? glm::dvec3(out.weight.r[i], out.weight.g[i], out.weight.b[i]) : glm::dvec3(0.0));
    uc.clear(), u0.clear(), u1.clear();
  };
  for_each_stratified<T>(samples, seed, [&](T c, const Vec2T<T>& u) {
    uc.push_back(c), u0.push_back(u.x), u1.push_back(u.y);
    if (uc.size() == kChunk) flush();
  });
  if (!uc.empty()) flush();
  return acc.result();
}

template <typename T> AlbedoEstimate albedo_uniform(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed) {
  Accumulator acc;
  batch::DirectionArray<T> wis, wos;
  batch::ColorArray<T> f;
  size_t n = 0;
  const auto flush = [&] {
    wos.resize(n);
    for (size_t i = 0; i < n; ++i) wos.set(i, wo);
    f.resize(n);
    batch::evaluate(m, wis.view(), wos.view(), n, f.view());
    for (size_t i = 0; i < n; ++i) acc.add(glm::dvec3(f.get(i)) * double(wis.z[i]) * 2.0 * M_PI);
    n = 0;
  };
  wis.resize(kChunk);
  for_each_stratified<T>(samples, seed, [&](T, const Vec2T<T>& u) {
    // Uniform hemisphere: z = u.x, density 1 / (2 pi).
    const T z = T(1) - u.x;
    const T r = safe_sqrt(T(1) - z * z);
    const T phi = T(2) * kPi<T> * u.y;
    wis.set(n++, Vec3T<T>(r * std::cos(phi), r * std::sin(phi), z));
    if (n == kChunk) {
      flush();
      wis.resize(kChunk);
    }
  });
  if (n > 0) {
    wis.resize(n);
    flush();
  }
  return acc.result();
}

template AlbedoEstimate albedo_importance<float>(const MaterialT<float>&, const Vec3T<float>&, int64_t, uint64_t);
template AlbedoEstimate albedo_importance<double>(const MaterialT<double>&, const Vec3T<double>&, int64_t, uint64_t);
template AlbedoEstimate albedo_uniform<float>(const MaterialT<float>&, const Vec3T<float>&, int64_t, uint64_t);
template AlbedoEstimate albedo_uniform<double>(const MaterialT<double>&, const Vec3T<double>&, int64_t, uint64_t);

}  // namespace aniso
