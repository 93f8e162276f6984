// aniso/core/frame.h: the tangent frame (t, b, n) that orients anisotropy, and its rotation.
//
// The lecture: "we're in surface space: rotate t and b by an angle, or use a tangent map, or
// procedural tangents". Every orientation method ends here: a unit normal n, a tangent t made
// orthogonal to n by Gram-Schmidt, and b = n x t (right-handed, docs/conventions.md).
#pragma once

#include "aniso/core/math.h"

namespace aniso {

template <typename T> struct FrameT {
  Vec3T<T> t{T(1), T(0), T(0)};
  Vec3T<T> b{T(0), T(1), T(0)};
  Vec3T<T> n{T(0), T(0), T(1)};

  ANISO_HD Vec3T<T> to_local(const Vec3T<T>& w) const { return Vec3T<T>(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)); }
  ANISO_HD Vec3T<T> to_world(const Vec3T<T>& w) const { return w.x * t + w.y * b + w.z * n; }

  // Any frame around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
  // Used where no tangent is given: isotropic materials do not care which one it is.
  ANISO_HD static FrameT from_normal(const Vec3T<T>& n) {
    using std::copysign;
    const T sign = copysign(T(1), n.z);
    const T a = T(-1) / (sign + n.z);
    const T bb = n.x * n.y * a;
    FrameT f;
    f.n = n;
    f.t = Vec3T<T>(T(1) + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    f.b = Vec3T<T>(bb, sign + n.y * n.y * a, -n.y);
    return f;
  }

  // Frame from a unit normal and an approximate tangent: Gram-Schmidt t' = normalize(t - (t.n) n),
  // b = n x t'. A tangent (nearly) parallel to n carries no direction: fall back to from_normal.
  ANISO_HD static FrameT from_normal_tangent(const Vec3T<T>& n, const Vec3T<T>& t_approx) {
    const Vec3T<T> t_perp = t_approx - glm::dot(t_approx, n) * n;
    const T len2 = glm::dot(t_perp, t_perp);
    // 1e-12 of a unit vector's squared length: below it the direction of t_perp is rounding noise.
    if (!(len2 > T(1e-12))) return from_normal(n);
    FrameT f;
    f.n = n;
    f.t = t_perp / std::sqrt(len2);
    f.b = glm::cross(n, f.t);
    return f;
  }

  // Rotate t and b about n by psi (radians): t' = cos psi t + sin psi b, b' = n x t'.
  ANISO_HD FrameT rotated(T psi) const {
    using std::cos;
    using std::sin;
    FrameT f;
    f.n = n;
    f.t = cos(psi) * t + sin(psi) * b;
    f.b = glm::cross(n, f.t);
    return f;
  }
};

using Frame = FrameT<float>;

}  // namespace aniso
