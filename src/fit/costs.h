// fit/costs.h (private): the residuals of a fit (docs/fitting.md): the prepared samples, the
// metric, the data and penalty cost functions, the cache of a block's kernels and the progress
// callback.
#pragma once

#include "fit/jet.h"  // first: the kernels' constants for ceres::Jet

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <ceres/ceres.h>

#include "aniso/fit/fit.h"
#include "fit/models.h"

namespace aniso::fit_detail {

using Clock = std::chrono::steady_clock;

// A sample as the residuals use it: the metric's target and weight computed once.
struct Prepared {
  Vec3d wi, wo;
  glm::dvec3 target;  // f cos(theta_i) (l2cos) or ln(1 + max(f cos, 0)) (log)
  double sqrt_w;      // sqrt(weight / total weight)
};

// The metric's residual for one channel (fit.h, docs/fitting.md). Measured values below 0 (a
// spectral reduction outside the sRGB gamut, spectral.h) count as 0 in the log metric, whose
// logarithm needs 1 + f cos > 0.
template <typename T> T metric_residual(FitMetric metric, const T& model, double cos_i, double target, double sqrt_w) {
  using std::log;
  if (metric == FitMetric::Log) return (log(T(1) + model * cos_i) - target) * sqrt_w;
  return (model * cos_i - target) * sqrt_w;
}

// A sample's directions in the frame turned by the fit's rotation entry (models.h, Orientation),
// in T's arithmetic so that a Jet carries d/d(rotation). Always the formula of FrameRotationT
// (material.h), never its identity shortcut, which would drop the derivative at exactly 0.
template <typename T> struct Turn {
  T c, s;
  Vec3T<T> operator()(const Vec3d& w) const { return Vec3T<T>(c * w.x + s * w.y, c * w.y - s * w.x, T(w.z)); }
};
template <typename T, class Model> Turn<T> turn_of(const Model& model, const T* x) {
  const int r = model.rotation_index();
  if (r < 0) return {T(1), T(0)};
  const FrameRotationT<T> f = frame_rotation_deg(x[r]);
  return {f.c, f.s};
}

inline double metric_target(FitMetric metric, double value, double cos_i) {
  return metric == FitMetric::Log ? std::log1p(std::max(value * cos_i, 0.0)) : value * cos_i;
}

// One residual block: `count` samples x 3 channels, all parameters in one block. The Jacobian
// comes from the kernel itself run on ceres::Jet<double, N> (N >= the parameter count: the extra
// lanes stay 0), the model's f() exactly as rendering calls it.
template <class Model, int N> class ChunkCost final : public ceres::CostFunction {
 public:
  ChunkCost(const Model& model, const Prepared* samples, int count, FitMetric metric, bool by_parts = true)
      : model_(model), samples_(samples), count_(count), metric_(metric), size_(int(model.defs.size())), by_parts_(by_parts) {
    set_num_residuals(3 * count);
    mutable_parameter_block_sizes()->push_back(size_);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* x = parameters[0];
    if (!jacobians || !jacobians[0]) {
      const auto m = model_.template build<double>(x);
      const Turn<double> turn = turn_of(model_, x);
      for (int i = 0; i < count_; ++i) {
        const Prepared& s = samples_[i];
        const RGBT<double> f = m.f(turn(s.wi), turn(s.wo));
        for (int c = 0; c < 3; ++c) residuals[3 * i + c] = metric_residual(metric_, f[c], s.wi.z, s.target[c], s.sqrt_w);
      }
      return all_finite(residuals, 3 * count_);
    }
    if constexpr (requires { Model::kHasParts; }) {
      if (by_parts_) return evaluate_by_parts(x, residuals, jacobians[0]);
    }
    using J = ceres::Jet<double, N>;
    J xj[N];
    for (int p = 0; p < size_; ++p) xj[p] = J(x[p], p);
    const auto m = model_.template build<J>(xj);
    const Turn<J> turn = turn_of(model_, xj);
    double* jac = jacobians[0];
    for (int i = 0; i < count_; ++i) {
      const Prepared& s = samples_[i];
      const RGBT<J> f = m.f(turn(s.wi), turn(s.wo));
      for (int c = 0; c < 3; ++c) {
        const J r = metric_residual(metric_, f[c], s.wi.z, s.target[c], s.sqrt_w);
        residuals[3 * i + c] = r.a;
        double* row = jac + size_t(3 * i + c) * size_t(size_);
        for (int p = 0; p < size_; ++p) row[p] = r.v[p];
      }
    }
    return all_finite(residuals, 3 * count_) && all_finite(jac, 3 * count_ * size_);
  }

 private:
  // f = sum of parts with disjoint parameters (models.h, LafortuneFit::kHasParts): each part's
  // kernel on a Jet of its own parameters gives df/dx for them; the rows are then scaled by the
  // metric's dr/df, which needs the whole f: (l2cos) cos sqrt(w), (log) sqrt(w) cos / (1 + f cos).
  bool evaluate_by_parts(const double* x, double* residuals, double* jac) const {
    constexpr int M = Model::kMaxPartSize;
    using JP = ceres::Jet<double, M>;
    std::fill(jac, jac + size_t(3 * count_) * size_t(size_), 0.0);
    std::vector<double> f(size_t(3 * count_), 0.0);
    std::vector<JP> full(size_t(size_), JP(0.0));
    for (int part = 0; part < model_.part_count(); ++part) {
      const std::vector<int> idx = model_.part_indices(part);
      for (int p = 0; p < size_; ++p) full[size_t(p)] = JP(x[p]);
      for (size_t j = 0; j < idx.size(); ++j) full[size_t(idx[j])] = JP(x[idx[j]], int(j));
      const auto m = model_.template build_part<JP>(part, full.data());
      const Turn<JP> turn = turn_of(model_, full.data());
      for (int i = 0; i < count_; ++i) {
        const Prepared& s = samples_[i];
        const RGBT<JP> fp = m.f(turn(s.wi), turn(s.wo));
        for (int c = 0; c < 3; ++c) {
          f[size_t(3 * i + c)] += fp[c].a;
          double* row = jac + size_t(3 * i + c) * size_t(size_);
          for (size_t j = 0; j < idx.size(); ++j) row[idx[j]] += fp[c].v[int(j)];
        }
      }
    }
    for (int i = 0; i < count_; ++i) {
      const Prepared& s = samples_[i];
      for (int c = 0; c < 3; ++c) {
        const double fc = f[size_t(3 * i + c)], cos_i = s.wi.z;
        residuals[3 * i + c] = metric_residual(metric_, fc, cos_i, s.target[c], s.sqrt_w);
        const double dr_df = metric_ == FitMetric::Log ? s.sqrt_w * cos_i / (1.0 + fc * cos_i) : s.sqrt_w * cos_i;
        double* row = jac + size_t(3 * i + c) * size_t(size_);
        for (int p = 0; p < size_; ++p) row[p] *= dr_df;
      }
    }
    return all_finite(residuals, 3 * count_) && all_finite(jac, 3 * count_ * size_);
  }

  static bool all_finite(const double* v, int n) {
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(v[i])) return false;
    return true;
  }
  const Model& model_;
  const Prepared* samples_;
  int count_;
  FitMetric metric_;
  int size_;
  bool by_parts_;
};

// The model's penalty residuals (LafortuneFit::penalties), differentiated the same way.
template <class Model, int N> class PenaltyCost final : public ceres::CostFunction {
 public:
  explicit PenaltyCost(const Model& model) : model_(model), size_(int(model.defs.size())) {
    set_num_residuals(model.penalty_count());
    mutable_parameter_block_sizes()->push_back(size_);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* x = parameters[0];
    const int m = model_.penalty_count();
    if (!jacobians || !jacobians[0]) {
      model_.penalties(x, residuals);
      return true;
    }
    using J = ceres::Jet<double, N>;
    J xj[N];
    for (int p = 0; p < size_; ++p) xj[p] = J(x[p], p);
    std::vector<J> r(static_cast<size_t>(m));
    model_.penalties(xj, r.data());
    for (int i = 0; i < m; ++i) {
      residuals[i] = r[size_t(i)].a;
      for (int p = 0; p < size_; ++p) jacobians[0][size_t(i) * size_t(size_) + size_t(p)] = r[size_t(i)].v[p];
    }
    return true;
  }

 private:
  const Model& model_;
  int size_;
};

// The blocks' residuals and Jacobians, computed before each of Ceres' evaluations on `threads`
// threads. Ceres' own multi-threaded evaluation sums the blocks' costs and gradients per thread
// and then over threads (ceres 2.1, internal/ceres/program_evaluator.h, Evaluate: one
// EvaluateScratch per thread, filled by a dynamically scheduled ParallelFor), so the sum's order,
// and with it the fit's last bits, would depend on the thread count and on scheduling. Ceres
// therefore runs on one thread and sums the blocks in their order; the expensive part, each
// block's values, runs here in parallel: every block depends on its own samples only, so its
// values are the same whatever thread computes it. CachedBlock hands them to Ceres.
class BlockCache final : public ceres::EvaluationCallback {
 public:
  BlockCache(std::vector<const ceres::CostFunction*> blocks, const double* x, int size, int threads)
      : blocks_(std::move(blocks)), x_(x), size_(size), threads_(threads), offset_(blocks_.size() + 1, 0) {
    for (size_t b = 0; b < blocks_.size(); ++b) offset_[b + 1] = offset_[b] + size_t(blocks_[b]->num_residuals());
    residuals_.resize(offset_.back());
    ok_.resize(blocks_.size());
  }
  // Ceres has written the point into the parameter array (x_) before this call (problem.h,
  // Problem::Options::evaluation_callback); CachedBlock still checks it.
  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    if (!new_evaluation_point && (has_jacobians_ || !evaluate_jacobians) && point_.size() == size_t(size_)) return;
    point_.assign(x_, x_ + size_);
    has_jacobians_ = evaluate_jacobians;
    if (evaluate_jacobians) jacobians_.resize(offset_.back() * size_t(size_));
    tbb::task_arena arena(threads_);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks_.size()), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t b = r.begin(); b < r.end(); ++b) {
          const double* params[1] = {point_.data()};
          double* jac[1] = {evaluate_jacobians ? jacobians_.data() + offset_[b] * size_t(size_) : nullptr};
          ok_[b] = blocks_[b]->Evaluate(params, residuals_.data() + offset_[b], evaluate_jacobians ? jac : nullptr);
        }
      });
    });
  }
  // Block b's values at x, from the cache when they were computed at x (false: not cached).
  bool lookup(size_t b, const double* x, double* residuals, double* jacobian, bool& ok) const {
    if (point_.size() != size_t(size_) || (jacobian && !has_jacobians_) || !std::equal(point_.begin(), point_.end(), x))
      return false;
    ok = ok_[b] != 0;
    std::copy(residuals_.begin() + long(offset_[b]), residuals_.begin() + long(offset_[b + 1]), residuals);
    if (jacobian)
      std::copy(jacobians_.begin() + long(offset_[b] * size_t(size_)), jacobians_.begin() + long(offset_[b + 1] * size_t(size_)),
                jacobian);
    return true;
  }

 private:
  std::vector<const ceres::CostFunction*> blocks_;
  const double* x_;
  int size_, threads_;
  std::vector<size_t> offset_;  // first residual of each block
  std::vector<double> point_, residuals_, jacobians_;
  std::vector<char> ok_;
  bool has_jacobians_ = false;
};

// Block b as Ceres sees it: its values from the cache (computed here when the point differs,
// which Ceres' documented order of calls never asks: no fit of krylon_blue.brdf did).
class CachedBlock final : public ceres::CostFunction {
 public:
  CachedBlock(const BlockCache& cache, size_t b, const ceres::CostFunction& block) : cache_(cache), b_(b), block_(block) {
    set_num_residuals(block.num_residuals());
    *mutable_parameter_block_sizes() = block.parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    bool ok = false;
    if (cache_.lookup(b_, parameters[0], residuals, jacobians ? jacobians[0] : nullptr, ok)) return ok;
    return block_.Evaluate(parameters, residuals, jacobians);
  }

 private:
  const BlockCache& cache_;
  size_t b_;
  const ceres::CostFunction& block_;
};

// Reports each iteration to the progress function.
class ProgressCallback final : public ceres::IterationCallback {
 public:
  ProgressCallback(const FitOptions& o, std::string stage, Clock::time_point t0, double per_iteration_guess,
                   int iterations_left_after)
      : o_(o), stage_(std::move(stage)), t0_(t0), guess_(per_iteration_guess), after_(iterations_left_after) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (o_.cancel && o_.cancel->load()) return ceres::SOLVER_ABORT;
    if (o_.progress) {
      FitProgress p;
      p.stage = stage_;
      p.iteration = s.iteration;
      p.cost = s.cost;
      p.elapsed_s = std::chrono::duration<double>(Clock::now() - t0_).count();
      const double per_it = s.iteration > 0 ? s.cumulative_time_in_seconds / s.iteration : guess_;
      p.remaining_s = per_it * std::max(0, after_ - s.iteration);
      o_.progress(p);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const FitOptions& o_;
  std::string stage_;
  Clock::time_point t0_;
  double guess_;
  int after_;
};

}  // namespace aniso::fit_detail
