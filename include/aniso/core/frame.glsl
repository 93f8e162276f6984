// aniso/core/frame.glsl: GLSL twin of frame.h: the tangent frame (t, b, n) that orients
// anisotropy, and its rotation. b = n x t (right-handed, docs/conventions.md).

struct Frame {
  vec3 t;
  vec3 b;
  vec3 n;
};

Frame Frame_identity() { return Frame(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0)); }

vec3 Frame_to_local(Frame f, vec3 w) { return vec3(dot(w, f.t), dot(w, f.b), dot(w, f.n)); }
vec3 Frame_to_world(Frame f, vec3 w) { return w.x * f.t + w.y * f.b + w.z * f.n; }

// Any frame around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
Frame Frame_from_normal(vec3 n) {
  float sgn = copysign_one(n.z);
  float a = -1.0 / (sgn + n.z);
  float bb = n.x * n.y * a;
  Frame f;
  f.n = n;
  f.t = vec3(1.0 + sgn * n.x * n.x * a, sgn * bb, -sgn * n.x);
  f.b = vec3(bb, sgn + n.y * n.y * a, -n.y);
  return f;
}

// Frame from a unit normal and an approximate tangent: Gram-Schmidt t' = normalize(t - (t.n) n),
// b = n x t'. A tangent (nearly) parallel to n carries no direction: fall back to from_normal.
Frame Frame_from_normal_tangent(vec3 n, vec3 t_approx) {
  vec3 t_perp = t_approx - dot(t_approx, n) * n;
  float len2 = dot(t_perp, t_perp);
  // 1e-12 of a unit vector's squared length: below it the direction of t_perp is rounding noise.
  if (!(len2 > 1e-12)) return Frame_from_normal(n);
  Frame f;
  f.n = n;
  f.t = t_perp / sqrt(len2);
  f.b = cross(n, f.t);
  return f;
}

// Rotate t and b about n by psi (radians): t' = cos psi t + sin psi b, b' = n x t'.
Frame Frame_rotated(Frame self, float psi) {
  Frame f;
  f.n = self.n;
  f.t = cos(psi) * self.t + sin(psi) * self.b;
  f.b = cross(self.n, f.t);
  return f;
}
