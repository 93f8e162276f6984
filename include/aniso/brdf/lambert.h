// aniso/brdf/lambert.h: the ideal diffuse reflector, f = kd / pi (Lambert 1760).
#pragma once

#include "aniso/core/kernel.h"
#include "aniso/core/sampling.h"

namespace aniso {

template <typename T> ANISO_INLINE T Fd_Lambert() { return kInvPi<T>; }

template <typename T> struct LambertT {
  RGBT<T> kd{T(0.5)};

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    return kd * Fd_Lambert<T>();
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    return cosine_hemisphere_pdf(wi.z);
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T /*uc*/, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    const Vec3T<T> wi = sample_cosine_hemisphere(u);
    return make_sample(wi, f(wi, wo), pdf(wi, wo));
  }
  // core/kernel.h: rough already (pbrt-v4's DiffuseBxDF::Regularize is empty, bxdfs.h:73); no GGX.
  ANISO_HD void regularize(T /*alpha*/) {}
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }
};

}  // namespace aniso
