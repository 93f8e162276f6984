// aniso/tangent/fields.glsl: GLSL twin of fields.h: where the tangent comes from. Procedural
// tangent fields and tangent-map decoding, as plain functions of the surface point.
//
// Each field returns an approximate world-space tangent; Frame_from_normal_tangent() makes it
// orthogonal to the shading normal (Gram-Schmidt) and `angle` rotates the result about n. A field
// without a direction at a point returns a zero vector and the frame falls back to
// Frame_from_normal(). Not mirrored yet: TangentFieldKind_Noise (its simplex noise, glm::simplex,
// has no GLSL twin here); tangent_frame() treats it as Natural plus `angle` (docs/glsl.md).

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
  return sp.dpdu;  // Natural (and Noise, see the file comment)
}

// The shading frame a field gives at sp: Gram-Schmidt against n, then the field's `angle` about n.
Frame tangent_frame(TangentField f, SurfacePoint sp) {
  Frame frame = Frame_from_normal_tangent(sp.n, tangent_field_direction(f, sp));
  float psi = f.angle;
  return psi != 0.0 ? Frame_rotated(frame, psi) : frame;
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
