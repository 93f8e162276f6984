// fit/identifiability.h (private): the entries the data do not constrain (docs/fitting.md,
// "Identifiability").
#pragma once

#include <Eigen/Dense>

#include "fit/costs.h"

namespace aniso::fit_detail {

// --- Identifiability (docs/fitting.md, "Identifiability") -------------------------------------

// The entries the data do not constrain at x: the eigenvectors of the scaled normal matrix
// D J^T J D (D: each entry's size, max(|x|, 0.01), or 1 for the rotation in degrees, so that a
// column's units do not decide) whose eigenvalue is below kWeakEigenvalue times the largest, i.e.
// singular values of J D below 1e-5 of the largest.
constexpr double kWeakEigenvalue = 1e-10, kWeakComponent = 0.5;

template <class Model> std::vector<int> weak_entries(const Model& model,
                                                     const std::vector<std::unique_ptr<ceres::CostFunction>>& costs,
                                                     const std::vector<double>& x) {
  const int P = int(model.defs.size());
  Eigen::VectorXd scale(P);
  for (int p = 0; p < P; ++p) scale[p] = p == model.rotation_index() ? 1.0 : std::max(std::abs(x[size_t(p)]), 1e-2);
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(P, P);
  for (const auto& c : costs) {
    const int rows = c->num_residuals();
    std::vector<double> r(static_cast<size_t>(rows)), j(static_cast<size_t>(rows) * static_cast<size_t>(P));
    const double* params[] = {x.data()};
    double* jac[] = {j.data()};
    if (!c->Evaluate(params, r.data(), jac)) continue;
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jm(j.data(), rows, P);
    const Eigen::MatrixXd js = jm * scale.asDiagonal();
    normal.noalias() += js.transpose() * js;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(normal);
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const double largest = lambda[P - 1];
  std::vector<int> weak;
  if (!(largest > 0.0)) return weak;
  // An entry is weak when its unit vector lies mostly in the weak subspace: the squares of its
  // components over the weak eigenvectors (a basis of that subspace, any basis when several
  // eigenvalues are 0) sum to more than kWeakComponent^2.
  Eigen::VectorXd in_weak = Eigen::VectorXd::Zero(P);
  for (int k = 0; k < P && lambda[k] <= kWeakEigenvalue * largest; ++k) in_weak += eig.eigenvectors().col(k).cwiseAbs2();
  for (int p = 0; p < P; ++p)
    if (in_weak[p] > kWeakComponent * kWeakComponent) weak.push_back(p);
  return weak;
}

}  // namespace aniso::fit_detail
