// aniso/stats/albedo.h: directional albedo rho(wo) = integral of f(wi, wo) cos(theta_i) d(wi), two ways:
// by the model's own importance sampling (low variance), and by uniform hemisphere sampling
// (independent of the sampler, for cross-checks).
#pragma once

#include <cstdint>

#include "aniso/brdf/material.h"

namespace aniso {

struct AlbedoEstimate {
  glm::dvec3 mean{0.0};
  glm::dvec3 std_error{0.0};  // standard error of the mean, per channel
};

// Importance-sampled: mean of sample().weight over `samples` stratified draws (invalid samples
// count as 0).
template <typename T> AlbedoEstimate albedo_importance(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed);

// Uniform hemisphere: mean of f(wi, wo) cos(theta_i) 2 pi.
template <typename T> AlbedoEstimate albedo_uniform(const MaterialT<T>& m, const Vec3T<T>& wo, int64_t samples, uint64_t seed);

}  // namespace aniso
