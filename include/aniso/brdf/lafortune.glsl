// aniso/brdf/lafortune.glsl: GLSL twin of lafortune.h: Lafortune, Foo, Torrance & Greenberg 1997,
// "Non-Linear Approximation of Reflectance Functions", SIGGRAPH, Eq. 5-6: generalised cosine lobes.
//
//   f = rho_d / pi + sum_i scale_i [Cx_i wi.x wo.x + Cy_i wi.y wo.y + Cz_i wi.z wo.z]^(n_i)
// per RGB channel; a lobe whose base is <= 0 contributes 0.
//
// Sampling: lobe i, channel c is the cosine-power lobe about the axis a = (Cx wo.x, Cy wo.y,
// Cz wo.z), mixed with the diffuse term and a defensive cosine share by weight
// (docs/models/lafortune.md).

// Kernels allocate nothing, so the lobe count has a fixed ceiling. Published fits use 1 to 3 lobes.
const int kLafortuneMaxLobes = 8;

// One lobe's value for one channel: scale max(Cx wi.x wo.x + Cy wi.y wo.y + Cz wi.z wo.z, 0)^n,
// computed as exp(n log(base) + log(scale)): the product is what the reader bounds
// (scale max|C|^n <= 1e30), its factors alone need not be finite (lafortune.h). A scale of 0
// switches the lobe off.
float Lafortune_Lobe(float base, float n, float scale) {
  return base > 0.0 && scale > 0.0 ? exp(n * log(base) + log(scale)) : 0.0;
}

struct LafortuneLobe {
  vec3 cx;
  vec3 cy;
  vec3 cz;
  vec3 n;
  vec3 scale;
};

vec3 LafortuneLobe_eval(LafortuneLobe self, vec3 wi, vec3 wo) {
  vec3 p = wi * wo;  // component-wise: the diagonal matrix acts on wi.x wo.x, ...
  vec3 outv;
  for (int c = 0; c < 3; ++c) {
    outv[c] = Lafortune_Lobe(self.cx[c] * p.x + self.cy[c] * p.y + self.cz[c] * p.z, self.n[c], self.scale[c]);
  }
  return outv;
}

// The lobe axis for channel c: a = M wo.
vec3 LafortuneLobe_axis(LafortuneLobe self, vec3 wo, int c) {
  return vec3(self.cx[c] * wo.x, self.cy[c] * wo.y, self.cz[c] * wo.z);
}

// Sampling weight of channel c: scale |a|^n 2 pi / (n + 1) times the axis' elevation a_hat.z,
// divided by 3 (lafortune.h says why).
float LafortuneLobe_channel_weight(LafortuneLobe self, vec3 wo, int c) {
  vec3 a = LafortuneLobe_axis(self, wo, c);
  float len = sqrt(dot(a, a));
  if (!(len > 0.0) || !(a.z > 0.0)) return 0.0;
  // scale |a|^n through Lafortune_Lobe: |a| <= max|C|, so the same bound keeps it finite.
  return Lafortune_Lobe(len, self.n[c], self.scale[c]) * (a.z / len) * 2.0 * kPi / ((self.n[c] + 1.0) * 3.0);
}

float LafortuneLobe_channel_pdf(LafortuneLobe self, vec3 wi, vec3 wo, int c) {
  vec3 a = LafortuneLobe_axis(self, wo, c);
  float len2 = dot(a, a);
  if (!(len2 > 0.0)) return 0.0;
  return cosine_power_pdf(dot(a, wi) / sqrt(len2), self.n[c]);
}

struct Lafortune {
  vec3 rho_d;
  int lobe_count;
  LafortuneLobe lobes[kLafortuneMaxLobes];
};

// Defensive share of cosine sampling (Hesterberg 1995, "Weighted average importance sampling and
// defensive mixture distributions").
const float Lafortune_kDefensiveShare = 0.1;

// The mixture's weights for one wo (LafortuneT::SamplingWeights); lobe[i][c] is lobe[i].c here
// (GLSL 3.30 / ES 3.00 have no arrays of arrays).
struct Lafortune_SamplingWeights {
  vec3 lobe[kLafortuneMaxLobes];
  float lobes_total;
  float cosine;  // the diffuse albedo plus the defensive share; all of it when nothing else weighs
};

Lafortune_SamplingWeights Lafortune_sampling_weights(Lafortune self, vec3 wo) {
  Lafortune_SamplingWeights w;
  w.lobes_total = 0.0;
  for (int i = 0; i < kLafortuneMaxLobes; ++i) w.lobe[i] = vec3(0.0);
  for (int i = 0; i < self.lobe_count; ++i)
    for (int c = 0; c < 3; ++c) {
      w.lobe[i][c] = LafortuneLobe_channel_weight(self.lobes[i], wo, c);
      w.lobes_total += w.lobe[i][c];
    }
  float cos_w = average_rgb(self.rho_d) + Lafortune_kDefensiveShare * w.lobes_total;
  w.cosine = cos_w > 0.0 || w.lobes_total > 0.0 ? cos_w : 1.0;
  return w;
}

vec3 Lafortune_f(Lafortune self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 outv = self.rho_d * kInvPi;
  for (int i = 0; i < self.lobe_count; ++i) outv += LafortuneLobe_eval(self.lobes[i], wi, wo);
  return outv;
}

// LafortuneT::pdf(const SamplingWeights&, wi, wo): the overload with precomputed weights.
float Lafortune_pdf(Lafortune self, Lafortune_SamplingWeights w, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  float p = w.cosine * cosine_hemisphere_pdf(wi.z);
  for (int i = 0; i < self.lobe_count; ++i)
    for (int c = 0; c < 3; ++c)
      if (w.lobe[i][c] > 0.0) p += w.lobe[i][c] * LafortuneLobe_channel_pdf(self.lobes[i], wi, wo, c);
  return p / (w.cosine + w.lobes_total);
}
float Lafortune_pdf(Lafortune self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return Lafortune_pdf(self, Lafortune_sampling_weights(self, wo), wi, wo);
}

BSDFSample Lafortune_sample(Lafortune self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  Lafortune_SamplingWeights w = Lafortune_sampling_weights(self, wo);
  // Walk the cumulative weights with uc: cosine first, then each (lobe, channel). Rounding that
  // leaves target >= 0 after the last lobe picks the last positive-weight candidate.
  float target = uc * (w.cosine + w.lobes_total) - w.cosine;
  int lobe = -1, channel = 0;
  for (int i = 0; i < self.lobe_count && !(target < 0.0); ++i)
    for (int c = 0; c < 3 && !(target < 0.0); ++c) {
      if (!(w.lobe[i][c] > 0.0)) continue;
      lobe = i;
      channel = c;
      target -= w.lobe[i][c];
    }
  vec3 wi;
  if (lobe < 0) {
    wi = sample_cosine_hemisphere(u);
  } else {
    vec3 a = LafortuneLobe_axis(self.lobes[lobe], wo, channel);
    wi = sample_cosine_power(a / sqrt(dot(a, a)), self.lobes[lobe].n[channel], u);
  }
  if (!above_horizon(wi)) return BSDFSample_none();
  return make_sample(wi, Lafortune_f(self, wi, wo), Lafortune_pdf(self, w, wi, wo));
}
