// export/report.cpp: what the report measures (the source's samples, the errors of a target model
// against them, the largest directional-albedo difference) and the report as JSON and text.
#include "export/common.h"

#include <cmath>

#include <fmt/format.h>

namespace aniso::exporter {

namespace {

// Rotates v about z by angle (radians), counter-clockwise: x towards y.
Vec3d rotate_z(const Vec3d& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// Rusinkiewicz 1998: h from (theta_h, phi_h), wi = d rotated by theta_h about y then phi_h about z.
void half_diff_to_dirs(double th, double ph, double td, double pd, Vec3d& wi, Vec3d& wo) {
  const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  const Vec3d d(std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td));
  // rotate d about y by theta_h
  const Vec3d dy(std::cos(th) * d.x + std::sin(th) * d.z, d.y, -std::sin(th) * d.x + std::cos(th) * d.z);
  wi = rotate_z(dy, ph);
  wo = 2.0 * glm::dot(wi, h) * h - wi;
}

}  // namespace

// --- sampling and errors ---------------------------------------------------------------------------

SampleSet sample_source(const MaterialD& m, int grid) {
  SampleSet set;
  set.source = "export: source sampled";
  set.format = "synthetic";
  const int nth = 4 * grid, nph = 4 * grid, ntd = 2 * grid, npd = 2 * grid;
  const double half_pi = kPi<double> / 2.0;
  for (int i = 0; i < nth; ++i) {
    // theta_h on MERL's quadratic spacing (dense at the peak): theta = ((i + 0.5) / n)^2 pi / 2.
    const double u = (i + 0.5) / nth, th = u * u * half_pi;
    const double dth = (2.0 * u / nth) * half_pi;  // d theta_h / d i
    for (int j = 0; j < nph; ++j) {
      const double ph = (j + 0.5) * 2.0 * kPi<double> / nph;
      for (int a = 0; a < ntd; ++a) {
        const double td = (a + 0.5) * half_pi / ntd;
        for (int b = 0; b < npd; ++b) {
          const double pd = (b + 0.5) * 2.0 * kPi<double> / npd;
          Vec3d wi, wo;
          half_diff_to_dirs(th, ph, td, pd, wi, wo);
          if (!(wi.z > 0.02) || !(wo.z > 0.02)) continue;
          MeasuredSample s;
          s.wi = glm::normalize(wi), s.wo = glm::normalize(wo);
          const RGBT<double> f = m.f(s.wi, s.wo);
          s.value = glm::dvec3(f.x, f.y, f.z);
          // Solid angle of the bin, dw_i dw_o = 4 cos(theta_d) sin(theta_h) sin(theta_d) dth dph dtd dpd
          // (measured/samples.h, merl_samples), the constant factors dropped (weights are relative).
          s.weight = 4.0 * std::cos(td) * std::sin(th) * std::sin(td) * dth;
          if (!(s.weight > 0.0) || !std::isfinite(s.value.x + s.value.y + s.value.z)) continue;
          set.samples.push_back(s);
        }
      }
    }
  }
  return set;
}

FitErrors target_errors(const TargetBrdf& t, const SampleSet& data) {
  return fit_errors([&t](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(t.f(wi, wo)); }, data);
}

namespace {
// rho(wo) = integral f cos_i dw_i, over the half vector h: wi = reflect(wo, h), dw_i = 4 (wo.h) dw_h,
// theta_h on a quadratic grid (dense near the normal, where the sharp lobes are).
template <typename F> glm::dvec3 albedo_by_half_vector(F&& f, const Vec3d& wo) {
  constexpr int nt = 128, np = 128;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < nt; ++i) {
    const double u = (i + 0.5) / nt, th = u * u * kPi<double> / 2.0, dth = 2.0 * u / nt * kPi<double> / 2.0;
    for (int j = 0; j < np; ++j) {
      const double ph = (j + 0.5) * 2.0 * kPi<double> / np;
      const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const double oh = glm::dot(wo, h);
      if (!(oh > 0.0)) continue;
      const Vec3d wi = 2.0 * oh * h - wo;
      if (!(wi.z > 0.0)) continue;
      sum += f(wi) * (wi.z * 4.0 * oh * std::sin(th) * dth * (2.0 * kPi<double> / np));
    }
  }
  return sum;
}
}  // namespace

double max_albedo_difference(const MaterialD& source, const TargetBrdf& t, double* theta_deg, double* phi_deg) {
  double worst = 0.0;
  for (double th : {0.0, 20.0, 40.0, 60.0, 75.0})
    for (double ph : {0.0, 45.0, 90.0}) {
      const double a = glm::radians(th), p = glm::radians(ph);
      const Vec3d wo(std::sin(a) * std::cos(p), std::sin(a) * std::sin(p), std::cos(a));
      const glm::dvec3 s = albedo_by_half_vector(
          [&](const Vec3d& wi) {
            const RGBT<double> f = source.f(wi, wo);
            return glm::dvec3(f.x, f.y, f.z);
          },
          wo);
      const glm::dvec3 g = albedo_by_half_vector([&](const Vec3d& wi) { return t.f(wi, wo); }, wo);
      const double d = max3(glm::abs(s - g));
      if (d > worst) {
        worst = d;
        if (theta_deg) *theta_deg = th;
        if (phi_deg) *phi_deg = ph;
      }
    }
  return worst;
}

// --- reports -----------------------------------------------------------------------------------------

json ImageCheck::to_json() const {
  return {
      {"size", size},
      {"scene", fmt::format("orthographic unit sphere, uniform environment {:g}, sun {:g} from normalize(-0.5, 0.6, 1)",
                            kCheckEnvironment, kCheckSunIrradiance)},
      {"mean", {{"source", mean_source}, {"target", mean_target}, {"relative_difference", mean_difference}}},
      {"lit", {{"source", lit_source}, {"target", lit_target}, {"relative_difference", lit_difference}}},
      {"colour",
       {{"source_rgb", j3(rgb_source)}, {"target_rgb", j3(rgb_target)}, {"chromaticity_difference", chromaticity_difference}}},
      {"warn", warn()},
      {"bounds", {{"mean", kCheckWarnMean}, {"lit", kCheckWarnLit}}}};
}

json ExportReport::to_json() const {
  json j = {{"target", target},
            {"target_model", target_model},
            {"path", exact ? "exact" : "fitted"},
            {"origin", origin},
            {"parameters", parameters},
            {"error", {{"l2cos", errors.l2cos_all}, {"log", errors.log_all}, {"relative_l2cos", errors.relative_l2cos}}},
            {"max_albedo_difference",
             {{"value", max_albedo_difference}, {"theta_o_deg", albedo_theta_deg}, {"phi_o_deg", albedo_phi_deg}}},
            {"samples", samples},
            {"notes", notes}};
  if (!blender_version.empty()) j["blender_version"] = blender_version;  // --to blender only
  if (image.size > 0) j["image_check"] = image.to_json();
  if (!measured_file.empty()) j["measured_file"] = measured_file;
  return j;
}

std::string ExportReport::text(std::string_view pre) const {
  std::string s;
  const auto line = [&](const std::string& l) { s += std::string(pre) + l + "\n"; };
  line(fmt::format("aniso export, target {}: {}", target, target_model));
  if (!blender_version.empty()) line(fmt::format("  the numbers below hold for {}", blender_version));
  line(fmt::format("  {}", origin));
  line(fmt::format("  parameters: {}", parameters.dump()));
  line(fmt::format("  error of the export against the source ({} samples): l2cos {:.4g} (relative {:.3g}), log {:.4g}", samples,
                   errors.l2cos_all, errors.relative_l2cos, errors.log_all));
  line(fmt::format("  largest directional-albedo difference: {:.4g} (theta_o {:g}, phi_o {:g} deg)", max_albedo_difference,
                   albedo_theta_deg, albedo_phi_deg));
  if (image.size > 0)
    line(fmt::format(
        "  image check (a sphere under a uniform environment and a sun, {} px): the target's mean {:.1f} % "
        "from the source's, its lit region's {:.1f} %{}; the mean colour {:.3f} / {:.3f} / {:.3f} (the source's {:.3f} / {:.3f} "
        "/ "
        "{:.3f}), chromaticity {:.3f} from the source's",
        image.size, 100.0 * image.mean_difference, 100.0 * image.lit_difference,
        image.warn() ? fmt::format(" (above {:g} % / {:g} %)", 100.0 * kCheckWarnMean, 100.0 * kCheckWarnLit) : std::string(),
        image.rgb_target.x, image.rgb_target.y, image.rgb_target.z, image.rgb_source.x, image.rgb_source.y, image.rgb_source.z,
        image.chromaticity_difference));
  for (const std::string& n : notes) line("  note: " + n);
  return s;
}

}  // namespace aniso::exporter
