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

// Both directions strictly above the horizon: the BRDFs are defined there and nowhere else.
bool same_upper_hemisphere(vec3 wi, vec3 wo) { return wi.z > 0.0 && wo.z > 0.0; }

// Mirror of w about the unit vector h: 2 (w.h) h - w.
vec3 reflect_about(vec3 w, vec3 h) { return 2.0 * dot(w, h) * h - w; }

// Mirror about the normal in the local frame: the Householder matrix M = diag(-1, -1, 1).
vec3 reflect_about_normal(vec3 w) { return vec3(-w.x, -w.y, w.z); }
