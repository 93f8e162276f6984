// aniso/core/sampling.glsl: GLSL twin of sampling.h: the sampling routines the models share, each
// with its density. u values are uniform in [0, 1).

// Result of <Model>_sample(self, wo, uc, u). weight = f(wi, wo) cos(theta_i) / pdf, per channel.
// valid == false is "no sample" (wi below the horizon, degenerate wo, zero pdf); all fields are 0.
struct BSDFSample {
  vec3 wi;
  vec3 weight;
  float pdf;
  bool valid;
};

// The C++ `return {};`: "no sample".
BSDFSample BSDFSample_none() { return BSDFSample(vec3(0.0), vec3(0.0), 0.0, false); }

// Builds the sample record for a sampled wi from the model's own f and pdf; any wi the model
// cannot use becomes "no sample". Keeps weight == f cos / pdf true by construction.
BSDFSample make_sample(vec3 wi, vec3 f, float pdf) {
  BSDFSample s = BSDFSample_none();
  if (!above_horizon(wi) || !(pdf > 0.0)) return s;
  s.wi = wi;
  s.pdf = pdf;
  s.weight = f * (wi.z / pdf);
  s.valid = true;
  return s;
}

// Cosine-weighted hemisphere (Malley's method via the concentric disk map, Shirley & Chiu 1997).
vec2 sample_uniform_disk_concentric(vec2 u) {
  float ox = 2.0 * u.x - 1.0, oy = 2.0 * u.y - 1.0;
  if (ox == 0.0 && oy == 0.0) return vec2(0.0);
  float r, theta;
  if ((ox < 0.0 ? -ox : ox) > (oy < 0.0 ? -oy : oy)) {
    r = ox;
    theta = kPi / 4.0 * (oy / ox);
  } else {
    r = oy;
    theta = kPiOver2 - kPi / 4.0 * (ox / oy);
  }
  return vec2(r * cos(theta), r * sin(theta));
}

vec3 sample_cosine_hemisphere(vec2 u) {
  vec2 d = sample_uniform_disk_concentric(u);
  return vec3(d.x, d.y, safe_sqrt(1.0 - d.x * d.x - d.y * d.y));
}

float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0.0 ? cos_theta * kInvPi : 0.0; }

// Any unit vectors t, b completing the unit axis a to a right-handed frame (Duff et al. 2017).
void orthonormal_basis(vec3 a, out vec3 t, out vec3 b) {
  float sgn = copysign_one(a.z);
  float k = -1.0 / (sgn + a.z);
  float m = a.x * a.y * k;
  t = vec3(1.0 + sgn * a.x * a.x * k, sgn * m, -sgn * a.x);
  b = vec3(m, sgn + a.y * a.y * k, -a.y);
}

// Cosine-power lobe about the unit axis a: density (n + 1) / (2 pi) (a . w)^n on the hemisphere
// around a (Phong / Lafortune lobes; Lafortune et al. 1997, Sec. 4; Lawrence's notes).
vec3 sample_cosine_power(vec3 a, float n, vec2 u) {
  float cos_t = pow(1.0 - u.x, 1.0 / (n + 1.0));  // 1 - u in (0, 1]: avoids pow(0, .)
  float sin_t = safe_sqrt(1.0 - cos_t * cos_t);
  float phi = 2.0 * kPi * u.y;
  vec3 t, b;
  orthonormal_basis(a, t, b);
  return sin_t * cos(phi) * t + sin_t * sin(phi) * b + cos_t * a;
}

float cosine_power_pdf(float cos_axis, float n) {
  return cos_axis > 0.0 ? (n + 1.0) * kInv2Pi * pow(cos_axis, n) : 0.0;
}
