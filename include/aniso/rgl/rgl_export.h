// aniso/rgl/rgl_export.h: writing any BRDF as an RGL tensor file (Dupuy & Jakob 2018), the tables the
// readers' interpolants (aniso/brdf/rgl.h = pbrt-v4's MeasuredBxDF) reproduce. docs/rgl.md
// "How each table is computed".
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/brdf/material.h"
#include "aniso/brdf/rgl.h"
#include "aniso/data/metals.h"
#include "aniso/rgl/tensor.h"

namespace aniso::rgl {

struct ExportOptions {
  bool spectral = true;  // spectra + wavelengths (pbrt-v4, spectral Mitsuba) or rgb (Mitsuba RGB variants)
  int colour = 32;       // colour and luminance grid n x n on the VNDF-warped square
  int theta_i = 16;      // incident elevations (placed by `placement`)
  int phi_i =
      33;  // incident azimuths over [-pi, pi] (anisotropic materials only; placed by `phi_placement`, +1 for a turned material)
  int ndf = 64;  // ndf and sigma grid, n x n over (u_theta, u_phi)
  int vndf = 0;  // vndf grid (each slice's warp), n x n over (u_theta, u_phi); 0: 32 anisotropic, `ndf` isotropic
  // D of the models without a closed form (every one but GGX): the lobe's mean shape over the
  // viewing angles, the retro-reflection's power iteration (Dupuy et al. 2015), or the envelope of
  // each incident direction's own distribution with warps that follow each slice's f; Auto writes
  // all three and keeps the file that reproduces f best (docs/rgl.md, step 2).
  enum class DEstimate { Auto, LobeAverage, RetroReflection, LobeEnvelope } d_estimate = DEstimate::Auto;
  int power_iterations = 8;
  // Each slice's warp is the VNDF of wo tilted towards the normal by this share, (1 - t) wo + t n
  // normalised (estimated D only; an exact GGX D keeps wo's own): neighbouring slices' warps then
  // differ less, and the readers' blend between them errs less. < 0: export_rgl tries 0 and 0.15
  // with the lobe-mean and the retro-reflection D and keeps the best (docs/rgl.md, step 4).
  double warp_tilt = -1.0;
  // theta_i placement: by the error of the readers' linear blend between slices (default), or by
  // the projected area sigma alone (half uniform in angle, half uniform in sigma).
  enum class Placement { BlendError, ProjectedArea } placement = Placement::BlendError;
  double placement_uniform = 0.3;  // share of the uniform density in the blend-error placement
  // phi_i placement (anisotropic files): by the error of the readers' linear blend between azimuth
  // slices, symmetric about the material's mirror axes (default), or uniform over [-pi, pi].
  enum class PhiPlacement { BlendError, Uniform } phi_placement = PhiPlacement::BlendError;
};

struct BrdfSource {
  // f(wi, wo) without the cosine, aniso's convention (aniso/brdf/material.h).
  std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)> f;
  // The microfacet distribution when it is known exactly (GGX with alpha_x, alpha_y), mixed with a
  // uniform distribution of weight `uniform_weight` for a diffuse part; absent: D estimated from
  // f (ExportOptions::d_estimate).
  std::optional<glm::dvec2> ggx_alpha;
  double uniform_weight = 0.0;
  std::string description;  // written verbatim (the material JSON and the aniso version)
  // Spectral files: f(wi, wo) at each of export_wavelengths() into out[0 .. size), when the source
  // has a spectral description of its own (a named metal's measured n, k); absent, a spectral file
  // spreads the RGB of f over box spectra (rgb_to_box_coefficients).
  std::function<void(const Vec3d& wi, const Vec3d& wo, double* out)> f_spectral;
  std::string spectral_origin;  // what f_spectral evaluates, for the report
};

struct ExportReport {
  bool isotropic = true;
  std::string d_method;  // how D was made ("exact GGX D and sigma", the estimate and its round-trip errors)
  std::string spectra;   // how the spectra of a spectral file were made
  double seconds = 0.0;  // CPU time of the export
};

// The source material as a BrdfSource (exact D for GGX and GGX metal lobes); `description` is
// filled by the caller. `metal`: the table row of a metal material named by "metal" (its eta, k are
// that row's): its spectral files then carry the Fresnel reflectance of the row's measured
// n(lambda), k(lambda) (metal_nk) instead of box spectra (docs/rgl.md, "Spectral files").
BrdfSource brdf_source(const MaterialD& m, const MetalData* metal = nullptr);

// f is isotropic when rotating both directions about the normal leaves it unchanged (checked at
// fixed pseudo-random pairs and angles, relative tolerance 1e-6).
bool is_isotropic(const BrdfSource& src);

std::vector<TensorField> export_rgl(const BrdfSource& src, const ExportOptions& opt, ExportReport* report = nullptr);

// The three non-negative box spectra (blue < 490 nm <= green < 590 nm <= red) and the wavelengths
// of spectral files, and the 3x3 inverse of their reduction (measured/spectral.h), so that a
// spectral file reduces back to the RGB it was made from. docs/rgl.md "Spectral files".
std::vector<float> export_wavelengths();
glm::dmat3 rgb_to_box_coefficients();

// How well a read file reproduces its source, at incident (viewing) elevations 0 to 80 degrees in
// 20-degree steps and azimuths 0, 60, 120, 210 and 300 degrees:
//   l1:     cosine-weighted relative L1 of f over the hemisphere, sum over channels of
//           integral |f_file - f_src| cos / integral f_src cos (the worst direction, and the mean);
//   albedo: directional albedo (luminance) of the file against the source's, worst relative error.
// Integrals by importance sampling (half the source's sampler, half cosine; fixed seed).
struct RoundTripStats {
  double l1_max = 0.0, l1_mean = 0.0, albedo_max = 0.0;
  double worst_theta_deg = 0.0, worst_phi_deg = 0.0;
  double l1_by_theta[5] = {0, 0, 0, 0, 0};  // worst over the azimuths at 0, 20, 40, 60, 80 degrees
};
struct SourceModel {
  std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)> f;
  std::function<double(const Vec3d& wi, const Vec3d& wo)> pdf;
  std::function<BSDFSampleT<double>(const Vec3d& wo, double uc, const Vec2T<double>& u)> sample;
};
SourceModel source_model(const MaterialD& m);
RoundTripStats compare_rgl(const SourceModel& src, const RglT<double>& file, int samples = 20000);

}  // namespace aniso::rgl
