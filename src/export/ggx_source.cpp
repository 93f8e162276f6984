// export/ggx_source.cpp: source -> GGX, the GGX every target maps from: exact by formula where
// the source has that distribution, else fitted (an alpha grid search, then the fitting engine).
#include "export/common.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "aniso/io/input_error.h"
#include "aniso/measured/measured.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"

namespace aniso::exporter {

// --- source -> GGX -----------------------------------------------------------------------------------

namespace {

// Exact where the model says it is a GGX as a whole (its kernel's ggx_distribution, the question
// rgl_source.cpp asks too): the alphas, the Fresnel and the Lambertian term are the model's.
std::optional<GgxSource> exact_ggx(const MaterialDesc& d) {
  const MaterialD m = build_material<double>(unrotated(d));
  const GgxDistributionT<double> dist = m.ggx_distribution();
  if (dist.part != GgxPart::Whole) return std::nullopt;
  GgxSource g;
  g.rotation_deg = rotation_of(d);
  g.alpha_x = dist.alpha_x, g.alpha_y = dist.alpha_y;
  if (dist.fresnel == GgxFresnel::Conductor) {
    g.conductor = true;
    g.eta = dist.eta, g.k = dist.k;
    if (d.params.has("metal")) {
      const MetalData* md = find_metal(d.params.text("metal"));
      if (md) g.metal = std::string(md->name), g.symbol = std::string(md->symbol);
    }
    g.origin = "exact: the source is a conductor with a GGX lobe (eta, k)";
    return g;
  }
  g.kd = dist.kd, g.f0 = dist.f0;
  if (dist.f90 != RGBT<double>(1.0)) {
    // A Fresnel with f90 below 1 (ggx.h) that no target writes (their GGX materials use Schlick's
    // F90 = 1): D, G and kd stay the source's, and F0 becomes the Schlick F0' closest to the source's
    // F over the difference angles of Ngan's range (theta_d uniform in [0, 80] degrees, least squares
    // per channel): F0' = F0 - (1 - F90) <w (1 - w)> / <(1 - w)^2>, w = (1 - cos theta_d)^5.
    // (Fitting the whole model on the analytic grid instead misses a sharp lobe's peak: alpha 0.01
    // is narrower than the grid's theta_h step.)
    double ww = 0.0, w1 = 0.0;
    constexpr int kSteps = 64;
    for (int i = 0; i < kSteps; ++i) {
      const double theta_d = (i + 0.5) / kSteps * kNganMaxThetaDeg * kPi<double> / 180.0;
      const double m = 1.0 - std::cos(theta_d), w = m * m * m * m * m;
      ww += w * (1.0 - w), w1 += (1.0 - w) * (1.0 - w);
    }
    for (int c = 0; c < 3; ++c) g.f0[c] = std::clamp(dist.f0[c] - (1.0 - dist.f90[c]) * ww / w1, 0.0, 1.0);
    g.origin = fmt::format(
        "the source's GGX (alphas, Lambertian kd) with the Schlick F0 {:.4g}, {:.4g}, {:.4g} closest to its Fresnel with "
        "f90 {:.4g}, {:.4g}, {:.4g} (theta_d 0 to 80 degrees): no target writes an f90",
        g.f0[0], g.f0[1], g.f0[2], dist.f90[0], dist.f90[1], dist.f90[2]);
    g.exact = false;  // not the source's F: refined for each target (refine.cpp), as a fit is
    return g;
  }
  if (dist.masking == GgxMasking::HeightCorrelated) {
    g.origin = "exact: the source is an anisotropic GGX (Schlick F0, Lambertian kd)";
  } else {
    g.origin = fmt::format(
        "exact: the source ({}) is a GGX lobe with Schlick F0{} (its separable Smith G differs from the targets' "
        "height-correlated one)",
        model_name(m.kind), max3(g.kd) > 0.0 ? " and a Lambertian kd" : " and no diffuse term");
  }
  return g;
}

}  // namespace

std::pair<bool, std::string> decide_source_isotropy(const MaterialDesc& desc) {
  if (desc.rgl && desc.rgl->isotropic)
    return {true, "isotropic by construction: an RGL tensor file with one phi_i (pbrt-v4 and Mitsuba 3 read it isotropic)"};
  if (desc.measured) return {true, "isotropic by construction: a MERL table (f of theta_h, theta_d, phi_d)"};
  const MaterialD m = build_material<double>(unrotated(desc));
  rgl::BrdfSource src = rgl::brdf_source(m);
  const double rd = rgl::rotation_difference(src);
  const bool iso = rd <= rgl::kMeasuredIsotropyTolerance;
  return {iso, fmt::format("{}: turning both directions about the normal changes f by {:.3g} % ({} the {:g} % of the "
                           "rotation test, rgl_export.h)",
                           iso ? "isotropic" : "anisotropic", 100.0 * rd, iso ? "within" : "beyond",
                           100.0 * rgl::kMeasuredIsotropyTolerance)};
}

bool negligible_diffuse(const GgxSource& g) {
  return !g.conductor && max3(g.kd) <= kNegligibleDiffuseAbs + kNegligibleDiffuseShare * max3(g.f0);
}

namespace {

// A GGX as the exporter fits it: error of aniso's GGX kernel (ggx.h / metal.h) against the samples.
FitErrors ggx_errors(const GgxSource& g, const SampleSet& data) {
  TargetBrdf t;
  t.lobe.alpha_x = g.alpha_x, t.lobe.alpha_y = g.alpha_y;
  t.lobe.masking = Masking::HeightCorrelated;
  if (g.conductor)
    t.lobe.fresnel = FresnelModel::Conductor, t.lobe.eta = g.eta, t.lobe.k = g.k;
  else
    t.lobe.fresnel = FresnelModel::Schlick, t.lobe.f0 = g.f0, t.diffuse = g.kd;
  return target_errors(t, data);
}

// The fit engine's starts (moments, Ngan's nearest fit, random draws) can miss the basin of a sharp
// anisotropic lobe (Ward 0.05 x 0.3: all 16 starts ended at alpha_y = 1). A second candidate that
// cannot: a search over the two alphas (log grid, 0.002 to 1, then a finer grid around the best),
// where everything else is linear (kd and F0 of the Schlick GGX: f = kd / pi + (F0 (1 - s) + s) L,
// s = (1 - wi.h)^5, solved by weighted least squares per channel, l2cos residuals) or fixed (the
// conductor's eta, k: the source's own). Its result is one of the fit's starts (FitOptions::start).
GgxSource grid_fit(const GgxSource& base, const SampleSet& all) {
  SampleSet data;
  const size_t stride = std::max<size_t>(1, all.samples.size() / 6000);
  for (size_t i = 0; i < all.samples.size(); i += stride) data.samples.push_back(all.samples[i]);
  struct Pre {
    Vec3d wi, wo;
    double c, s5, w;
    glm::dvec3 v;
  };
  std::vector<Pre> pre;
  for (const MeasuredSample& m : data.samples) {
    const Vec3d h = glm::normalize(m.wi + m.wo);
    const double s = 1.0 - std::clamp(glm::dot(m.wi, h), 0.0, 1.0);
    pre.push_back({m.wi, m.wo, m.wi.z, s * s * s * s * s, m.weight, m.value});
  }
  const auto solve = [&](double ax, double ay, GgxSource& g) {
    GGXLobeT<double> lobe;
    lobe.alpha_x = ax, lobe.alpha_y = ay;
    g.alpha_x = ax, g.alpha_y = ay;
    double err = 0.0;
    if (g.conductor) {
      for (const Pre& p : pre) {
        const glm::dvec3 F = F_Conductor(glm::dot(p.wi, glm::normalize(p.wi + p.wo)), RGBT<double>(g.eta), RGBT<double>(g.k));
        const glm::dvec3 r = (F * lobe.eval(p.wi, p.wo) - p.v) * p.c;
        err += p.w * glm::dot(r, r);
      }
      return err;
    }
    // Normal equations of [c / pi, (1 - s) L c] (kd, F0) against (v - s L) c, per channel.
    double a11 = 0, a12 = 0, a22 = 0;
    glm::dvec3 b1(0.0), b2(0.0);
    std::vector<double> L(pre.size());
    for (size_t i = 0; i < pre.size(); ++i) {
      const Pre& p = pre[i];
      L[i] = lobe.eval(p.wi, p.wo);
      const double x1 = p.c * kInvPi<double>, x2 = (1.0 - p.s5) * L[i] * p.c;
      const glm::dvec3 y = (p.v - p.s5 * L[i]) * p.c;
      a11 += p.w * x1 * x1, a12 += p.w * x1 * x2, a22 += p.w * x2 * x2;
      b1 += p.w * x1 * y, b2 += p.w * x2 * y;
    }
    for (int c = 0; c < 3; ++c) {
      const double det = a11 * a22 - a12 * a12;
      double kd = det != 0.0 ? (b1[c] * a22 - b2[c] * a12) / det : 0.0;
      double f0 = det != 0.0 ? (a11 * b2[c] - a12 * b1[c]) / det : 0.0;
      // The box [0, 1]^2: clamp one, re-solve the other.
      if (kd < 0.0 || kd > 1.0)
        kd = std::clamp(kd, 0.0, 1.0), f0 = a22 > 0 ? std::clamp((b2[c] - a12 * kd) / a22, 0.0, 1.0) : 0.0;
      if (f0 < 0.0 || f0 > 1.0)
        f0 = std::clamp(f0, 0.0, 1.0), kd = a11 > 0 ? std::clamp((b1[c] - a12 * f0) / a11, 0.0, 1.0) : 0.0;
      g.kd[c] = kd, g.f0[c] = f0;
    }
    for (size_t i = 0; i < pre.size(); ++i) {
      const Pre& p = pre[i];
      const glm::dvec3 f = g.kd * kInvPi<double> + (g.f0 * (1.0 - p.s5) + p.s5) * L[i];
      const glm::dvec3 r = (f - p.v) * p.c;
      err += p.w * glm::dot(r, r);
    }
    return err;
  };
  constexpr int n = 24;
  const double lo = std::log(0.002), hi = std::log(1.0), step = (hi - lo) / (n - 1);
  GgxSource best = base, g = base;
  double best_err = INFINITY, bx = 0, by = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double e = solve(std::exp(lo + i * step), std::exp(lo + j * step), g);
      if (e < best_err) best_err = e, best = g, bx = lo + i * step, by = lo + j * step;
    }
  constexpr int m = 9;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = std::min(hi, bx + (i - (m - 1) / 2) * step / ((m - 1) / 2));
      const double y = std::min(hi, by + (j - (m - 1) / 2) * step / ((m - 1) / 2));
      const double e = solve(std::exp(x), std::exp(y), g);
      if (e < best_err) best_err = e, best = g;
    }
  return best;
}

}  // namespace

SampleSet export_samples(const MaterialDesc& d, const MaterialD& source, const ExportOptions& o) {
  if (!d.rgl && !d.measured) return sample_source(source, o.grid);
  SampleSet s = d.rgl ? rgl_samples(*d.rgl, d.rgl->source, rgl_sample_grid(d.rgl->isotropic, o.measured_grid))
                      : merl_samples(d.measured->brdf, d.measured->source);
  // fit_samples' range test (fit.cpp): a sample at the edge is in.
  const double c = std::cos(kNganMaxThetaDeg * kPi<double> / 180.0) - 1e-12;
  std::erase_if(s.samples, [c](const MeasuredSample& m) { return m.wi.z < c || m.wo.z < c; });
  return s;
}

GgxSource ggx_source(const MaterialDesc& d, const SampleSet& samples, const ExportOptions& o) {
  if (std::optional<GgxSource> g = exact_ggx(d)) {
    g->isotropic = g->alpha_x == g->alpha_y;
    return *g;
  }
  if (samples.samples.empty())
    throw InputError(
        fmt::format("{}: the material reflects nothing above the horizon: there is nothing to export", d.params.where));
  double total = 0.0;
  for (const MeasuredSample& s : samples.samples) total += s.value.x + s.value.y + s.value.z;
  if (!(total > 0.0))
    throw InputError(
        fmt::format("{}: the material is black (f = 0 at every sampled pair): no target can represent it "
                    "other than as black, and a fit has nothing to fit",
                    d.params.where.empty() ? d.model : d.params.where));
  FitOptions fo;
  // Anisotropic only when the source is (decide_source_isotropy): an isotropic source gets an
  // isotropic fit, which no target writes with an anisotropy. The fit follows the source where
  // that gains energy: the export reproduces the source, it does not correct it.
  const auto [isotropic, isotropy_why] = decide_source_isotropy(d);
  fo.anisotropy = isotropic ? Anisotropy::No : Anisotropy::Yes;
  fo.allow_energy_gain = true;
  // An analytic source: every sample of its grid, grazing ones included (the export's errors are
  // measured over all of them, target_errors). A measured one: the fit protocol of `aniso fit`
  // (docs/fitting.md): Ngan 2005's 80 degrees, so that grazing outliers do not decide the fit, on
  // the file's own samples (rgl_samples, merl_samples); export_material measures its errors over
  // the same range.
  const bool measured = d.rgl || d.measured;
  fo.max_theta_deg = measured ? kNganMaxThetaDeg : 90.0;
  fo.metric = o.metric;
  fo.starts = o.starts;
  fo.seed = o.seed;
  fo.threads = o.threads;
  fo.max_iterations = 100;
  GgxSource g;
  g.rotation_deg = rotation_of(d);
  if (d.model == "metal") {
    fo.model = "metal";
    fo.metal_lobe = "ggx";
    if (d.params.has("metal")) fo.metal = d.params.text("metal");
  } else {
    fo.model = "ggx";
  }
  if (d.params.has("metal")) {
    if (const MetalData* md = find_metal(d.params.text("metal")))
      g.metal = std::string(md->name), g.symbol = std::string(md->symbol);
  }
  // The alpha grid search first (the conductor keeps the source's own eta, k), then Ceres with its
  // result as one more start beside its own (Levenberg-Marquardt does not raise the cost of a start
  // on the solver's samples).
  GgxSource start = g;
  if (fo.model == "metal") {
    start.conductor = true;
    const MaterialD src = build_material<double>(unrotated(d));
    start.eta = glm::dvec3(src.metal.eta.x, src.metal.eta.y, src.metal.eta.z);
    start.k = glm::dvec3(src.metal.k.x, src.metal.k.y, src.metal.k.z);
  }
  // A measured source: `aniso fit`'s own path (its separable grid start and the linear entries
  // solved exactly, fit/linear.h) on the file's samples (export_samples), max_iterations as `aniso fit`'s.
  const GgxSource grid = measured ? start : grid_fit(start, samples);
  const char* ch[3] = {"r", "g", "b"};
  if (!measured) {
    fo.start = {{"alpha_x", grid.alpha_x}, {"alpha_y", grid.alpha_y}};
    if (!isotropic) fo.start.emplace_back("rotation_deg", 0.0);
    for (int c = 0; c < 3; ++c) {
      if (fo.model == "ggx")
        fo.start.emplace_back(fmt::format("kd.{}", ch[c]), grid.kd[c]),
            fo.start.emplace_back(fmt::format("f0.{}", ch[c]), grid.f0[c]);
      else if (fo.metal.empty())
        fo.start.emplace_back(fmt::format("eta.{}", ch[c]), grid.eta[c]),
            fo.start.emplace_back(fmt::format("k.{}", ch[c]), grid.k[c]);
    }
  } else {
    fo.max_iterations = 200;
  }
  const FitResult r = fit_samples(samples, fo);
  const MaterialDesc fitted = parse_material(r.material, "fitted GGX");
  std::optional<GgxSource> e = exact_ggx(fitted);
  if (!e) throw std::logic_error("export: the fitted material is not a GGX");
  g.alpha_x = e->alpha_x, g.alpha_y = e->alpha_y;
  // The source was sampled unturned, so the fitted turn is 0 or a quarter turn: the fit writes its
  // canonical form, the narrower direction along the tangent (src/fit/models.h, Orientation), which
  // for a source wider along the tangent is the swapped pair turned by 90 degrees.
  if (r.anisotropic && std::abs(std::remainder(r.material.value("rotation_deg", 0.0), 180.0)) > 45.0)
    std::swap(g.alpha_x, g.alpha_y);
  g.conductor = e->conductor;
  g.kd = e->kd, g.f0 = e->f0, g.eta = e->eta, g.k = e->k;
  g.exact = false;
  g.isotropic = isotropic;
  g.isotropy = isotropy_why;
  if (isotropic) g.alpha_y = g.alpha_x = std::sqrt(g.alpha_x * g.alpha_y);
  g.source_fit = r.errors;
  const FitErrors grid_err = measured ? FitErrors{} : ggx_errors(grid, samples);
  const std::string how =
      measured ? fmt::format(
                     "aniso fit's protocol on the file's {} samples: theta up to {:g} deg, {} starts, best {}; "
                     "relative l2cos {:.4g} there",
                     samples.samples.size(), fo.max_theta_deg, fo.starts, r.best_start, r.errors.relative_l2cos)
               : fmt::format("Ceres from {} starts and the alpha grid search's result (l2cos {:.4g}, log {:.4g}), best {}",
                             fo.starts, grid_err.l2cos_all, grid_err.log_all, r.best_start);
  g.origin = fmt::format(
      "fitted: aniso's {} {} to {} samples of the {} source ({} metric; {}): l2cos {:.4g}, "
      "log {:.4g}",
      isotropic ? "isotropic" : "anisotropic", fo.model == "metal" ? "GGX conductor" : "GGX", samples.samples.size(), d.model,
      o.metric == FitMetric::L2Cos ? "l2cos" : "log", how, g.source_fit.l2cos_all, g.source_fit.log_all);
  return g;
}

}  // namespace aniso::exporter
