// fit/energy.h (private): the energy constraint (docs/fitting.md, "Energy"): the albedo grid, the
// watched directions and their penalty, and the constraint met on the linear entries or by scaling.
#pragma once

#include <optional>
#include <vector>

#include "aniso/stats/albedo.h"
#include "fit/separable.h"

namespace aniso::fit_detail {

// --- Energy (docs/fitting.md, "Energy") ---------------------------------------------------------

// The grid the largest directional albedo is measured on: theta_o from 0 to 89 degrees, and for an
// anisotropic material phi_o over the half circle (every anisotropic lobe repeats after a half
// turn), with kAlbedoSamples importance samples each (stats/albedo.h, the model's own sampler:
// standard errors of a few 1e-3 for the fitted lobes).
constexpr double kAlbedoThetaDeg[] = {0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 85, 89};
constexpr int kAlbedoPhiSteps = 12;  // 0, 15, ..., 165 degrees
constexpr int64_t kAlbedoSamples = 4096;
// The constraint: the penalty pushes each watched albedo below kAlbedoTarget (a margin under 1 for
// the estimators' noise), and the fit is accepted when the measured largest is <= kAlbedoLimit.
constexpr double kAlbedoTarget = 0.995, kAlbedoLimit = 1.005;

struct AlbedoAt {
  double value = 0.0;  // the largest channel
  double theta_deg = 0.0, phi_deg = 0.0;
  Vec3d wo{0.0, 0.0, 1.0};
};

// Every grid direction's albedo (largest channel), largest first.
std::vector<AlbedoAt> albedo_grid(const MaterialD& m, bool anisotropic);

// One watched direction of the energy penalty: wo and fixed directions wi_j with their proposal
// density q_j, drawn once from the material being constrained (half from its sampler, half
// cosine-distributed: a defensive mixture, Hesterberg 1995, so that q stays > 0 wherever the
// moving lobe may go). A(x) = mean_j f_x(wi_j, wo) cos / q_j is then an unbiased albedo estimate
// for every x, differentiable through the kernel's Jet like the data residuals.
struct WatchedDirection {
  Vec3d wo;
  std::vector<Vec3d> wi;
  std::vector<double> inv_q;
};

// A watched direction at wo: count directions wi_j drawn with the given seed (energy.cpp).
WatchedDirection watch(const MaterialD& m, const Vec3d& wo, int count, uint64_t seed);

// The penalty residuals: per watched direction and channel, weight max(0, A(x) - kAlbedoTarget).
template <class Model, int N> class EnergyCost final : public ceres::CostFunction {
 public:
  EnergyCost(const Model& model, std::vector<WatchedDirection> dirs, double weight)
      : model_(model), dirs_(std::move(dirs)), weight_(weight), size_(int(model.defs.size())) {
    set_num_residuals(3 * int(dirs_.size()));
    mutable_parameter_block_sizes()->push_back(size_);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* x = parameters[0];
    if (!jacobians || !jacobians[0]) return evaluate<double>(x, residuals, nullptr);
    using J = ceres::Jet<double, N>;
    J xj[N];
    for (int p = 0; p < size_; ++p) xj[p] = J(x[p], p);
    return evaluate<J>(xj, residuals, jacobians[0]);
  }

 private:
  template <typename T> bool evaluate(const T* x, double* residuals, double* jac) const {
    const auto m = model_.template build<T>(x);
    const Turn<T> turn = turn_of(model_, x);
    for (size_t k = 0; k < dirs_.size(); ++k) {
      const WatchedDirection& d = dirs_[k];
      const Vec3T<T> wo = turn(d.wo);
      RGBT<T> a(T(0));
      for (size_t j = 0; j < d.wi.size(); ++j) a += m.f(turn(d.wi[j]), wo) * T(d.wi[j].z * d.inv_q[j]);
      for (int c = 0; c < 3; ++c) {
        const T excess = a[c] - T(kAlbedoTarget);
        const T r = excess > T(0) ? excess * weight_ : T(0);
        if constexpr (std::is_same_v<T, double>) {
          residuals[3 * k + c] = r;
        } else {
          residuals[3 * k + c] = r.a;
          for (int p = 0; p < size_; ++p) jac[(3 * k + size_t(c)) * size_t(size_) + size_t(p)] = r.v[p];
        }
      }
    }
    for (size_t i = 0; i < 3 * dirs_.size(); ++i)
      if (!std::isfinite(residuals[i])) return false;
    return true;
  }
  const Model& model_;
  std::vector<WatchedDirection> dirs_;
  double weight_;
  int size_;
};

// The energy constraint on the linear entries (fit_with, "Energy"): the albedo in a watched
// direction wo is estimated with fixed directions wi_j and densities (WatchedDirection: drawn once,
// so the estimate is affine in the linear entries, as f is), which makes "albedo_c(wo) <=
// kAlbedoTarget" one linear inequality per direction and channel; the linear entries are then
// solved exactly under them (solve_linear). Directions whose measured albedo (albedo_grid, the
// model's own sampler) still exceeds kAlbedoLimit join the watched ones for another round.
constexpr int kEnergyRounds = 4, kMaxWatched = 24;
template <class Model, class Build>
std::optional<std::vector<double>> energy_by_linear(const Model& model, const LinearLayout& layout, std::vector<double> x,
                                                    std::vector<AlbedoAt> grid, const std::vector<Prepared>& samples,
                                                    const Build& build_fitted) {
  constexpr int kWatchSamples = 1024;
  const int k = int(layout.channel[0].size());
  std::vector<Vec3d> watched;
  for (int round = 0; round < kEnergyRounds; ++round) {
    for (const AlbedoAt& a : grid)
      if (a.value > kAlbedoTarget && int(watched.size()) < kMaxWatched &&
          std::find(watched.begin(), watched.end(), a.wo) == watched.end())
        watched.push_back(a.wo);
    const MaterialD current = build_fitted(x);
    const auto kernels = basis_kernels(model, layout, x);
    const Turn<double> turn = turn_of(model, x.data());
    const int rows = int(watched.size());
    std::array<std::pair<Eigen::MatrixXd, Eigen::VectorXd>, 3> limits;
    for (auto& [G, h] : limits) G = Eigen::MatrixXd(rows, k), h = Eigen::VectorXd(rows);
    for (int d = 0; d < rows; ++d) {
      const WatchedDirection w = watch(current, watched[size_t(d)], kWatchSamples, 0xe4e7 + 97 * uint64_t(d) + uint64_t(round));
      const Vec3d wo = turn(w.wo);
      std::vector<glm::dvec3> albedo(kernels.size(), glm::dvec3(0.0));
      for (size_t j = 0; j < w.wi.size(); ++j) {
        const Vec3d wi = turn(w.wi[j]);
        for (size_t p = 0; p < kernels.size(); ++p) {
          const RGBT<double> f = kernels[p].f(wi, wo);
          albedo[p] += glm::dvec3(f.x, f.y, f.z) * (w.wi[j].z * w.inv_q[j]);
        }
      }
      for (int c = 0; c < 3; ++c) {
        for (int j = 0; j < k; ++j) limits[size_t(c)].first(d, j) = albedo[size_t(j) + 1][c] - albedo[0][c];
        limits[size_t(c)].second(d) = kAlbedoTarget - albedo[0][c];
      }
    }
    if (!std::isfinite(solve_linear(model, layout, x, samples, &limits))) return std::nullopt;
    grid = albedo_grid(build_fitted(x), model.rotation_index() >= 0);
    if (grid.front().value <= kAlbedoLimit) return x;
  }
  return std::nullopt;
}

// Each channel scaled as a whole, f_c -> s_c f_c, s_c = kAlbedoTarget / its largest albedo on the
// grid, for a model that can scale itself exactly: Lafortune, whose rho_d scales and whose lobe
// max(C . )^n scales by s when C does by s^(1/n) (a lobe with n = 0 is a constant and stays).
// Nothing for the other models (their linear entries cover every term, energy_by_linear).
template <class Model, class Build>
std::optional<std::vector<double>> energy_by_scaling(const Model& model, std::vector<double> x, std::vector<AlbedoAt> grid,
                                                     const Build& build_fitted) {
  if constexpr (!std::is_same_v<Model, LafortuneFit>) {
    return std::nullopt;
  } else {
    for (int round = 0; round < kEnergyRounds; ++round) {
      const MaterialD m = build_fitted(x);
      glm::dvec3 largest(0.0);
      uint64_t seed = 0x5ca1e;
      for (const AlbedoAt& a : grid) {
        if (a.value <= kAlbedoTarget) break;  // the grid is sorted, largest first
        const AlbedoEstimate e = albedo_importance(m, a.wo, kAlbedoSamples, seed++);
        largest = glm::max(largest, glm::dvec3(e.mean.x, e.mean.y, e.mean.z));
      }
      for (int c = 0; c < 3; ++c) {
        if (!(largest[c] > kAlbedoTarget)) continue;
        const double scale = kAlbedoTarget / largest[c];
        x[size_t(model.rho(c))] *= scale;
        for (int lobe = 0; lobe + 1 < model.part_count(); ++lobe) {
          const double n = x[size_t(model.n(lobe, c))];
          if (!(n > 0.0)) continue;
          const double f = std::pow(scale, 1.0 / n);
          std::vector<int> entries = {model.cx(lobe, c), model.cy(lobe, c), model.cz(lobe, c)};
          std::sort(entries.begin(), entries.end());
          entries.erase(std::unique(entries.begin(), entries.end()), entries.end());  // isotropic: cy is cx
          for (int i : entries) x[size_t(i)] *= f;
        }
      }
      grid = albedo_grid(build_fitted(x), model.rotation_index() >= 0);
      if (grid.front().value <= kAlbedoLimit) return x;
    }
    return std::nullopt;
  }
}

}  // namespace aniso::fit_detail
