// aniso/brdf/material.h: every model behind one value type, dispatched by a tag (no virtual calls,
// no allocation: the same code runs in the renderer's inner loop and, under nvcc, on the GPU).
//
// Interface of every model (docs/conventions.md): directions in the local shading frame
// (z = normal, x = tangent), wi towards the light, wo towards the viewer, both unit and pointing
// away from the surface.
//   f(wi, wo)            the BRDF without the cosine; 0 unless both are above the horizon
//   pdf(wi, wo)          the solid-angle density of sample() producing wi for this wo
//   sample(wo, uc, u)    {wi, weight = f cos / pdf, pdf} or "no sample"; uc picks the lobe,
//                        u (2D) the direction; all uniform in [0, 1)
#pragma once

#include "aniso/brdf/ashikhmin_shirley.h"
#include "aniso/brdf/ggx.h"
#include "aniso/brdf/lafortune.h"
#include "aniso/brdf/lambert.h"
#include "aniso/brdf/measured.h"
#include "aniso/brdf/metal.h"
#include "aniso/brdf/phong.h"
#include "aniso/brdf/ward.h"

namespace aniso {

// Measured: a tabulated BRDF (MERL layout, aniso/brdf/measured.h); its tables are host-owned
// arrays the kernel only points to (lifetime: src/measured/measured.h).
enum class ModelKind : int { Lambert = 0, Phong, Ward, AshikhminShirley, Lafortune, GGX, Metal, Measured };

template <typename T> struct MaterialT {
  ModelKind kind = ModelKind::Lambert;
  union {
    LambertT<T> lambert;
    PhongT<T> phong;
    WardT<T> ward;
    AshikhminShirleyT<T> ashikhmin_shirley;
    LafortuneT<T> lafortune;
    GGXT<T> ggx;
    MetalT<T> metal;
    MeasuredT<T> measured;
  };

  ANISO_HD MaterialT() : lambert() {}
  ANISO_HD MaterialT(const LambertT<T>& m) : kind(ModelKind::Lambert), lambert(m) {}
  ANISO_HD MaterialT(const PhongT<T>& m) : kind(ModelKind::Phong), phong(m) {}
  ANISO_HD MaterialT(const WardT<T>& m) : kind(ModelKind::Ward), ward(m) {}
  ANISO_HD MaterialT(const AshikhminShirleyT<T>& m) : kind(ModelKind::AshikhminShirley), ashikhmin_shirley(m) {}
  ANISO_HD MaterialT(const LafortuneT<T>& m) : kind(ModelKind::Lafortune), lafortune(m) {}
  ANISO_HD MaterialT(const GGXT<T>& m) : kind(ModelKind::GGX), ggx(m) {}
  ANISO_HD MaterialT(const MetalT<T>& m) : kind(ModelKind::Metal), metal(m) {}
  ANISO_HD MaterialT(const MeasuredT<T>& m) : kind(ModelKind::Measured), measured(m) {}

  // Calls fn(model) with the active alternative (a tag switch the compiler turns into a jump table).
  template <typename Fn> ANISO_HD auto visit(Fn&& fn) const {
    switch (kind) {
      case ModelKind::Phong: return fn(phong);
      case ModelKind::Ward: return fn(ward);
      case ModelKind::AshikhminShirley: return fn(ashikhmin_shirley);
      case ModelKind::Lafortune: return fn(lafortune);
      case ModelKind::GGX: return fn(ggx);
      case ModelKind::Metal: return fn(metal);
      case ModelKind::Measured: return fn(measured);
      default: return fn(lambert);
    }
  }

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return visit([&](const auto& m) { return m.f(wi, wo); });
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    return visit([&](const auto& m) { return m.pdf(wi, wo); });
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    return visit([&](const auto& m) { return m.sample(wo, uc, u); });
  }
};

using Material = MaterialT<float>;
using MaterialD = MaterialT<double>;

}  // namespace aniso
