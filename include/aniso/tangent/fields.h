// aniso/tangent/fields.h: where the tangent comes from. Procedural tangent fields and tangent-map
// decoding, as plain functions of the surface point, shared by the CPU renderer, (under nvcc) CUDA
// and (through the GLSL twin, later) the shaders.
//
// The lecture (VGP352 week 5, last slide): the tangent frame can be "rotated by an angle", read
// from "a tangent map", or computed by "procedural tangents". Each field here returns an
// approximate world-space tangent; FrameT::from_normal_tangent() makes it orthogonal to the
// shading normal (Gram-Schmidt) and `angle` (the scene's angle_deg) rotates the result about n.
// A field that has no direction at a point (the centre of a radial field, a projected direction
// parallel to n) returns a zero vector and the frame falls back to FrameT::from_normal(): the
// anisotropy there is arbitrary, as it is on a real lathe-turned disc's centre.
//
// Anisotropic reflection is symmetric under t -> -t for every model here (f depends on h.x^2,
// h.y^2 or on C_x, C_y applied to both directions alike), so tangents are directions modulo pi:
// the tangent-map encodings below use that.
#pragma once

#include <glm/gtc/noise.hpp>

#include "aniso/core/frame.h"

namespace aniso {

enum class TangentFieldKind : int {
  Natural = 0,  // dp/du of the shape's parametrisation (docs/scenes.md, per shape)
  Projected,    // a fixed world direction projected onto the surface (a plate brushed along one axis)
  Radial,       // away from an axis through `center` (spokes)
  Concentric,   // around that axis (lathe-turned: circles about the axis)
  Swirl,        // concentric turned towards radial by `swirl` radians (a spiral)
  Noise,        // the natural tangent rotated about n by a smooth noise angle
};

// The surface point a field is evaluated at (world space; n unit).
template <typename T> struct SurfacePointT {
  Vec3T<T> p{T(0)};
  Vec3T<T> n{T(0), T(0), T(1)};
  Vec3T<T> dpdu{T(1), T(0), T(0)};  // the natural tangent (any length)
  Vec2T<T> uv{T(0)};
};

template <typename T> struct TangentFieldT {
  TangentFieldKind kind = TangentFieldKind::Natural;
  Vec3T<T> direction{T(1), T(0), T(0)};  // Projected: the world direction
  Vec3T<T> center{T(0)};                 // Radial, Concentric, Swirl: a point on the axis
  Vec3T<T> axis{T(0), T(1), T(0)};       // ... and its unit direction
  T swirl = T(0.7853981633974483);       // Swirl: angle from concentric towards radial (pi/4)
  T scale = T(1);                        // Noise: spatial frequency (1 / world units)
  T strength = T(0.5);                   // Noise: largest rotation, in radians
  T angle = T(0);                        // rotation about n applied last (angle_deg), radians
};

// Radial direction at p: p - c with its component along the axis removed.
template <typename T> ANISO_INLINE Vec3T<T> Tangent_Radial(const Vec3T<T>& p, const Vec3T<T>& center, const Vec3T<T>& axis) {
  const Vec3T<T> d = p - center;
  return d - glm::dot(d, axis) * axis;
}

// Concentric direction at p: axis x (p - c), tangent to the circle through p about the axis.
template <typename T> ANISO_INLINE Vec3T<T> Tangent_Concentric(const Vec3T<T>& p, const Vec3T<T>& center, const Vec3T<T>& axis) {
  return glm::cross(axis, p - center);
}

// Smooth noise angle in [-strength, strength]: 3D simplex noise (Perlin 2001; glm::simplex, the
// same function GLSL implementations of simplex noise compute) at p * scale.
template <typename T> ANISO_INLINE T Tangent_NoiseAngle(const Vec3T<T>& p, T scale, T strength) {
  return strength * T(glm::simplex(glm::vec3(p * scale)));
}

// The unnormalised tangent a field gives at sp (before Gram-Schmidt and before `angle`).
template <typename T> ANISO_INLINE Vec3T<T> tangent_field_direction(const TangentFieldT<T>& f, const SurfacePointT<T>& sp) {
  using std::cos;
  using std::sin;
  switch (f.kind) {
    case TangentFieldKind::Projected: return f.direction;
    case TangentFieldKind::Radial: return Tangent_Radial(sp.p, f.center, f.axis);
    case TangentFieldKind::Concentric: return Tangent_Concentric(sp.p, f.center, f.axis);
    case TangentFieldKind::Swirl: {
      const Vec3T<T> c = Tangent_Concentric(sp.p, f.center, f.axis);
      const Vec3T<T> r = Tangent_Radial(sp.p, f.center, f.axis);
      // |c| == |r| (both are the distance to the axis times a unit vector), so the blend is a rotation.
      return cos(f.swirl) * c + sin(f.swirl) * r;
    }
    default: return sp.dpdu;  // Natural; Noise rotates it in tangent_frame()
  }
}

// The shading frame a field gives at sp: Gram-Schmidt against n, then the noise rotation (Noise)
// and the field's `angle`, both about n.
template <typename T> ANISO_INLINE FrameT<T> tangent_frame(const TangentFieldT<T>& f, const SurfacePointT<T>& sp) {
  FrameT<T> frame = FrameT<T>::from_normal_tangent(sp.n, tangent_field_direction(f, sp));
  T psi = f.angle;
  if (f.kind == TangentFieldKind::Noise) psi += Tangent_NoiseAngle(sp.p, f.scale, f.strength);
  return psi != T(0) ? frame.rotated(psi) : frame;
}

// Tangent maps (docs/scenes.md). A texel gives a direction in the surface's (dp/du, dp/dv) basis,
// as (a, b) meaning a * dpdu_unit + b * dpdv_unit; both encodings read linear texel values in [0, 1]:
//   "angle": red channel v -> angle pi * v from dp/du towards dp/dv (tangents are directions modulo
//            pi, so [0, 1] covers every orientation once and 0 and 1 are the same orientation);
//   "xy":    red, green -> (2 r - 1, 2 g - 1), as normal maps store x and y.
template <typename T> ANISO_INLINE Vec2T<T> TangentMap_DecodeAngle(T v) {
  using std::cos;
  using std::sin;
  return Vec2T<T>(cos(kPi<T> * v), sin(kPi<T> * v));
}
template <typename T> ANISO_INLINE Vec2T<T> TangentMap_DecodeXY(T r, T g) { return Vec2T<T>(T(2) * r - T(1), T(2) * g - T(1)); }

// Tangent-map directions are filtered as doubled-angle vectors (a, b) -> (a^2 - b^2, 2ab) / |.|:
// t and -t map to the same point, so interpolating between neighbouring texels that hold nearly
// opposite vectors (the same orientation) does not cancel to zero. TangentMap_FromDoubled undoes it.
template <typename T> ANISO_INLINE Vec2T<T> TangentMap_ToDoubled(const Vec2T<T>& d) {
  const T len2 = d.x * d.x + d.y * d.y;
  if (!(len2 > T(0))) return Vec2T<T>(T(0));
  return Vec2T<T>((d.x * d.x - d.y * d.y) / len2, T(2) * d.x * d.y / len2);
}
template <typename T> ANISO_INLINE Vec2T<T> TangentMap_FromDoubled(const Vec2T<T>& q) {
  using std::atan2;
  using std::cos;
  using std::sin;
  if (q.x == T(0) && q.y == T(0)) return Vec2T<T>(T(0));
  const T half = T(0.5) * atan2(q.y, q.x);
  return Vec2T<T>(cos(half), sin(half));
}

}  // namespace aniso
