// bench/bench_measured.cpp: the measured (MERL-layout) BRDF: f, pdf and sample throughput of the
// kernel, single thread, float, on the bench's directions (bench_eval.cpp); and the time to build
// the sampling tables. The table is the `gold` preset written in MERL layout (tabulate_merl):
// lookups cost the same whatever the numbers. docs/measured.md quotes the figures.
#include <memory>

#include <benchmark/benchmark.h>

#include "aniso/io/materials.h"
#include "aniso/measured/measured.h"
#include "stats/rng.h"

using namespace aniso;

std::span<const Vec3> bench_wi();  // bench_eval.cpp
std::span<const Vec3> bench_wo();

namespace {

const std::shared_ptr<const MeasuredData>& gold_table() {
  static const auto d = make_measured(tabulate_merl(build_material<double>(load_material("gold"))), "gold (tabulated)");
  return d;
}

void BM_MeasuredF(benchmark::State& state) {
  const Material m = measured_kernel<float>(*gold_table());
  const auto wi = bench_wi(), wo = bench_wo();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.f(wi[i], wo[i]));
    i = i + 1 == wi.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MeasuredF);

void BM_MeasuredPdf(benchmark::State& state) {
  const Material m = measured_kernel<float>(*gold_table());
  const auto wi = bench_wi(), wo = bench_wo();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.pdf(wi[i], wo[i]));
    i = i + 1 == wi.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MeasuredPdf);

void BM_MeasuredSample(benchmark::State& state) {
  const Material m = measured_kernel<float>(*gold_table());
  const auto wo = bench_wo();
  Rng rng(5);
  std::vector<float> u(3 * wo.size());
  for (float& x : u) x = rng.uniform_as<float>();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.sample(wo[i], u[3 * i], Vec2(u[3 * i + 1], u[3 * i + 2])));
    i = i + 1 == wo.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MeasuredSample);

// The sampling tables of one MERL table (oneTBB over the viewing-angle bins, all cores).
void BM_MeasuredTableBuild(benchmark::State& state) {
  const MerlBrdf table = gold_table()->brdf;
  for (auto _ : state) benchmark::DoNotOptimize(make_measured(table, "bench"));
}
BENCHMARK(BM_MeasuredTableBuild)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
