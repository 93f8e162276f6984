// aniso/fit/fit.h: fitting the library's models to measured samples (measured/samples.h) with Ceres.
//
// Levenberg-Marquardt on the residuals of one of two metrics (docs/fitting.md gives the formulas):
//   l2cos  Ngan, Durand & Matusik 2005's cosine-weighted L2: r = sqrt(w) (f_model - f_data) cos(theta_i)
//   log    a relative metric (Loew et al. 2012): r = sqrt(w) (ln(1 + f_model cos) - ln(1 + f_data cos))
// with w the sample's weight over the total weight. The derivatives come from the kernels
// themselves (include/aniso/brdf/*.h instantiated on ceres::Jet, fit/jet.h), not from finite
// differences; the bounds are the parameter tables' (src/io/params.cpp). Several starts (moments
// of the data, the Ngan 2005 fit of the nearest MERL material, random draws from --seed) are each
// refined briefly, the best is refined to convergence; the same input gives the same output.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/measured/samples.h"

namespace aniso {

enum class FitMetric { L2Cos, Log };

// Whether the fitted model is anisotropic (docs/fitting.md, "Anisotropy"): Auto fits both when
// the data's half vectors cover the azimuths, and keeps the anisotropic one when it lowers the
// error by at least kAutoAnisotropicGain; Yes and No force it. An anisotropic fit also fits the
// orientation (rotation_deg).
enum class Anisotropy { Auto, Yes, No };
// Auto's rule: the anisotropic fit must lower the relative l2cos error by at least this fraction.
inline constexpr double kAutoAnisotropicGain = 0.10;

// What a fit reports while it runs (the CLI draws it on stderr for fits over a second).
struct FitProgress {
  std::string stage;  // "start 3/8 (random)", "refining the best start"
  int iteration = 0;
  double cost = 0.0;  // the solver's cost, 1/2 sum r^2
  double elapsed_s = 0.0;
  double remaining_s = 0.0;  // an estimate from the iterations done so far
};

// The default of FitOptions::max_theta_deg (degrees).
inline constexpr double kNganMaxThetaDeg = 80.0;

struct FitOptions {
  std::string model = "lafortune";           // a row of fittable_models()
  int lobes = 1;                             // Lafortune: 1 to 8
  Anisotropy anisotropy = Anisotropy::Auto;  // Cx != Cy, alpha_x != alpha_y, n_u != n_v, and rotation_deg
  // Off: every fitted material's directional albedo stays <= 1 (docs/fitting.md, "Energy"); on:
  // the fit may gain energy (data that do), and says so.
  bool allow_energy_gain = false;
  bool shared_exponents = false;       // Lafortune: one n per lobe for all channels
  std::string normalization = "ward";  // Ward: ward | duer | balanced
  std::string metal;                   // metal: a named metal (fixed eta, k); empty fits eta and k
  std::string metal_lobe = "ggx";      // metal: ggx | ward | ashikhmin-shirley
  // GGX: "schlick" holds f90 at 1 (Schlick 1994, what the renderers' GGX materials write);
  // "free-f90" fits f90 per channel too, a Fresnel the data can keep flat (docs/fitting.md).
  std::string fresnel = "schlick";
  FitMetric metric = FitMetric::L2Cos;
  // Ngan, Matusik & Durand 2005's range (Sec. 4: "we discard [...] samples with incident or
  // outgoing angles larger than 80 degrees"): the samples with either direction farther than this
  // from the normal are left out of the fit and its errors, so that grazing outliers, where
  // measurements are least reliable, cannot decide the fit. 90 keeps every sample.
  double max_theta_deg = kNganMaxThetaDeg;
  std::string loss = "none";  // robust loss per sample: none | huber | cauchy | soft_l1
  double loss_scale = 0.0;    // its scale in residual units; 0 = from the data (docs/fitting.md)
  int starts = 6;
  // A start of the caller's (a previous fit, a search over some of the parameters), by the names
  // of FitResult::parameter_names ("kd.r", "alpha_x", "rotation_deg"): tried first, in addition to
  // the `starts` above, at its own orientation. Parameters it does not name come from the moments
  // start; values are clamped into the parameters' bounds. An isotropic fit (Anisotropy::No, or
  // Auto's isotropic candidate) gives its parameter the geometric mean of an _x/_y or _u/_v pair
  // ("alpha_x", "alpha_y" -> "alpha"; "n_u", "n_v" -> "n") and has no rotation_deg. A name the fit
  // does not have, or a value that is not finite, is an InputError naming it.
  std::vector<std::pair<std::string, double>> start;
  uint64_t seed = 1;
  int threads = 0;  // 0: all cores
  int max_iterations = 200;
  // Ceres' convergence test: stop when an iteration lowers the cost by less than this fraction.
  double function_tolerance = 1e-9;
  // Above this many samples the solver runs on a fixed random subset of this size: the Jacobian of
  // 1.46 M samples x 30 parameters would take 1 GB, and 32768 samples already pin 30 parameters
  // down far below any measurement's noise (docs/fitting.md). The errors are always reported on
  // all samples.
  size_t max_solver_samples = size_t(1) << 15;
  // What parse_fit_options read differently from the text (a model alias: "blinnphong" is phong);
  // the CLI prints each as a note.
  std::vector<std::string> notes;
  std::function<void(const FitProgress&)> progress;
  // When set, the fit stops at the solver's next iteration once *cancel is true and throws
  // FitCancelled (the Python binding's Ctrl-C).
  const std::atomic<bool>* cancel = nullptr;
};

// Thrown by fit_samples when FitOptions::cancel was set during the fit.
struct FitCancelled : std::runtime_error {
  FitCancelled() : std::runtime_error("the fit was cancelled") {}
};

// The options as `aniso fit` takes them on its command line, as text (the Python binding aniso.fit
// passes its keywords through here too), read with the CLI's checks and messages ("--lobes: ...").
struct FitOptionText {
  std::string model = "lafortune", lobes = "1", normalization = "ward", metal, metal_lobe = "ggx", metric = "l2cos";
  std::string loss = "none", loss_scale = "0", starts = "6", seed = "1", threads = "0", max_iterations = "200";
  std::string anisotropic = "auto";  // auto | yes | no
  std::string max_theta = "80";      // --max-theta: degrees, (0, 90]
  std::string fresnel = "schlick";   // --fresnel: schlick | free-f90 (GGX)
  bool shared_exponents = false, allow_energy_gain = false;
};
// Throws InputError naming the option for a value out of range (the model's own options, such as an
// unknown --model or --normalization, are checked by fit_samples).
FitOptions parse_fit_options(const FitOptionText& text);

// Per channel and over all channels (root mean square of the three).
struct FitErrors {
  glm::dvec3 l2cos{0.0}, log{0.0};
  double l2cos_all = 0.0, log_all = 0.0;
  double relative_l2cos = 0.0;  // l2cos_all / the same norm of the data (0: exact, 1: as large as the data)
};

struct FitResult {
  nlohmann::json material;  // a valid material ({"model": ...}), without the "fit" object
  std::vector<std::string> parameter_names;
  std::vector<double> parameters;
  FitErrors errors;
  std::string best_start;  // "moments", "ngan2005 <material>", "random 3"
  int iterations = 0;      // of the best start, both phases
  double seconds = 0.0;
  size_t samples_total = 0, samples_used = 0;  // in the range: every error is over these
  // The range (FitOptions::max_theta_deg) and how many of the data's samples lay beyond it.
  double max_theta_deg = 90.0;
  size_t samples_beyond_range = 0;
  std::string termination;  // Ceres' message for the final refinement
  // Anisotropy: what was fitted and why (Anisotropy::Auto's decision, or the option).
  bool anisotropic = false;
  std::string anisotropy_reason;
  // Parameters the data did not constrain, tied to their isotropic partner or a default and
  // refitted ("cy = cx (every lobe)", "rotation_deg = 0"), each with the reason; and the weak
  // directions that were left free (combinations, printed as warnings).
  std::vector<std::string> tied, weakly_constrained;
  std::vector<std::string> unconstrained_anisotropy;  // the anisotropy entries among the weak ones
  // The largest directional albedo of the fitted material over the grid of docs/fitting.md
  // ("Energy"), where it is, and whether the energy constraint acted.
  double largest_albedo = 0.0, largest_albedo_theta_deg = 0.0, largest_albedo_phi_deg = 0.0;
  bool energy_constrained = false;
  double unconstrained_l2cos = 0.0;   // the relative l2cos error before the constraint acted
  double unconstrained_albedo = 0.0;  // and the largest directional albedo before it
  // How the constraint was met: "the linear entries re-solved under it", "each channel scaled", or
  // "refitted with the albedo penalty" (docs/fitting.md, "Energy"); empty when it did not act.
  std::string energy_method;
};

// Throws InputError for options that do not make a model (unknown model, --lobes out of range).
FitResult fit_samples(const SampleSet& data, const FitOptions& options);

// The models fit_samples accepts (FitOptions::model), in order.
std::vector<std::string_view> fittable_models();

// Both metrics of a material against the data (every sample).
FitErrors fit_errors(const MaterialD& m, const SampleSet& data);
// The same for any BRDF given as f(wi, wo) (RGB, no cosine): a renderer's target model (src/export).
FitErrors fit_errors(const std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)>& f, const SampleSet& data);

// The "fit" object stored beside the material in fitted.json (ignored by the material reader).
nlohmann::json fit_provenance(const FitResult& r, const SampleSet& data, const FitOptions& o);

// The models `--compare` fits, in its order, each with its options.
std::vector<std::pair<std::string, FitOptions>> compare_models(const FitOptions& base);

// A one-line description of the parameters (`--compare` table): "kd=(..) ks=(..) alpha=0.12".
std::string describe_parameters(const FitResult& r);

}  // namespace aniso
