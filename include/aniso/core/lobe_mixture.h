// aniso/core/lobe_mixture.h: the one-model-two-lobes pattern shared by Phong, Ward,
// Ashikhmin-Shirley and GGX: a cosine-distributed diffuse term plus one specular lobe, chosen with
// probability p_spec (the model's estimate of the specular share; any value in [0, 1] is unbiased).
// The reported pdf is the mixture's, so weight = f cos / pdf stays exact (Veach 1997, Sec. 9.2).
#pragma once

#include "aniso/core/sampling.h"

namespace aniso {

// Lobe: pdf(wi, wo) and sample(wo, u) -> wi of the specular part alone.
template <typename T, typename Lobe>
ANISO_INLINE T pdf_diffuse_specular(T p_spec, const Lobe& lobe, const Vec3T<T>& wi, const Vec3T<T>& wo) {
  if (!same_upper_hemisphere(wi, wo)) return T(0);
  return (T(1) - p_spec) * cosine_hemisphere_pdf(wi.z) + p_spec * lobe.pdf(wi, wo);
}

// Model: f(wi, wo) and pdf(wi, wo) of the whole model.
template <typename T, typename Model, typename Lobe>
ANISO_INLINE BSDFSampleT<T> sample_diffuse_specular(const Model& model, const Lobe& lobe, T p_spec,
                                                    const Vec3T<T>& wo, T uc, const Vec2T<T>& u) {
  if (!(wo.z > T(0))) return {};
  const Vec3T<T> wi = uc < p_spec ? lobe.sample(wo, u) : sample_cosine_hemisphere(u);
  if (!(wi.z > T(0))) return {};
  return make_sample(wi, model.f(wi, wo), model.pdf(wi, wo));
}

// Probability of the specular lobe from the two lobes' weights; no weight at all samples diffuse.
template <typename T> ANISO_INLINE T specular_share(T diffuse_weight, T specular_weight) {
  const T total = diffuse_weight + specular_weight;
  return total > T(0) ? specular_weight / total : T(0);
}

}  // namespace aniso
