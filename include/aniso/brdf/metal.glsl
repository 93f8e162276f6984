// aniso/brdf/metal.glsl: GLSL twin of metal.h: a conductor (no subsurface term). The reflection
// has two parts (the lecture, "Metals"; Cook & Torrance 1982):
//   f = (1 - a) F_conductor(wi.h; eta, k) specular(wi, wo)  +  directional_diffuse(wi, wo)
// - specular: an anisotropic Ward, Ashikhmin-Shirley or GGX lobe without colour or Fresnel;
// - directional diffuse: an optional broad Lafortune lobe coloured by the metal, with Ngan et
//   al. 2005's normalisation folded in by the host (docs/models/metal.md).

// enum class SpecularLobeKind (enumerator values as in metal.h).
const int SpecularLobeKind_Ward = 0;
const int SpecularLobeKind_AshikhminShirley = 1;
const int SpecularLobeKind_GGX = 2;

struct Metal {
  vec3 eta;
  vec3 k;
  int lobe_kind;  // SpecularLobeKind_*
  WardLobe ward;
  AshikhminShirleyLobe ashikhmin_shirley;
  GGXLobe ggx;
  // (1 - directional-diffuse albedo): the energy the directional lobe takes from the specular one.
  vec3 specular_weight;
  bool has_directional_diffuse;
  LafortuneLobe directional_diffuse;
};

float Metal_specular(Metal self, vec3 wi, vec3 wo) {
  if (self.lobe_kind == SpecularLobeKind_Ward) return WardLobe_eval(self.ward, wi, wo);
  if (self.lobe_kind == SpecularLobeKind_AshikhminShirley) return AshikhminShirleyLobe_eval(self.ashikhmin_shirley, wi, wo);
  return GGXLobe_eval(self.ggx, wi, wo);
}
float Metal_specular_pdf(Metal self, vec3 wi, vec3 wo) {
  if (self.lobe_kind == SpecularLobeKind_Ward) return WardLobe_pdf(self.ward, wi, wo);
  if (self.lobe_kind == SpecularLobeKind_AshikhminShirley) return AshikhminShirleyLobe_pdf(self.ashikhmin_shirley, wi, wo);
  return GGXLobe_pdf(self.ggx, wi, wo);
}
vec3 Metal_specular_sample(Metal self, vec3 wo, vec2 u) {
  if (self.lobe_kind == SpecularLobeKind_Ward) return WardLobe_sample(self.ward, wo, u);
  if (self.lobe_kind == SpecularLobeKind_AshikhminShirley) return AshikhminShirleyLobe_sample(self.ashikhmin_shirley, wo, u);
  return GGXLobe_sample(self.ggx, wo, u);
}

vec3 Metal_f(Metal self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  vec3 outv = self.specular_weight * F_Conductor(dot(wi, h), self.eta, self.k) * Metal_specular(self, wi, wo);
  if (self.has_directional_diffuse) outv += LafortuneLobe_eval(self.directional_diffuse, wi, wo);
  return outv;
}

// Lobe choice: the specular lobe weighs its Fresnel reflectance seen from wo, the directional
// diffuse lobe its channel weights (an albedo bound, lafortune.h).
float Metal_specular_probability(Metal self, vec3 wo) {
  float s = average_rgb(self.specular_weight * F_Conductor(wo.z, self.eta, self.k));
  float d = 0.0;
  if (self.has_directional_diffuse)
    for (int c = 0; c < 3; ++c) d += LafortuneLobe_channel_weight(self.directional_diffuse, wo, c);
  return s + d > 0.0 ? s / (s + d) : 1.0;
}
float Metal_directional_diffuse_pdf(Metal self, vec3 wi, vec3 wo) {
  float wsum = 0.0, p = 0.0;
  for (int c = 0; c < 3; ++c) {
    float w = LafortuneLobe_channel_weight(self.directional_diffuse, wo, c);
    if (w > 0.0) {
      wsum += w;
      p += w * LafortuneLobe_channel_pdf(self.directional_diffuse, wi, wo, c);
    }
  }
  return wsum > 0.0 ? p / wsum : 0.0;
}
float Metal_pdf(Metal self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  float ps = Metal_specular_probability(self, wo);
  float p = ps * Metal_specular_pdf(self, wi, wo);
  if (ps < 1.0) p += (1.0 - ps) * Metal_directional_diffuse_pdf(self, wi, wo);
  return p;
}
BSDFSample Metal_sample(Metal self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  float ps = Metal_specular_probability(self, wo);
  vec3 wi;
  if (uc < ps) {
    wi = Metal_specular_sample(self, wo, u);
  } else {
    // Pick the channel of the directional-diffuse lobe by weight, reusing uc rescaled to [0, 1).
    vec3 ws;
    float wsum = 0.0;
    for (int c = 0; c < 3; ++c) {
      ws[c] = LafortuneLobe_channel_weight(self.directional_diffuse, wo, c);
      wsum += ws[c];
    }
    if (!(wsum > 0.0)) return BSDFSample_none();
    float target = (uc - ps) / (1.0 - ps) * wsum;
    int chosen = 2;
    for (int c = 0; c < 3; ++c) {
      if (ws[c] > 0.0 && target < ws[c]) {
        chosen = c;
        break;
      }
      target -= ws[c];
    }
    while (chosen > 0 && !(ws[chosen] > 0.0)) --chosen;
    vec3 a = LafortuneLobe_axis(self.directional_diffuse, wo, chosen);
    wi = sample_cosine_power(a / sqrt(dot(a, a)), self.directional_diffuse.n[chosen], u);
  }
  if (!above_horizon(wi)) return BSDFSample_none();
  return make_sample(wi, Metal_f(self, wi, wo), Metal_pdf(self, wi, wo));
}
