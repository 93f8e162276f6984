// aniso/brdf/metal.h: a conductor. Light cannot penetrate a metal beyond a skin of tens of
// nanometres (penetration depth lambda / (4 pi k)), so there is no subsurface (Lambertian) term.
// The reflection has two parts (the lecture, "Metals"; Cook & Torrance 1982):
//   f = (1 - a) F_conductor(wi.h; eta, k) specular(wi, wo)  +  directional_diffuse(wi, wo)
// - specular: an anisotropic Ward, Ashikhmin-Shirley or GGX lobe without colour or Fresnel;
// - directional diffuse: an optional broad Lafortune lobe coloured by the metal, with Ngan et
//   al. 2005's normalisation folded in by the host (scale = a F0 (n + 2) / (2 pi), C / max|C|),
//   a its albedo; the (1 - a) on the specular lobe keeps the sum's albedo <= 1.
// docs/models/metal.md; the RGB eta, k come from measured spectra (docs/metals.md).
#pragma once

#include <type_traits>

#include "aniso/brdf/ashikhmin_shirley.h"
#include "aniso/brdf/fresnel.h"
#include "aniso/brdf/ggx.h"
#include "aniso/brdf/lafortune.h"
#include "aniso/brdf/ward.h"

namespace aniso {

enum class SpecularLobeKind : int { Ward = 0, AshikhminShirley = 1, GGX = 2 };

template <typename T> struct MetalT {
  RGBT<T> eta{T(0.2)};
  RGBT<T> k{T(3)};
  SpecularLobeKind lobe_kind = SpecularLobeKind::GGX;
  WardLobeT<T> ward;
  AshikhminShirleyLobeT<T> ashikhmin_shirley;
  GGXLobeT<T> ggx;
  // (1 - directional-diffuse albedo): the energy the directional lobe takes from the specular one.
  RGBT<T> specular_weight{T(1)};
  bool has_directional_diffuse = false;
  LafortuneLobeT<T> directional_diffuse;

  ANISO_HD T specular(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    switch (lobe_kind) {
      case SpecularLobeKind::Ward: return ward.eval(wi, wo);
      case SpecularLobeKind::AshikhminShirley: return ashikhmin_shirley.eval(wi, wo);
      default: return ggx.eval(wi, wo);
    }
  }
  ANISO_HD T specular_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    switch (lobe_kind) {
      case SpecularLobeKind::Ward: return ward.pdf(wi, wo);
      case SpecularLobeKind::AshikhminShirley: return ashikhmin_shirley.pdf(wi, wo);
      default: return ggx.pdf(wi, wo);
    }
  }
  // specular() and specular_pdf() together, bit for bit (lobe_eval_pdf).
  ANISO_HD T specular_eval_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf) const {
    switch (lobe_kind) {
      case SpecularLobeKind::Ward: return lobe_eval_pdf(ward, wi, wo, pdf);
      case SpecularLobeKind::AshikhminShirley: return lobe_eval_pdf(ashikhmin_shirley, wi, wo, pdf);
      default: return lobe_eval_pdf(ggx, wi, wo, pdf);
    }
  }
  ANISO_HD Vec3T<T> specular_sample(const Vec3T<T>& wo, const Vec2T<T>& u) const {
    switch (lobe_kind) {
      case SpecularLobeKind::Ward: return ward.sample(wo, u);
      case SpecularLobeKind::AshikhminShirley: return ashikhmin_shirley.sample(wo, u);
      default: return ggx.sample(wo, u);
    }
  }

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    return f_of_specular(wi, wo, specular(wi, wo), has_directional_diffuse && directional_diffuse.channels_share_shape());
  }
  // Lobe choice: the specular lobe weighs its Fresnel reflectance seen from wo, the directional
  // diffuse lobe its channel weights (an albedo bound, lafortune.h). They depend on wo alone and
  // cost three Fresnel terms and three pows: computed once and shared by the lobe choice of sample()
  // and its pdf, and by a caller's pdfs at one wo (as LafortuneT::SamplingWeights).
  struct SamplingWeights {
    T specular_probability = T(1);
    T channel[3] = {T(0), T(0), T(0)};  // the directional-diffuse channels' weights (0 without it)
    T channel_total = T(0);             // their sum, in channel order
    bool one_shape = false;             // directional_diffuse.channels_share_shape() (false without it)
  };
  ANISO_HD SamplingWeights sampling_weights(const Vec3T<T>& wo) const {
    SamplingWeights w;
    const T s = average(specular_weight * F_Conductor(wo.z, eta, k));
    if (has_directional_diffuse) {
      w.one_shape = directional_diffuse.channels_share_shape();
      directional_diffuse.channel_weights(wo, w.channel, w.one_shape);
      for (int c = 0; c < 3; ++c) w.channel_total += w.channel[c];
    }
    w.specular_probability = s + w.channel_total > T(0) ? s / (s + w.channel_total) : T(1);
    return w;
  }
  ANISO_HD T specular_probability(const Vec3T<T>& wo) const { return sampling_weights(wo).specular_probability; }
  ANISO_HD T directional_diffuse_pdf(const SamplingWeights& ws, const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    // Channels of one shape have one channel pdf (a pow): computed once, at the first channel that
    // needs it, and summed with the same weights in the same order.
    const bool one_shape = ws.one_shape;
    T wsum = T(0), p = T(0), shared_pdf = T(-1);
    for (int c = 0; c < 3; ++c) {
      const T w = ws.channel[c];
      if (w > T(0)) {
        wsum += w;
        T pc;
        if (one_shape) {
          if (shared_pdf < T(0)) shared_pdf = directional_diffuse.channel_pdf(wi, wo, c);
          pc = shared_pdf;
        } else {
          pc = directional_diffuse.channel_pdf(wi, wo, c);
        }
        p += w * pc;
      }
    }
    return wsum > T(0) ? p / wsum : T(0);
  }
  ANISO_HD T pdf(const SamplingWeights& ws, const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    const T ps = ws.specular_probability;
    T p = ps * specular_pdf(wi, wo);
    if (ps < T(1)) p += (T(1) - ps) * directional_diffuse_pdf(ws, wi, wo);
    return p;
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    return pdf(sampling_weights(wo), wi, wo);
  }
  // f() and pdf(ws, .) together, bit for bit: the specular lobe's value and density share terms
  // (lobe_eval_pdf).
  ANISO_HD RGBT<T> f_pdf(const SamplingWeights& ws, const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf_out) const {
    if (!same_upper_hemisphere(wi, wo)) {
      *pdf_out = T(0);
      return RGBT<T>(T(0));
    }
    const T ps = ws.specular_probability;
    T spec_pdf;
    const T spec = specular_eval_pdf(wi, wo, &spec_pdf);
    T p = ps * spec_pdf;
    if (ps < T(1)) p += (T(1) - ps) * directional_diffuse_pdf(ws, wi, wo);
    *pdf_out = p;
    return f_of_specular(wi, wo, spec, ws.one_shape);
  }
  ANISO_HD RGBT<T> f_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo, T* pdf_out) const {
    if (!same_upper_hemisphere(wi, wo)) {
      *pdf_out = T(0);
      return RGBT<T>(T(0));
    }
    return f_pdf(sampling_weights(wo), wi, wo, pdf_out);
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    return sample(sampling_weights(wo), wo, uc, u);
  }
  // sample() with the weights of this wo already computed (ws == sampling_weights(wo)).
  ANISO_HD BSDFSampleT<T> sample(const SamplingWeights& ws, const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    const T ps = ws.specular_probability;
    Vec3T<T> wi;
    if (uc < ps) {
      wi = specular_sample(wo, u);
    } else {
      // Pick the channel of the directional-diffuse lobe by weight, reusing uc rescaled to [0, 1).
      const T wsum = ws.channel_total;
      if (!(wsum > T(0))) return {};
      T target = (uc - ps) / (T(1) - ps) * wsum;
      int chosen = 2;
      for (int c = 0; c < 3; ++c) {
        if (ws.channel[c] > T(0) && target < ws.channel[c]) {
          chosen = c;
          break;
        }
        target -= ws.channel[c];
      }
      while (chosen > 0 && !(ws.channel[chosen] > T(0))) --chosen;
      const Vec3T<T> a = directional_diffuse.axis(wo, chosen);
      wi = sample_cosine_power(a / std::sqrt(glm::dot(a, a)), directional_diffuse.n[chosen], u);
    }
    if (!above_horizon(wi)) return {};
    T pdf_wi;
    const RGBT<T> f_wi = f_pdf(ws, wi, wo, &pdf_wi);
    return make_sample(wi, f_wi, pdf_wi);
  }

  // core/kernel.h: the specular lobes roughen (all three, whichever lobe_kind picks); the
  // directional diffuse lobe, broad already, is a Lafortune lobe and stays as it is (lafortune.h).
  ANISO_HD void regularize(T alpha) {
    ward.regularize(alpha);
    ashikhmin_shirley.regularize(alpha);
    ggx.regularize(alpha);
  }
  // A GGX lobe is the whole model without the directional diffuse lobe, one lobe beside it.
  ANISO_HD GgxDistributionT<T> ggx_distribution() const {
    GgxDistributionT<T> d;
    if (lobe_kind != SpecularLobeKind::GGX) return d;
    d.part = has_directional_diffuse ? GgxPart::Lobe : GgxPart::Whole;
    d.alpha_x = ggx.alpha_x, d.alpha_y = ggx.alpha_y;
    d.fresnel = GgxFresnel::Conductor;
    d.eta = eta, d.k = k;
    return d;
  }

 private:
  // f from the specular lobe's value spec = specular(wi, wo), same upper hemisphere; one_shape is
  // the directional diffuse lobe's channels_share_shape().
  ANISO_HD RGBT<T> f_of_specular(const Vec3T<T>& wi, const Vec3T<T>& wo, T spec, bool one_shape) const {
    RGBT<T> out(T(0));
    // A specular value of +0 (Ward's exponential rounds to 0 away from the highlight: Ward_Exp)
    // makes the Fresnel-weighted term +0 whatever F is (F and the weight are finite and >= 0), so
    // F and its half vector are skipped there: the same sum bit for bit. Not for a derivative
    // type (the fitter's ceres::Jet), whose zero value may carry a non-zero derivative.
    if (!std::is_floating_point_v<T> || !(spec == T(0))) {
      const Vec3T<T> h = glm::normalize(wi + wo);
      out = specular_weight * F_Conductor(glm::dot(wi, h), eta, k) * spec;
    }
    if (has_directional_diffuse) out += directional_diffuse.eval(wi, wo, one_shape);
    return out;
  }
};

}  // namespace aniso
