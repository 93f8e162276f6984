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

// PhongT = LambertPlusLobeT<T, PhongLobeT<T>> (lobe_mixture.h): f = kd / pi + ks lobe(wi, wo).
struct Phong {
  vec3 kd;
  vec3 ks;
  PhongLobe lobe;
};

float pdf_diffuse_specular(float p_spec, PhongLobe lobe, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return pdf_diffuse_specular_mix(p_spec, PhongLobe_pdf(lobe, wi, wo), wi, wo);
}

vec3 Phong_f(Phong self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  return self.kd * kInvPi + self.ks * PhongLobe_eval(self.lobe, wi, wo);
}
// Lobe choice by average colour (Walter 2005, Sec. 4).
float Phong_specular_probability(Phong self, vec3 wo) { return specular_share(average_rgb(self.kd), average_rgb(self.ks)); }
float Phong_pdf(Phong self, vec3 wi, vec3 wo) {
  return pdf_diffuse_specular(Phong_specular_probability(self, wo), self.lobe, wi, wo);
}
BSDFSample sample_diffuse_specular(Phong model, PhongLobe lobe, float p_spec, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  vec3 wi = uc < p_spec ? PhongLobe_sample(lobe, wo, u) : sample_cosine_hemisphere(u);
  if (!above_horizon(wi)) return BSDFSample_none();
  return make_sample(wi, Phong_f(model, wi, wo), Phong_pdf(model, wi, wo));
}
BSDFSample Phong_sample(Phong self, vec3 wo, float uc, vec2 u) {
  return sample_diffuse_specular(self, self.lobe, Phong_specular_probability(self, wo), wo, uc, u);
}
