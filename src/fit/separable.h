// fit/separable.h (private): separable least squares (fit/linear.h): the linear entries of a model
// solved exactly, and the separable grid start over the roughness.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Dense>
#include <boost/math/tools/minima.hpp>

#include "fit/linear.h"
#include "fit/starts.h"

namespace aniso::fit_detail {

// --- Separable least squares (fit/linear.h) ----------------------------------------------------

// The linear entries of a model, by their names in its defs (models.h): the diffuse and specular
// weights of each channel ("kd.r", "ks.g", "f0.b", "f90.r", "rho_d.r", "ks_scale.g"), in which f_c is
// affine when the other entries are held: kd / pi, ks times Ward's or Phong's lobe, ks_scale times
// the AS lobe, F0 and F90 in Schlick's F0 (1 - (1 - c)^5) + F90 (1 - c)^5 times the GGX lobe, rho_d
// / pi beside the Lafortune lobes. A model with none (metal: eta and k; principled) gets an empty layout.
template <class Model> LinearLayout linear_layout(const Model& model) {
  static constexpr std::string_view kLinear[] = {"kd", "ks", "f0", "f90", "rho_d", "ks_scale"};
  LinearLayout layout;
  for (size_t i = 0; i < model.defs.size(); ++i) {
    const std::string_view n = model.defs[i].name;
    const size_t dot = n.find('.');
    if (dot == std::string_view::npos || dot + 2 != n.size()) continue;
    const int c = n[dot + 1] == 'r' ? 0 : n[dot + 1] == 'g' ? 1 : n[dot + 1] == 'b' ? 2 : -1;
    if (c >= 0 && std::find(std::begin(kLinear), std::end(kLinear), n.substr(0, dot)) != std::end(kLinear))
      layout.channel[size_t(c)].push_back(int(i));
  }
  if (layout.channel[0].size() != layout.channel[1].size() || layout.channel[0].size() != layout.channel[2].size()) return {};
  return layout;
}

// The kernels of the basis: x with every linear entry 0 (part 0), then with entry j of every
// channel 1 and the others 0 (part j + 1); f_c = f_c(part 0) + sum_j b_cj (f_c(part j+1) - f_c(part 0)).
template <class Model> auto basis_kernels(const Model& model, const LinearLayout& layout, const std::vector<double>& x) {
  const size_t k = layout.channel[0].size();
  using Kernel = decltype(model.template build<double>(x.data()));
  std::vector<Kernel> out;
  for (size_t j = 0; j <= k; ++j) {
    std::vector<double> v = x;
    for (const std::vector<int>& ch : layout.channel)
      for (size_t i = 0; i < k; ++i) v[size_t(ch[i])] = (j == i + 1) ? 1.0 : 0.0;
    out.push_back(model.template build<double>(v.data()));
  }
  return out;
}

// The normal equations of each channel's linear entries over `samples` (l2cos metric): A_j =
// sqrt(w) cos_i g_cj, y = sqrt(w) (target_c - cos_i f_c(part 0)); N = A^T A, r = A^T y, t = y^T y.
struct LinearSystem {
  std::array<Eigen::MatrixXd, 3> N;
  std::array<Eigen::VectorXd, 3> r;
  std::array<double, 3> t{};
};
template <class Model> LinearSystem linear_system(const Model& model, const LinearLayout& layout, const std::vector<double>& x,
                                                  const std::vector<Prepared>& samples) {
  const int k = int(layout.channel[0].size());
  const auto kernels = basis_kernels(model, layout, x);
  const Turn<double> turn = turn_of(model, x.data());
  LinearSystem sys;
  for (int c = 0; c < 3; ++c) sys.N[size_t(c)] = Eigen::MatrixXd::Zero(k, k), sys.r[size_t(c)] = Eigen::VectorXd::Zero(k);
  std::vector<RGBT<double>> f(size_t(k) + 1);
  Eigen::VectorXd a(k);
  for (const Prepared& s : samples) {
    const Vec3d wi = turn(s.wi), wo = turn(s.wo);
    for (size_t j = 0; j < kernels.size(); ++j) f[j] = kernels[j].f(wi, wo);
    for (int c = 0; c < 3; ++c) {
      for (int j = 0; j < k; ++j) a[j] = s.sqrt_w * s.wi.z * (f[size_t(j) + 1][c] - f[0][c]);
      const double y = s.sqrt_w * (s.target[c] - s.wi.z * f[0][c]);
      sys.N[size_t(c)].noalias() += a * a.transpose();
      sys.r[size_t(c)] += a * y;
      sys.t[size_t(c)] += y * y;
    }
  }
  return sys;
}

// The linear entries of x solved exactly at its other entries (fit/linear.h): per channel, the
// bounded least squares over `samples`, with `extra` rows G b <= h per channel (the energy
// constraint) when given. Returns the data cost sum r^2 at the result (infinity when a channel
// has no feasible point; x is then unchanged).
template <class Model> double solve_linear(const Model& model, const LinearLayout& layout, std::vector<double>& x,
                                           const std::vector<Prepared>& samples,
                                           const std::array<std::pair<Eigen::MatrixXd, Eigen::VectorXd>, 3>* extra = nullptr) {
  const LinearSystem sys = linear_system(model, layout, x, samples);
  const size_t k = layout.channel[0].size();
  std::vector<double> out = x;
  double total = 0.0;
  for (size_t c = 0; c < 3; ++c) {
    Eigen::MatrixXd G(0, int(k));
    Eigen::VectorXd h(0);
    if (extra) G = (*extra)[c].first, h = (*extra)[c].second;
    std::vector<double> lo, hi;
    for (int i : layout.channel[c]) lo.push_back(model.defs[size_t(i)].lo), hi.push_back(model.defs[size_t(i)].hi);
    add_box(lo, hi, G, h);
    Eigen::VectorXd b;
    double cost = 0.0;
    if (!constrained_lsq(sys.N[c], sys.r[c], sys.t[c], G, h, b, &cost)) return INFINITY;
    for (size_t i = 0; i < k; ++i) out[size_t(layout.channel[c][i])] = std::clamp(b[int(i)], lo[i], hi[i]);
    total += std::max(cost, 0.0);
  }
  x = std::move(out);
  return total;
}

// The data cost sum r^2 of x over `samples` in the fit's metric (as the Ceres blocks compute it).
template <class Model>
double data_cost(const Model& model, const std::vector<double>& x, const std::vector<Prepared>& samples, FitMetric metric) {
  const auto m = model.template build<double>(x.data());
  const Turn<double> turn = turn_of(model, x.data());
  double e = 0.0;
  for (const Prepared& s : samples) {
    const RGBT<double> f = m.f(turn(s.wi), turn(s.wo));
    for (int c = 0; c < 3; ++c) e += sqr(metric_residual(metric, f[c], s.wi.z, s.target[c], s.sqrt_w));
  }
  return std::isfinite(e) ? e : INFINITY;
}

// The roughness entries a separable grid search runs over (by name): GGX's and Ward's alpha, AS's
// and Phong's exponents; both of an anisotropic pair take the grid's value (an isotropic seed that
// the turned starts and the solver then open up).
constexpr std::string_view kRoughnessNames[] = {"alpha", "alpha_x", "alpha_y", "n", "n_u", "n_v", "exponent"};

// The separable grid start: the moments start with its roughness entries at kGridSteps values,
// log-spaced over [lo, hi] below and clamped to their bounds, the linear entries solved
// exactly at each; the best. Nothing when the model has no roughness entry by those names or no
// linear entries (Lafortune: its lobes' C and n are many; its other starts cover them).
template <class Model> std::optional<StartPoint> separable_grid_start(const Model& model, const LinearLayout& layout,
                                                                      const DataMoments& dm,
                                                                      const std::vector<Prepared>& samples) {
  if (layout.empty()) return std::nullopt;
  std::vector<int> rough;
  for (size_t i = 0; i < model.defs.size(); ++i)
    if (std::find(std::begin(kRoughnessNames), std::end(kRoughnessNames), model.defs[i].name) != std::end(kRoughnessNames))
      rough.push_back(int(i));
  if (rough.empty()) return std::nullopt;
  const std::string_view first = model.defs[size_t(rough[0])].name;
  const bool exponent = first == "n" || first == "n_u" || first == "exponent";
  // alpha 0.002 to 0.8 (GGX and Ward lobes from near-mirror to matte); exponents 1 to 1e5.
  const double lo = exponent ? 1.0 : 0.002, hi = exponent ? 1e5 : 0.8;
  constexpr int kGridSteps = 24;
  StartPoint best{"", {}};
  double best_cost = INFINITY;
  for (int g = 0; g < kGridSteps; ++g) {
    std::vector<double> x = model.moment_start(dm);
    const double v = lo * std::pow(hi / lo, double(g) / (kGridSteps - 1));
    for (int i : rough) x[size_t(i)] = std::clamp(v, model.defs[size_t(i)].lo, model.defs[size_t(i)].hi);
    const double cost = solve_linear(model, layout, x, samples);
    if (cost < best_cost) best_cost = cost, best = {fmt::format("separable grid ({} {:.4g})", first, v), x};
  }
  if (!std::isfinite(best_cost)) return std::nullopt;
  return best;
}

// The roughness span of project_roughness, a factor either way: beyond the spacing of the separable
// grid's 24 steps over 0.002 to 0.8 (a factor of 1.3) and of what ten iterations from a start move
// the roughness, so the minimum near the best start lies inside; farther minima are other starts'
// business. From a point converged on a subset of the samples, kProjectionSpanNear.
inline constexpr double kProjectionSpan = 8.0, kProjectionSpanNear = 1.5;

// Variable projection (Golub & Pereyra 1973, "The differentiation of pseudo-inverses and nonlinear
// least squares problems whose variables separate", SIAM J. Numer. Anal. 10(2)): where the model's
// only entry that is not linear is one roughness entry (an isotropic GGX, with or without a free
// f90, an isotropic Ward), the cost is a function of that entry alone once the linear entries are
// solved exactly at each of its values (solve_linear), and it is minimised over it by Brent's method
// (Boost.Math's brent_find_minima) on its logarithm, within a factor `span` of x's value and the
// entry's bounds. The solver then starts at that minimum: a free-f90 GGX, whose F0 and F90 are
// nearly collinear for a sharp lobe, took about 70 Levenberg-Marquardt iterations from the best
// start to get there (docs/fitting.md). x is changed only where the projected cost is below its own
// (its linear entries solved); returns whether it was. projected_entry: that roughness entry, or
// -1 for a model with a penalty (Lafortune's), a turn, two roughness entries or other entries that
// are not linear (metal's eta and k), which are left to the solver.
template <class Model> int projected_entry(const Model& model, const LinearLayout& layout) {
  if (layout.empty() || model.penalty_count() > 0) return -1;
  std::vector<bool> linear(model.defs.size(), false);
  for (const std::vector<int>& ch : layout.channel)
    for (int i : ch) linear[size_t(i)] = true;
  int rough = -1;
  for (size_t i = 0; i < model.defs.size(); ++i) {
    if (linear[i]) continue;
    if (rough >= 0 ||
        std::find(std::begin(kRoughnessNames), std::end(kRoughnessNames), model.defs[i].name) == std::end(kRoughnessNames))
      return -1;
    rough = int(i);
  }
  return rough;
}
template <class Model> bool project_roughness(const Model& model, const LinearLayout& layout, std::vector<double>& x,
                                              const std::vector<Prepared>& samples, double span = kProjectionSpan) {
  const int rough = projected_entry(model, layout);
  if (rough < 0) return false;
  const double lo = model.defs[size_t(rough)].lo, hi = model.defs[size_t(rough)].hi, v0 = x[size_t(rough)];
  if (!(v0 > 0.0) || !(lo > 0.0)) return false;  // the search runs on the logarithm
  const auto cost_at = [&](double log_v, std::vector<double>* solved) {
    std::vector<double> y = x;
    y[size_t(rough)] = std::exp(log_v);
    const double c = solve_linear(model, layout, y, samples);
    if (solved) *solved = std::move(y);
    return std::isfinite(c) ? c : std::numeric_limits<double>::max();
  };
  const double c0 = cost_at(std::log(v0), nullptr);
  // 24 bits of the logarithm: the roughness to about 1e-7 relatively, far below what the solver's
  // tolerances resolve; 60 evaluations at most (Brent's method needs about 15 on a smooth valley).
  std::uintmax_t evaluations = 60;
  const auto [log_v, c] =
      boost::math::tools::brent_find_minima([&](double t) { return cost_at(t, nullptr); }, std::log(std::max(lo, v0 / span)),
                                            std::log(std::min(hi, v0 * span)), 24, evaluations);
  if (!(c < c0)) return false;
  cost_at(log_v, &x);
  return true;
}

}  // namespace aniso::fit_detail
