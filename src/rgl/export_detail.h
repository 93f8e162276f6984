// rgl/export_detail.h (private): what the files of export-rgl share (rgl_export.cpp the driver,
// rgl_source.cpp the source's spectra and isotropy, rgl_warp.cpp the warps and the placement of
// the slices, rgl_tables.cpp the tables of one file, rgl_check.cpp the round trip).
#pragma once

#include <cmath>
#include <ctime>
#include <optional>
#include <vector>

#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"

namespace aniso::rgl {

inline constexpr double kPiD = 3.14159265358979323846;

inline double luminance_of(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }  // Rec. 709 Y

inline Vec3d dir(double theta, double phi) {
  return Vec3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Grid node k of n on [0, 1] and the (u_theta, u_phi) -> angle maps of pbrt-v4 bxdfs.h:1058-1065.
inline double node(int k, int n) { return double(k) / double(n - 1); }
inline double u2theta(double u) { return u * u * (kPiD / 2.0); }
inline double u2phi(double u) { return (2.0 * u - 1.0) * kPiD; }

inline double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// sigma(w) = integral of D(m) <w, m>+ over the hemisphere of m: the projected area of the
// microfacets (Dupuy & Jakob 2018, Sec. 3; for GGX, cos(theta) (1 + Lambda(w)), Heitz 2014 Eq. 80).
inline double sigma_ggx(const Vec3d& w, double ax, double ay) {
  return 0.5 * (w.z + std::sqrt(w.z * w.z + ax * ax * w.x * w.x + ay * ay * w.y * w.y));
}
inline double d_ggx(const Vec3d& m, double ax, double ay) {
  const double d = (m.x / ax) * (m.x / ax) + (m.y / ay) * (m.y / ay) + m.z * m.z;
  return 1.0 / (kPiD * ax * ay * d * d);
}
// The uniform distribution D = 1/pi (normalised: integral of D cos = 1) has sigma = (1 + cos) / 2.
inline double sigma_uniform(const Vec3d& w) { return 0.5 * (1.0 + w.z); }

inline double box(int c, double nm) {  // c: 0 red, 1 green, 2 blue
  const int band = nm < 490.0 ? 2 : (nm < 590.0 ? 1 : 0);
  return band == c ? 1.0 : 0.0;
}

// The warps and the slices' placement (rgl_warp.cpp).
void warp_slice(const BrdfSource& src, const PL2D& ndf, bool iso, const Vec3d& wo, double phi_w, int N, double tilt,
                double f_share, float* out);
std::vector<float> place_theta_by_blend_error(const BrdfSource& src, const PL2D& ndf, const PL2D& sigma, bool iso, int N,
                                              double tilt, double f_share, double theta_max, int count, double uniform);
std::vector<float> place_phi_by_blend_error(const BrdfSource& src, const PL2D& ndf, const PL2D& sigma, int N, double tilt,
                                            double f_share, const std::vector<float>& theta_i, int count, double uniform);
// The tables of one file (rgl_tables.cpp).
std::vector<TensorField> export_tables(const BrdfSource& src, const ExportOptions& opt, ExportReport* report);
// How well a written file reproduces src (rgl_check.cpp).
double roundtrip_score(const BrdfSource& src, const std::vector<TensorField>& fields);

}  // namespace aniso::rgl
