// bench/bench_fit.cpp: how long `aniso fit` takes (docs/fitting.md, "Performance"): three
// Lafortune lobes to a Cornell paint, `--compare` on it, and a MERL-sized set of 1.46 million
// samples, each with the error it reached (the counters). Threads: 2 (the CI machine's cores).
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "aniso/fit/fit.h"
#include "aniso/io/materials.h"
#include "stats/rng.h"

namespace aniso {
namespace {

const std::string kCornell = std::string(ANISO_SOURCE_DIR) + "/data/measured/cornell/";

void report(benchmark::State& state, const FitResult& r) {
  state.counters["l2cos"] = r.errors.l2cos_all;
  state.counters["log"] = r.errors.log_all;
  state.counters["relative"] = r.errors.relative_l2cos;
  state.counters["iterations"] = r.iterations;
}

void BM_FitCornellLafortune3(benchmark::State& state, const char* paint) {
  const SampleSet data = read_cornell(kCornell + paint + ".brdf");
  FitOptions o;
  o.model = "lafortune";
  o.lobes = 3;
  o.threads = 2;
  FitResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = fit_samples(data, o));
  report(state, r);
}

void BM_FitCompareCornell(benchmark::State& state, const char* paint) {
  const SampleSet data = read_cornell(kCornell + paint + ".brdf");
  FitOptions base;
  base.threads = 2;
  double best = INFINITY;
  for (auto _ : state)
    for (const auto& [label, o] : compare_models(base)) best = std::min(best, fit_samples(data, o).errors.l2cos_all);
  state.counters["best_l2cos"] = best;
}

// 1,458,000 samples (the number of MERL bins) from a known material: pairs uniform over the
// hemispheres and a third near the mirror direction, with 2% noise.
SampleSet merl_sized(const char* material) {
  const MaterialD m = build_material<double>(load_material(material));
  Rng rng(2005);
  std::mt19937_64 gen(2005);
  std::normal_distribution<double> normal;
  const auto hemi = [&] {
    const double z = rng.uniform(), phi = 2 * M_PI * rng.uniform(), r = std::sqrt(1 - z * z);
    return Vec3d(r * std::cos(phi), r * std::sin(phi), std::max(z, 1e-3));
  };
  SampleSet s;
  s.source = "synthetic MERL-sized";
  s.format = "synthetic";
  s.samples.resize(1458000);
  for (size_t i = 0; i < s.samples.size(); ++i) {
    MeasuredSample& x = s.samples[i];
    x.wo = hemi();
    x.wi = i % 3 == 0 ? glm::normalize(Vec3d(-x.wo.x, -x.wo.y, x.wo.z) + 0.15 * (hemi() - Vec3d(0, 0, 0.5))) : hemi();
    if (!(x.wi.z > 0.01)) x.wi = hemi();
    const RGBT<double> f = m.f(x.wi, x.wo);
    for (int c = 0; c < 3; ++c) x.value[c] = std::max(0.0, f[c] * (1 + 0.02 * normal(gen)));
  }
  return s;
}

void BM_FitMerlSized(benchmark::State& state, const char* model, int lobes) {
  static const SampleSet data = merl_sized(R"({"model": "lafortune", "rho_d": [0.2, 0.15, 0.1], "lobes": [
      {"cxy": -1.02, "cz": 0.98, "n": 60}, {"cxy": -0.8, "cz": 0.7, "n": 6}]})");
  FitOptions o;
  o.model = model;
  o.lobes = lobes;
  o.threads = 2;
  FitResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = fit_samples(data, o));
  report(state, r);
  state.counters["solver_samples"] = double(r.samples_used);
}

BENCHMARK_CAPTURE(BM_FitCornellLafortune3, krylon_blue, "krylon_blue")->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_FitCornellLafortune3, cayman, "cayman")->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_FitCompareCornell, krylon_blue, "krylon_blue")->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_FitMerlSized, lafortune3, "lafortune", 3)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_FitMerlSized, ggx, "ggx", 1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace aniso

BENCHMARK_MAIN();
