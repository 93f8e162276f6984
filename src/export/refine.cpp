// export/refine.cpp: the fitted path's last step, the GGX refined with the target's own model.
#include "export/common.h"

#include <cmath>
#include <utility>
#include <vector>

namespace aniso::exporter {

// The fitted path, last step: the target's own model (its masking, its Fresnel) against the source,
// over the roughness and the colours. The GGX fit is aniso's (height-correlated Smith, Schlick,
// Lambert); the target model differs (Mitsuba 3's separable G, MaterialX's G2 at the mean alpha,
// exact Fresnel curves, Blender 3.4's Burley diffuse and interpolated Fresnel), so the alphas are
// searched again with the written model itself: factors 0.6 to 1.5 on each alpha (a 9 x 9 log grid,
// then 7 x 7 around the best), on at most o.refine_samples of the samples (export_samples: a measured
// source's own, whose peak a --grid of 3 misses), in the chosen metric. At
// each alpha pair the colours (kd and F0 of the Schlick GGX, per channel, which every target writes
// as its diffuse colour and its F0 / specular / base colour) are re-solved by weighted least squares
// in the target model (relinearise), and kept when that lowers the error.
GgxSource refine_for_target(Target t, const GgxSource& g, const SampleSet& all, const ExportOptions& o, BlenderV1Nodes nodes) {
  SampleSet data;
  const size_t stride = std::max<size_t>(1, all.samples.size() / size_t(std::max(o.refine_samples, 100)));
  for (size_t i = 0; i < all.samples.size(); i += stride) data.samples.push_back(all.samples[i]);
  const auto model = [&](const GgxSource& x) { return target_model(t, x, nullptr, nullptr, o.blender_version, nodes); };
  const auto error = [&](const GgxSource& x) { return metric_of(target_errors(model(x), data), o.metric); };
  // The other metric, which a re-solve of the colours may not raise: the report gives both, and a
  // change that trades one for the other is not an improvement.
  const FitMetric other = o.metric == FitMetric::L2Cos ? FitMetric::Log : FitMetric::L2Cos;
  // The colours a conductor does not have (its eta, k are the source's); a source without a diffuse
  // part keeps none (a diffuse colour would change what the target writes: a metal becomes a
  // dielectric), one with a diffuse part keeps some (kd >= 1e-5, above no_diffuse's 1e-6).
  const bool has_kd = !no_diffuse(g);
  std::vector<int> vars;  // 0..2 kd, 3..5 f0
  if (!g.conductor)
    for (int v = has_kd ? 0 : 3; v < 6; ++v) vars.push_back(v);
  const auto get = [](GgxSource& x, int v) -> double& { return v < 3 ? x.kd[v] : x.f0[v - 3]; };
  const size_t n_s = data.samples.size();
  std::vector<glm::dvec3> f0v(n_s), f1v(n_s);
  const auto eval_all = [&](const GgxSource& x, std::vector<glm::dvec3>& out) {
    const TargetBrdf m = model(x);
    for (size_t i = 0; i < n_s; ++i) out[i] = m.f(data.samples[i].wi, data.samples[i].wo);
  };
  // One Gauss-Newton step on the l2cos residuals (f - v) cos_i, weight w, over the colours, with
  // forward-difference columns: exact for the targets whose model is affine in them (the diffuse
  // colour everywhere; Schlick, F82-tint and 3.4's interpolated Fresnel in F0), a linearisation for
  // the others (an exact Fresnel fitted to Schlick's curve). Clamped to [0, 1] (kd >= 1e-5 where the
  // source has one); returns x unchanged when the step does not lower the error.
  const auto relinearise = [&](const GgxSource& x, double ex) {
    if (vars.empty()) return std::pair{x, ex};
    const int n = int(vars.size());
    eval_all(x, f0v);
    std::vector<std::vector<glm::dvec3>> J(n, std::vector<glm::dvec3>(n_s));
    for (int j = 0; j < n; ++j) {
      GgxSource y = x;
      double& v = get(y, vars[j]);
      const double h = v > 0.5 ? -1e-4 : 1e-4;
      v += h;
      eval_all(y, f1v);
      for (size_t i = 0; i < n_s; ++i) J[j][i] = (f1v[i] - f0v[i]) / h;
    }
    double A[6][6] = {}, b[6] = {};
    for (size_t i = 0; i < n_s; ++i) {
      const MeasuredSample& sm = data.samples[i];
      const double c2w = sm.weight * sm.wi.z * sm.wi.z;
      const glm::dvec3 r = sm.value - f0v[i];
      for (int j = 0; j < n; ++j) {
        b[j] += c2w * glm::dot(J[j][i], r);
        for (int k = j; k < n; ++k) A[j][k] += c2w * glm::dot(J[j][i], J[k][i]);
      }
    }
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < j; ++k) A[j][k] = A[k][j];
    // Gaussian elimination with partial pivoting; a singular system (a colour the target ignores,
    // such as the F0 channels a grey IOR averages) gets a small ridge first.
    double trace = 0.0;
    for (int j = 0; j < n; ++j) trace += A[j][j];
    for (int j = 0; j < n; ++j) A[j][j] += 1e-9 * trace / n + 1e-300;
    double d[6];
    for (int j = 0; j < n; ++j) d[j] = b[j];
    for (int c = 0; c < n; ++c) {
      int piv = c;
      for (int r = c + 1; r < n; ++r)
        if (std::abs(A[r][c]) > std::abs(A[piv][c])) piv = r;
      std::swap(A[c], A[piv]), std::swap(d[c], d[piv]);
      if (!(std::abs(A[c][c]) > 0.0)) return std::pair{x, ex};
      for (int r = c + 1; r < n; ++r) {
        const double f = A[r][c] / A[c][c];
        for (int k = c; k < n; ++k) A[r][k] -= f * A[c][k];
        d[r] -= f * d[c];
      }
    }
    for (int c = n - 1; c >= 0; --c) {
      for (int k = c + 1; k < n; ++k) d[c] -= A[c][k] * d[k];
      d[c] /= A[c][c];
    }
    GgxSource y = x;
    for (int j = 0; j < n; ++j) {
      double& v = get(y, vars[j]);
      v = std::clamp(v + d[j], vars[j] < 3 ? 1e-5 : 0.0, 1.0);
      if (!std::isfinite(v)) return std::pair{x, ex};
    }
    const FitErrors fy = target_errors(model(y), data);
    if (metric_of(fy, o.metric) < ex && metric_of(fy, other) <= metric_of(target_errors(model(x), data), other))
      return std::pair{y, metric_of(fy, o.metric)};
    return std::pair{x, ex};
  };
  // The alpha search, with the colours re-solved at each pair or (colours = false) kept.
  const auto search = [&](bool colours) {
    const auto err = [&](double fx, double fy, GgxSource& out) {
      out = g;
      out.alpha_x = std::clamp(g.alpha_x * fx, 1e-3, 1.0), out.alpha_y = std::clamp(g.alpha_y * fy, 1e-3, 1.0);
      if (!colours) return error(out);
      auto [y, e] = relinearise(out, error(out));
      out = y;
      return e;
    };
    GgxSource best = g, trial;
    double best_err = err(1.0, 1.0, trial), bx = 0.0, by = 0.0;
    best = trial;
    const double lo = std::log(0.6), hi = std::log(1.5);
    constexpr int n = 9;
    const double step = (hi - lo) / (n - 1);
    // An isotropic source (GgxSource::isotropic) keeps alpha_x == alpha_y: the diagonal alone.
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (g.isotropic && i != j) continue;
        const double x = lo + i * step, y = lo + j * step, e = err(std::exp(x), std::exp(y), trial);
        if (e < best_err) best_err = e, best = trial, bx = x, by = y;
      }
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j) {
        if (g.isotropic && i != j) continue;
        const double e = err(std::exp(bx + i * step / 3), std::exp(by + j * step / 3), trial);
        if (e < best_err) best_err = e, best = trial;
      }
    // A second step at the best alphas (the linearisation of an exact Fresnel).
    return colours ? relinearise(best, best_err).first : best;
  };
  // Kept only if better on every sample, not just on the subset searched: the alphas alone when
  // they lower the chosen metric, the colours too when that is no worse in either metric.
  const auto full = [&](const GgxSource& x) { return target_errors(model(x), all); };
  const FitErrors e_g = full(g);
  const GgxSource alphas = search(false);
  const FitErrors e_a = full(alphas);
  const bool alphas_better = metric_of(e_a, o.metric) < metric_of(e_g, o.metric);
  const GgxSource& base = alphas_better ? alphas : g;
  const FitErrors& e_base = alphas_better ? e_a : e_g;
  if (vars.empty()) return base;
  const GgxSource both = search(true);
  const FitErrors e_b = full(both);
  const bool both_better =
      metric_of(e_b, o.metric) < metric_of(e_base, o.metric) && metric_of(e_b, other) <= metric_of(e_base, other);
  return both_better ? both : base;
}

}  // namespace aniso::exporter
