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
//
// Orientation (the anisotropic models' `rotation_deg`, docs/conventions.md): the model's tangent
// is the frame's tangent turned about the normal by a, t' = cos a t + sin a b, exactly as a
// scene's tangent.angle_deg turns it (aniso/tangent/fields.h), and composed with it. MaterialT
// applies it around every model: directions enter the model in the turned frame and sampled
// directions leave it turned back, so no kernel (C++, SIMD twin or GLSL) carries its own angle.
#pragma once

#include "aniso/brdf/registry.h"

namespace aniso {

// Every model of the registry (aniso/brdf/registry.h); Measured's tables are host-owned arrays
// the kernel only points to (lifetime: include/aniso/measured/measured.h).
// The turn of the frame by a about the normal: (cos a, sin a). Directions of the frame have the
// coordinates x' = c x + s y, y' = -s x + c y in the turned one (to_model), and back (from_model).
// The identity (s = 0, the default) returns the direction unchanged, bit for bit.
template <typename T> struct FrameRotationT {
  T c = T(1), s = T(0);
  ANISO_HD bool identity() const { return s == T(0) && c == T(1); }
  ANISO_HD Vec3T<T> to_model(const Vec3T<T>& w) const {
    if (identity()) return w;
    return Vec3T<T>(c * w.x + s * w.y, c * w.y - s * w.x, w.z);
  }
  ANISO_HD Vec3T<T> from_model(const Vec3T<T>& w) const {
    if (identity()) return w;
    return Vec3T<T>(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
  }
};

// The turn by `degrees` (a material's rotation_deg): cos and sin of the angle in radians, in T's
// arithmetic (a ceres::Jet for the fitter's derivatives); 0 gives the identity exactly.
template <typename T> ANISO_HD FrameRotationT<T> frame_rotation_deg(const T& degrees) {
  using std::cos;
  using std::sin;
  const T a = degrees * T(0.017453292519943295769);  // pi / 180
  return FrameRotationT<T>{cos(a), sin(a)};
}

template <typename T> struct MaterialT {
  ModelKind kind = ModelKind::Lambert;
  FrameRotationT<T> rotation;  // rotation_deg (identity for the isotropic models)
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
  template <typename Fn> ANISO_HD auto visit(Fn&& fn) const { return visit_of(*this, fn); }
  // visit for a change of the active model (regularize).
  template <typename Fn> ANISO_HD auto visit_mutable(Fn&& fn) { return visit_of(*this, fn); }

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> i = rotation.to_model(wi), o = rotation.to_model(wo);
    return visit([&](const auto& m) { return m.f(i, o); });
  }
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    const Vec3T<T> i = rotation.to_model(wi), o = rotation.to_model(wo);
    return visit([&](const auto& m) { return m.pdf(i, o); });
  }
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    const Vec3T<T> o = rotation.to_model(wo);
    BSDFSampleT<T> s = visit([&](const auto& m) { return m.sample(o, uc, u); });
    s.wi = rotation.from_model(s.wi);
    return s;
  }

  // The model's roughness raised to at least alpha (core/kernel.h, each kernel's regularize); no
  // change for alpha <= 0 or NaN. The turn is about the normal, so it commutes with the widening.
  ANISO_HD void regularize(T alpha) {
    if (!(alpha > T(0))) return;
    visit_mutable([&](auto& m) { m.regularize(alpha); });
  }
  // Whether the model is a GGX and with which alphas, in the model's own frame (rotation turns it
  // in the shading frame; core/kernel.h).
  ANISO_HD GgxDistributionT<T> ggx_distribution() const {
    return visit([](const auto& m) { return m.ggx_distribution(); });
  }

 private:
  // The switch of visit and visit_mutable, for a const or a non-const material.
  template <typename Self, typename Fn> ANISO_HD static auto visit_of(Self& self, Fn& fn) {
    switch (self.kind) {
#define ANISO_X(Tag, Type, member, name, batch, glsl) \
  case ModelKind::Tag: return fn(self.member);
      ANISO_MODELS(ANISO_X)
#undef ANISO_X
    }
    return fn(self.lambert);
  }
};

// Calls fn(ModelType<Type<T>>{}) for the kernel type of kind k: dispatch on a kind before a model
// exists (the builders of src/io/materials.cpp, the GLSL builders). Generated like visit.
template <typename M> struct ModelType { using type = M; };
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
