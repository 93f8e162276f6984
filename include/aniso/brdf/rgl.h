// aniso/brdf/rgl.h: a BRDF tabulated in the RGL tensor format (Dupuy & Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering", ACM TOG 37(6)), evaluated and
// sampled exactly as pbrt-v4's MeasuredBxDF does (src/pbrt/bxdfs.cpp:1018-1117), so that a file
// looks the same here, in pbrt-v4 and in Mitsuba 3 (src/bsdfs/measured.cpp:285-470).
// docs/rgl.md describes the tables; src/rgl/ reads and writes them.
//
// PL2D is pbrt-v4's PiecewiseLinear2D<Dimension> (src/pbrt/util/sampling.h:1299-1760, Mitsuba 3's
// Marginal2D): a bilinear density on a regular grid over [0,1]^2, possibly conditioned on up to
// three extra parameters (each on its own grid, linear between slices), with Sample, Invert and
// Evaluate. Kernels see plain pointers into host-owned tables (include/aniso/rgl/rgl_material.h builds them,
// with the constructor's normalisation and cdfs).
//
// Directions: aniso's wo (towards the viewer, the direction given to sample()) is pbrt-v4's wo, the
// one that selects the slice (phi_o, theta_o); aniso's wi is pbrt-v4's wi.
#pragma once

#include "aniso/core/kernel.h"
#include "aniso/core/sampling.h"

namespace aniso {

struct PL2DSample {
  float x = 0.f, y = 0.f, pdf = 0.f;
  // False where the tables gave 0 / 0 (a sample or an inversion through a cell of zero density,
  // which pbrt-v4 does not guard: there it yields NaN and out-of-range indices).
  ANISO_HD bool finite() const { return x >= 0.f && x <= 1.f && y >= 0.f && y <= 1.f && pdf >= 0.f && pdf < 3.4e38f; }
};

// [0, 1], NaN to 0: the table index of a NaN coordinate would be undefined.
ANISO_INLINE float pl2d_unit(float x) { return x >= 0.f ? (x <= 1.f ? x : 1.f) : 0.f; }

// pbrt-v4 util/math.h FindInterval: the largest index i in [0, size - 2] with pred(i) true (pred
// monotone, true then false), clamped.
template <typename Pred> ANISO_INLINE int pl2d_find_interval(int size, const Pred& pred) {
  int sz = size - 2, first = 1;
  while (sz > 0) {
    const int half = sz >> 1, middle = first + half;
    const bool r = pred(middle);
    first = r ? middle + 1 : first;
    sz = r ? sz - (half + 1) : half;
  }
  const int i = first - 1;
  return i < 0 ? 0 : (i > size - 2 ? size - 2 : i);
}

struct PL2D {
  int size_x = 0, size_y = 0;  // grid resolution (>= 2 each)
  int dim = 0;                 // number of conditioning parameters, 0 to 3
  int param_size[3] = {1, 1, 1};
  int param_stride[3] = {0, 0, 0};  // in slices; 0 where param_size is 1 (sampling.h:1368)
  const float* param_values[3] = {nullptr, nullptr, nullptr};
  const float* data = nullptr;             // slices x size_y x size_x, normalised per slice
  const float* marginal_cdf = nullptr;     // slices x size_y (Sample / Invert only)
  const float* conditional_cdf = nullptr;  // slices x size_y x size_x

  ANISO_HD float inv_patch_x() const { return float(size_x - 1); }
  ANISO_HD float inv_patch_y() const { return float(size_y - 1); }

  // Slice offset and the 2 * dim interpolation weights of the parameters (sampling.h:1478-1497).
  ANISO_HD unsigned param_lookup(const float* param, float* w) const {
    unsigned slice_offset = 0;
    for (int d = 0; d < dim; ++d) {
      if (param_size[d] == 1) {
        w[2 * d] = 1.f;
        w[2 * d + 1] = 0.f;
        continue;
      }
      const float* pv = param_values[d];
      const float p = param[d];
      const int idx = pl2d_find_interval(param_size[d], [&](int i) { return pv[i] <= p; });
      const float p0 = pv[idx], p1 = pv[idx + 1];
      float t = (p - p0) / (p1 - p0);
      t = t < 0.f ? 0.f : (t > 1.f ? 1.f : t);
      w[2 * d + 1] = t;
      w[2 * d] = 1.f - t;
      slice_offset += unsigned(param_stride[d]) * unsigned(idx);
    }
    return slice_offset;
  }

  // pbrt-v4's lookup<Dim> (sampling.h:1727-1745): multilinear blend of the 2^dim neighbouring
  // slices, the last parameter innermost, as its recursion.
  ANISO_HD float lookup(const float* base, unsigned i0, unsigned size, const float* w) const {
    return lookup_rec(base, i0, size, w, dim);
  }
  ANISO_HD float lookup_rec(const float* base, unsigned i0, unsigned size, const float* w, int d) const {
    if (d == 0) return base[i0];
    const unsigned i1 = i0 + unsigned(param_stride[d - 1]) * size;
    const float w0 = w[2 * d - 2], w1 = w[2 * d - 1];
    const float v0 = lookup_rec(base, i0, size, w, d - 1), v1 = lookup_rec(base, i1, size, w, d - 1);
    return std::fma(v0, w0, v1 * w1);
  }

  // sampling.h:1462-1567.
  ANISO_HD PL2DSample sample(float sx, float sy, const float* param) const {
    using std::abs;
    constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
    sx = sx < 1.f - kOneMinusEpsilon ? 1.f - kOneMinusEpsilon : (sx > kOneMinusEpsilon ? kOneMinusEpsilon : sx);
    sy = sy < 1.f - kOneMinusEpsilon ? 1.f - kOneMinusEpsilon : (sy > kOneMinusEpsilon ? kOneMinusEpsilon : sy);
    float w[6];
    const unsigned slice_offset = param_lookup(param, w);
    unsigned offset = dim ? slice_offset * unsigned(size_y) : 0u;
    const unsigned ysz = unsigned(size_y);
    const int row =
        pl2d_find_interval(size_y, [&](int idx) { return lookup(marginal_cdf, offset + unsigned(idx), ysz, w) < sy; });
    sy -= lookup(marginal_cdf, offset + unsigned(row), ysz, w);
    const unsigned slice_size = unsigned(size_x * size_y);
    offset = unsigned(row * size_x);
    if (dim) offset += slice_offset * slice_size;
    const float r0 = lookup(conditional_cdf, offset + unsigned(size_x) - 1, slice_size, w),
                r1 = lookup(conditional_cdf, offset + unsigned(size_x * 2 - 1), slice_size, w);
    bool is_const = abs(r0 - r1) < 1e-4f * (r0 + r1);
    sy = is_const ? (2.f * sy) : (r0 - safe_sqrt(r0 * r0 - 2.f * sy * (r0 - r1)));
    sy /= is_const ? (r0 + r1) : (r0 - r1);
    sx *= (1.f - sy) * r0 + sy * r1;
    const int col = pl2d_find_interval(size_x, [&](int idx) {
      const float v0 = lookup(conditional_cdf, offset + unsigned(idx), slice_size, w),
                  v1 = lookup(conditional_cdf + size_x, offset + unsigned(idx), slice_size, w);
      return (1.f - sy) * v0 + sy * v1 < sx;
    });
    {
      const float v0 = lookup(conditional_cdf, offset + unsigned(col), slice_size, w),
                  v1 = lookup(conditional_cdf + size_x, offset + unsigned(col), slice_size, w);
      sx -= (1.f - sy) * v0 + sy * v1;
    }
    offset += unsigned(col);
    const float v00 = lookup(data, offset, slice_size, w), v10 = lookup(data + 1, offset, slice_size, w),
                v01 = lookup(data + size_x, offset, slice_size, w), v11 = lookup(data + size_x + 1, offset, slice_size, w);
    const float c0 = std::fma(1.f - sy, v00, sy * v01), c1 = std::fma(1.f - sy, v10, sy * v11);
    is_const = abs(c0 - c1) < 1e-4f * (c0 + c1);
    sx = is_const ? (2.f * sx) : (c0 - safe_sqrt(c0 * c0 - 2.f * sx * (c0 - c1)));
    sx /= is_const ? (c0 + c1) : (c0 - c1);
    PL2DSample s;
    s.x = (float(col) + sx) / inv_patch_x();
    s.y = (float(row) + sy) / inv_patch_y();
    s.pdf = ((1.f - sx) * c0 + sx * c1) * inv_patch_x() * inv_patch_y();
    return s;
  }

  // The inverse of sample() (sampling.h:1570-1655).
  ANISO_HD PL2DSample invert(float sx, float sy, const float* param) const {
    sx = pl2d_unit(sx);
    sy = pl2d_unit(sy);
    float w[6];
    const unsigned slice_offset = param_lookup(param, w);
    sx *= inv_patch_x();
    sy *= inv_patch_y();
    int px = int(sx), py = int(sy);
    px = px < size_x - 2 ? px : size_x - 2;
    py = py < size_y - 2 ? py : size_y - 2;
    sx -= float(px);
    sy -= float(py);
    const unsigned slice_size = unsigned(size_x * size_y);
    unsigned offset = unsigned(px + py * size_x);
    if (dim) offset += slice_offset * slice_size;
    const float v00 = lookup(data, offset, slice_size, w), v10 = lookup(data + 1, offset, slice_size, w),
                v01 = lookup(data + size_x, offset, slice_size, w), v11 = lookup(data + size_x + 1, offset, slice_size, w);
    const float w1x = sx, w1y = sy, w0x = 1.f - sx, w0y = 1.f - sy;
    const float c0 = std::fma(w0y, v00, w1y * v01), c1 = std::fma(w0y, v10, w1y * v11), pdf = std::fma(w0x, c0, w1x * c1);
    sx *= c0 + .5f * sx * (c1 - c0);
    const float v0 = lookup(conditional_cdf, offset, slice_size, w), v1 = lookup(conditional_cdf + size_x, offset, slice_size, w);
    sx += (1.f - sy) * v0 + sy * v1;
    offset = unsigned(py * size_x);
    if (dim) offset += slice_offset * slice_size;
    const float r0 = lookup(conditional_cdf, offset + unsigned(size_x) - 1, slice_size, w),
                r1 = lookup(conditional_cdf, offset + unsigned(size_x * 2 - 1), slice_size, w);
    sx /= (1.f - sy) * r0 + sy * r1;
    sy *= r0 + .5f * sy * (r1 - r0);
    offset = unsigned(py);
    if (dim) offset += slice_offset * unsigned(size_y);
    sy += lookup(marginal_cdf, offset, unsigned(size_y), w);
    PL2DSample s;
    s.x = sx;
    s.y = sy;
    s.pdf = pdf * inv_patch_x() * inv_patch_y();
    return s;
  }

  // sampling.h:1661-1715.
  ANISO_HD float evaluate(float x, float y, const float* param) const {
    float w[6];
    const unsigned slice_offset = dim ? param_lookup(param, w) : 0u;
    x = pl2d_unit(x) * inv_patch_x();
    y = pl2d_unit(y) * inv_patch_y();
    int ox = int(x), oy = int(y);
    ox = ox < size_x - 2 ? ox : size_x - 2;
    oy = oy < size_y - 2 ? oy : size_y - 2;
    const float w1x = x - float(ox), w1y = y - float(oy), w0x = 1.f - w1x, w0y = 1.f - w1y;
    unsigned index = unsigned(ox + oy * size_x);
    const unsigned size = unsigned(size_x * size_y);
    if (dim) index += slice_offset * size;
    const float v00 = lookup(data, index, size, w), v10 = lookup(data + 1, index, size, w),
                v01 = lookup(data + size_x, index, size, w), v11 = lookup(data + size_x + 1, index, size, w);
    return std::fma(w0y, std::fma(w0x, v00, w1x * v10), w1y * std::fma(w0x, v01, w1x * v11)) * inv_patch_x() * inv_patch_y();
  }
};

// pbrt-v4 bxdfs.h:1058-1065: the warped unit square of the tables.
ANISO_INLINE float rgl_theta2u(float theta) { return std::sqrt(theta * (2.f / kPi<float>)); }
ANISO_INLINE float rgl_phi2u(float phi) { return phi * (1.f / (2.f * kPi<float>)) + .5f; }
ANISO_INLINE float rgl_u2theta(float u) { return u * u * (kPi<float> / 2.f); }
ANISO_INLINE float rgl_u2phi(float u) { return (2.f * u - 1.f) * kPi<float>; }

// The interpolants of one file (pbrt-v4's MeasuredBxDFData, bxdfs.cpp:861-869), host-owned.
struct RglTables {
  PL2D ndf, sigma, vndf, luminance;
  PL2D rgb;  // spectra interpolant with 3 "wavelengths" 0, 1, 2 (Mitsuba's RGB path, measured.cpp:116-124)
  bool isotropic = true;
};

// The kernel: one pointer, so that it stays small inside a material value.
template <typename T> struct RglT {
  const RglTables* t = nullptr;

  // pbrt-v4 SphericalTheta (SafeACos(z)) and atan2 for phi, in float as pbrt-v4's default build.
  ANISO_HD static float theta_of(const Vec3T<T>& w) {
    const float z = float(w.z);
    return std::acos(z < -1.f ? -1.f : (z > 1.f ? 1.f : z));
  }

  // Colour at the sample-space point (x, y) of slice (phi_o, theta_o), clamped at 0 per channel as
  // pbrt-v4 does (bxdfs.cpp:1043-1045).
  ANISO_HD RGBT<T> colour(float x, float y, float phi_o, float theta_o) const {
    RGBT<T> c;
    for (int i = 0; i < 3; ++i) {
      const float p[3] = {phi_o, theta_o, float(i)};
      const float v = t->rgb.evaluate(x, y, p);
      c[i] = T(v > 0.f ? v : 0.f);
    }
    return c;
  }

  // bxdfs.cpp:1018-1050 (MeasuredBxDF::f), one-sided: 0 unless both directions are above the
  // horizon (aniso's convention; Mitsuba's measured plugin is one-sided too, measured.cpp:392-393).
  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
    Vec3T<T> wm = wi + wo;
    if (glm::dot(wm, wm) == T(0)) return RGBT<T>(T(0));
    wm = glm::normalize(wm);
    const float theta_o = theta_of(wo), phi_o = std::atan2(float(wo.y), float(wo.x));
    const float theta_m = theta_of(wm), phi_m = std::atan2(float(wm.y), float(wm.x));
    const float uo_x = rgl_theta2u(theta_o), uo_y = rgl_phi2u(phi_o);
    const float um_x = rgl_theta2u(theta_m);
    float um_y = rgl_phi2u(t->isotropic ? (phi_m - phi_o) : phi_m);
    um_y = um_y - std::floor(um_y);
    const float p[2] = {phi_o, theta_o};
    const PL2DSample ui = t->vndf.invert(um_x, um_y, p);
    if (!ui.finite()) return RGBT<T>(T(0));
    const RGBT<T> fr = colour(ui.x, ui.y, phi_o, theta_o);
    return fr * T(t->ndf.evaluate(um_x, um_y, nullptr) / (4.f * t->sigma.evaluate(uo_x, uo_y, nullptr) * float(wi.z)));
  }

  // bxdfs.cpp:1085-1114 (MeasuredBxDF::PDF).
  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    Vec3T<T> wm = wi + wo;
    if (glm::dot(wm, wm) == T(0)) return T(0);
    wm = glm::normalize(wm);
    const float theta_o = theta_of(wo), phi_o = std::atan2(float(wo.y), float(wo.x));
    const float theta_m = theta_of(wm), phi_m = std::atan2(float(wm.y), float(wm.x));
    const float um_x = rgl_theta2u(theta_m);
    float um_y = rgl_phi2u(t->isotropic ? (phi_m - phi_o) : phi_m);
    um_y = um_y - std::floor(um_y);
    const float p[2] = {phi_o, theta_o};
    const PL2DSample ui = t->vndf.invert(um_x, um_y, p);
    if (!ui.finite()) return T(0);
    const float lum = t->luminance.evaluate(ui.x, ui.y, p);
    const float sin_m = std::sqrt(float(wm.x * wm.x + wm.y * wm.y));
    // 1e-6: pbrt-v4's floor on the Jacobian of the (u_theta, u_phi) -> solid angle map, which is 0
    // at the pole (bxdfs.cpp:1110-1111).
    const float jac = 4.f * float(glm::dot(wo, wm)) * std::fmax(2.f * kPi<float> * kPi<float> * um_x * sin_m, 1e-6f);
    return T(ui.pdf * lum / jac);
  }

  // bxdfs.cpp:1052-1083 (MeasuredBxDF::Sample_f); uc is unused, as in pbrt-v4.
  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T /*uc*/, const Vec2T<T>& u) const {
    if (!above_horizon(wo)) return {};
    const float theta_o = theta_of(wo), phi_o = std::atan2(float(wo.y), float(wo.x));
    const float p[2] = {phi_o, theta_o};
    const PL2DSample sl = t->luminance.sample(float(u.x), float(u.y), p);
    if (!sl.finite()) return {};
    const PL2DSample sv = t->vndf.sample(sl.x, sl.y, p);
    if (!sv.finite()) return {};
    float phi_m = rgl_u2phi(sv.y);
    const float theta_m = rgl_u2theta(sv.x);
    if (t->isotropic) phi_m += phi_o;
    const float sin_m = std::sin(theta_m), cos_m = std::cos(theta_m);
    const Vec3T<T> wm(T(sin_m * std::cos(phi_m)), T(sin_m * std::sin(phi_m)), T(cos_m));
    const Vec3T<T> wi = T(2) * glm::dot(wo, wm) * wm - wo;
    if (!(wi.z > T(0))) return {};
    RGBT<T> fr = colour(sl.x, sl.y, phi_o, theta_o);
    const float uo_x = rgl_theta2u(theta_o), uo_y = rgl_phi2u(phi_o);
    fr *= T(t->ndf.evaluate(sv.x, sv.y, nullptr) / (4.f * t->sigma.evaluate(uo_x, uo_y, nullptr) * float(wi.z)));
    const float pdf = sv.pdf / (4.f * float(glm::dot(wo, wm)) * std::fmax(2.f * kPi<float> * kPi<float> * sv.x * sin_m, 1e-6f));
    return make_sample(wi, fr, T(pdf * sl.pdf));
  }
  // core/kernel.h: the tables have no roughness parameter to raise, so they stay as measured
  // (pbrt-v4's MeasuredBxDF::Regularize, the BxDF this kernel transcribes, is empty: bxdfs.h:1045);
  // their D is tabulated (ndf), not a GGX.
  ANISO_HD void regularize(T /*alpha*/) {}
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }
};

}  // namespace aniso
