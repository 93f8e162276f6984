// aniso/brdf/principled.glsl: GLSL twin of principled.h: the Disney principled BRDF (Burley 2012,
// "Physically-Based Shading at Disney"), as Disney's BRDF Explorer src/brdfs/disney.brdf with a
// linear base_color. The formulas and their line numbers in disney.brdf are in principled.h.

// mix(a, b, t) is GLSL's own: a (1 - t) + b t, as Principled_Mix in principled.h.

// SchlickFresnel(u) = (1 - u)^5 with 1 - u clamped to [0, 1] (disney.brdf lines 42-47).
float Principled_SchlickWeight(float u) {
  float m = clamp01(1.0 - u);
  float m2 = m * m;
  return m2 * m2 * m;
}

// GTR1 (lines 49-55) with the denominator as a^2 cos^2(theta_h) + sin^2(theta_h) (principled.h:
// no cancellation in float near the peak). h unit.
float D_GTR1(vec3 h, float a) {
  if (a >= 1.0) return kInvPi;
  float a2 = a * a;
  float t = a2 * sqr(h.z) + (sqr(h.x) + sqr(h.y));
  return (a2 - 1.0) / (kPi * log(a2) * t);
}

// Smith's G1 for GGX divided by 2 n.v (lines 69-74).
float Principled_SmithG_GGX(float NoV, float alpha) {
  float a = alpha * alpha;
  float b = NoV * NoV;
  return 1.0 / (NoV + sqrt(a + b - a * b));
}

// The anisotropic G1 / (2 n.v) (lines 76-79).
float Principled_SmithG_GGX_Aniso(vec3 w, float ax, float ay) {
  return 1.0 / (w.z + sqrt(sqr(w.x * ax) + sqr(w.y * ay) + sqr(w.z)));
}

struct Principled {
  vec3 base_color;
  float metallic;
  float subsurface;
  float specular;
  float roughness;
  float specular_tint;
  float anisotropic;
  float sheen;
  float sheen_tint;
  float clearcoat;
  float clearcoat_gloss;
};

GGXLobe Principled_specular_lobe(Principled self) {
  float aspect = sqrt(1.0 - self.anisotropic * 0.9);
  float ax = sqr(self.roughness) / aspect;
  float ay = sqr(self.roughness) * aspect;
  return GGXLobe(ax > 0.001 ? ax : 0.001, ay > 0.001 ? ay : 0.001);
}
float Principled_clearcoat_alpha(Principled self) { return mix(0.1, 0.001, self.clearcoat_gloss); }
vec3 Principled_tint(Principled self) {
  vec3 c = self.base_color;
  float lum = 0.3 * c.x + 0.6 * c.y + 0.1 * c.z;
  return lum > 0.0 ? c / lum : vec3(1.0);
}
vec3 Principled_specular_f0(Principled self) {
  return mix(self.specular * 0.08 * mix(vec3(1.0), Principled_tint(self), self.specular_tint), self.base_color,
             self.metallic);
}

vec3 Principled_f(Principled self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  float NoL = wi.z;
  float NoV = wo.z;
  float LoH = dot(wi, h);
  vec3 Csheen = mix(vec3(1.0), Principled_tint(self), self.sheen_tint);
  float FL = Principled_SchlickWeight(NoL);
  float FV = Principled_SchlickWeight(NoV);
  float Fd90 = 0.5 + 2.0 * LoH * LoH * self.roughness;
  float Fd = mix(1.0, Fd90, FL) * mix(1.0, Fd90, FV);
  float Fss90 = LoH * LoH * self.roughness;
  float Fss = mix(1.0, Fss90, FL) * mix(1.0, Fss90, FV);
  float ss = 1.25 * (Fss * (1.0 / (NoL + NoV) - 0.5) + 0.5);
  GGXLobe lobe = Principled_specular_lobe(self);
  float Ds = D_GGX_Aniso(h.x, h.y, h.z, lobe.alpha_x, lobe.alpha_y);
  float FH = Principled_SchlickWeight(LoH);
  vec3 Fs = mix(Principled_specular_f0(self), vec3(1.0), FH);
  float Gs = Principled_SmithG_GGX_Aniso(wi, lobe.alpha_x, lobe.alpha_y) *
             Principled_SmithG_GGX_Aniso(wo, lobe.alpha_x, lobe.alpha_y);
  vec3 Fsheen = FH * self.sheen * Csheen;
  float Dr = D_GTR1(h, Principled_clearcoat_alpha(self));
  float Fr = mix(0.04, 1.0, FH);
  float Gr = Principled_SmithG_GGX(NoL, 0.25) * Principled_SmithG_GGX(NoV, 0.25);
  return (kInvPi * mix(Fd, ss, self.subsurface) * self.base_color + Fsheen) * (1.0 - self.metallic) + Gs * Fs * Ds +
         0.25 * self.clearcoat * Gr * Fr * Dr;
}

// {p_specular, p_clearcoat}; the rest is diffuse (principled.h, lobe_probabilities).
vec2 Principled_lobe_probabilities(Principled self, vec3 wo) {
  float Fv = Principled_SchlickWeight(wo.z);
  float wd = (1.0 - self.metallic) * average_rgb(self.base_color);
  float ws = average_rgb(mix(Principled_specular_f0(self), vec3(1.0), Fv));
  float wc = 0.25 * self.clearcoat * mix(0.04, 1.0, Fv);
  float total = wd + ws + wc;
  if (!(total > 0.0)) return vec2(0.0);
  return vec2(ws / total, wc / total);
}

float Principled_clearcoat_pdf(Principled self, vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  float WoH = dot(wo, h);
  if (!(WoH > 0.0) || !(h.z > 0.0)) return 0.0;
  return D_GTR1(h, Principled_clearcoat_alpha(self)) * h.z / (4.0 * WoH);
}
vec3 Principled_clearcoat_sample(Principled self, vec3 wo, vec2 u) {
  float a = Principled_clearcoat_alpha(self);
  float a2 = a * a;
  float cos2 = clamp01((1.0 - pow(a2, 1.0 - u.x)) / (1.0 - a2));
  float cos_t = safe_sqrt(cos2);
  float sin_t = safe_sqrt(1.0 - cos2);
  float phi = 2.0 * kPi * u.y;
  return reflect_about(wo, vec3(sin_t * cos(phi), sin_t * sin(phi), cos_t));
}

float Principled_pdf(Principled self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  vec2 p = Principled_lobe_probabilities(self, wo);
  return (1.0 - p.x - p.y) * cosine_hemisphere_pdf(wi.z) + p.x * GGXLobe_pdf(Principled_specular_lobe(self), wi, wo) +
         p.y * Principled_clearcoat_pdf(self, wi, wo);
}
BSDFSample Principled_sample(Principled self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  vec2 p = Principled_lobe_probabilities(self, wo);
  vec3 wi = uc < p.x ? GGXLobe_sample(Principled_specular_lobe(self), wo, u)
                     : (uc < p.x + p.y ? Principled_clearcoat_sample(self, wo, u) : sample_cosine_hemisphere(u));
  if (!above_horizon(wi)) return BSDFSample_none();
  return make_sample(wi, Principled_f(self, wi, wo), Principled_pdf(self, wi, wo));
}
