// aniso/brdf/phong.glsl: GLSL twin of phong.h: Phong's lobe about the mirror direction, as a BRDF
// (Phong 1975), plain and energy-normalised ("modified Phong", Lewis 1994, "Making Shaders More
// Physically Plausible").
//   plain:       f = kd / pi + ks (r . wo)^s,                  r = 2 (n . wi) n - wi = M wi
//   normalised:  f = kd / pi + ks (s + 2) / (2 pi) (r . wo)^s,  M = diag(-1, -1, 1)

// (r . wo)^s, 0 when the lobe base is not positive.
float Phong_Lobe(float RoV, float exponent) { return RoV > 0.0 ? pow(RoV, exponent) : 0.0; }

// Lewis 1994: (s + 2) / (2 pi) makes the lobe's cosine-weighted integral 1 at normal incidence.
float Phong_Normalization(float exponent) { return (exponent + 2.0) * kInv2Pi; }

// The specular lobe without its colour; sampled as the cosine power about r(wo), which is the same
// lobe because (M wi) . wo = wi . (M wo).
struct PhongLobe {
  float exponent;
  bool normalized;
};

float PhongLobe_eval(PhongLobe self, vec3 wi, vec3 wo) {
  float lobe = Phong_Lobe(dot(reflect_about_normal(wi), wo), self.exponent);
  return self.normalized ? lobe * Phong_Normalization(self.exponent) : lobe;
}
float PhongLobe_pdf(PhongLobe self, vec3 wi, vec3 wo) {
  return cosine_power_pdf(dot(reflect_about_normal(wo), wi), self.exponent);
}
vec3 PhongLobe_sample(PhongLobe self, vec3 wo, vec2 u) {
  return sample_cosine_power(reflect_about_normal(wo), self.exponent, u);
}

// PhongT = LambertPlusLobeT<T, PhongLobeT<T>> (lobe_mixture.h): the struct Phong { kd, ks, lobe } with
// Phong_f, Phong_pdf and Phong_sample is generated from the template's GLSL twin after this file
// (gl::glsl_lobe_mixture, src/gl/glsl_library.cpp).
