// aniso/rgl/rgl_export.h: writing any BRDF as an RGL tensor file (Dupuy & Jakob 2018), the tables the
// readers' interpolants (aniso/brdf/rgl.h = pbrt-v4's MeasuredBxDF) reproduce. docs/rgl.md
// "How each table is computed".
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/brdf/material.h"
#include "aniso/brdf/rgl.h"
#include "aniso/data/metals.h"
#include "aniso/rgl/rgl_material.h"
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
  // One phi_i slice (isotropic) or the full circle: decided from the source (Auto, decide_isotropy)
  // or forced (`--isotropic`, `--anisotropic`). A forced isotropic file holds f as seen from
  // azimuth 0.
  enum class Isotropy { Auto, Isotropic, Anisotropic } isotropy = Isotropy::Auto;
  // A tensor-file source (BrdfSource::tensor) is written from its own tables when the decision
  // keeps its isotropy (transcode_tensor); true resamples it on the grids above instead.
  bool resample = false;
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
  // f is a measurement (a tensor file, a MERL table): the rotation test allows for its noise
  // (kMeasuredIsotropyTolerance).
  bool measured = false;
  // The source is isotropic by construction, and why: a tensor file with one phi_i (pbrt-v4 and
  // Mitsuba 3 read it isotropic, bxdfs.cpp:938, measured.cpp:165), a MERL table (its three
  // angles are isotropic).
  std::string isotropic_by_construction;
  // The source is this tensor file (set by the caller, who holds the MaterialDesc): written from
  // its own tables unless resampled (ExportOptions::resample).
  std::shared_ptr<const RglData> tensor;
};

struct ExportReport {
  bool isotropic = true;
  std::string d_method;     // how D was made ("exact GGX D and sigma", the estimate and its round-trip errors)
  std::string spectra;      // how the spectra of a spectral file were made
  double seconds = 0.0;     // CPU time of the export
  std::string isotropy;     // what was decided (isotropic or not) and why, one line
  bool transcoded = false;  // written from a tensor source's own tables (transcode_tensor)
};

// The source material as a BrdfSource (exact D for GGX and GGX metal lobes); `description` is
// filled by the caller. `metal`: the table row of a metal material named by "metal" (its eta, k are
// that row's): its spectral files then carry the Fresnel reflectance of the row's measured
// n(lambda), k(lambda) (metal_nk) instead of box spectra (docs/rgl.md, "Spectral files").
BrdfSource brdf_source(const MaterialD& m, const MetalData* metal = nullptr);

// f is isotropic when rotating both directions about the normal leaves it unchanged (checked at
// fixed pseudo-random pairs and angles, relative tolerance 1e-6). For analytic sources.
bool is_isotropic(const BrdfSource& src);

// How much f changes when both directions turn about the normal: the relative RMS difference
//   sqrt( sum w |f(R wi, R wo) - f(wi, wo)|^2 / sum w |(f(R wi, R wo) + f(wi, wo)) / 2|^2 )
// (|.| over the three channels, w = cos(theta_i) cos(theta_o)) over 256 fixed pairs with elevations
// up to 80 degrees (Ngan et al. 2005's range: beyond it measurements are least reliable), half of
// them mirror pairs about half vectors within 60 degrees of the normal (denser near it, where
// sharp lobes are) and half spread over the hemispheres, each turned by an angle in [0.3, 2.3] rad.
double rotation_difference(const BrdfSource& src);
// The largest rotation_difference of a measured source that is still isotropic: 4 %. Isotropic
// materials on anisotropic grids (33 phi_i slices written by export-rgl --anisotropic) change by
// 0.28 % (chm_mint), 1.8 % (aurora_white), 0.36 % and 1.0 % (GGX alpha 0.1 and 0.3): the readers'
// blend between azimuth slices; the RGL database's isotropic files by < 0.01 %. Anisotropy shows
// beyond it: GGX with alpha_y / alpha_x = 1.5 changes by 7.3 % to 16 % (alpha 0.02 to 0.3), 1.2 by
// 2.9 % to 7.2 %, 1.1 by 1.5 % to 3.7 % (read isotropic: within the noise). docs/rgl.md
// "Isotropic or not".
inline constexpr double kMeasuredIsotropyTolerance = 0.04;

struct IsotropyDecision {
  bool isotropic = true;
  double rotation_difference = -1.0;  // when it was measured (measured sources), else -1
  std::string why;                    // one line, for the user
};
// opt.isotropy when forced; else the source's construction (isotropic_by_construction), else the
// rotation test: rotation_difference <= kMeasuredIsotropyTolerance for a measured source,
// is_isotropic for an analytic one.
IsotropyDecision decide_isotropy(const BrdfSource& src, const ExportOptions& opt);

// A tensor source written from its own tables (no resampling): every field as read (the rounding
// noise read as 0 and sigma raised as rgl_from_tensor does), the description prefixed to
// src.description; an RGB source written spectral gets the box spectra of its rgb values at
// export_wavelengths() (each grid point's, clamped at 0 as every spectral export's), a spectral
// source written RGB the reduction of its spectra (measured/spectral.h).
std::vector<TensorField> transcode_tensor(const RglData& d, const BrdfSource& src, bool spectral);

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

// compare_rgl's estimator at one viewing direction wo, for any f against src.f: the
// cosine-weighted relative L1 (sum over channels of integral |f - f_src| cos / integral f_src cos)
// and the relative error of f's directional albedo (luminance) against src's. `samples` draws
// from Rng(seed), the even ones by src.sample, the odd ones cosine-distributed, weighted by the
// mixture's pdf (0.5 src.pdf + 0.5 cos / pi); a draw src rejects still counts.
struct ViewError {
  double l1 = 0.0, albedo = 0.0;
};
ViewError compare_view(const SourceModel& src, const std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)>& f,
                       const Vec3d& wo, int samples, uint64_t seed);

}  // namespace aniso::rgl
