// aniso/core/math.glsl: GLSL twin of math.h: small scalar helpers (vec3 is the C++ Vec3T / RGBT).

float sqr(float x) { return x * x; }

// max(x, 0) before sqrt: rounding can push a mathematically non-negative argument below zero.
float safe_sqrt(float x) { return sqrt(x > 0.0 ? x : 0.0); }

float clamp01(float x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

// average() in math.h; renamed: glslang reserves `average` in GLSL ES (docs/glsl.md, "Naming").
float average_rgb(vec3 c) { return (c.x + c.y + c.z) / 3.0; }

float max_component(vec3 c) {
  float m = c.x > c.y ? c.x : c.y;
  return m > c.z ? m : c.z;
}

// std::copysign(1, x): the sign bit decides, so -0.0 gives -1 as in C++ (GLSL's sign() gives 0).
float copysign_one(float x) { return (floatBitsToUint(x) & 0x80000000u) != 0u ? -1.0 : 1.0; }

// Local shading frame (docs/conventions.md): z = n, x = t, y = b.
float cos_theta(vec3 w) { return w.z; }

// The horizon (docs/conventions.md, "The horizon"; math.h HorizonCos): a unit direction whose
// cos(theta) is at or below horizon_cos() is on the horizon, where every BRDF and pdf is 0 and
// sampling gives no sample. The float threshold 1e-6 (theta = 89.99994 deg): below it a float
// unit vector's z is mostly rounding, and the normalisations (1 / cos, 1 / (h.n)^4) stay below
// ~1e25 with alpha >= 1e-3.
const float HorizonCos = 1e-6;
float horizon_cos() { return HorizonCos; }

// w strictly above the horizon (see HorizonCos).
bool above_horizon(vec3 w) { return w.z > horizon_cos(); }

// Both directions above the horizon: the BRDFs are defined there and nowhere else.
bool same_upper_hemisphere(vec3 wi, vec3 wo) { return above_horizon(wi) && above_horizon(wo); }

// Mirror of w about the unit vector h: 2 (w.h) h - w.
vec3 reflect_about(vec3 w, vec3 h) { return 2.0 * dot(w, h) * h - w; }

// Mirror about the normal in the local frame: the Householder matrix M = diag(-1, -1, 1).
vec3 reflect_about_normal(vec3 w) { return vec3(-w.x, -w.y, w.z); }
