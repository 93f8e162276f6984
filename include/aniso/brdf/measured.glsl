// aniso/brdf/measured.glsl: GLSL twin of measured.h: a MERL table (Matusik et al. 2003) with its
// tabulated sampling, and the float texture that holds the tables of every measured material
// (this file's and rgl.glsl's).
//
// The tables texture (docs/glsl.md, "Measured materials"): one R32F texture, kMeasuredTablesWidth
// = 4096 texels wide, read with texelFetch (no filtering: the kernels interpolate themselves), the
// tables one after the other as a flat array of floats, texel i at (i % 4096, i / 4096). A
// material's part starts at a base index with a header of small integers (sizes and offsets, exact
// in float below 2^24) followed by its tables; gl::glsl_tables() (src/gl/glsl_material.cpp) writes
// it, the web page's explorer.js writes the same. The host binds the texture to the sampler
// MeasuredTables_texture.
//
// A MERL part (kind 2), header of 16 floats:
//   [0] 2  [1] theta_o_bins  [2] phi_h_bins  [3] uniform_fraction
//   [4] table            3 x 90 x 90 x 180 values, R then G then B, phi_d fastest (merl_index)
//   [5] marginal_cdf     [theta_o_bins][91]
//   [6] conditional_cdf  [theta_o_bins][90][phi_h_bins + 1]
//   [7] v_edges          [91]
//   [8] cell_density     [theta_o_bins][90][phi_h_bins]: P(cell) / solid angle(cell), computed in
//                        double from the cdfs: a difference of two float cdf entries near 1 would
//                        lose the small cells (an entry of 1 - 1e-7 has 2 correct bits of its cell)
// offsets relative to the base.

uniform highp sampler2D MeasuredTables_texture;
const int kMeasuredTablesWidth = 4096;

float MeasuredTables_at(int i) { return texelFetch(MeasuredTables_texture, ivec2(i & 4095, i >> 12), 0).r; }
int MeasuredTables_int(int i) { return int(MeasuredTables_at(i) + 0.5); }

// atan2 with C's value at the origin (0): GLSL's atan(0, 0) is undefined.
float measured_atan2(float y, float x) { return (x == 0.0 && y == 0.0) ? 0.0 : atan(y, x); }

// MERL's table dimensions (BRDFRead.cpp).
const int kMerlThetaH = 90;
const int kMerlThetaD = 90;
const int kMerlPhiD = 180;
const int kMerlBins = 1458000;

// MERL's index maps (BRDFRead.cpp, theta_half_index, theta_diff_index, phi_diff_index).
int merl_theta_half_index(float theta_h) {
  if (!(theta_h > 0.0)) return 0;
  int i = int(sqrt(theta_h / kPiOver2) * float(kMerlThetaH));
  return i < 0 ? 0 : (i >= kMerlThetaH ? kMerlThetaH - 1 : i);
}
int merl_theta_diff_index(float theta_d) {
  int i = int(theta_d / kPiOver2 * float(kMerlThetaD));
  return i < 0 ? 0 : (i >= kMerlThetaD ? kMerlThetaD - 1 : i);
}
int merl_phi_diff_index(float phi_d) {
  if (phi_d < 0.0) phi_d += kPi;  // reciprocity: f is unchanged under phi_d -> phi_d + pi
  int i = int(phi_d / kPi * float(kMerlPhiD));
  return i < 0 ? 0 : (i >= kMerlPhiD ? kMerlPhiD - 1 : i);
}
int merl_index(int i_theta_h, int i_theta_d, int i_phi_d) { return i_phi_d + kMerlPhiD * (i_theta_d + kMerlThetaD * i_theta_h); }

// The bin of (wi, wo): Rusinkiewicz's half/difference angles as MERL computes them, with atan2 as
// measured.h (float keeps the smallest theta_h bins).
int merl_bin(vec3 wi, vec3 wo) {
  vec3 h = normalize(wi + wo);
  float sin_h = sqrt(h.x * h.x + h.y * h.y);
  float theta_h = measured_atan2(sin_h, h.z);
  float cp = sin_h > 0.0 ? h.x / sin_h : 1.0, sp = sin_h > 0.0 ? h.y / sin_h : 0.0;
  float x1 = wi.x * cp + wi.y * sp, y1 = -wi.x * sp + wi.y * cp, z1 = wi.z;
  float ct = h.z, st = sin_h;
  float dx = x1 * ct - z1 * st, dy = y1, dz = x1 * st + z1 * ct;
  float theta_d = measured_atan2(sqrt(dx * dx + dy * dy), dz);
  float phi_d = measured_atan2(dy, dx);
  return merl_index(merl_theta_half_index(theta_h), merl_theta_diff_index(theta_d), merl_phi_diff_index(phi_d));
}

// The kernel: absolute indices of its tables in the texture.
struct Measured {
  int table;
  int marginal_cdf;
  int conditional_cdf;
  int v_edges;
  int cell_density;
  int theta_o_bins;
  int phi_h_bins;
  float uniform_fraction;
};

// The kernel of the MERL part at `base` (its header, above).
Measured Measured_load(int base) {
  Measured m;
  m.theta_o_bins = MeasuredTables_int(base + 1);
  m.phi_h_bins = MeasuredTables_int(base + 2);
  m.uniform_fraction = MeasuredTables_at(base + 3);
  m.table = base + MeasuredTables_int(base + 4);
  m.marginal_cdf = base + MeasuredTables_int(base + 5);
  m.conditional_cdf = base + MeasuredTables_int(base + 6);
  m.v_edges = base + MeasuredTables_int(base + 7);
  m.cell_density = base + MeasuredTables_int(base + 8);
  return m;
}

// merl_lookup: 0 below the horizon and for a missing bin (any channel negative).
vec3 Measured_f(Measured self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  int k = self.table + merl_bin(wi, wo);
  float r = MeasuredTables_at(k), g = MeasuredTables_at(k + kMerlBins), b = MeasuredTables_at(k + 2 * kMerlBins);
  if (r < 0.0 || g < 0.0 || b < 0.0) return vec3(0.0);
  return vec3(r, g, b);
}

// Index k of the interval [cdf[k], cdf[k+1]) holding u, and u's position within it in [0, 1)
// (measured.h sample_cdf, on the float cdf).
int measured_sample_cdf(int cdf, int n, float u, out float u_remapped) {
  int lo = 0, hi = n;  // invariant: cdf[lo] <= u < cdf[hi]
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (MeasuredTables_at(cdf + mid) <= u)
      lo = mid;
    else
      hi = mid;
  }
  float c0 = MeasuredTables_at(cdf + lo);
  float w = MeasuredTables_at(cdf + lo + 1) - c0;
  float r = w > 0.0 ? (u - c0) / w : 0.0;
  u_remapped = r < 0.0 ? 0.0 : (r < 1.0 ? r : 0.99999994);  // < 1
  return lo;
}

// wo's azimuth (cos, sin) and its viewing-angle bin (measured.h view_frame).
void Measured_view_frame(Measured self, vec3 wo, out float c, out float s, out int o) {
  float r = sqrt(wo.x * wo.x + wo.y * wo.y);
  c = r > 0.0 ? wo.x / r : 1.0;
  s = r > 0.0 ? wo.y / r : 0.0;
  int bin = int(measured_atan2(r, wo.z) / kPiOver2 * float(self.theta_o_bins));
  o = bin < 0 ? 0 : (bin >= self.theta_o_bins ? self.theta_o_bins - 1 : bin);
}

// Density of the tabulated part at wi: P(cell) / solid angle(cell) / (4 wo.h) (Walter et al. 2007, Eq. 14).
float Measured_table_pdf(Measured self, vec3 wi, vec3 wo) {
  float c, s;
  int o;
  Measured_view_frame(self, wo, c, s, o);
  vec3 h = normalize(wi + wo);
  float hx = h.x * c + h.y * s, hy = -h.x * s + h.y * c;
  float sin_h = sqrt(hx * hx + hy * hy);
  int i = merl_theta_half_index(measured_atan2(sin_h, h.z));
  float phi = measured_atan2(hy, hx);
  if (phi < 0.0) phi += 2.0 * kPi;
  int j = int(phi * kInv2Pi * float(self.phi_h_bins));
  j = j < 0 ? 0 : (j >= self.phi_h_bins ? self.phi_h_bins - 1 : j);
  float density = MeasuredTables_at(self.cell_density + (o * kMerlThetaH + i) * self.phi_h_bins + j);
  float woh = dot(wo, h);
  if (!(density > 0.0) || !(woh > 0.0)) return 0.0;
  return density / (4.0 * woh);
}

float Measured_pdf(Measured self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return self.uniform_fraction * cosine_hemisphere_pdf(wi.z) + (1.0 - self.uniform_fraction) * Measured_table_pdf(self, wi, wo);
}

BSDFSample Measured_sample(Measured self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  vec3 wi;
  if (uc < self.uniform_fraction) {
    wi = sample_cosine_hemisphere(u);
  } else {
    float c, s;
    int o;
    Measured_view_frame(self, wo, c, s, o);
    float fx, fy;
    int i = measured_sample_cdf(self.marginal_cdf + o * (kMerlThetaH + 1), kMerlThetaH, u.x, fx);
    int j = measured_sample_cdf(self.conditional_cdf + (o * kMerlThetaH + i) * (self.phi_h_bins + 1), self.phi_h_bins, u.y, fy);
    // uniform in solid angle within the cell: v = 1 - cos(theta_h) linear in fx; sin from v(2 - v)
    float v0 = MeasuredTables_at(self.v_edges + i), v1 = MeasuredTables_at(self.v_edges + i + 1);
    float v = v0 + (v1 - v0) * fx;
    float sin_h = safe_sqrt(v * (2.0 - v)), cos_h = 1.0 - v;
    float phi = (float(j) + fy) * 2.0 * kPi / float(self.phi_h_bins);
    float hx = sin_h * cos(phi), hy = sin_h * sin(phi);
    vec3 h = vec3(hx * c - hy * s, hx * s + hy * c, cos_h);  // back to the shading frame
    float woh = dot(wo, h);
    if (!(woh > 0.0)) return BSDFSample_none();
    wi = reflect_about(wo, h);
  }
  return make_sample(wi, Measured_f(self, wi, wo), Measured_pdf(self, wi, wo));
}
