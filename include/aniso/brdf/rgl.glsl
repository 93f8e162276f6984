// aniso/brdf/rgl.glsl: GLSL twin of rgl.h: a BRDF tabulated in the RGL tensor format (Dupuy & Jakob
// 2018), evaluated and sampled exactly as pbrt-v4's MeasuredBxDF (src/pbrt/bxdfs.cpp:1018-1117),
// with PL2D = pbrt-v4's PiecewiseLinear2D (src/pbrt/util/sampling.h:1299-1760) reading its tables
// from the measured tables texture (measured.glsl, MeasuredTables_at).
//
// An RGL part of the texture (kind 1), header of 96 floats (offsets relative to the base):
//   [0] 1  [1] isotropic (0 / 1)
//   [16 + 16 k], k = 0..4 for ndf, sigma, vndf, luminance, rgb: one PL2D header
//     size_x, size_y, dim, param_size[3], param_stride[3], param_values[3] (offsets),
//     data, marginal_cdf, conditional_cdf (offsets; the cdfs only where the PL2D samples)
// then the tables, each as rgl_material.h's PL2DTables holds it (slices x size_y x size_x, ...).
//
// GLSL has neither recursion nor fma: lookup() is pbrt-v4's recursion written out for dim <= 3 (the
// last parameter outermost, as there), and fma(a, b, c) is a * b + c, which a driver may or may
// not contract: one rounding of difference (docs/glsl.md gives the parity bound).

struct PL2D {
  int size_x;
  int size_y;
  int dim;
  ivec3 param_size;
  ivec3 param_stride;  // in slices; 0 where param_size is 1
  ivec3 param_values;  // absolute indices of each parameter's grid
  int data;
  int marginal_cdf;
  int conditional_cdf;
};

struct PL2DSample {
  float x;
  float y;
  float pdf;
};

// False where the tables gave 0 / 0 (rgl.h PL2DSample::finite).
bool PL2DSample_finite(PL2DSample s) {
  return s.x >= 0.0 && s.x <= 1.0 && s.y >= 0.0 && s.y <= 1.0 && s.pdf >= 0.0 && s.pdf < 3.4e38;
}

// [0, 1], NaN to 0.
float pl2d_unit(float x) { return x >= 0.0 ? (x <= 1.0 ? x : 1.0) : 0.0; }

PL2D PL2D_load(int base, int at) {
  PL2D p;
  p.size_x = MeasuredTables_int(at);
  p.size_y = MeasuredTables_int(at + 1);
  p.dim = MeasuredTables_int(at + 2);
  p.param_size = ivec3(MeasuredTables_int(at + 3), MeasuredTables_int(at + 4), MeasuredTables_int(at + 5));
  p.param_stride = ivec3(MeasuredTables_int(at + 6), MeasuredTables_int(at + 7), MeasuredTables_int(at + 8));
  p.param_values = ivec3(base) + ivec3(MeasuredTables_int(at + 9), MeasuredTables_int(at + 10), MeasuredTables_int(at + 11));
  p.data = base + MeasuredTables_int(at + 12);
  p.marginal_cdf = base + MeasuredTables_int(at + 13);
  p.conditional_cdf = base + MeasuredTables_int(at + 14);
  return p;
}

float PL2D_inv_patch_x(PL2D self) { return float(self.size_x - 1); }
float PL2D_inv_patch_y(PL2D self) { return float(self.size_y - 1); }

// One parameter of param_lookup (sampling.h:1478-1497): pbrt-v4's FindInterval over the grid at
// `values` (size entries), the weight t of the upper slice, and the interval's index.
int PL2D_param_axis(int size, int values, float p, out float t) {
  t = 0.0;
  if (size == 1) return 0;
  int sz = size - 2, first = 1;
  while (sz > 0) {
    int half_ = sz >> 1, middle = first + half_;
    bool r = MeasuredTables_at(values + middle) <= p;
    first = r ? middle + 1 : first;
    sz = r ? sz - (half_ + 1) : half_;
  }
  int idx = first - 1;
  idx = idx < 0 ? 0 : (idx > size - 2 ? size - 2 : idx);
  float p0 = MeasuredTables_at(values + idx), p1 = MeasuredTables_at(values + idx + 1);
  t = (p - p0) / (p1 - p0);
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return idx;
}

// The slice offset and the weights (w0 = 1 - t, w1 = t) of each parameter.
int PL2D_param_lookup(PL2D self, vec3 param, out vec3 w0, out vec3 w1) {
  int slice_offset = 0;
  float t0 = 0.0, t1 = 0.0, t2 = 0.0;
  if (self.dim > 0) slice_offset += self.param_stride.x * PL2D_param_axis(self.param_size.x, self.param_values.x, param.x, t0);
  if (self.dim > 1) slice_offset += self.param_stride.y * PL2D_param_axis(self.param_size.y, self.param_values.y, param.y, t1);
  if (self.dim > 2) slice_offset += self.param_stride.z * PL2D_param_axis(self.param_size.z, self.param_values.z, param.z, t2);
  w1 = vec3(t0, t1, t2);
  w0 = vec3(1.0) - w1;
  return slice_offset;
}

// pbrt-v4's lookup<Dim> (sampling.h:1727-1745): the multilinear blend of the 2^dim neighbouring
// slices of table entry i0 (absolute index `table` + i0), `size` values per slice.
float PL2D_lookup1(PL2D self, int table, int i0, int size, vec3 w0, vec3 w1) {
  int s0 = self.param_stride.x * size;
  return MeasuredTables_at(table + i0) * w0.x + MeasuredTables_at(table + i0 + s0) * w1.x;
}
float PL2D_lookup2(PL2D self, int table, int i0, int size, vec3 w0, vec3 w1) {
  int s1 = self.param_stride.y * size;
  return PL2D_lookup1(self, table, i0, size, w0, w1) * w0.y + PL2D_lookup1(self, table, i0 + s1, size, w0, w1) * w1.y;
}
float PL2D_lookup(PL2D self, int table, int i0, int size, vec3 w0, vec3 w1) {
  if (self.dim == 0) return MeasuredTables_at(table + i0);
  if (self.dim == 1) return PL2D_lookup1(self, table, i0, size, w0, w1);
  if (self.dim == 2) return PL2D_lookup2(self, table, i0, size, w0, w1);
  int s2 = self.param_stride.z * size;
  return PL2D_lookup2(self, table, i0, size, w0, w1) * w0.z + PL2D_lookup2(self, table, i0 + s2, size, w0, w1) * w1.z;
}

// sampling.h:1462-1567.
PL2DSample PL2D_sample(PL2D self, float sx, float sy, vec3 param) {
  const float kOneMinusEpsilon = 0.99999994;  // 0x1.fffffep-1
  sx = sx < 1.0 - kOneMinusEpsilon ? 1.0 - kOneMinusEpsilon : (sx > kOneMinusEpsilon ? kOneMinusEpsilon : sx);
  sy = sy < 1.0 - kOneMinusEpsilon ? 1.0 - kOneMinusEpsilon : (sy > kOneMinusEpsilon ? kOneMinusEpsilon : sy);
  vec3 w0, w1;
  int slice_offset = PL2D_param_lookup(self, param, w0, w1);
  int offset = self.dim > 0 ? slice_offset * self.size_y : 0;
  // FindInterval over the marginal cdf.
  int sz = self.size_y - 2, first = 1;
  while (sz > 0) {
    int half_ = sz >> 1, middle = first + half_;
    bool r = PL2D_lookup(self, self.marginal_cdf, offset + middle, self.size_y, w0, w1) < sy;
    first = r ? middle + 1 : first;
    sz = r ? sz - (half_ + 1) : half_;
  }
  int row = first - 1;
  row = row < 0 ? 0 : (row > self.size_y - 2 ? self.size_y - 2 : row);
  sy -= PL2D_lookup(self, self.marginal_cdf, offset + row, self.size_y, w0, w1);
  int slice_size = self.size_x * self.size_y;
  offset = row * self.size_x;
  if (self.dim > 0) offset += slice_offset * slice_size;
  float r0 = PL2D_lookup(self, self.conditional_cdf, offset + self.size_x - 1, slice_size, w0, w1),
        r1 = PL2D_lookup(self, self.conditional_cdf, offset + self.size_x * 2 - 1, slice_size, w0, w1);
  bool is_const = abs(r0 - r1) < 1e-4 * (r0 + r1);
  sy = is_const ? (2.0 * sy) : (r0 - safe_sqrt(r0 * r0 - 2.0 * sy * (r0 - r1)));
  sy /= is_const ? (r0 + r1) : (r0 - r1);
  sx *= (1.0 - sy) * r0 + sy * r1;
  // FindInterval over the conditional cdf, blended between the two rows.
  sz = self.size_x - 2;
  first = 1;
  while (sz > 0) {
    int half_ = sz >> 1, middle = first + half_;
    float v0 = PL2D_lookup(self, self.conditional_cdf, offset + middle, slice_size, w0, w1),
          v1 = PL2D_lookup(self, self.conditional_cdf + self.size_x, offset + middle, slice_size, w0, w1);
    bool r = (1.0 - sy) * v0 + sy * v1 < sx;
    first = r ? middle + 1 : first;
    sz = r ? sz - (half_ + 1) : half_;
  }
  int col = first - 1;
  col = col < 0 ? 0 : (col > self.size_x - 2 ? self.size_x - 2 : col);
  {
    float v0 = PL2D_lookup(self, self.conditional_cdf, offset + col, slice_size, w0, w1),
          v1 = PL2D_lookup(self, self.conditional_cdf + self.size_x, offset + col, slice_size, w0, w1);
    sx -= (1.0 - sy) * v0 + sy * v1;
  }
  offset += col;
  float v00 = PL2D_lookup(self, self.data, offset, slice_size, w0, w1),
        v10 = PL2D_lookup(self, self.data + 1, offset, slice_size, w0, w1),
        v01 = PL2D_lookup(self, self.data + self.size_x, offset, slice_size, w0, w1),
        v11 = PL2D_lookup(self, self.data + self.size_x + 1, offset, slice_size, w0, w1);
  float c0 = (1.0 - sy) * v00 + sy * v01, c1 = (1.0 - sy) * v10 + sy * v11;
  is_const = abs(c0 - c1) < 1e-4 * (c0 + c1);
  sx = is_const ? (2.0 * sx) : (c0 - safe_sqrt(c0 * c0 - 2.0 * sx * (c0 - c1)));
  sx /= is_const ? (c0 + c1) : (c0 - c1);
  PL2DSample s;
  s.x = (float(col) + sx) / PL2D_inv_patch_x(self);
  s.y = (float(row) + sy) / PL2D_inv_patch_y(self);
  s.pdf = ((1.0 - sx) * c0 + sx * c1) * PL2D_inv_patch_x(self) * PL2D_inv_patch_y(self);
  return s;
}

// The inverse of PL2D_sample (sampling.h:1570-1655).
PL2DSample PL2D_invert(PL2D self, float sx, float sy, vec3 param) {
  sx = pl2d_unit(sx);
  sy = pl2d_unit(sy);
  vec3 w0, w1;
  int slice_offset = PL2D_param_lookup(self, param, w0, w1);
  sx *= PL2D_inv_patch_x(self);
  sy *= PL2D_inv_patch_y(self);
  int px = int(sx), py = int(sy);
  px = px < self.size_x - 2 ? px : self.size_x - 2;
  py = py < self.size_y - 2 ? py : self.size_y - 2;
  sx -= float(px);
  sy -= float(py);
  int slice_size = self.size_x * self.size_y;
  int offset = px + py * self.size_x;
  if (self.dim > 0) offset += slice_offset * slice_size;
  float v00 = PL2D_lookup(self, self.data, offset, slice_size, w0, w1),
        v10 = PL2D_lookup(self, self.data + 1, offset, slice_size, w0, w1),
        v01 = PL2D_lookup(self, self.data + self.size_x, offset, slice_size, w0, w1),
        v11 = PL2D_lookup(self, self.data + self.size_x + 1, offset, slice_size, w0, w1);
  float w1x = sx, w1y = sy, w0x = 1.0 - sx, w0y = 1.0 - sy;
  float c0 = w0y * v00 + w1y * v01, c1 = w0y * v10 + w1y * v11, pdf = w0x * c0 + w1x * c1;
  sx *= c0 + 0.5 * sx * (c1 - c0);
  float v0 = PL2D_lookup(self, self.conditional_cdf, offset, slice_size, w0, w1),
        v1 = PL2D_lookup(self, self.conditional_cdf + self.size_x, offset, slice_size, w0, w1);
  sx += (1.0 - sy) * v0 + sy * v1;
  offset = py * self.size_x;
  if (self.dim > 0) offset += slice_offset * slice_size;
  float r0 = PL2D_lookup(self, self.conditional_cdf, offset + self.size_x - 1, slice_size, w0, w1),
        r1 = PL2D_lookup(self, self.conditional_cdf, offset + self.size_x * 2 - 1, slice_size, w0, w1);
  sx /= (1.0 - sy) * r0 + sy * r1;
  sy *= r0 + 0.5 * sy * (r1 - r0);
  offset = py;
  if (self.dim > 0) offset += slice_offset * self.size_y;
  sy += PL2D_lookup(self, self.marginal_cdf, offset, self.size_y, w0, w1);
  PL2DSample s;
  s.x = sx;
  s.y = sy;
  s.pdf = pdf * PL2D_inv_patch_x(self) * PL2D_inv_patch_y(self);
  return s;
}

// sampling.h:1661-1715.
float PL2D_evaluate(PL2D self, float x, float y, vec3 param) {
  vec3 w0 = vec3(1.0), w1 = vec3(0.0);
  int slice_offset = self.dim > 0 ? PL2D_param_lookup(self, param, w0, w1) : 0;
  x = pl2d_unit(x) * PL2D_inv_patch_x(self);
  y = pl2d_unit(y) * PL2D_inv_patch_y(self);
  int ox = int(x), oy = int(y);
  ox = ox < self.size_x - 2 ? ox : self.size_x - 2;
  oy = oy < self.size_y - 2 ? oy : self.size_y - 2;
  float w1x = x - float(ox), w1y = y - float(oy), w0x = 1.0 - w1x, w0y = 1.0 - w1y;
  int index = ox + oy * self.size_x;
  int size = self.size_x * self.size_y;
  if (self.dim > 0) index += slice_offset * size;
  float v00 = PL2D_lookup(self, self.data, index, size, w0, w1), v10 = PL2D_lookup(self, self.data + 1, index, size, w0, w1),
        v01 = PL2D_lookup(self, self.data + self.size_x, index, size, w0, w1),
        v11 = PL2D_lookup(self, self.data + self.size_x + 1, index, size, w0, w1);
  return (w0y * (w0x * v00 + w1x * v10) + w1y * (w0x * v01 + w1x * v11)) * PL2D_inv_patch_x(self) * PL2D_inv_patch_y(self);
}

// pbrt-v4 bxdfs.h:1058-1065: the warped unit square of the tables.
float rgl_theta2u(float theta) { return sqrt(theta * (2.0 / kPi)); }
float rgl_phi2u(float phi) { return phi * (1.0 / (2.0 * kPi)) + 0.5; }
float rgl_u2theta(float u) { return u * u * (kPi / 2.0); }
float rgl_u2phi(float u) { return (2.0 * u - 1.0) * kPi; }

// The interpolants of one file (pbrt-v4's MeasuredBxDFData).
struct Rgl {
  PL2D ndf;
  PL2D sigma;
  PL2D vndf;
  PL2D luminance;
  PL2D rgb;  // spectra interpolant with 3 "wavelengths" 0, 1, 2
  bool isotropic;
};

// The kernel of the RGL part at `base` (its header, above).
Rgl Rgl_load(int base) {
  Rgl r;
  r.isotropic = MeasuredTables_int(base + 1) != 0;
  r.ndf = PL2D_load(base, base + 16);
  r.sigma = PL2D_load(base, base + 32);
  r.vndf = PL2D_load(base, base + 48);
  r.luminance = PL2D_load(base, base + 64);
  r.rgb = PL2D_load(base, base + 80);
  return r;
}

// pbrt-v4 SphericalTheta (SafeACos(z)), written as atan2(|w.xy|, z), the same angle for a unit w:
// GLSL's acos is not held to glibc's accuracy (llvmpipe's was 6e-5 rad off at z = 0.68, as an
// acos(z) = atan(sqrt(1 - z^2), z) loses in 1 - z^2), where atan2 of the two components is
// within a few ulp of the C++'s acos.
float Rgl_theta_of(vec3 w) { return measured_atan2(sqrt(w.x * w.x + w.y * w.y), w.z); }

// Colour at (x, y) of slice (phi_o, theta_o), clamped at 0 per channel (bxdfs.cpp:1043-1045).
vec3 Rgl_colour(Rgl self, float x, float y, float phi_o, float theta_o) {
  float r = PL2D_evaluate(self.rgb, x, y, vec3(phi_o, theta_o, 0.0)), g = PL2D_evaluate(self.rgb, x, y, vec3(phi_o, theta_o, 1.0)),
        b = PL2D_evaluate(self.rgb, x, y, vec3(phi_o, theta_o, 2.0));
  return vec3(r > 0.0 ? r : 0.0, g > 0.0 ? g : 0.0, b > 0.0 ? b : 0.0);  // NaN to 0, as the C++
}

// bxdfs.cpp:1018-1050 (MeasuredBxDF::f), one-sided.
vec3 Rgl_f(Rgl self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  vec3 wm = wi + wo;
  if (dot(wm, wm) == 0.0) return vec3(0.0);
  wm = normalize(wm);
  float theta_o = Rgl_theta_of(wo), phi_o = measured_atan2(wo.y, wo.x);
  float theta_m = Rgl_theta_of(wm), phi_m = measured_atan2(wm.y, wm.x);
  float uo_x = rgl_theta2u(theta_o), uo_y = rgl_phi2u(phi_o);
  float um_x = rgl_theta2u(theta_m);
  float um_y = rgl_phi2u(self.isotropic ? (phi_m - phi_o) : phi_m);
  um_y = um_y - floor(um_y);
  vec3 p = vec3(phi_o, theta_o, 0.0);
  PL2DSample ui = PL2D_invert(self.vndf, um_x, um_y, p);
  if (!PL2DSample_finite(ui)) return vec3(0.0);
  vec3 fr = Rgl_colour(self, ui.x, ui.y, phi_o, theta_o);
  return fr * (PL2D_evaluate(self.ndf, um_x, um_y, p) / (4.0 * PL2D_evaluate(self.sigma, uo_x, uo_y, p) * wi.z));
}

// bxdfs.cpp:1085-1114 (MeasuredBxDF::PDF).
float Rgl_pdf(Rgl self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  vec3 wm = wi + wo;
  if (dot(wm, wm) == 0.0) return 0.0;
  wm = normalize(wm);
  float theta_o = Rgl_theta_of(wo), phi_o = measured_atan2(wo.y, wo.x);
  float theta_m = Rgl_theta_of(wm), phi_m = measured_atan2(wm.y, wm.x);
  float um_x = rgl_theta2u(theta_m);
  float um_y = rgl_phi2u(self.isotropic ? (phi_m - phi_o) : phi_m);
  um_y = um_y - floor(um_y);
  vec3 p = vec3(phi_o, theta_o, 0.0);
  PL2DSample ui = PL2D_invert(self.vndf, um_x, um_y, p);
  if (!PL2DSample_finite(ui)) return 0.0;
  float lum = PL2D_evaluate(self.luminance, ui.x, ui.y, p);
  float sin_m = sqrt(wm.x * wm.x + wm.y * wm.y);
  // 1e-6: pbrt-v4's floor on the Jacobian, 0 at the pole (bxdfs.cpp:1110-1111).
  float jac = 4.0 * dot(wo, wm) * max(2.0 * kPi * kPi * um_x * sin_m, 1e-6);
  return ui.pdf * lum / jac;
}

// bxdfs.cpp:1052-1083 (MeasuredBxDF::Sample_f); uc is unused, as in pbrt-v4.
BSDFSample Rgl_sample(Rgl self, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  float theta_o = Rgl_theta_of(wo), phi_o = measured_atan2(wo.y, wo.x);
  vec3 p = vec3(phi_o, theta_o, 0.0);
  PL2DSample sl = PL2D_sample(self.luminance, u.x, u.y, p);
  if (!PL2DSample_finite(sl)) return BSDFSample_none();
  PL2DSample sv = PL2D_sample(self.vndf, sl.x, sl.y, p);
  if (!PL2DSample_finite(sv)) return BSDFSample_none();
  float phi_m = rgl_u2phi(sv.y);
  float theta_m = rgl_u2theta(sv.x);
  if (self.isotropic) phi_m += phi_o;
  float sin_m = sin(theta_m), cos_m = cos(theta_m);
  vec3 wm = vec3(sin_m * cos(phi_m), sin_m * sin(phi_m), cos_m);
  vec3 wi = 2.0 * dot(wo, wm) * wm - wo;
  if (!(wi.z > 0.0)) return BSDFSample_none();
  vec3 fr = Rgl_colour(self, sl.x, sl.y, phi_o, theta_o);
  float uo_x = rgl_theta2u(theta_o), uo_y = rgl_phi2u(phi_o);
  fr *= PL2D_evaluate(self.ndf, sv.x, sv.y, p) / (4.0 * PL2D_evaluate(self.sigma, uo_x, uo_y, p) * wi.z);
  float pdf = sv.pdf / (4.0 * dot(wo, wm) * max(2.0 * kPi * kPi * sv.x * sin_m, 1e-6));
  return make_sample(wi, fr, pdf * sl.pdf);
}
