// aniso/brdf/measured.h: a measured, tabulated isotropic BRDF in the MERL BRDF database layout
// (Matusik, Pfister, Brand & McMillan 2003, "A Data-Driven Reflectance Model", SIGGRAPH), with a
// tabulated importance-sampling scheme. docs/measured.md describes the format, the lookup and
// the sampling tables; src/measured/ reads, writes and builds them.
//
// The kernel sees plain data: pointers to host-owned arrays and their sizes, no containers. The
// arrays belong to a MeasuredData (include/aniso/measured/measured.h) held by a shared_ptr; every file that
// load_material() opens stays in a process-wide registry until the program ends, so a MaterialT
// built from it never dangles (lifetime rule: docs/measured.md, "Lifetime").
//
// Lookup (MERL's BRDFRead.cpp): the pair (wi, wo) becomes Rusinkiewicz's half/difference angles
// (theta_h, phi_h, theta_d, phi_d) (Rusinkiewicz 1998, "A New Change of Variables for Efficient BRDF
// Representation"); the bin is
//   i_theta_h = floor(90 sqrt(theta_h / (pi/2)))    (the non-linear, square-root map)
//   i_theta_d = floor(90 theta_d / (pi/2))
//   i_phi_d   = floor(180 phi_d / pi), phi_d folded to [0, pi) by reciprocity (phi_d ~ phi_d + pi)
// nearest bin, no interpolation, exactly as MERL's reference code. A missing sample (a negative
// value in any channel of the bin) evaluates to 0.
//
// Sampling (docs/measured.md, "Sampling"): with probability 1 - uniform_fraction the half vector h
// is drawn from a piecewise-constant density over (theta_h, phi_h) cells, tabulated for each of
// theta_o_bins viewing angles (phi_h measured from wo's azimuth: the data are isotropic), with
// cell masses proportional to the integral of f cos(theta_i) |d omega_i / d omega_h| over the cell;
// theta_h cells are MERL's own (square-root spaced, fine near the highlight), phi_h cells uniform.
// Within a cell h is uniform in solid angle, and wi = reflect(wo, h). With probability
// uniform_fraction wi is cosine-distributed instead (defensive mixture, Hesterberg 1995): every
// direction where f > 0 keeps a positive pdf, whatever the tables missed. pdf() uses the same
// tables and cells, so it is the exact density of sample().
#pragma once

#include "aniso/core/kernel.h"
#include "aniso/core/sampling.h"

namespace aniso {

// MERL's table dimensions (BRDFRead.cpp: BRDF_SAMPLING_RES_THETA_H 90, _THETA_D 90, _PHI_D 360 of
// which 180 are stored, phi_d in [0, pi)).
struct MerlLayout {
  static constexpr int kThetaH = 90, kThetaD = 90, kPhiD = 180;
  static constexpr int kBins = kThetaH * kThetaD * kPhiD;  // per channel: 1,458,000
};

// MERL's index maps (BRDFRead.cpp, theta_half_index, theta_diff_index, phi_diff_index).
template <typename T> ANISO_INLINE int merl_theta_half_index(T theta_h) {
  using std::sqrt;
  if (!(theta_h > T(0))) return 0;
  const int i = int(sqrt(theta_h / kPiOver2<T>) * T(MerlLayout::kThetaH));
  return i < 0 ? 0 : (i >= MerlLayout::kThetaH ? MerlLayout::kThetaH - 1 : i);
}
template <typename T> ANISO_INLINE int merl_theta_diff_index(T theta_d) {
  const int i = int(theta_d / kPiOver2<T> * T(MerlLayout::kThetaD));
  return i < 0 ? 0 : (i >= MerlLayout::kThetaD ? MerlLayout::kThetaD - 1 : i);
}
template <typename T> ANISO_INLINE int merl_phi_diff_index(T phi_d) {
  if (phi_d < T(0)) phi_d += kPi<T>;  // reciprocity: f is unchanged under phi_d -> phi_d + pi
  const int i = int(phi_d / kPi<T> * T(MerlLayout::kPhiD));
  return i < 0 ? 0 : (i >= MerlLayout::kPhiD ? MerlLayout::kPhiD - 1 : i);
}
// Offset of a bin in one channel's block (phi_d fastest, then theta_d, then theta_h).
ANISO_INLINE int merl_index(int i_theta_h, int i_theta_d, int i_phi_d) {
  return i_phi_d + MerlLayout::kPhiD * (i_theta_d + MerlLayout::kThetaD * i_theta_h);
}

// The bin of (wi, wo): Rusinkiewicz's half/difference angles as MERL computes them
// (std_coords_to_half_diff_coords), written with atan2 instead of acos so that float keeps the
// smallest theta_h bins (the first ends at 1.9e-4 rad, where acos(h.z) in float is already 3e-4
// off). Both directions unit and above the horizon.
template <typename T> ANISO_INLINE int merl_bin(const Vec3T<T>& wi, const Vec3T<T>& wo) {
  using std::atan2;
  using std::sqrt;
  const Vec3T<T> h = glm::normalize(wi + wo);
  const T sin_h = sqrt(h.x * h.x + h.y * h.y);
  const T theta_h = atan2(sin_h, h.z);
  // rotate wi by -phi_h about n, then by -theta_h about the bitangent (MERL's rotate_vector);
  // phi_h = atan2(h.y, h.x) is 0 where h = n, as MERL's atan2(0, 0).
  const T cp = sin_h > T(0) ? h.x / sin_h : T(1), sp = sin_h > T(0) ? h.y / sin_h : T(0);
  const T x1 = wi.x * cp + wi.y * sp, y1 = -wi.x * sp + wi.y * cp, z1 = wi.z;
  const T ct = h.z, st = sin_h;
  const T dx = x1 * ct - z1 * st, dy = y1, dz = x1 * st + z1 * ct;
  const T theta_d = atan2(sqrt(dx * dx + dy * dy), dz);
  const T phi_d = atan2(dy, dx);
  return merl_index(merl_theta_half_index(theta_h), merl_theta_diff_index(theta_d), merl_phi_diff_index(phi_d));
}

// f from a MERL table (3 blocks of kBins doubles, R then G then B, already scaled): 0 below the
// horizon and for a missing bin (any channel negative).
template <typename T> ANISO_INLINE RGBT<T> merl_lookup(const double* table, const Vec3T<T>& wi, const Vec3T<T>& wo) {
  if (!same_upper_hemisphere(wi, wo)) return RGBT<T>(T(0));
  const int k = merl_bin(wi, wo);
  const double r = table[k], g = table[k + MerlLayout::kBins], b = table[k + 2 * MerlLayout::kBins];
  if (r < 0.0 || g < 0.0 || b < 0.0) return RGBT<T>(T(0));
  return RGBT<T>(T(r), T(g), T(b));
}

// Index k of the interval [cdf[k], cdf[k+1]) holding u (cdf[0] = 0, cdf[n] = 1, non-decreasing),
// and u's position within it in [0, 1). Zero-width intervals are never returned for u in [0, 1).
template <typename T> ANISO_INLINE int sample_cdf(const double* cdf, int n, T u, T& u_remapped) {
  int lo = 0, hi = n;  // invariant: cdf[lo] <= u < cdf[hi]
  const double x = double(u);
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (cdf[mid] <= x)
      lo = mid;
    else
      hi = mid;
  }
  const double w = cdf[lo + 1] - cdf[lo];
  const double r = w > 0.0 ? (x - cdf[lo]) / w : 0.0;
  u_remapped = T(r < 0.0 ? 0.0 : (r < 1.0 ? r : 0.99999994));  // < 1 in float too
  return lo;
}

template <typename T> struct MeasuredT {
  // The MERL table: 3 * MerlLayout::kBins values, channel-major, scaled (reflectance / sr).
  const double* table = nullptr;
  // Sampling tables (docs/measured.md, "Sampling"), per viewing-angle bin o < theta_o_bins
  // (theta_o uniform in [0, pi/2)):
  //   marginal_cdf    [o][kThetaH + 1]              cdf over theta_h cells
  //   conditional_cdf [o][kThetaH][phi_h_bins + 1]  cdf over phi_h cells of each theta_h row
  //   v_edges         [kThetaH + 1]   1 - cos(theta_h) at MERL's theta_h edges ((i / 90)^2 pi / 2)
  //   cell_solid_angle[kThetaH]       solid angle of one (theta_h, phi_h) cell of row i
  const double* marginal_cdf = nullptr;
  const double* conditional_cdf = nullptr;
  const double* v_edges = nullptr;
  const double* cell_solid_angle = nullptr;
  int theta_o_bins = 0;
  int phi_h_bins = 0;
  T uniform_fraction = T(0.05);

  ANISO_HD RGBT<T> f(const Vec3T<T>& wi, const Vec3T<T>& wo) const { return merl_lookup(table, wi, wo); }

  // wo's azimuth (cos, sin) and its viewing-angle bin. phi_o = 0 where wo = n (any azimuth would do;
  // sample and pdf agree because both call this).
  ANISO_HD void view_frame(const Vec3T<T>& wo, T& c, T& s, int& o) const {
    using std::atan2;
    using std::sqrt;
    const T r = sqrt(wo.x * wo.x + wo.y * wo.y);
    c = r > T(0) ? wo.x / r : T(1);
    s = r > T(0) ? wo.y / r : T(0);
    const int bin = int(atan2(r, wo.z) / kPiOver2<T> * T(theta_o_bins));
    o = bin < 0 ? 0 : (bin >= theta_o_bins ? theta_o_bins - 1 : bin);
  }

  // Density of the tabulated part at wi: P(cell) / solid angle(cell) / (4 wo.h), the last factor the
  // Jacobian of wi = reflect(wo, h) (Walter et al. 2007, Eq. 14).
  ANISO_HD T table_pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    using std::atan2;
    using std::sqrt;
    T c, s;
    int o;
    view_frame(wo, c, s, o);
    const Vec3T<T> h = glm::normalize(wi + wo);
    // h in wo's azimuthal frame (rotated by -phi_o about n)
    const T hx = h.x * c + h.y * s, hy = -h.x * s + h.y * c;
    const T sin_h = sqrt(hx * hx + hy * hy);
    const int i = merl_theta_half_index(atan2(sin_h, h.z));
    T phi = atan2(hy, hx);
    if (phi < T(0)) phi += T(2) * kPi<T>;
    int j = int(phi * kInv2Pi<T> * T(phi_h_bins));
    j = j < 0 ? 0 : (j >= phi_h_bins ? phi_h_bins - 1 : j);
    const double* mcdf = marginal_cdf + o * (MerlLayout::kThetaH + 1);
    const double* ccdf = conditional_cdf + (size_t(o) * MerlLayout::kThetaH + size_t(i)) * size_t(phi_h_bins + 1);
    const double p_cell = (mcdf[i + 1] - mcdf[i]) * (ccdf[j + 1] - ccdf[j]);
    const T woh = glm::dot(wo, h);
    if (!(p_cell > 0.0) || !(woh > T(0))) return T(0);
    return T(p_cell / cell_solid_angle[i]) / (T(4) * woh);
  }

  ANISO_HD T pdf(const Vec3T<T>& wi, const Vec3T<T>& wo) const {
    if (!same_upper_hemisphere(wi, wo)) return T(0);
    return uniform_fraction * cosine_hemisphere_pdf(wi.z) + (T(1) - uniform_fraction) * table_pdf(wi, wo);
  }

  ANISO_HD BSDFSampleT<T> sample(const Vec3T<T>& wo, T uc, const Vec2T<T>& u) const {
    using std::cos;
    using std::sin;
    if (!above_horizon(wo)) return {};
    Vec3T<T> wi;
    if (uc < uniform_fraction) {
      wi = sample_cosine_hemisphere(u);
    } else {
      T c, s;
      int o;
      view_frame(wo, c, s, o);
      T fx, fy;
      const int i = sample_cdf(marginal_cdf + o * (MerlLayout::kThetaH + 1), MerlLayout::kThetaH, u.x, fx);
      const int j = sample_cdf(conditional_cdf + (size_t(o) * MerlLayout::kThetaH + size_t(i)) * size_t(phi_h_bins + 1),
                               phi_h_bins, u.y, fy);
      // uniform in solid angle within the cell: v = 1 - cos(theta_h) linear in fx; sin from v(2 - v)
      // keeps the smallest cells (v ~ 1e-8) exact in float, where cos(theta_h) rounds to 1.
      const T v = T(v_edges[i] + (v_edges[i + 1] - v_edges[i]) * double(fx));
      const T sin_h = safe_sqrt(v * (T(2) - v)), cos_h = T(1) - v;
      const T phi = (T(j) + fy) * T(2) * kPi<T> / T(phi_h_bins);
      const T hx = sin_h * cos(phi), hy = sin_h * sin(phi);
      const Vec3T<T> h(hx * c - hy * s, hx * s + hy * c, cos_h);  // back to the shading frame
      const T woh = glm::dot(wo, h);
      if (!(woh > T(0))) return {};
      wi = reflect_about(wo, h);
    }
    return make_sample(wi, f(wi, wo), pdf(wi, wo));
  }
  // core/kernel.h: a table has no roughness parameter to raise, so it stays as measured (as
  // pbrt-v4's MeasuredBxDF::Regularize, which is empty: bxdfs.h:1045); no analytic distribution.
  ANISO_HD void regularize(T /*alpha*/) {}
  ANISO_HD GgxDistributionT<T> ggx_distribution() const { return {}; }
};

}  // namespace aniso
