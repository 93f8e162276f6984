// rgl/rgl_export.cpp: an RGL tensor file from any BRDF (rgl/rgl_export.h; docs/rgl.md): the driver,
// export_rgl, and the transcoding of a tensor source; the steps are rgl_source.cpp, rgl_warp.cpp,
// rgl_tables.cpp and rgl_check.cpp (export_detail.h).
#include "aniso/rgl/rgl_export.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include <fmt/format.h>

#include "aniso/measured/spectral.h"
#include "aniso/rgl/rgl_material.h"
#include "rgl/export_detail.h"

namespace aniso::rgl {
namespace {

// The tilt of the warps that export_rgl tries with the estimated D (docs/rgl.md, step 4: measured,
// L1 at 80 degrees, lobe-mean D: anisotropic Ward 6.7 % at 0, 4.8 % at 0.15, 5.1 % at 0.3).
constexpr double kAutoTilt = 0.15;

}  // namespace

std::vector<TensorField> transcode_tensor(const RglData& d, const BrdfSource& src, bool spectral) {
  const TensorFile t = read_tensor_file(d.source);
  std::vector<TensorField> out;
  const std::string desc = src.description.empty() ? d.description : fmt::format("{} ({})", d.description, src.description);
  for (const TensorField& f : t.fields) {
    if (f.name == "description") {
      out.push_back(
          make_field("description", {desc.size()}, std::span(reinterpret_cast<const uint8_t*>(desc.data()), desc.size())));
      continue;
    }
    if (auto it = std::find_if(d.read_as.begin(), d.read_as.end(), [&](const TensorField& r) { return r.name == f.name; });
        it != d.read_as.end()) {
      out.push_back(*it);
      continue;
    }
    const bool colour = f.name == "rgb" || f.name == "spectra" || f.name == "wavelengths";
    if (!colour || spectral == d.spectral) {
      out.push_back(f);
      continue;
    }
    if (f.name != (d.spectral ? "spectra" : "rgb")) continue;  // wavelengths: written with the spectra, or dropped
    const size_t slices = size_t(f.shape[0] * f.shape[1]), plane = size_t(f.shape[3] * f.shape[4]);
    const std::vector<float> in = f.floats();
    if (spectral) {
      // rgb -> box spectra: each grid point's coefficients (rgb_to_box_coefficients, clamped at 0
      // as box_spectrum's) spread over its band; the reduction gives the rgb back within the box
      // gamut.
      const std::vector<float> lambda = export_wavelengths();
      const glm::dmat3 to_box = rgb_to_box_coefficients();
      std::vector<float> spec(slices * lambda.size() * plane);
      for (size_t s = 0; s < slices; ++s)
        for (size_t k = 0; k < plane; ++k) {
          const glm::dvec3 rgb(in[(s * 3 + 0) * plane + k], in[(s * 3 + 1) * plane + k], in[(s * 3 + 2) * plane + k]);
          const glm::dvec3 coef = glm::max(to_box * rgb, glm::dvec3(0.0));
          for (size_t j = 0; j < lambda.size(); ++j) {
            double v = 0.0;
            for (int c = 0; c < 3; ++c) v += coef[c] * box(c, lambda[j]);
            spec[(s * lambda.size() + j) * plane + k] = float(v);
          }
        }
      out.push_back(make_field("wavelengths", {lambda.size()}, lambda));
      out.push_back(make_field("spectra", {f.shape[0], f.shape[1], lambda.size(), f.shape[3], f.shape[4]}, spec));
    } else {
      // spectra -> rgb: the reduction rgl_from_tensor applies (measured/spectral.h).
      const std::vector<double> lambda(d.wavelengths.begin(), d.wavelengths.end());
      const SpectralToRgb reduce(lambda);
      std::vector<float> rgb(slices * 3 * plane, 0.f);
      for (size_t s = 0; s < slices; ++s)
        for (size_t j = 0; j < lambda.size(); ++j)
          for (int c = 0; c < 3; ++c)
            for (size_t k = 0; k < plane; ++k)
              rgb[(s * 3 + size_t(c)) * plane + k] += float(reduce.weights[j][c]) * in[(s * lambda.size() + j) * plane + k];
      out.push_back(make_field("rgb", {f.shape[0], f.shape[1], 3, f.shape[3], f.shape[4]}, rgb));
    }
  }
  return out;
}

std::vector<TensorField> export_rgl(const BrdfSource& src, const ExportOptions& opt_in, ExportReport* report) {
  const double t_start = cpu_seconds();
  const IsotropyDecision decision = decide_isotropy(src, opt_in);
  ExportOptions opt = opt_in;
  opt.isotropy = decision.isotropic ? ExportOptions::Isotropy::Isotropic : ExportOptions::Isotropy::Anisotropic;
  const std::string decided = fmt::format("{}: {}", decision.isotropic ? "isotropic" : "anisotropic", decision.why);
  // A tensor source whose isotropy stays: its own tables, exactly (no grid of ours can do better,
  // and the file stays the source's size; docs/rgl.md "From a tensor file").
  if (src.tensor && !opt.resample && decision.isotropic == src.tensor->isotropic) {
    std::vector<TensorField> fields = transcode_tensor(*src.tensor, src, opt.spectral);
    if (report) {
      *report = ExportReport{};
      report->isotropic = decision.isotropic;
      report->transcoded = true;
      report->d_method = "the source file's own tables";
      report->spectra = !opt.spectral          ? ""
                        : src.tensor->spectral ? "the source file's own spectra"
                                               : "box spectra of the source file's rgb values";
      report->isotropy = decided;
      report->seconds = cpu_seconds() - t_start;
    }
    return fields;
  }
  if (src.ggx_alpha || opt.d_estimate != ExportOptions::DEstimate::Auto) {
    ExportOptions o = opt;  // a fixed D: the tilt chosen by the caller, or none
    o.warp_tilt = std::max(0.0, opt.warp_tilt);
    std::vector<TensorField> fields = export_tables(src, o, report);
    if (report) report->isotropy = decided;
    return fields;
  }
  // No estimate of D wins for every model (docs/rgl.md, "Where the error comes from"): the lobe's
  // mean shape follows forward and grazing lobes (Ashikhmin-Shirley, anisotropic Ward), the
  // retro-reflection suits tables whose grazing values are least like a microfacet lobe (a MERL
  // table), the envelope with warps that follow f lobes that turn towards the horizon (a
  // Lafortune fit); and the warps of the two first either follow each wo (its VNDF) or, tilted
  // towards the normal, change less from slice to slice (warp_tilt). Each file is written (RGB)
  // and the one that reproduces f best is kept; warp_tilt >= 0 fixes the tilt.
  using E = ExportOptions::DEstimate;
  struct Candidate {
    E d;
    double tilt;
    const char* name;
  };
  std::vector<Candidate> candidates;
  for (const double t : opt.warp_tilt >= 0.0 ? std::vector<double>{opt.warp_tilt} : std::vector<double>{0.0, kAutoTilt}) {
    candidates.push_back({E::LobeAverage, t, t > 0.0 ? "lobe mean, tilted" : "lobe mean"});
    candidates.push_back({E::RetroReflection, t, t > 0.0 ? "retro-reflection, tilted" : "retro-reflection"});
  }
  candidates.push_back({E::LobeEnvelope, std::max(0.0, opt.warp_tilt), "envelope"});
  ExportOptions o = opt;
  o.spectral = false;
  std::vector<TensorField> best;
  ExportReport best_report;
  Candidate pick = candidates.front();
  double best_score = 0.0;
  std::string scores;
  for (const Candidate& c : candidates) {
    o.d_estimate = c.d;
    o.warp_tilt = c.tilt;
    ExportReport r;
    std::vector<TensorField> fields = export_tables(src, o, &r);
    const double score = roundtrip_score(src, fields);
    scores += fmt::format("{}{} {:.2f} %", scores.empty() ? "" : ", ", c.name, 100.0 * score);
    if (best.empty() || score < best_score) best = std::move(fields), best_report = r, best_score = score, pick = c;
  }
  if (opt.spectral) {
    o = opt;
    o.d_estimate = pick.d;
    o.warp_tilt = pick.tilt;
    best = export_tables(src, o, &best_report);
  }
  if (report) {
    *report = best_report;
    report->d_method += fmt::format(" (chosen by the round trip: error {:.2f} %; {})", 100.0 * best_score, scores);
    report->seconds = cpu_seconds() - t_start;
    report->isotropy = decided;
  }
  return best;
}

}  // namespace aniso::rgl
