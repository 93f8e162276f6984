// aniso/core/kernel.h: what every model kernel answers beside f, pdf and sample (brdf/material.h), so
// that no caller keeps a switch over the models of its own. brdf/registry.h checks each row against
// ModelKernel below at compile time: a model without one of these methods does not compile.
//
//   regularize(alpha)    raises the model's roughness to at least alpha (the widths of its
//                        glossy lobes), for a renderer's glossy filter; a no-op where the model
//                        has no roughness to raise (Lambert, a measured table). The method is
//                        pbrt-v4's BxDF::Regularize (github.com/mmp/pbrt-v4 @ 5f7a6068,
//                        src/pbrt/base/bxdf.h:195, dispatched in src/pbrt/bxdfs.h:1159-1162):
//                        every BxDF has one, DiffuseBxDF's and MeasuredBxDF's empty
//                        (bxdfs.h:73, 1045), the microfacet ones regularize their distribution
//                        (bxdfs.h:200, 375). Its rule here is Cycles' bsdf_blur, max(alpha, blur)
//                        (src/render/integrator.cpp, blur_roughness), not pbrt-v4's doubling into
//                        [0.1, 0.3] (TrowbridgeReitzDistribution::Regularize,
//                        src/pbrt/util/scattering.h:200-205).
//   ggx_distribution()   whether the model's glossy reflection is a GGX (Trowbridge-Reitz)
//                        distribution and with which alphas, in the model's own frame: the one
//                        question of the exporters (src/export/ggx_source.cpp exact_ggx: a target's
//                        GGX is exact; src/rgl/rgl_source.cpp brdf_source: the tensor file's warps
//                        built from the exact D).
#pragma once

#include <concepts>

#include "aniso/core/sampling.h"

namespace aniso {

// How much of a model a GGX distribution describes (GgxDistributionT::part).
enum class GgxPart : int {
  None = 0,   // no GGX distribution, or one beside another glossy lobe it does not describe
  Lobe = 1,   // a GGX lobe beside broad terms that are not Lambertian (a metal's directional
              // diffuse lobe; the principled model's Burley diffuse and sheen)
  Whole = 2,  // the whole model: F(wi.h) D(h) G / (4 cos_i cos_o) plus at most a Lambertian kd / pi
};
enum class GgxFresnel : int { Schlick = 0, Conductor = 1 };
// The masking-shadowing term beside D: Heitz 2014's height-correlated Smith G2 (ggx.h) or the
// product of two Smith G1 (the principled model, Burley 2012).
enum class GgxMasking : int { HeightCorrelated = 0, Separable = 1 };

template <typename T> struct GgxDistributionT {
  GgxPart part = GgxPart::None;
  T alpha_x = T(0), alpha_y = T(0);  // D's alphas (Lobe and Whole)
  // The rest of the model, where part is Whole.
  GgxFresnel fresnel = GgxFresnel::Schlick;
  RGBT<T> f0{T(0)};            // Schlick: the reflectance at normal incidence
  RGBT<T> f90{T(1)};           // Schlick: the reflectance at grazing incidence (1 in Schlick 1994)
  RGBT<T> eta{T(0)}, k{T(0)};  // Conductor: the complex refractive index
  RGBT<T> kd{T(0)};            // the Lambertian term's albedo (f adds kd / pi); 0 without one
  GgxMasking masking = GgxMasking::HeightCorrelated;
};

// regularize's two rules. An alpha widens to at least alpha; a Phong-like exponent narrows to at
// most exponent_for_roughness(alpha). Written as std::max(a, alpha) and std::min(n, limit) are
// (the same comparisons, so the same values bit for bit), which kernels do not call under nvcc.
template <typename T> ANISO_INLINE void widen_alpha(T& a, T alpha) { a = a < alpha ? alpha : a; }
template <typename T> ANISO_INLINE void narrow_exponent(T& n, T limit) { n = limit < n ? limit : n; }

// A Phong-like exponent no sharper than a Beckmann lobe of width alpha: n = 2 / alpha^2 - 2
// (Walter et al. 2007, "Microfacet Models for Refraction", Sec. 5.2, the Phong-Beckmann
// correspondence alpha_p = 2 alpha_b^-2 - 2), at least 1.
template <typename T> ANISO_INLINE T exponent_for_roughness(T alpha) {
  const T n = T(2) / (alpha * alpha) - T(2);
  return T(1) < n ? n : T(1);
}

// A registry row's kernel Type<T>: the interface of material.h and the methods above.
template <typename M, typename T>
concept ModelKernel = requires(M& m, const M& c, const Vec3T<T>& w, T x, const Vec2T<T>& u) {
  { c.f(w, w) } -> std::same_as<RGBT<T>>;
  { c.pdf(w, w) } -> std::same_as<T>;
  { c.sample(w, x, u) } -> std::same_as<BSDFSampleT<T>>;
  { m.regularize(x) } -> std::same_as<void>;
  { c.ggx_distribution() } -> std::same_as<GgxDistributionT<T>>;
};

}  // namespace aniso
