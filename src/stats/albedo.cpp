#include "stats/albedo.h"

#include <cmath>

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

template <typename T>
AlbedoEstimate albedo_importance(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed) {
  Accumulator acc;
  for_each_stratified<T>(samples, seed, [&](T uc, const Vec2T<T>& u) {
    const BSDFSampleT<T> s = m.sample(wo, uc, u);
    acc.add(s.valid ? glm::dvec3(s.weight) : glm::dvec3(0.0));
  });
  return acc.result();
}

template <typename T>
AlbedoEstimate albedo_uniform(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed) {
  Accumulator acc;
  for_each_stratified<T>(samples, seed, [&](T, const Vec2T<T>& u) {
    // Uniform hemisphere: z = u.x, density 1 / (2 pi).
    const T z = T(1) - u.x;
    const T r = safe_sqrt(T(1) - z * z);
    const T phi = T(2) * kPi<T> * u.y;
    const Vec3T<T> wi(r * std::cos(phi), r * std::sin(phi), z);
    acc.add(glm::dvec3(m.f(wi, wo)) * double(z) * 2.0 * M_PI);
  });
  return acc.result();
}

template AlbedoEstimate albedo_importance<float>(const MaterialT<float>&, const Vec3T<float>&, int64_t, uint64_t);
template AlbedoEstimate albedo_importance<double>(const MaterialT<double>&, const Vec3T<double>&, int64_t, uint64_t);
template AlbedoEstimate albedo_uniform<float>(const MaterialT<float>&, const Vec3T<float>&, int64_t, uint64_t);
template AlbedoEstimate albedo_uniform<double>(const MaterialT<double>&, const Vec3T<double>&, int64_t, uint64_t);

}  // namespace aniso
