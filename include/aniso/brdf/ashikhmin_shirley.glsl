// aniso/brdf/ashikhmin_shirley.glsl: GLSL twin of ashikhmin_shirley.h: Ashikhmin & Shirley 2000,
// "An Anisotropic Phong BRDF Model", JGT 5(2), 25-32: Eq. 4 (specular), Eq. 5 (diffuse),
// Sec. 5 / Eqs. 9-10 (sampling).
//
//   f = ks_scale * f_s + f_d + kd / pi
//   f_s = sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e / ((h.wi) max(n.wi, n.wo)) F(wi.h)
//   e   = nu cos^2 phi_h + nv sin^2 phi_h = (nu (h.t)^2 + nv (h.b)^2) / (1 - (h.n)^2)
//   F   = Rs + (1 - Rs)(1 - wi.h)^5 (Schlick)
//   f_d = 28 Rd / (23 pi) (1 - Rs) (1 - (1 - n.wi / 2)^5) (1 - (1 - n.wo / 2)^5)

// The anisotropic exponent; the denominator (h.t)^2 + (h.b)^2 is exact near h = n, where
// (n.h)^e = 1 for every e (ashikhmin_shirley.h).
float AS_Exponent(float HoT, float HoB, float nu, float nv) {
  float s2 = HoT * HoT + HoB * HoB;
  return s2 > 0.0 ? (nu * HoT * HoT + nv * HoB * HoB) / s2 : nu;
}

// The specular term without Fresnel (Eq. 4 with F = 1); 0 unless h.wi > 0, as the pdf is unless
// h.wo > 0 (h.wi is rounding alone for nearly opposite grazing directions: ashikhmin_shirley.h).
float AS_Specular(float HoT, float HoB, float HoN, float HoL, float NoL, float NoV, float nu, float nv) {
  if (!(HoL > 0.0)) return 0.0;
  float e = AS_Exponent(HoT, HoB, nu, nv);
  return sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * kPi) * pow(HoN, e) / (HoL * (NoL > NoV ? NoL : NoV));
}

// Eq. 5 without the colour: 28 / (23 pi) (1 - (1 - n.wi / 2)^5) (1 - (1 - n.wo / 2)^5).
float AS_Diffuse(float NoL, float NoV) {
  float a = 1.0 - NoL * 0.5, b = 1.0 - NoV * 0.5;
  float a5 = a * a * a * a * a, b5 = b * b * b * b * b;
  return 28.0 / (23.0 * kPi) * (1.0 - a5) * (1.0 - b5);
}

// Density of the unit half vector (Sec. 5): sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^e.
float AS_PdfHalf(vec3 h, float nu, float nv) {
  if (!(h.z > 0.0)) return 0.0;
  return sqrt((nu + 1.0) * (nv + 1.0)) * kInv2Pi * pow(h.z, AS_Exponent(h.x, h.y, nu, nv));
}

// Eq. 9: phi = atan(sqrt((nu + 1) / (nv + 1)) tan(pi xi / 2)) in the first quadrant, mapped to the
// four quadrants by splitting u.x into quarters; Eq. 10: cos theta_h = xi2^(1 / (e + 1)).
vec3 AS_SampleHalf(vec2 u, float nu, float nv) {
  float ratio = sqrt((nu + 1.0) / (nv + 1.0));
  float q = 4.0 * u.x;  // which quarter, and where in it
  float phi;
  if (q < 1.0) {
    phi = atan(ratio * tan(kPiOver2 * q));
  } else if (q < 2.0) {
    phi = kPi - atan(ratio * tan(kPiOver2 * (2.0 - q)));
  } else if (q < 3.0) {
    phi = kPi + atan(ratio * tan(kPiOver2 * (q - 2.0)));
  } else {
    phi = 2.0 * kPi - atan(ratio * tan(kPiOver2 * (4.0 - q)));
  }
  float c = cos(phi), s = sin(phi);
  float e = nu * c * c + nv * s * s;
  float cos_t = pow(1.0 - u.y, 1.0 / (e + 1.0));  // 1 - u in (0, 1]
  float sin_t = safe_sqrt(1.0 - cos_t * cos_t);
  return vec3(sin_t * c, sin_t * s, cos_t);
}

// The colourless, Fresnel-less specular lobe, shared with the metal material.
struct AshikhminShirleyLobe {
  float n_u;
  float n_v;
};

// Requires both directions above the horizon. Returns f_s / F.
float AshikhminShirleyLobe_eval(AshikhminShirleyLobe self, vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  return AS_Specular(h.x, h.y, h.z, dot(h, wi), wi.z, wo.z, self.n_u, self.n_v);
}
// pdf(wi) = p_h(h) / (4 (wo.h)).
float AshikhminShirleyLobe_pdf(AshikhminShirleyLobe self, vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  float WoH = dot(wo, h);
  if (!(WoH > 0.0)) return 0.0;
  return AS_PdfHalf(h, self.n_u, self.n_v) / (4.0 * WoH);
}
vec3 AshikhminShirleyLobe_sample(AshikhminShirleyLobe self, vec3 wo, vec2 u) {
  return reflect_about(wo, AS_SampleHalf(u, self.n_u, self.n_v));
}

struct AshikhminShirley {
  vec3 rd;
  vec3 rs;
  vec3 kd;
  vec3 ks_scale;
  AshikhminShirleyLobe lobe;
};

vec3 AshikhminShirley_f(AshikhminShirley self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  vec3 F = F_Schlick(self.rs, dot(wi, h));
  float spec = AS_Specular(h.x, h.y, h.z, dot(h, wi), wi.z, wo.z, self.lobe.n_u, self.lobe.n_v);
  return self.ks_scale * F * spec + self.rd * (vec3(1.0) - self.rs) * AS_Diffuse(wi.z, wo.z) + self.kd * kInvPi;
}
// Lobe choice: the specular weight is its Fresnel reflectance seen from wo, the diffuse weight its
// colour (ashikhmin_shirley.h).
float AshikhminShirley_specular_probability(AshikhminShirley self, vec3 wo) {
  return specular_share(average_rgb(self.rd * (vec3(1.0) - self.rs)) + average_rgb(self.kd),
                        average_rgb(self.ks_scale * F_Schlick(self.rs, wo.z)));
}
// AshikhminShirley_pdf and AshikhminShirley_sample, the diffuse + specular mixture of lobe_mixture.h
// (pdf_diffuse_specular, sample_diffuse_specular), are generated from its template after this file
// (gl::glsl_lobe_mixture, src/gl/glsl_library.cpp).
