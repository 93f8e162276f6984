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

#include "aniso/brdf/registry.h"

namespace aniso {

// Every model of the registry (aniso/brdf/registry.h); Measured's tables are host-owned arrays
// the kernel only points to (lifetime: src/measured/measured.h).
template <typename T> struct MaterialT {
  ModelKind kind = ModelKind::Lambert;
  union {
#define ANISO_X(Tag, Type, member, name, batch, glsl) Type<T> member;
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
  };

  ANISO_HD MaterialT() : lambert() {}
#define ANISO_X(Tag, Type, member, name, batch, glsl) \
  ANISO_HD MaterialT(const Type<T>& m) : kind(ModelKind::Tag), member(m) {}
  ANISO_MODELS(ANISO_X)
#undef ANISO_X

  // Calls fn(model) with the active alternative (a tag switch the compiler turns into a jump
  // table). The cases are generated from the registry, one per row, and there is no default; a
  // kind outside the enumeration (corrupted memory only) gets Lambert's member after the switch.
  template <typename Fn> ANISO_HD auto visit(Fn&& fn) const {
    switch (kind) {
#define ANISO_X(Tag, Type, member, name, batch, glsl) \
  case ModelKind::Tag: return fn(member);
      ANISO_MODELS(ANISO_X)
#undef ANISO_X
    }
    return fn(lambert);
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

// Calls fn(ModelType<Type<T>>{}) for the kernel type of kind k: dispatch on a kind before a model
// exists (the builders of src/io/materials.cpp, the GLSL builders). Generated like visit.
template <typename M> struct ModelType {
  using type = M;
};
template <typename T, typename Fn> auto visit_kind(ModelKind k, Fn&& fn) {
  switch (k) {
#define ANISO_X(Tag, Type, member, name, batch, glsl) \
  case ModelKind::Tag: return fn(ModelType<Type<T>>{});
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
  }
  return fn(ModelType<LambertT<T>>{});
}

using Material = MaterialT<float>;
using MaterialD = MaterialT<double>;

}  // namespace aniso
