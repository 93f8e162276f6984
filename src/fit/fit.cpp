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
#include "fit/costs.h"
#include "fit/energy.h"
#include "fit/identifiability.h"
#include "fit/linear.h"
#include "fit/models.h"
#include "fit/options.h"
#include "fit/separable.h"
#include "fit/starts.h"
#include "io/enum_names.h"
#include "io/text_escape.h"
#include "io/text_input.h"

namespace aniso {
namespace {

using namespace fit_detail;

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

  const bool projectable = projected_entry(model, layout) >= 0;  // separable.h, project_roughness

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
    // With bounds, Ceres's trust-region minimizer runs a projected Armijo line search on every step
    // (trust_region_minimizer.cc, TrustRegionMinimizer::DoLineSearch), whose CUBIC interpolation,
    // the default, evaluates the Jacobian at every trial point (line_search.cc, ArmijoLineSearch::
    // DoSearch: interpolation_uses_gradients); QUADRATIC needs only the costs: a free-f90 GGX fit of
    // chm_light_blue took 81 Jacobians in 7 iterations, 1 with it (docs/fitting.md, "Speed"). Only
    // where the roughness is projected (separable.h, projected_entry), so that the solver starts
    // next to the minimum: the other models' fits need the cubic steps (Lafortune's 3 lobes on
    // cayman: relative l2cos 0.073 with QUADRATIC, 0.0025 without; metal on cm_military_green:
    // 0.213, 0.164).
    if (projectable) so.line_search_interpolation_type = ceres::QUADRATIC;
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
  // Before the best start is refined: where only one roughness entry is not linear, its minimum
  // over that entry with the linear entries solved exactly (separable.h, project_roughness), on the
  // samples the refinement runs on; the solver then starts there. Its cost is on other samples
  // (or at another point) than phase 1's: the refinement's own cost is taken.
  const bool refine_more =
      !ranking.empty() || (o.max_iterations > kPhase1Iterations && final_fit.iterations >= kPhase1Iterations);
  bool projected = false;
  if (refine_more && project_roughness(model, layout, final_fit.x, ranking.empty() ? used : coarse))
    projected = true, final_fit.cost = INFINITY;
  // With the subsets, the best start converges on the coarse one, then polishes on every solver
  // sample (at most kPolishIterations); without them, it is refined on every solver sample when it
  // had not converged within the ranking's iterations.
  if (!ranking.empty()) {
    const Solved converged = solve(final_fit.x, std::max(1, o.max_iterations - kPhase1Iterations), "refining the best start",
                                   kPolishIterations, On::Coarse);
    iterations += converged.iterations;
    if (std::isfinite(converged.cost)) final_fit = converged;  // costs on different sets do not compare
    // The coarse subset's minimum is near every solver sample's: projected once more, on them.
    projected = project_roughness(model, layout, final_fit.x, used, kProjectionSpanNear) || projected;
    Solved refined = solve(final_fit.x, kPolishIterations, "refining on every solver sample", 0, On::All);
    iterations += refined.iterations;
    final_fit = refined;
  } else if (refine_more) {
    Solved refined = solve(final_fit.x, std::max(1, o.max_iterations - kPhase1Iterations), "refining the best start", 0, On::All);
    iterations += refined.iterations;
    if (refined.cost <= final_fit.cost) final_fit = refined;
    if (!std::isfinite(final_fit.cost)) final_fit = phase1[best];  // the projected start diverged
  }
  if (!std::isfinite(final_fit.cost)) throw std::runtime_error(fmt::format("{}: the fit diverged from every start", data.source));
  // The linear entries exactly at the solution (the solver's stop leaves them within its
  // tolerance); kept when they lower the cost.
  if (!layout.empty()) {
    std::vector<double> x = final_fit.x;
    if (solve_linear(model, layout, x, used) < data_cost(model, final_fit.x, used, o.metric)) final_fit.x = std::move(x);
  }
  // The canonical form (models.h: orientation, Lafortune's lobe order) from here on, so that the
  // names of weak or tied entries refer to the entries as written.
  model.canonicalize(final_fit.x.data());

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
  r.best_start = starts[best].name + (projected ? ", its roughness projected (variable projection)" : "");
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
  // measured in docs/fitting.md, "Real measurements"); GGX with a free f90 (10 entries) on Jet<12>
  // takes about three quarters of Jet<16>'s time.
  if (p <= 8 && !requires { Model::kHasParts; }) return fit_with<Model, 8>(model, data, o);
  if (p <= 12 && !requires { Model::kHasParts; }) return fit_with<Model, 12>(model, data, o);
  if (p <= 16) return fit_with<Model, 16>(model, data, o);
  if (p <= 32) return fit_with<Model, 32>(model, data, o);
  if (p <= 64) return fit_with<Model, 64>(model, data, o);
  return fit_with<Model, 112>(model, data, o);  // Lafortune: 8 anisotropic lobes, 3 + 8 x 12 = 99
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
    {"ggx",
     [](const SampleSet& data, const FitOptions& o, bool aniso) {
       std::vector<std::string_view> freed;
       if (o.fresnel == "free-f90") freed.push_back("f90");
       return dispatch(GGXFit(aniso, {}, freed), data, o);
     }},
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
  if (o.fresnel != "schlick" && o.fresnel != "free-f90")
    throw InputError(fmt::format("--fresnel: expected schlick or free-f90, got \"{}\"", text_escape(o.fresnel)));
  if (o.fresnel != "schlick" && o.model != "ggx")
    throw InputError(
        fmt::format("--fresnel {}: applies to --model ggx only (its f90), not to --model {}", o.fresnel, text_escape(o.model)));
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
  if (o.model == "ggx")
    f["fresnel"] = o.fresnel == "free-f90" ? "Schlick's form with a fitted f90: F0 + (F90 - F0)(1 - c)^5"
                                           : "Schlick 1994: F0 + (1 - F0)(1 - c)^5 (f90 = 1)";
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
  add("ggx", [](FitOptions& o) { o.model = "ggx", o.fresnel = "schlick"; });
  add("ggx (free f90)", [](FitOptions& o) { o.model = "ggx", o.fresnel = "free-f90"; });
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
