// aniso/brdf/ggx.glsl: GLSL twin of ggx.h: anisotropic GGX / Trowbridge-Reitz microfacets with
// height-correlated Smith masking-shadowing and visible-normal sampling.
//
// Trowbridge & Reitz 1975; Walter et al. 2007, "Microfacet Models for Refraction", Eq. 20, 33;
// Heitz 2014, "Understanding the Masking-Shadowing Function", Eq. 86 (anisotropic Lambda), Eq. 99
// (height-correlated G2); Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4).
//
//   f = kd / pi + F(wi.h) D(h) G2(wi, wo) / (4 cos_i cos_o),   F = Schlick with f0 and f90

// D(h) = 1 / (pi ax ay ((h.t / ax)^2 + (h.b / ay)^2 + (h.n)^2)^2), h unit.
float D_GGX_Aniso(float HoT, float HoB, float HoN, float ax, float ay) {
  float d = sqr(HoT / ax) + sqr(HoB / ay) + sqr(HoN);
  return kInvPi / (ax * ay * d * d);
}

// Lambda(w) = (-1 + sqrt(1 + (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2)) / 2 (Heitz 2014 Eq. 86).
float Lambda_GGX_Aniso(vec3 w, float ax, float ay) {
  float tan2_alpha2 = (sqr(ax * w.x) + sqr(ay * w.y)) / sqr(w.z);
  return (sqrt(1.0 + tan2_alpha2) - 1.0) * 0.5;
}

// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wi) + Lambda(wo)) (Heitz 2014 Eq. 99).
float G2_SmithGGX_HeightCorrelated(float lambda_i, float lambda_o) { return 1.0 / (1.0 + lambda_i + lambda_o); }

float G1_SmithGGX(float lambda) { return 1.0 / (1.0 + lambda); }

// Heitz 2018, Listing 1: sample a visible normal for the view direction wo (upper hemisphere).
vec3 GGX_SampleVisibleNormal(vec3 wo, vec2 u, float ax, float ay) {
  // Stretch the view vector to the hemisphere configuration (alpha = 1).
  vec3 vh = normalize(vec3(ax * wo.x, ay * wo.y, wo.z));
  // Orthonormal basis around vh (vh.z > 0, so lensq = 0 only at normal view).
  float lensq = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) / sqrt(lensq) : vec3(1.0, 0.0, 0.0);
  vec3 t2 = cross(vh, t1);
  // Uniform point on the disk, warped towards the visible half (Section 4.2).
  float r = sqrt(u.x);
  float phi = 2.0 * kPi * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * safe_sqrt(1.0 - p1 * p1) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + safe_sqrt(1.0 - p1 * p1 - p2 * p2) * vh;
  // Unstretch; nh.z >= 0, and the max() keeps the normal strictly above the horizon (Listing 1).
  return normalize(vec3(ax * nh.x, ay * nh.y, nh.z > 0.0 ? nh.z : 0.0));
}

// The colourless, Fresnel-less specular lobe D G2 / (4 cos_i cos_o), shared with the metal.
struct GGXLobe {
  float alpha_x;
  float alpha_y;
};

float GGXLobe_eval(GGXLobe self, vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  float D = D_GGX_Aniso(h.x, h.y, h.z, self.alpha_x, self.alpha_y);
  float G2 = G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, self.alpha_x, self.alpha_y),
                                          Lambda_GGX_Aniso(wo, self.alpha_x, self.alpha_y));
  return D * G2 / (4.0 * wi.z * wo.z);
}
// Visible-normal density: pdf(wi) = G1(wo) D(h) / (4 wo.z).
float GGXLobe_pdf(GGXLobe self, vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  if (!(dot(wo, h) > 0.0) || !(h.z > 0.0)) return 0.0;
  float D = D_GGX_Aniso(h.x, h.y, h.z, self.alpha_x, self.alpha_y);
  return G1_SmithGGX(Lambda_GGX_Aniso(wo, self.alpha_x, self.alpha_y)) * D / (4.0 * wo.z);
}
vec3 GGXLobe_sample(GGXLobe self, vec3 wo, vec2 u) {
  return reflect_about(wo, GGX_SampleVisibleNormal(wo, u, self.alpha_x, self.alpha_y));
}

struct GGX {
  vec3 kd;
  vec3 f0;
  vec3 f90;
  GGXLobe lobe;
};

vec3 GGX_f(GGX self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  return F_Schlick(self.f0, self.f90, dot(wi, h)) * GGXLobe_eval(self.lobe, wi, wo) + self.kd * kInvPi;
}
// Specular weight: Schlick's Fresnel at the view angle (the lobe's albedo is <= that).
float GGX_specular_probability(GGX self, vec3 wo) {
  return specular_share(average_rgb(self.kd), average_rgb(F_Schlick(self.f0, self.f90, wo.z)));
}
// GGX_pdf and GGX_sample, the diffuse + specular mixture of lobe_mixture.h
// (pdf_diffuse_specular, sample_diffuse_specular), are generated from its template after this file
// (gl::glsl_lobe_mixture, src/gl/glsl_library.cpp).
