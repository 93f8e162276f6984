// fit/linear.h: the linear entries of a fit (diffuse and specular weights per channel) solved
// exactly for given values of the other entries: separable least squares (Golub & Pereyra 1973,
// "The differentiation of pseudo-inverses and nonlinear least squares problems whose variables
// separate", SIAM J. Numer. Anal. 10(2); their 2003 review, Inverse Problems 19(2), R1), with the
// parameter tables' bounds and, for the energy constraint, linear inequalities.
//
// A model's f_c is affine in its linear entries of channel c when the others are held: kd / pi,
// ks times a lobe, F0 in Schlick's F0 + (1 - F0)(1 - c)^5 = F0 (1 - (1 - c)^5) + (1 - c)^5, rho_d.
// The model says which entries those are (LinearLayout); the basis functions are read off the
// kernel itself (f with every linear entry 0, then with one of them 1), so no model writes its
// basis twice. The problems are tiny (at most 3 unknowns per channel): each is solved exactly by
// enumerating its active sets (below), not iteratively.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

namespace aniso::fit_detail {

// Per channel, the indices of the linear entries of the parameter vector (empty: none).
struct LinearLayout {
  std::array<std::vector<int>, 3> channel;
  bool empty() const { return channel[0].empty() && channel[1].empty() && channel[2].empty(); }
};

// min |A b - y|^2 subject to G b <= h, given the normal equations N = A^T A, r = A^T y and
// t = y^T y (so the cost is b^T N b - 2 b^T r + t). A convex quadratic over a polyhedron: at its
// minimum some set S of at most k = dim(b) constraints is active and b solves the equality-
// constrained problem on S (the KKT conditions, Nocedal & Wright 2006, Thm. 16.4). Every subset
// of at most k rows is tried (its KKT system by a complete orthogonal decomposition, which also
// takes a singular N) and the feasible point of least cost kept: exact, and cheap for k <= 3 and
// tens of rows. kFeasible absorbs rounding in the feasibility test (relative to |h| + 1: the
// KKT solve of an active row reproduces h to about 1e-15 relative, far inside 1e-10).
// Returns false when no subset gives a feasible point (an empty feasible set).
inline bool constrained_lsq(const Eigen::MatrixXd& N, const Eigen::VectorXd& r, double t, const Eigen::MatrixXd& G,
                            const Eigen::VectorXd& h, Eigen::VectorXd& best, double* best_cost = nullptr) {
  const int k = int(N.rows()), m = int(G.rows());
  constexpr double kFeasible = 1e-10;
  double lowest = std::numeric_limits<double>::infinity();
  std::vector<int> active;
  const auto try_active = [&] {
    const int a = int(active.size());
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(k + a, k + a);
    Eigen::VectorXd rhs(k + a);
    K.topLeftCorner(k, k) = N;
    rhs.head(k) = r;
    for (int i = 0; i < a; ++i) {
      K.block(k + i, 0, 1, k) = G.row(active[size_t(i)]);
      K.block(0, k + i, k, 1) = G.row(active[size_t(i)]).transpose();
      rhs(k + i) = h(active[size_t(i)]);
    }
    const Eigen::VectorXd s = K.completeOrthogonalDecomposition().solve(rhs);
    const Eigen::VectorXd b = s.head(k);
    if (!b.allFinite()) return;
    for (int i = 0; i < m; ++i)
      if (G.row(i).dot(b) > h(i) + kFeasible * (std::abs(h(i)) + 1.0)) return;
    const double cost = b.dot(N * b) - 2.0 * b.dot(r) + t;
    if (cost < lowest) lowest = cost, best = b;
  };
  // Subsets in increasing size: the unconstrained optimum first.
  const auto recurse = [&](auto&& self, int from, int left) -> void {
    try_active();
    if (left == 0) return;
    for (int i = from; i < m; ++i) {
      active.push_back(i);
      self(self, i + 1, left - 1);
      active.pop_back();
    }
  };
  recurse(recurse, 0, k);
  if (best_cost) *best_cost = lowest;
  return std::isfinite(lowest);
}

// The box lo <= b <= hi as rows of G b <= h.
inline void add_box(const std::vector<double>& lo, const std::vector<double>& hi, Eigen::MatrixXd& G, Eigen::VectorXd& h) {
  const int k = int(lo.size()), m = int(G.rows());
  G.conservativeResize(m + 2 * k, k);
  h.conservativeResize(m + 2 * k);
  for (int j = 0; j < k; ++j) {
    G.row(m + 2 * j).setZero();
    G(m + 2 * j, j) = 1.0;
    h(m + 2 * j) = hi[size_t(j)];
    G.row(m + 2 * j + 1).setZero();
    G(m + 2 * j + 1, j) = -1.0;
    h(m + 2 * j + 1) = -lo[size_t(j)];
  }
}

}  // namespace aniso::fit_detail
