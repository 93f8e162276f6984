// aniso/tangent/fields.glsl: GLSL twin of fields.h: where the tangent comes from. Procedural
// tangent fields and tangent-map decoding, as plain functions of the surface point.
//
// Each field returns an approximate world-space tangent; Frame_from_normal_tangent() makes it
// orthogonal to the shading normal (Gram-Schmidt) and `angle` rotates the result about n. A field
// without a direction at a point returns a zero vector and the frame falls back to
// Frame_from_normal(). The Noise field's simplex noise is glm::simplex(vec3) (glm/gtc/noise.inl,
// itself a port of Ashima Arts' GLSL webgl-noise, MIT licence), transcribed back line for line.

const int TangentFieldKind_Natural = 0;
const int TangentFieldKind_Projected = 1;
const int TangentFieldKind_Radial = 2;
const int TangentFieldKind_Concentric = 3;
const int TangentFieldKind_Swirl = 4;
const int TangentFieldKind_Noise = 5;

// The surface point a field is evaluated at (world space; n unit).
struct SurfacePoint {
  vec3 p;
  vec3 n;
  vec3 dpdu;  // the natural tangent (any length)
  vec2 uv;
};

struct TangentField {
  int kind;        // TangentFieldKind_*
  vec3 direction;  // Projected: the world direction
  vec3 center;     // Radial, Concentric, Swirl: a point on the axis
  vec3 axis;       // ... and its unit direction
  float swirl;     // Swirl: angle from concentric towards radial
  float scale;     // Noise: spatial frequency (1 / world units)
  float strength;  // Noise: largest rotation, in radians
  float angle;     // rotation about n applied last (angle_deg), radians
};

// Radial direction at p: p - c with its component along the axis removed.
vec3 Tangent_Radial(vec3 p, vec3 center, vec3 axis) {
  vec3 d = p - center;
  return d - dot(d, axis) * axis;
}

// Concentric direction at p: axis x (p - c), tangent to the circle through p about the axis.
vec3 Tangent_Concentric(vec3 p, vec3 center, vec3 axis) { return cross(axis, p - center); }

// glm::detail::mod289, permute, taylorInvSqrt (glm/detail/_noise.hpp).
vec3 mod289(vec3 x) { return x - floor(x * (1.0 / 289.0)) * 289.0; }
vec4 mod289(vec4 x) { return x - floor(x * (1.0 / 289.0)) * 289.0; }
vec4 permute(vec4 x) { return mod289(((x * 34.0) + 1.0) * x); }
vec4 taylorInvSqrt(vec4 r) { return 1.79284291400159 - 0.85373472095314 * r; }

// glm::simplex(vec3): 3D simplex noise in [-1, 1] (Perlin 2001; Gustavson's formulation).
float simplex(vec3 v) {
  const vec2 C = vec2(1.0 / 6.0, 1.0 / 3.0);
  const vec4 D = vec4(0.0, 0.5, 1.0, 2.0);
  // First corner
  vec3 i = floor(v + dot(v, vec3(C.y)));
  vec3 x0 = v - i + dot(i, vec3(C.x));
  // Other corners
  vec3 g = step(vec3(x0.y, x0.z, x0.x), x0);
  vec3 l = 1.0 - g;
  vec3 i1 = min(g, vec3(l.z, l.x, l.y));
  vec3 i2 = max(g, vec3(l.z, l.x, l.y));
  vec3 x1 = x0 - i1 + C.x;
  vec3 x2 = x0 - i2 + C.y;  // 2.0 * C.x = 1/3 = C.y
  vec3 x3 = x0 - D.y;       // -1.0 + 3.0 * C.x = -0.5 = -D.y
  // Permutations
  i = mod289(i);
  vec4 p = permute(permute(permute(i.z + vec4(0.0, i1.z, i2.z, 1.0)) + i.y + vec4(0.0, i1.y, i2.y, 1.0)) + i.x +
                   vec4(0.0, i1.x, i2.x, 1.0));
  // Gradients: 7x7 points over a square, mapped onto an octahedron.
  float n_ = 0.142857142857;  // 1.0 / 7.0
  vec3 ns = n_ * vec3(D.w, D.y, D.z) - vec3(D.x, D.z, D.x);
  vec4 j = p - 49.0 * floor(p * ns.z * ns.z);  // mod(p, 7 * 7)
  vec4 x_ = floor(j * ns.z);
  vec4 y_ = floor(j - 7.0 * x_);  // mod(j, N)
  vec4 x = x_ * ns.x + ns.y;
  vec4 y = y_ * ns.x + ns.y;
  vec4 h = 1.0 - abs(x) - abs(y);
  vec4 b0 = vec4(x.x, x.y, y.x, y.y);
  vec4 b1 = vec4(x.z, x.w, y.z, y.w);
  vec4 s0 = floor(b0) * 2.0 + 1.0;
  vec4 s1 = floor(b1) * 2.0 + 1.0;
  vec4 sh = -step(h, vec4(0.0));
  vec4 a0 = vec4(b0.x, b0.z, b0.y, b0.w) + vec4(s0.x, s0.z, s0.y, s0.w) * vec4(sh.x, sh.x, sh.y, sh.y);
  vec4 a1 = vec4(b1.x, b1.z, b1.y, b1.w) + vec4(s1.x, s1.z, s1.y, s1.w) * vec4(sh.z, sh.z, sh.w, sh.w);
  vec3 p0 = vec3(a0.x, a0.y, h.x);
  vec3 p1 = vec3(a0.z, a0.w, h.y);
  vec3 p2 = vec3(a1.x, a1.y, h.z);
  vec3 p3 = vec3(a1.z, a1.w, h.w);
  // Normalise gradients
  vec4 norm = taylorInvSqrt(vec4(dot(p0, p0), dot(p1, p1), dot(p2, p2), dot(p3, p3)));
  p0 *= norm.x;
  p1 *= norm.y;
  p2 *= norm.z;
  p3 *= norm.w;
  // Mix final noise value
  vec4 m = max(0.6 - vec4(dot(x0, x0), dot(x1, x1), dot(x2, x2), dot(x3, x3)), vec4(0.0));
  m = m * m;
  return 42.0 * dot(m * m, vec4(dot(p0, x0), dot(p1, x1), dot(p2, x2), dot(p3, x3)));
}

// Smooth noise angle in [-strength, strength]: 3D simplex noise at p * scale.
float Tangent_NoiseAngle(vec3 p, float scale, float strength) { return strength * simplex(p * scale); }

// The unnormalised tangent a field gives at sp (before Gram-Schmidt and before `angle`).
vec3 tangent_field_direction(TangentField f, SurfacePoint sp) {
  if (f.kind == TangentFieldKind_Projected) return f.direction;
  if (f.kind == TangentFieldKind_Radial) return Tangent_Radial(sp.p, f.center, f.axis);
  if (f.kind == TangentFieldKind_Concentric) return Tangent_Concentric(sp.p, f.center, f.axis);
  if (f.kind == TangentFieldKind_Swirl) {
    vec3 c = Tangent_Concentric(sp.p, f.center, f.axis);
    vec3 r = Tangent_Radial(sp.p, f.center, f.axis);
    // |c| == |r| (both are the distance to the axis times a unit vector), so the blend is a rotation.
    return cos(f.swirl) * c + sin(f.swirl) * r;
  }
  return sp.dpdu;  // Natural; Noise rotates it in tangent_frame()
}

// The shading frame a field gives at sp: Gram-Schmidt against n, then the noise rotation (Noise)
// and the field's `angle`, both about n.
Frame tangent_frame(TangentField f, SurfacePoint sp) {
  Frame frame = Frame_from_normal_tangent(sp.n, tangent_field_direction(f, sp));
  float psi = f.angle;
  if (f.kind == TangentFieldKind_Noise) psi += Tangent_NoiseAngle(sp.p, f.scale, f.strength);
  // if, not ?: : WebGL refuses the conditional operator on structures (ANGLE: "ternary operator is
  // not allowed for structures or arrays"), and the library also runs in browsers (docs/web.md).
  if (psi != 0.0) return Frame_rotated(frame, psi);
  return frame;
}

// Tangent maps (docs/scenes.md): "angle" red channel v -> angle pi v from dp/du towards dp/dv;
// "xy": red, green -> (2 r - 1, 2 g - 1).
vec2 TangentMap_DecodeAngle(float v) { return vec2(cos(kPi * v), sin(kPi * v)); }
vec2 TangentMap_DecodeXY(float r, float g) { return vec2(2.0 * r - 1.0, 2.0 * g - 1.0); }

// Doubled-angle filtering of tangent-map directions (fields.h): t and -t map to the same point.
vec2 TangentMap_ToDoubled(vec2 d) {
  float len2 = d.x * d.x + d.y * d.y;
  if (!(len2 > 0.0)) return vec2(0.0);
  return vec2((d.x * d.x - d.y * d.y) / len2, 2.0 * d.x * d.y / len2);
}
vec2 TangentMap_FromDoubled(vec2 q) {
  if (q.x == 0.0 && q.y == 0.0) return vec2(0.0);
  float half_angle = 0.5 * atan(q.y, q.x);
  return vec2(cos(half_angle), sin(half_angle));
}
