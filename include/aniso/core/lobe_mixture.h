// aniso/core/lobe_mixture.h: the one-model-two-lobes pattern shared by Phong, Ward,
// Ashikhmin-Shirley and GGX: a cosine-distributed diffuse term plus one specular lobe, chosen with
// probability p_spec (the model's estimate of the specular share; any value in [0, 1] is unbiased).
// The reported pdf is the mixture's, so weight = f cos / pdf stays exact (Veach 1997, Sec. 9.2).
#pragma once

#include "aniso/core/kernel.h"
#include "aniso/core/sampling.h"

namespace aniso {

// A lobe's eval(wi, wo) and pdf(wi, wo) at one pair, bit for bit: through its eval_pdf where it has
// one (a lobe whose value and density share terms: Ward's Gaussian, GGX's D and Lambda(wo)), else
// the two calls.
template <typename T, typename Lobe>
ANISO_INLINE T lobe_eval_pdf(const Lobe& lobe, const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf) {
  if constexpr (requires { lobe.eval_pdf(wi, wo, pdf); }) {
    return lobe.eval_pdf(wi, wo, pdf);
  } else {
    *pdf = lobe.pdf(wi, wo);
    return lobe.eval(wi, wo);
  }
}

// A model's f(wi, wo) and pdf(wi, wo) at one pair, bit for bit: through its f_pdf where it has one,
// else the two calls. A next-event estimate needs both of every light sample, and a BRDF sample
// both of its direction.
template <typename T, typename Model>
ANISO_INLINE RGBT<T> model_f_pdf(const Model& model, const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf) {
  if constexpr (requires { model.f_pdf(wi, wo, pdf); }) {
    return model.f_pdf(wi, wo, pdf);
  } else {
    *pdf = model.pdf(wi, wo);
    return model.f(wi, wo);
  }
}

// pdf_diffuse_specular's mixture of the two densities, the lobe's given.
template <typename T> ANISO_INLINE T mix_diffuse_specular_pdf(T p_spec, T lobe_pdf, const Vec3T<T>& wi) {
  return (T(1) - p_spec) * cosine_hemisphere_pdf(wi.z) + p_spec * lobe_pdf;
}

// Lobe: pdf(wi, wo) and sample(wo, u) -> wi of the specular part alone.
template <typename T, typename Lobe>
ANISO_INLINE T pdf_diffuse_specular(T p_spec, const Lobe& lobe, const Vec3T<T>& wi, const Vec3T<T>& wo) {
  if (!same_upper_hemisphere(wi, wo)) return T(0);
  return mix_diffuse_specular_pdf(p_spec, lobe.pdf(wi, wo), wi);
}

// Model: f(wi, wo) and pdf(wi, wo) of the whole model.
template <typename T, typename Model, typename Lobe>
ANISO_INLINE BSDFSampleT<T> sample_diffuse_specular(const Model& model, const Lobe& lobe, T p_spec, const Vec3T<T>& wo, T uc,
                                                    const Vec2T<T>& u) {
  if (!above_horizon(wo)) return {};
  const Vec3T<T> wi = uc < p_spec ? lobe.sample(wo, u) : sample_cosine_hemisphere(u);
  if (!above_horizon(wi)) return {};
  T pdf;
  const RGBT<T> f = model_f_pdf(model, wi, wo, &pdf);
  return make_sample(wi, f, pdf);
}

// Probability of the specular lobe from the two lobes' weights; no weight at all samples diffuse.
template <typename T> ANISO_INLINE T specular_share(T diffuse_weight, T specular_weight) {
  const T total = diffuse_weight + specular_weight;
  return total > T(0) ? specular_weight / total : T(0);
}

// f = kd / pi + ks lobe(wi, wo): the shape of Phong and Ward, which differ only in their lobe.
// Lobe choice by average colour (Walter 2005, Sec. 4: "choose between the diffuse and specular
// terms with probability proportional to their weights").
template <typename T, typename Lobe> struct LambertPlusLobeT {
  RGBT<T> kd{T(0)};
  RGBT<T> ks{T(0.5)};
  Lobe lobe;

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    return kd * kInvPi<T> + ks * lobe.eval(wi, wo);
  }
  ANISO_HD T specular_probability(const Vec3T<T>& /*wo*/) const { return specular_share(average(kd), average(ks)); }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return pdf_diffuse_specular(specular_probability(wo), lobe, wi, wo);
  }
  // f() and pdf() together (model_f_pdf), bit for bit.
  ANISO_HD RGBT<T> f_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf_out) const {
    if (!same_upper_hemisphere(wi, wo)) {
      *pdf_out = T(0);
      return RGBT<T>(T(0));
    }
    T lobe_pdf;
    const T e = lobe_eval_pdf(lobe, wi, wo, &lobe_pdf);
    *pdf_out = mix_diffuse_specular_pdf(specular_probability(wo), lobe_pdf, wi);
    return kd * kInvPi<T> + ks * e;
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    return sample_diffuse_specular(*this, lobe, specular_probability(wo), wo, uc, u);
  }
  // kernel.h: the lobe roughens (the diffuse term has no roughness); the lobes of this shape,
  // Ward's and Phong's, are no GGX.
  ANISO_HD void regularize(T alpha) { lobe.regularize(alpha); }
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }
};

}  // namespace aniso
