// aniso/brdf/fresnel.glsl: GLSL twin of fresnel.h: Fresnel reflectance of conductors (exact, from
// n + ik) and Schlick's approximation. Unpolarised light, incident from air (n = 1).

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", Eq. 15:
// F(c) = F0 + (1 - F0)(1 - c)^5, c = cos of the angle between the light and the half vector.
float F_Schlick(float f0, float cos_theta) {
  float m = 1.0 - clamp01(cos_theta);
  float m2 = m * m;
  return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// With a free reflectance at grazing incidence F90 (fresnel.h): F0 + (F90 - F0)(1 - c)^5.
vec3 F_Schlick(vec3 f0, vec3 f90, float cos_theta) {
  float m = 1.0 - clamp01(cos_theta);
  float m2 = m * m;
  return f0 + (f90 - f0) * (m2 * m2 * m);
}
vec3 F_Schlick(vec3 f0, float cos_theta) { return F_Schlick(f0, vec3(1.0), cos_theta); }

// Exact unpolarised reflectance of a conductor with complex index eta + i k, from air.
// Real-arithmetic form of the Fresnel equations (Born & Wolf, Principles of Optics, Sec. 14.2;
// the a^2 + b^2 formulation as in pbrt-v3's FrConductor); fresnel.h has the formulas.
// F = (R_s + R_p) / 2. At cos = 0 both are 1 (grazing incidence reflects everything).
float F_Conductor(float cos_theta, float eta, float k) {
  float c = clamp01(cos_theta);
  float cos2 = c * c;
  float sin2 = 1.0 - cos2;
  float eta2 = eta * eta, k2 = k * k;
  float t0 = eta2 - k2 - sin2;
  float a2_plus_b2 = sqrt(t0 * t0 + 4.0 * eta2 * k2);
  float t1 = a2_plus_b2 + cos2;
  float a = safe_sqrt(0.5 * (a2_plus_b2 + t0));
  float t2 = 2.0 * c * a;
  float rs = (t1 - t2) / (t1 + t2);
  float t3 = cos2 * a2_plus_b2 + sin2 * sin2;
  float t4 = t2 * sin2;
  float rp = rs * (t3 - t4) / (t3 + t4);
  // Clamp at 0: for an index matched to air (eta = 1, k = 0) the true reflectance is 0, and the
  // differences t1 - t2 and t3 - t4 cancel to a rounding-size value of either sign.
  float f = 0.5 * (rp + rs);
  return f > 0.0 ? f : 0.0;
}

vec3 F_Conductor(float cos_theta, vec3 eta, vec3 k) {
  return vec3(F_Conductor(cos_theta, eta.x, k.x), F_Conductor(cos_theta, eta.y, k.y),
              F_Conductor(cos_theta, eta.z, k.z));
}
