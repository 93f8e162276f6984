// fit/fit.cpp: the Ceres problem, the starts and the error figures (fit.h, docs/fitting.md).
#include "fit/jet.h"  // first: the kernels' constants for ceres::Jet

#include "aniso/fit/fit.h"
#include "aniso/version.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <glog/logging.h>

#include <Eigen/Dense>

#include "aniso/core/sampling.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "aniso/stats/albedo.h"
#include "fit/linear.h"
#include "fit/models.h"
#include "io/enum_names.h"
#include "io/text_escape.h"
#include "io/text_input.h"

namespace aniso {
namespace {

using namespace fit_detail;
using Clock = std::chrono::steady_clock;

// Ceres logs through glog. Its messages during a fit are internal diagnostics (for example "Failed
// to extract eigenvalues from companion matrix" when the line search of a bounded step cannot
// interpolate, after which it falls back to bisection): not the user's business, and stderr is
// where `aniso` writes its own messages. Initialise glog once, quietly, and show fatal errors only.
void quiet_ceres_logging() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("aniso");
    FLAGS_minloglevel = google::GLOG_FATAL;
    FLAGS_logtostderr = true;
  });
}

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

double metric_target(FitMetric metric, double value, double cos_i) {
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
std::vector<AlbedoAt> albedo_grid(const MaterialD& m, bool anisotropic) {
  std::vector<AlbedoAt> out;
  uint64_t seed = 0xa1bed0;
  for (double theta : kAlbedoThetaDeg)
    for (int k = 0; k < (anisotropic ? kAlbedoPhiSteps : 1); ++k) {
      AlbedoAt a;
      a.theta_deg = theta, a.phi_deg = 180.0 * k / kAlbedoPhiSteps,
      a.wo = direction_from_angles(a.theta_deg * M_PI / 180.0, a.phi_deg * M_PI / 180.0);
      const AlbedoEstimate e = albedo_importance(m, a.wo, kAlbedoSamples, seed++);
      a.value = std::max({e.mean.x, e.mean.y, e.mean.z});
      out.push_back(a);
    }
  std::sort(out.begin(), out.end(), [](const AlbedoAt& a, const AlbedoAt& b) { return a.value > b.value; });
  return out;
}

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

WatchedDirection watch(const MaterialD& m, const Vec3d& wo, int count, uint64_t seed) {
  WatchedDirection w{wo, {}, {}};
  Rng rng(seed);
  for (int j = 0; j < count; ++j) {
    Vec3d wi;
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    if (j % 2 == 0) {
      const BSDFSampleT<double> s = m.sample(wo, rng.uniform(), u);
      if (!s.valid) continue;  // counts as a zero of the estimator (the denominator stays `count`)
      wi = s.wi;
    } else {
      wi = sample_cosine_hemisphere(u);
    }
    const double q = 0.5 * m.pdf(wi, wo) + 0.5 * std::max(wi.z, 0.0) / M_PI;
    if (!(q > 0.0) || !(wi.z > 0.0)) continue;
    w.wi.push_back(wi);
    w.inv_q.push_back(1.0 / (q * count));
  }
  return w;
}

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

DataMoments data_moments(const SampleSet& data) {
  DataMoments m;
  const size_t n = data.samples.size();
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = data.samples[i].value[c];
    const size_t k = n / 20;  // the 5th percentile
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    m.floor_albedo[c] = std::clamp(v[k] * M_PI, 0.0, 1.0);
    double peak = 0.0;
    for (const MeasuredSample& s : data.samples) peak = std::max(peak, s.value[c] - m.floor_albedo[c] / M_PI);
    m.peak[c] = std::max(peak, 1e-6);
  }
  // The mirror exponent: the excess e over the floor against the cosine a to the mirror direction,
  // ln(e / peak) = n ln(a), least squares through the origin over the samples whose excess is at
  // least 1% of the peak.
  const double peak = average(m.peak);
  double num = 0.0, den = 0.0;
  for (const MeasuredSample& s : data.samples) {
    const double e = average(s.value) - average(m.floor_albedo) / M_PI;
    const double a = glm::dot(s.wi, Vec3d(-s.wo.x, -s.wo.y, s.wo.z));
    if (!(e > 0.01 * peak) || !(a > 0.0) || !(a < 1.0)) continue;
    const double la = std::log(a);
    num += std::log(std::min(e / peak, 1.0)) * la;
    den += la * la;
  }
  m.mirror_exponent = den > 0.0 ? std::clamp(num / den, 1.0, 1e4) : 10.0;
  return m;
}

struct StartPoint {
  std::string name;
  std::vector<double> x;
};

// The Ngan 2005 preset of `ngan_model` nearest to the data: the smallest l2cos error on (up to 4096
// of) the samples.
template <class Model>
std::optional<StartPoint> nearest_ngan_start(const Model& model, const std::vector<Prepared>& prep, const DataMoments& dm) {
  const std::string prefix = fmt::format("ngan/{}/", model.ngan_model());
  const size_t stride = std::max<size_t>(1, prep.size() / 4096);
  double best = INFINITY;
  const PresetInfo* best_preset = nullptr;
  for (const PresetInfo& p : presets()) {
    if (p.name.rfind(prefix, 0) != 0) continue;
    const MaterialD m = build_material<double>(parse_material(p.json, p.name));
    double e = 0.0;
    for (size_t i = 0; i < prep.size(); i += stride) {
      const Prepared& s = prep[i];
      const RGBT<double> f = m.f(s.wi, s.wo);
      for (int c = 0; c < 3; ++c) e += sqr(f[c] * s.wi.z - s.target[c]);  // l2cos on the cosine-weighted target
    }
    if (e < best) best = e, best_preset = &p;
  }
  if (!best_preset) return std::nullopt;
  auto x = model.from_preset(parse_material(best_preset->json, best_preset->name), dm);
  if (!x) return std::nullopt;
  return StartPoint{fmt::format("ngan2005 {}", best_preset->name.substr(prefix.size())), *x};
}

// FitOptions::start as a start of this model's parameters (nullopt when none is given).
template <class Model> std::optional<StartPoint> given_start(const Model& model, const DataMoments& dm, const FitOptions& o) {
  if (o.start.empty()) return std::nullopt;
  const auto index = [&](std::string_view name) {
    for (size_t i = 0; i < model.defs.size(); ++i)
      if (model.defs[i].name == name) return int(i);
    return -1;
  };
  std::vector<double> x = model.moment_start(dm);
  std::vector<std::pair<int, double>> pairs;  // the isotropic parameter and one of its pair's values
  for (const auto& [name, value] : o.start) {
    if (!std::isfinite(value)) throw InputError(fmt::format("the fit's start: {} = {} is not a finite number", name, value));
    if (const int i = index(name); i >= 0) {
      x[size_t(i)] = value;
      continue;
    }
    const std::string_view n = name;
    const bool xy = n.size() > 2 && (n.ends_with("_x") || n.ends_with("_y") || n.ends_with("_u") || n.ends_with("_v"));
    if (xy && index(n.substr(0, n.size() - 2)) >= 0) {
      pairs.emplace_back(index(n.substr(0, n.size() - 2)), value);
      continue;
    }
    if (name == "rotation_deg" && model.rotation_index() < 0) continue;  // an isotropic fit has no orientation
    std::string names;
    for (const ParamDef& d : model.defs) names += fmt::format("{}{}", names.empty() ? "" : ", ", d.name);
    throw InputError(fmt::format("the fit's start: \"{}\" is not a parameter of this fit (its parameters: {})", name, names));
  }
  for (size_t i = 0; i < model.defs.size(); ++i) {
    double log_sum = 0.0;
    int count = 0;
    for (const auto& [k, v] : pairs)
      if (size_t(k) == i) log_sum += std::log(std::max(v, 1e-300)), ++count;
    if (count > 0) x[i] = std::exp(log_sum / count);
  }
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], model.defs[i].lo, model.defs[i].hi);
  return StartPoint{"given", x};
}

struct Solved {
  std::vector<double> x;
  double cost = INFINITY;
  int iterations = 0;
  std::string termination;
};

// --- Separable least squares (fit/linear.h) ----------------------------------------------------

// The linear entries of a model, by their names in its defs (models.h): the diffuse and specular
// weights of each channel ("kd.r", "ks.g", "f0.b", "rho_d.r", "ks_scale.g"), in which f_c is affine
// when the other entries are held: kd / pi, ks times Ward's or Phong's lobe, ks_scale times the AS
// lobe, F0 in Schlick's F0 (1 - (1 - c)^5) + (1 - c)^5 times the GGX lobe, rho_d / pi beside the
// Lafortune lobes. A model with none (metal: eta and k; principled) gets an empty layout.
template <class Model> LinearLayout linear_layout(const Model& model) {
  static constexpr std::string_view kLinear[] = {"kd", "ks", "f0", "rho_d", "ks_scale"};
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
// log-spaced over [kGridLow, kGridHigh] clamped to their bounds, the linear entries solved
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

template <class Model, int N> FitResult fit_with(const Model& model, const SampleSet& data, const FitOptions& o) {
  quiet_ceres_logging();
  const auto t0 = Clock::now();
  const size_t total = data.samples.size();
  if (total == 0) throw InputError(fmt::format("{}: no samples to fit", data.source));
  // All samples prepared (the error figures and the Ngan start use them); the solver's subset.
  double wsum = 0.0;
  for (const MeasuredSample& s : data.samples) wsum += s.weight;
  std::vector<Prepared> all(total);
  for (size_t i = 0; i < total; ++i) {
    const MeasuredSample& s = data.samples[i];
    Prepared& p = all[i];
    p.wi = s.wi;
    p.wo = s.wo;
    p.sqrt_w = std::sqrt(s.weight / wsum);
    for (int c = 0; c < 3; ++c) p.target[c] = metric_target(o.metric, s.value[c], s.wi.z);
  }
  std::vector<Prepared> used = all;
  if (total > o.max_solver_samples) {
    // A fixed pseudo-random subset (Fisher-Yates with a fixed seed: the same data gives the same
    // subset), reweighted so that its weights sum to 1 again.
    Rng rng(0x5eed5a3b1e5ULL);
    std::vector<size_t> idx(total);
    for (size_t i = 0; i < total; ++i) idx[i] = i;
    for (size_t i = 0; i < o.max_solver_samples; ++i) std::swap(idx[i], idx[i + size_t(rng.uniform() * double(total - i))]);
    idx.resize(o.max_solver_samples);
    std::sort(idx.begin(), idx.end());
    used.clear();
    double sub = 0.0;
    for (size_t i : idx) used.push_back(all[i]), sub += sqr(all[i].sqrt_w);
    for (Prepared& p : used) p.sqrt_w /= std::sqrt(sub);
  }
  const DataMoments dm = data_moments(data);
  // Above kCoarseSamples solver samples, two subsets spread evenly over them (reweighted to a
  // total weight of 1): the starts are ranked on kRankingSamples of them, and the best converges
  // on kCoarseSamples before a polish on every solver sample. Ten iterations from each start on
  // 32768 samples, or the whole refinement on them, would cost most of the fit (a real RGL file:
  // 0.2 s per iteration; docs/fitting.md, "Real measurements"); next to the optimum the polish
  // takes a few.
  constexpr size_t kRankingSamples = 2048, kCoarseSamples = 8192;
  const auto spread = [&](size_t n) {
    std::vector<Prepared> out;
    double sub = 0.0;
    for (size_t i = 0; i < n; ++i) out.push_back(used[i * used.size() / n]), sub += sqr(out.back().sqrt_w);
    for (Prepared& p : out) p.sqrt_w /= std::sqrt(sub);
    return out;
  };
  const std::vector<Prepared> ranking = used.size() > kCoarseSamples ? spread(kRankingSamples) : std::vector<Prepared>{};
  const std::vector<Prepared> coarse = used.size() > kCoarseSamples ? spread(kCoarseSamples) : std::vector<Prepared>{};
  const std::vector<Prepared>& start_samples = coarse.empty() ? used : coarse;  // the starts' linear solves
  // Separable least squares (fit/linear.h) where the problem is one: the l2cos metric without a
  // robust loss, and a model with linear entries. Every start gets its linear entries solved
  // exactly before the solver sees it, and a grid over the roughness with them solved is one more
  // start: so no fit can lose to a least-squares fit of the same lobe shape for want of a start
  // near its diffuse and specular weights, and a weight is 0 only where the data put it there.
  const LinearLayout layout = o.metric == FitMetric::L2Cos && o.loss == "none" ? linear_layout(model) : LinearLayout{};

  // The starts: moments, the separable grid, the nearest Ngan fit, random draws; the caller's
  // first, beside them.
  const std::optional<StartPoint> given = given_start(model, dm, o);
  std::vector<StartPoint> starts;
  starts.push_back({"moments", model.moment_start(dm)});
  const std::optional<StartPoint> grid_start = separable_grid_start(model, layout, dm, start_samples);
  if (o.starts > 1)
    if (auto s = nearest_ngan_start(model, used, dm)) starts.push_back(*s);
  Rng rng(o.seed);
  for (int i = 1; int(starts.size()) < o.starts; ++i)
    starts.push_back({fmt::format("random {}", i), model.random_start(rng, dm)});
  if (grid_start) starts.insert(starts.begin() + 1, *grid_start);  // beside the `starts` asked for
  // The orientation (models.h, Orientation): each deterministic start at kRotationStarts turns
  // spread over the lobe's period (the isotropic starts have no preferred direction, and the
  // solver turns a start by at most about half the spacing), each random start at a random turn
  // (its own stream: the other entries of the random starts do not change).
  const int ri = model.rotation_index();
  if (ri >= 0) {
    constexpr int kRotationStarts = 4;
    Rng turn_rng(o.seed ^ 0x7e57a7e5ULL);
    std::vector<StartPoint> turned;
    for (const StartPoint& st : starts) {
      if (st.name.rfind("random", 0) == 0) {
        StartPoint t = st;
        t.x[size_t(ri)] = model.rotation_period() * turn_rng.uniform();
        turned.push_back(std::move(t));
        continue;
      }
      for (int k = 0; k < kRotationStarts; ++k) {
        StartPoint t = st;
        t.x[size_t(ri)] = model.rotation_period() * k / kRotationStarts;
        t.name += fmt::format(", turned {:g} deg", t.x[size_t(ri)]);
        turned.push_back(std::move(t));
      }
    }
    starts = std::move(turned);
  }
  if (!layout.empty())  // at each start's own orientation
    for (StartPoint& st : starts) {
      std::vector<double> x = st.x;
      if (std::isfinite(solve_linear(model, layout, x, start_samples))) st.x = std::move(x);
    }
  if (given) starts.insert(starts.begin(), *given);  // at its own orientation

  // Residual blocks: chunks of 64 samples (fewer blocks, less overhead); one sample per block when a
  // robust loss is asked, because the loss acts on a block's squared norm.
  const bool robust = o.loss != "none";
  const int chunk = robust ? 1 : 64;
  const auto make_costs = [&](const std::vector<Prepared>& samples) {
    std::vector<std::unique_ptr<ceres::CostFunction>> out;
    for (size_t i = 0; i < samples.size(); i += size_t(chunk))
      out.push_back(std::make_unique<ChunkCost<Model, N>>(model, samples.data() + i,
                                                          int(std::min(samples.size() - i, size_t(chunk))), o.metric));
    return out;
  };
  const auto costs = make_costs(used);
  const auto ranking_costs = make_costs(ranking);
  const auto coarse_costs = make_costs(coarse);
  // The loss scale: the given one, or by default a tenth of the median weighted sample value
  // |target| sqrt(w) (a residual beyond 10% of a typical sample's value counts as an outlier; 2%
  // measurement noise stays well inside).
  double scale = o.loss_scale;
  if (robust && !(scale > 0.0)) {
    std::vector<double> v;
    for (const Prepared& p : used) v.push_back(std::abs(average(p.target)) * p.sqrt_w);
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    scale = 0.1 * v[v.size() / 2] + 1e-300;
  }
  std::unique_ptr<ceres::CostFunction> penalty;
  if (model.penalty_count() > 0) penalty = std::make_unique<PenaltyCost<Model, N>>(model);
  std::unique_ptr<ceres::LossFunction> loss;
  if (o.loss == "huber")
    loss = std::make_unique<ceres::HuberLoss>(scale);
  else if (o.loss == "cauchy")
    loss = std::make_unique<ceres::CauchyLoss>(scale);
  else if (o.loss == "soft_l1")
    loss = std::make_unique<ceres::SoftLOneLoss>(scale);
  else if (robust)
    throw InputError(fmt::format("--loss: expected none, huber, cauchy or soft_l1, got \"{}\"", o.loss));

  const int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  const int P = int(model.defs.size());
  enum class On { Ranking, Coarse, All };  // the samples a solve runs on (All when the subsets are empty)
  const auto solve = [&](std::vector<double> x, int max_iterations, const std::string& stage, int iterations_after, On on,
                         const ceres::CostFunction* energy = nullptr) {
    const bool subset = on != On::All && !ranking.empty();
    const auto& blocks = !subset ? costs : on == On::Ranking ? ranking_costs : coarse_costs;
    const size_t rows = !subset ? used.size() : on == On::Ranking ? ranking.size() : coarse.size();
    std::vector<const ceres::CostFunction*> block_ptrs;
    for (const auto& c : blocks) block_ptrs.push_back(c.get());
    BlockCache cache(std::move(block_ptrs), x.data(), P, threads);
    std::vector<std::unique_ptr<CachedBlock>> cached;
    for (size_t b = 0; b < blocks.size(); ++b) cached.push_back(std::make_unique<CachedBlock>(cache, b, *blocks[b]));
    ceres::Problem::Options popt;
    popt.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    popt.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    popt.evaluation_callback = &cache;
    ceres::Problem problem(popt);
    for (auto& c : cached) problem.AddResidualBlock(c.get(), loss.get(), x.data());
    if (penalty) problem.AddResidualBlock(penalty.get(), nullptr, x.data());
    if (energy) problem.AddResidualBlock(const_cast<ceres::CostFunction*>(energy), nullptr, x.data());
    for (int i = 0; i < P; ++i) {
      problem.SetParameterLowerBound(x.data(), i, model.defs[size_t(i)].lo);
      problem.SetParameterUpperBound(x.data(), i, model.defs[size_t(i)].hi);
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    // Tall, thin problems (thousands of rows, tens of columns): the normal equations are small and
    // cheap; QR for the small ones, where its better conditioning costs nothing.
    so.linear_solver_type = rows * 3 * size_t(P) < 2000000 ? ceres::DENSE_QR : ceres::DENSE_NORMAL_CHOLESKY;
    so.num_threads = 1;  // the blocks' values in parallel, summed in order: BlockCache
    so.max_num_iterations = max_iterations;
    so.function_tolerance = o.function_tolerance;
    so.gradient_tolerance = 1e-14;
    so.parameter_tolerance = 1e-10;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ProgressCallback cb(o, stage, t0, 0.0, max_iterations + iterations_after);
    so.callbacks.push_back(&cb);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (o.cancel && o.cancel->load()) throw FitCancelled();
    Solved r;
    r.x = x;
    r.cost = summary.final_cost;
    r.iterations = int(summary.iterations.size()) - 1;
    r.termination = summary.message;
    if (!std::isfinite(r.cost)) r.cost = INFINITY;
    return r;
  };

  // Phase 1: every start, briefly; phase 2: the best one to convergence.
  constexpr int kPhase1Iterations = 10, kPolishIterations = 30;
  std::vector<Solved> phase1;
  size_t best = 0;
  for (size_t i = 0; i < starts.size(); ++i) {
    const int after = kPhase1Iterations * int(starts.size() - i - 1) + o.max_iterations;
    phase1.push_back(solve(starts[i].x, std::min(kPhase1Iterations, o.max_iterations),
                           fmt::format("start {}/{} ({})", i + 1, starts.size(), starts[i].name), after, On::Ranking));
    if (phase1[i].cost < phase1[best].cost) best = i;
  }
  Solved final_fit = phase1[best];
  int iterations = final_fit.iterations;
  // With the subsets, the best start converges on the coarse one, then polishes on every solver
  // sample (at most kPolishIterations); without them, it is refined on every solver sample when it
  // had not converged within the ranking's iterations.
  if (!ranking.empty()) {
    const Solved converged = solve(final_fit.x, std::max(1, o.max_iterations - kPhase1Iterations), "refining the best start",
                                   kPolishIterations, On::Coarse);
    iterations += converged.iterations;
    if (std::isfinite(converged.cost)) final_fit = converged;  // costs on different sets do not compare
    Solved refined = solve(final_fit.x, kPolishIterations, "refining on every solver sample", 0, On::All);
    iterations += refined.iterations;
    final_fit = refined;
  } else if (o.max_iterations > kPhase1Iterations && final_fit.iterations >= kPhase1Iterations) {
    Solved refined = solve(final_fit.x, std::max(1, o.max_iterations - kPhase1Iterations), "refining the best start", 0, On::All);
    iterations += refined.iterations;
    if (refined.cost <= final_fit.cost) final_fit = refined;
  }
  if (!std::isfinite(final_fit.cost)) throw std::runtime_error(fmt::format("{}: the fit diverged from every start", data.source));
  // The linear entries exactly at the solution (the solver's stop leaves them within its
  // tolerance); kept when they lower the cost.
  if (!layout.empty()) {
    std::vector<double> x = final_fit.x;
    if (solve_linear(model, layout, x, used) < data_cost(model, final_fit.x, used, o.metric)) final_fit.x = std::move(x);
  }

  // The material as every tool reads it (validated and built by the material reader), in its
  // canonical orientation (models.h, Orientation::canonicalize).
  const auto material_of = [&](std::vector<double> x) {
    model.canonicalize(x.data());
    nlohmann::json j = model.to_json(x.data());
    if (ri >= 0) j["rotation_deg"] = x[size_t(ri)];
    return j;
  };
  const auto build_fitted = [&](const std::vector<double>& x) {
    return build_material<double>(parse_material(material_of(x), "fitted material"));
  };

  FitResult r;
  r.anisotropic = ri >= 0;
  // Identifiability: the entries the solver's samples do not constrain at the solution.
  for (int p : weak_entries(model, costs, final_fit.x)) {
    const std::string& name = model.defs[size_t(p)].name;
    r.weakly_constrained.push_back(name);
    const auto& an = model.anisotropy_indices();
    if (std::find(an.begin(), an.end(), p) != an.end()) r.unconstrained_anisotropy.push_back(name);
  }
  // Energy (docs/fitting.md, "Energy"): the largest directional albedo on the grid; above
  // kAlbedoLimit (and unless allowed) the fit is brought under it at the least cost to the data,
  // in this order of preference: (1) the linear entries re-solved exactly under the constraint
  // (linear inequalities in them: energy_by_linear), (2) each channel scaled down as a whole where
  // the model can scale itself exactly (Lafortune: rho_d and every lobe, C -> C s^(1/n)), the better
  // of the two kept; (3) only when neither applies or meets it, a refit with the albedo penalty.
  // (1) and (2) keep the shape the data chose: a fit that exceeds 1 slightly stays close to its
  // unconstrained error, where a penalty refit could wander to another minimum.
  // A fit whose anisotropy the data do not constrain is replaced by the isotropic one (fit_samples):
  // its albedo is never reported, so it is not measured.
  const bool replaced = !r.unconstrained_anisotropy.empty();
  const MaterialD unconstrained = build_fitted(final_fit.x);
  std::vector<AlbedoAt> grid = replaced ? std::vector<AlbedoAt>{AlbedoAt{}} : albedo_grid(unconstrained, ri >= 0);
  r.unconstrained_l2cos = fit_errors(unconstrained, data).relative_l2cos;
  r.unconstrained_albedo = grid.front().value;
  if (!o.allow_energy_gain && grid.front().value > kAlbedoLimit && !replaced) {
    struct Candidate {
      std::vector<double> x;
      std::vector<AlbedoAt> grid;
      double cost;
      const char* method;
    };
    std::optional<Candidate> pick;
    const auto consider = [&](std::optional<std::vector<double>> x, const char* method) {
      if (!x) return;
      std::vector<AlbedoAt> g = albedo_grid(build_fitted(*x), ri >= 0);
      if (g.front().value > kAlbedoLimit) return;
      const double cost = data_cost(model, *x, used, o.metric);
      if (!pick || cost < pick->cost) pick = Candidate{std::move(*x), std::move(g), cost, method};
    };
    if (!layout.empty())
      consider(energy_by_linear(model, layout, final_fit.x, grid, used, build_fitted),
               "the linear entries re-solved under the constraint");
    consider(energy_by_scaling(model, final_fit.x, grid, build_fitted), "each channel scaled down as a whole");
    if (pick) {
      final_fit.x = std::move(pick->x);
      grid = std::move(pick->grid);
      r.energy_constrained = true;
      r.energy_method = pick->method;
    }
  }
  if (!o.allow_energy_gain && grid.front().value > kAlbedoLimit && !replaced) {
    r.energy_method = "refitted with the albedo penalty";
    constexpr int kWatchSamples = 512;
    std::vector<Vec3d> watched;
    for (int round = 0; round < kEnergyRounds && grid.front().value > kAlbedoLimit; ++round) {
      for (const AlbedoAt& a : grid)
        if (a.value > kAlbedoTarget && watched.size() < 24 && std::find(watched.begin(), watched.end(), a.wo) == watched.end())
          watched.push_back(a.wo);
      const MaterialD current = build_fitted(final_fit.x);
      std::vector<WatchedDirection> dirs;
      for (size_t k = 0; k < watched.size(); ++k)
        dirs.push_back(watch(current, watched[k], kWatchSamples, 0xe4e7 + 97 * k + round));
      // An excess of 0.005 costs ten times the data term: the constraint wins, the data decide
      // everything it leaves free.
      const double weight = std::sqrt(20.0 * std::max(final_fit.cost, 1e-12)) / 0.005;
      EnergyCost<Model, N> energy(model, std::move(dirs), weight);
      Solved constrained =
          solve(final_fit.x, o.max_iterations, fmt::format("energy constraint, round {}", round + 1), 0, On::All, &energy);
      iterations += constrained.iterations;
      if (!std::isfinite(constrained.cost)) break;
      final_fit = constrained;
      r.energy_constrained = true;
      grid = albedo_grid(build_fitted(final_fit.x), ri >= 0);
    }
  }
  r.largest_albedo = grid.front().value;
  r.largest_albedo_theta_deg = grid.front().theta_deg;
  r.largest_albedo_phi_deg = grid.front().phi_deg;

  r.material = material_of(final_fit.x);
  const MaterialD built = build_material<double>(parse_material(r.material, "fitted material"));
  r.errors = fit_errors(built, data);
  model.canonicalize(final_fit.x.data());
  for (const ParamDef& d : model.defs) r.parameter_names.push_back(d.name);
  r.parameters = final_fit.x;
  r.best_start = starts[best].name;
  r.iterations = iterations;
  r.termination = final_fit.termination;
  r.samples_total = total;
  r.samples_used = used.size();
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

template <class Model> FitResult dispatch(const Model& model, const SampleSet& data, const FitOptions& o) {
  const size_t p = model.defs.size();
  // The Jet's width is the cost of every derivative: the isotropic GGX, Ward, AS, Phong and Lambert
  // fits (3 to 8 entries) on Jet<8> take half the time of Jet<16> (an AS fit of a real RGL file:
  // measured in docs/fitting.md, "Real measurements").
  if (p <= 8 && !requires { Model::kHasParts; }) return fit_with<Model, 8>(model, data, o);
  if (p <= 16) return fit_with<Model, 16>(model, data, o);
  if (p <= 32) return fit_with<Model, 32>(model, data, o);
  if (p <= 64) return fit_with<Model, 64>(model, data, o);
  return fit_with<Model, 112>(model, data, o);  // Lafortune: 8 anisotropic lobes, 3 + 8 x 12 = 99
}

// "ward, duer or balanced": the names of an enumeration (io/enum_names.h) for an error message.
template <typename E> std::string name_list() {
  const auto names = enum_names<E>();
  std::string s;
  for (size_t i = 0; i < names.size(); ++i)
    s += fmt::format("{}{}", i == 0 ? "" : i + 1 == names.size() ? " or " : ", ", names[i]);
  return s;
}

template <typename E> E option_enum(const std::string& s, std::string_view option) {
  const std::optional<E> e = enum_from_name<E>(s);
  if (!e) throw InputError(fmt::format("{}: expected {}, got \"{}\"", option, name_list<E>(), s));
  return *e;
}

}  // namespace

namespace fit_detail {

double lafortune_parts_jacobian_difference(int lobes, bool anisotropic, bool shared, FitMetric metric, const SampleSet& data,
                                           const std::vector<double>& x) {
  const LafortuneFit model(lobes, anisotropic, shared);
  std::vector<Prepared> prep;
  for (const MeasuredSample& s : data.samples) {
    Prepared p{s.wi, s.wo, {}, 1.0 / std::sqrt(double(data.samples.size()))};
    for (int c = 0; c < 3; ++c) p.target[c] = metric_target(metric, s.value[c], s.wi.z);
    prep.push_back(p);
  }
  const int n = int(prep.size()), P = int(model.defs.size());
  const ChunkCost<LafortuneFit, 112> parts(model, prep.data(), n, metric, true), whole(model, prep.data(), n, metric, false);
  std::vector<double> r1(size_t(3 * n)), r2(size_t(3 * n)), j1(size_t(3 * n * P)), j2(size_t(3 * n * P));
  const double* params[] = {x.data()};
  double* jac1[] = {j1.data()};
  double* jac2[] = {j2.data()};
  if (!parts.Evaluate(params, r1.data(), jac1) || !whole.Evaluate(params, r2.data(), jac2)) return INFINITY;
  double worst = 0.0;
  for (size_t i = 0; i < r1.size(); ++i) worst = std::max(worst, std::abs(r1[i] - r2[i]) / (std::abs(r2[i]) + 1e-12));
  for (size_t i = 0; i < j1.size(); ++i) worst = std::max(worst, std::abs(j1[i] - j2[i]) / (std::abs(j2[i]) + 1e-12));
  return worst;
}

}  // namespace fit_detail

FitErrors fit_errors(const std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)>& f_of, const SampleSet& data) {
  FitErrors e;
  double wsum = 0.0, data_norm = 0.0;
  glm::dvec3 l2(0.0), lg(0.0);
  for (const MeasuredSample& s : data.samples) {
    const glm::dvec3 f = f_of(s.wi, s.wo);
    const double c = s.wi.z;
    wsum += s.weight;
    for (int k = 0; k < 3; ++k) {
      l2[k] += s.weight * sqr((f[k] - s.value[k]) * c);
      lg[k] += s.weight * sqr(std::log1p(f[k] * c) - std::log1p(std::max(s.value[k] * c, 0.0)));
      data_norm += s.weight * sqr(s.value[k] * c);
    }
  }
  if (!(wsum > 0.0)) return e;
  for (int k = 0; k < 3; ++k) e.l2cos[k] = std::sqrt(l2[k] / wsum), e.log[k] = std::sqrt(lg[k] / wsum);
  e.l2cos_all = std::sqrt((l2.x + l2.y + l2.z) / (3.0 * wsum));
  e.log_all = std::sqrt((lg.x + lg.y + lg.z) / (3.0 * wsum));
  e.relative_l2cos = data_norm > 0.0 ? std::sqrt((l2.x + l2.y + l2.z) / data_norm) : 0.0;
  return e;
}

FitErrors fit_errors(const MaterialD& m, const SampleSet& data) {
  return fit_errors([&m](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(wi, wo)); }, data);
}

namespace {

// The model names of the presets and of Ngan 2005 / bbm, accepted by --model with a note
// (docs/presets.md: each maps onto an aniso model exactly).
struct ModelAlias {
  std::string_view alias, model, normalization, note;
};
constexpr ModelAlias kModelAliases[] = {
    {"blinnphong", "phong", "", "Ngan 2005's \"Blinn-Phong\" (bbm's NganBlinnPhong) is the mirror lobe of aniso's phong"},
    {"ashikhminshirley", "ashikhmin-shirley", "", "the Ngan 2005 preset name"},
    {"as", "ashikhmin-shirley", "", "short name"},
    {"wardduer", "ward", "duer", "Ngan 2005's Ward-Duer is ward with --normalization duer"},
    {"disney", "principled", "", "Disney's BRDF Explorer model is aniso's principled"},
};

}  // namespace

FitOptions parse_fit_options(const FitOptionText& a) {
  FitOptions o;
  o.model = a.model;
  o.normalization = a.normalization;
  for (const ModelAlias& alias : kModelAliases)
    if (alias.alias == a.model) {
      o.model = alias.model;
      std::string note = fmt::format("--model {} is read as --model {}", alias.alias, alias.model);
      if (!alias.normalization.empty()) {
        if (a.normalization != "ward" && a.normalization != alias.normalization)
          throw InputError(
              fmt::format("--model {} sets --normalization {}, not {}", alias.alias, alias.normalization, a.normalization));
        o.normalization = alias.normalization;
        note += fmt::format(" --normalization {}", alias.normalization);
      }
      o.notes.push_back(fmt::format("{}: {}", note, alias.note));
    }
  o.lobes = int(parse_integer(a.lobes, 1, kLafortuneMaxLobes, "--lobes"));
  if (a.anisotropic == "auto")
    o.anisotropy = Anisotropy::Auto;
  else if (a.anisotropic == "yes")
    o.anisotropy = Anisotropy::Yes;
  else if (a.anisotropic == "no")
    o.anisotropy = Anisotropy::No;
  else
    throw InputError(fmt::format("--anisotropic: expected auto, yes or no, got \"{}\"", a.anisotropic));
  o.allow_energy_gain = a.allow_energy_gain;
  o.shared_exponents = a.shared_exponents;
  o.metal = a.metal;
  o.metal_lobe = a.metal_lobe;
  if (a.metric == "l2cos")
    o.metric = FitMetric::L2Cos;
  else if (a.metric == "log")
    o.metric = FitMetric::Log;
  else
    throw InputError(fmt::format("--metric: expected l2cos or log, got \"{}\"", a.metric));
  o.loss = a.loss;
  const std::optional<double> scale = parse_decimal(a.loss_scale);
  if (!scale || !(*scale >= 0.0))
    throw InputError(fmt::format("--loss-scale: expected a finite decimal number >= 0, got \"{}\"", a.loss_scale));
  o.loss_scale = *scale;
  o.starts = int(parse_integer(a.starts, 1, 1000, "--starts"));
  o.seed = parse_unsigned(a.seed, UINT64_MAX, "--seed");
  o.threads = int(parse_integer(a.threads, 0, 256, "--threads"));
  o.max_iterations = int(parse_integer(a.max_iterations, 1, 100000, "--max-iterations"));
  const std::optional<double> theta = parse_decimal(a.max_theta);
  if (!theta || !(*theta > 0.0 && *theta <= 90.0))
    throw InputError(fmt::format("--max-theta: expected degrees in (0, 90], got \"{}\"", text_escape(a.max_theta)));
  o.max_theta_deg = *theta;
  return o;
}

namespace {

// The fittable models, one row each (its class in fit/models.h), in the order `--model` lists them;
// `anisotropic` is the decision fit_samples made (FitOptions::anisotropy).
struct Fittable {
  std::string_view model;
  FitResult (*fit)(const SampleSet& data, const FitOptions& o, bool anisotropic);
  bool anisotropic = true;  // has an anisotropic form (with rotation_deg)
};
constexpr Fittable kFittable[] = {
    {"lafortune",
     [](const SampleSet& data, const FitOptions& o, bool aniso) {
       if (o.lobes < 1 || o.lobes > kLafortuneMaxLobes)
         throw InputError(fmt::format("--lobes: expected 1 to {}, got {}", kLafortuneMaxLobes, o.lobes));
       return dispatch(LafortuneFit(o.lobes, aniso, o.shared_exponents), data, o);
     }},
    {"ward",
     [](const SampleSet& data, const FitOptions& o, bool aniso) {
       return dispatch(WardFit(aniso, option_enum<WardNormalization>(o.normalization, "--normalization")), data, o);
     }},
    {"ashikhmin-shirley",
     [](const SampleSet& data, const FitOptions& o, bool aniso) { return dispatch(AshikhminShirleyFit(aniso), data, o); }},
    {"ggx", [](const SampleSet& data, const FitOptions& o, bool aniso) { return dispatch(GGXFit(aniso), data, o); }},
    {"metal",
     [](const SampleSet& data, const FitOptions& o, bool aniso) {
       const SpecularLobeKind lobe = option_enum<SpecularLobeKind>(o.metal_lobe, "--metal-lobe");
       return dispatch(MetalFit(aniso, o.metal, lobe), data, o);
     }},
    {"principled",
     [](const SampleSet& data, const FitOptions& o, bool aniso) { return dispatch(PrincipledFit(aniso), data, o); }},
    {"phong", [](const SampleSet& data, const FitOptions& o, bool) { return dispatch(PhongFit(), data, o); }, false},
    {"lambert", [](const SampleSet& data, const FitOptions& o, bool) { return dispatch(LambertFit(), data, o); }, false},
};

// Whether the data can show anisotropy at all (docs/fitting.md, "Anisotropy"): the azimuths of
// their half vectors, modulo the half turn every anisotropic lobe repeats after, in 12 bins of 15
// degrees. An anisotropic lobe is a function of the half vector's azimuth; data whose half
// vectors sit at fewer than kCoverageBins bins (a MERL table: one azimuth) cannot tell its
// directions apart. Half vectors within 1 degree of the normal have no azimuth and are skipped.
constexpr int kAzimuthBins = 12, kCoverageBins = 4;
struct Coverage {
  int bins = 0;
  bool enough() const { return bins >= kCoverageBins; }
};
Coverage azimuth_coverage(const SampleSet& data) {
  std::array<size_t, kAzimuthBins> count{};
  size_t total = 0;
  for (const MeasuredSample& s : data.samples) {
    const Vec3d h = s.wi + s.wo;
    const double len = glm::length(h);
    if (!(len > 0.0) || std::hypot(h.x, h.y) < std::sin(M_PI / 180.0) * len) continue;
    double phi = std::atan2(h.y, h.x);
    if (phi < 0.0) phi += M_PI;
    if (phi >= M_PI) phi -= M_PI;
    ++count[std::min(size_t(phi / M_PI * kAzimuthBins), size_t(kAzimuthBins - 1))];
    ++total;
  }
  Coverage c;
  // A bin counts when it holds at least half a percent of the samples (a stray sample does not).
  for (size_t n : count) c.bins += total > 0 && double(n) >= 0.005 * double(total);
  return c;
}

}  // namespace

std::vector<std::string_view> fittable_models() {
  std::vector<std::string_view> out;
  for (const Fittable& f : kFittable) out.push_back(f.model);
  return out;
}

namespace {
FitResult fit_in_range(const SampleSet& data, const FitOptions& o);
}  // namespace

// Ngan 2005's range first (FitOptions::max_theta_deg): the fit, its starts and its errors see the
// samples within it only.
FitResult fit_samples(const SampleSet& data, const FitOptions& o) {
  if (!(o.max_theta_deg > 0.0 && o.max_theta_deg <= 90.0))
    throw InputError(fmt::format("--max-theta: expected degrees in (0, 90], got {}", o.max_theta_deg));
  // A sample exactly at the range's edge (a grid at 80 degrees) is in: the cosine's last ulps.
  const double lowest_cos = o.max_theta_deg >= 90.0 ? -1.0 : std::cos(o.max_theta_deg * M_PI / 180.0) - 1e-12;
  const auto in_range = [&](const MeasuredSample& s) { return s.wi.z >= lowest_cos && s.wo.z >= lowest_cos; };
  const size_t beyond =
      size_t(std::count_if(data.samples.begin(), data.samples.end(), [&](const MeasuredSample& s) { return !in_range(s); }));
  FitResult r;
  if (beyond == 0) {
    r = fit_in_range(data, o);
  } else {
    SampleSet kept = data;
    kept.samples.clear();
    std::copy_if(data.samples.begin(), data.samples.end(), std::back_inserter(kept.samples), in_range);
    if (kept.samples.empty())
      throw InputError(
          fmt::format("{}: none of the {} samples has both directions within {:g} degrees of the normal "
                      "(--max-theta; 90 keeps every sample)",
                      data.source, data.samples.size(), o.max_theta_deg));
    r = fit_in_range(kept, o);
  }
  r.max_theta_deg = o.max_theta_deg;
  r.samples_beyond_range = beyond;
  return r;
}

namespace {

FitResult fit_in_range(const SampleSet& data, const FitOptions& o) {
  if (o.starts < 1 || o.starts > 1000) throw InputError(fmt::format("--starts: expected 1 to 1000, got {}", o.starts));
  if (o.max_iterations < 1) throw InputError("--max-iterations: expected at least 1");
  // Every sample 0: any black material fits exactly, and the relative error (error / data norm)
  // is 0 / 0. Nothing to fit.
  if (!data.samples.empty() &&
      std::all_of(data.samples.begin(), data.samples.end(), [](const MeasuredSample& s) { return s.value == Vec3d(0.0); }))
    throw InputError(
        fmt::format("{}: every sample is 0: there is nothing to fit (any black material matches, and the "
                    "relative error is undefined)",
                    data.source));
  const Fittable* row = nullptr;
  std::string names;
  for (size_t i = 0; i < std::size(kFittable); ++i) {
    if (kFittable[i].model == o.model) row = &kFittable[i];
    names += fmt::format("{}{}", i == 0 ? "" : i + 1 == std::size(kFittable) ? " or " : ", ", kFittable[i].model);
  }
  if (!row) throw InputError(fmt::format("--model: expected {}, got \"{}\"", names, o.model));
  if (!row->anisotropic) {
    if (o.anisotropy == Anisotropy::Yes)
      throw InputError(fmt::format("--anisotropic yes: {} is isotropic (it has no anisotropic form to fit)", o.model));
    FitResult r = row->fit(data, o, false);
    r.anisotropy_reason = fmt::format("isotropic: {} has no anisotropic form", o.model);
    return r;
  }

  // The anisotropic fit, with its ties: entries the data do not constrain (the second halves of
  // the pairs, the rotation) make the fit isotropic again, which ties each to its partner.
  const auto anisotropic_fit = [&](std::string why) {
    FitResult a = row->fit(data, o, true);
    a.anisotropy_reason = std::move(why);
    if (a.unconstrained_anisotropy.empty()) return a;
    std::string list;
    for (const std::string& n : a.unconstrained_anisotropy) list += fmt::format("{}{}", list.empty() ? "" : ", ", n);
    FitResult iso = row->fit(data, o, false);
    iso.tied.push_back(
        fmt::format("the anisotropic pair to its isotropic partner (alpha_y = alpha_x, n_v = n_u, cy = cx) "
                    "and rotation_deg to 0: the data do not constrain {}",
                    list));
    iso.anisotropy_reason = a.anisotropy_reason + "; then isotropic: the data do not constrain the anisotropic entries";
    return iso;
  };
  const auto with_reason = [](FitResult r, std::string why) {
    r.anisotropy_reason = std::move(why);
    return r;
  };
  switch (o.anisotropy) {
    case Anisotropy::No: return with_reason(row->fit(data, o, false), "isotropic (--anisotropic no)");
    case Anisotropy::Yes: return anisotropic_fit("anisotropic (--anisotropic yes)");
    case Anisotropy::Auto: break;
  }
  const Coverage cov = azimuth_coverage(data);
  if (!cov.enough())
    return with_reason(row->fit(data, o, false),
                       fmt::format("isotropic: the data's half vectors lie at {} of {} azimuths (15-degree bins over the "
                                   "half circle), fewer than the {} that show an anisotropic lobe's directions",
                                   cov.bins, kAzimuthBins, kCoverageBins));
  FitResult iso = row->fit(data, o, false);
  FitResult an = anisotropic_fit("");
  const double gain = iso.errors.relative_l2cos > 0.0 ? 1.0 - an.errors.relative_l2cos / iso.errors.relative_l2cos : 0.0;
  const std::string figures =
      fmt::format("{:.1f}% (relative l2cos {:.4g} -> {:.4g})", 100.0 * gain, iso.errors.relative_l2cos, an.errors.relative_l2cos);
  if (an.anisotropic && gain >= kAutoAnisotropicGain) {
    an.anisotropy_reason = fmt::format(
        "anisotropic: the anisotropic fit lowers the error by {}, at least the {:g}% the "
        "auto rule asks",
        figures, 100.0 * kAutoAnisotropicGain);
    an.seconds += iso.seconds;
    return an;
  }
  if (!an.anisotropic) iso.tied = an.tied;
  iso.anisotropy_reason = an.anisotropic
                              ? fmt::format(
                                    "isotropic: the anisotropic fit lowers the error by only {}, less than the {:g}% the "
                                    "auto rule asks",
                                    figures, 100.0 * kAutoAnisotropicGain)
                              : "isotropic: the data do not constrain the anisotropic fit's extra entries (tied below)";
  iso.seconds += an.seconds;
  return iso;
}

}  // namespace

nlohmann::json fit_provenance(const FitResult& r, const SampleSet& data, const FitOptions& o) {
  nlohmann::json f;
  // A file name need not be UTF-8 and a file's description may hold any byte: JSON needs UTF-8.
  f["data"] = text_escape(data.source);
  f["format"] = data.format;
  if (!data.description.empty()) f["sampled"] = text_escape(data.description);
  f["samples"] = r.samples_total;
  f["samples_in_solver"] = r.samples_used;
  f["range"] = {{"max_theta_deg", r.max_theta_deg},
                {"samples_beyond", r.samples_beyond_range},
                {"rule",
                 "samples with either direction farther from the normal left out (Ngan, Matusik & Durand 2005, Sec. 4: 80 "
                 "degrees); every error is over the samples in range"}};
  f["model"] = o.model;
  if (o.model == "lafortune") f["lobes"] = o.lobes, f["shared_exponents"] = o.shared_exponents;
  if (o.model == "ward") f["normalization"] = o.normalization;
  if (o.model == "metal") f["metal"] = o.metal.empty() ? "fitted eta, k" : o.metal, f["lobe"] = o.metal_lobe;
  f["anisotropic"] = r.anisotropic;
  f["anisotropy"] = o.anisotropy == Anisotropy::Auto ? "auto" : o.anisotropy == Anisotropy::Yes ? "yes" : "no";
  f["anisotropy_reason"] = r.anisotropy_reason;
  f["tied"] = r.tied;
  f["weakly_constrained"] = r.weakly_constrained;
  f["largest_albedo"] = {
      {"value", r.largest_albedo},
      {"theta_deg", r.largest_albedo_theta_deg},
      {"phi_deg", r.largest_albedo_phi_deg},
      {"grid", fmt::format("theta_o 0 to 89 deg ({} values) x phi_o {}, {} importance samples each", std::size(kAlbedoThetaDeg),
                           r.anisotropic ? "0 to 165 deg in steps of 15" : "0 (isotropic)", kAlbedoSamples)}};
  f["energy"] =
      o.allow_energy_gain ? "unconstrained (--allow-energy-gain)"
      : r.energy_constrained
          ? fmt::format(
                "constrained: directional albedo <= 1, {} (relative l2cos {:.4g} and largest albedo {:.4f} "
                "before, {:.4g} and {:.4f} after)",
                r.energy_method, r.unconstrained_l2cos, r.unconstrained_albedo, r.errors.relative_l2cos, r.largest_albedo)
          : "directional albedo <= 1 without the constraint acting";
  f["metric"] = o.metric == FitMetric::Log ? "log" : "l2cos";
  f["loss"] = o.loss;
  f["starts"] = o.starts;
  f["seed"] = o.seed;
  f["best_start"] = r.best_start;
  f["iterations"] = r.iterations;
  f["solver"] = "Ceres Levenberg-Marquardt, derivatives from the kernels on ceres::Jet";
  f["aniso_version"] = ANISO_VERSION;
  f["termination"] = r.termination;
  const auto rgb = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  f["error"] = {{"l2cos", r.errors.l2cos_all},
                {"l2cos_rgb", rgb(r.errors.l2cos)},
                {"log", r.errors.log_all},
                {"log_rgb", rgb(r.errors.log)},
                {"relative_l2cos", r.errors.relative_l2cos}};
  f["seconds"] = r.seconds;
  return f;
}

std::vector<std::pair<std::string, FitOptions>> compare_models(const FitOptions& base) {
  std::vector<std::pair<std::string, FitOptions>> out;
  const auto add = [&](std::string label, auto&& edit) {
    FitOptions o = base;
    edit(o);
    out.emplace_back(std::move(label), o);
  };
  add("lafortune (1 lobe)", [](FitOptions& o) { o.model = "lafortune", o.lobes = 1; });
  add("lafortune (3 lobes)", [](FitOptions& o) { o.model = "lafortune", o.lobes = 3; });
  add("ward", [](FitOptions& o) { o.model = "ward", o.normalization = "ward"; });
  add("ward (duer)", [](FitOptions& o) { o.model = "ward", o.normalization = "duer"; });
  add("ward (balanced)", [](FitOptions& o) { o.model = "ward", o.normalization = "balanced"; });
  add("ashikhmin-shirley", [](FitOptions& o) { o.model = "ashikhmin-shirley"; });
  add("ggx", [](FitOptions& o) { o.model = "ggx"; });
  add("metal (ggx, fitted eta, k)", [](FitOptions& o) { o.model = "metal", o.metal.clear(), o.metal_lobe = "ggx"; });
  add("phong", [](FitOptions& o) { o.model = "phong"; });
  return out;
}

std::string describe_parameters(const FitResult& r) {
  std::string s;
  for (size_t i = 0; i < r.parameters.size(); ++i) {
    // Colour triples r, g, b print as one (r, g, b) entry.
    const std::string& n = r.parameter_names[i];
    if (n.size() > 2 && n.compare(n.size() - 2, 2, ".r") == 0 && i + 2 < r.parameters.size()) {
      s += fmt::format("{}{}=({:.3g}, {:.3g}, {:.3g})", s.empty() ? "" : " ", n.substr(0, n.size() - 2), r.parameters[i],
                       r.parameters[i + 1], r.parameters[i + 2]);
      i += 2;
      continue;
    }
    s += fmt::format("{}{}={:.4g}", s.empty() ? "" : " ", n, r.parameters[i]);
  }
  return s;
}

}  // namespace aniso
