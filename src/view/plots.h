// view/plots.h: the data of the explorer's plots, computed from the kernels (no window): polar
// slices of the lobe, the directional albedo against theta, and the 3D lobe mesh. The window draws
// exactly these numbers; tests/test_view.cpp checks them against the scalar evaluator.
#pragma once

#include <cstdint>
#include <vector>

#include "aniso/brdf/material.h"

namespace aniso::view {

// Luminance of linear Rec. 709 RGB (ITU-R BT.709 weights): the value the plots draw.
inline double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// A slice of the lobe: the incident (light) direction wi fixed, the outgoing direction swept
// through the plane that contains the normal and the azimuth plane_phi, theta_o signed from -90
// to 90 degrees (positive: towards plane_phi, negative: towards plane_phi + 180 degrees).
// The plane of incidence is plane_phi = phi_i; the perpendicular slice is plane_phi = phi_i + 90.
struct PolarSample {
  double theta_deg = 0.0;  // signed, in the slice
  Vec3T<double> wo{0.0};
  glm::dvec3 f{0.0};   // the BRDF, no cosine
  double value = 0.0;  // luminance(f), times cos(theta_o) when asked
};
std::vector<PolarSample> polar_slice(const MaterialT<double>& m, const Vec3T<double>& wi, double plane_phi_deg, int samples,
                                     bool times_cos);

// The radius a polar plot draws for a value: linear (value / max), or log10 over kLogDecades
// decades below the maximum (values below that at the centre).
inline constexpr double kLogDecades = 4.0;
double plot_radius(double value, double max_value, bool log_scale);

// Directional albedo rho(theta) = integral of f(wi, wo) cos theta_i dwi for wo at (theta, phi),
// estimated by the model's importance sampling through the batch API (aniso/batch/batch.h) with a
// fixed stratified set of uniforms per theta (the same numbers on every call). theta from 0 to
// 89 degrees in `thetas` steps.
struct AlbedoPoint {
  double theta_deg = 0.0;
  glm::dvec3 albedo{0.0};
};
std::vector<AlbedoPoint> albedo_curve(const MaterialT<double>& m, double phi_deg, int thetas, int samples_per_theta);
// The uniforms albedo_curve uses for sample j of n (stratified in (u0, u1), uc from a second
// stratification): tests repeat them through the scalar sampler.
void albedo_uniforms(int j, int n, double* uc, double* u0, double* u1);

// The 3D lobe: vertices r(wo) * wo over the hemisphere, r = luminance(f(wi, wo)) (times cos theta_o
// when asked) divided by its maximum, on a (theta, phi) grid; triangles as index triples.
struct LobeMesh {
  std::vector<float> positions;  // x y z per vertex, local frame (z = normal)
  std::vector<float> values;     // r per vertex (colouring)
  std::vector<uint32_t> indices;
  double max_value = 0.0;
};
LobeMesh lobe_mesh(const MaterialT<double>& m, const Vec3T<double>& wi, int n_theta, int n_phi, bool times_cos);

}  // namespace aniso::view
