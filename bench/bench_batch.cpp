// bench/bench_batch.cpp: the batch path (include/aniso/batch/batch.h) on the benchmarks' materials
// and pairs (docs/benchmarks.md, docs/performance.md).
//
//   batch/<name>           batch::evaluate, one thread        (<name>: every f/<name>)
//   batch_mt/<name>        batch::evaluate, all threads (oneTBB)
//   batch/pdf/<name>, batch_mt/pdf/<name>        batch::pdf   (<name>: every pdf/<name>)
//   batch/sample/<name>, batch_mt/sample/<name>  batch::sample (<name>: every sample/<name>)
//
// Inputs: bench_eval.cpp's 4096 pairs repeated kCopies times in SoA arrays (kPairs elements), the
// uniforms likewise; items_per_second counts elements per second of wall-clock time, so that the
// multi-threaded runs are timed as a caller sees them (CPU time of the main thread would not).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "aniso/batch/batch.h"
#include "aniso/brdf/material.h"
#include "bench_common.h"
#include "stats/rng.h"

using namespace aniso;

namespace {

// 16 copies of the 4096 pairs: 65536 elements, 1.8 MB of float input and output for evaluate
// (28 bytes per element), within the 2 MB L2 of one core of the benchmark machine; enough work per
// call (60 us and up on one core) that oneTBB's fork and join (a few us) is a small share of it.
constexpr size_t kCopies = 16;

struct BatchInputs {
  batch::DirectionArray<float> wi, wo;
  std::vector<float> uc, u0, u1;
  size_t n = 0;
  BatchInputs() {
    const std::span<const Vec3> swi = bench_wi(), swo = bench_wo();
    n = swi.size() * kCopies;
    wi.resize(n);
    wo.resize(n);
    uc.resize(n), u0.resize(n), u1.resize(n);
    Rng rng(7777);
    for (size_t i = 0; i < n; ++i) {
      wi.set(i, swi[i % swi.size()]);
      wo.set(i, swo[i % swo.size()]);
      uc[i] = rng.uniform_as<float>(), u0[i] = rng.uniform_as<float>(), u1[i] = rng.uniform_as<float>();
    }
  }
};

const BatchInputs& batch_inputs() {
  static const BatchInputs in;
  return in;
}

enum class What { Eval, Pdf, Sample };

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void bm_batch(benchmark::State& state, const Material m, What what, batch::Threads threads) {
  const BatchInputs& in = batch_inputs();
  const size_t n = in.n;
  batch::ColorArray<float> f(n);
  std::vector<float> p(n);
  batch::SampleArray<float> s(n);
  double wall_seconds = 0.0;
  const double cpu_start = process_cpu_seconds();
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    switch (what) {
      case What::Eval: batch::evaluate(m, in.wi.view(), in.wo.view(), n, f.view(), threads); break;
      case What::Pdf: batch::pdf(m, in.wi.view(), in.wo.view(), n, p.data(), threads); break;
      case What::Sample: batch::sample(m, in.wo.view(), in.uc.data(), in.u0.data(), in.u1.data(), n, s.view(), threads); break;
    }
    benchmark::ClobberMemory();
    wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // items_per_second by the wall clock (UseRealTime would do the same but rename the benchmark
  // ".../real_time", and the names are fixed).
  const double items = double(state.iterations()) * double(n);
  state.counters["items_per_second"] = benchmark::Counter(items / std::max(wall_seconds, 1e-12));
  // Items per CPU second of the whole process (all threads): items_per_second / items_per_cpu_second
  // is the average number of threads that worked, which tells a batch_mt run on a machine whose
  // other cores are busy with other work (1.0: the calling thread did all the blocks) from one
  // that had them.
  state.counters["items_per_cpu_second"] = benchmark::Counter(items / std::max(process_cpu_seconds() - cpu_start, 1e-12));
  state.SetLabel(batch::simd_target());
}

void register_one(const std::string& prefix, const std::string& key, What what) {
  const Material m = bench_material(key);
  for (const auto& [name, threads] :
       {std::pair{std::string("batch/"), batch::Threads::One}, std::pair{std::string("batch_mt/"), batch::Threads::All}}) {
    benchmark::RegisterBenchmark((name + prefix + key).c_str(),
                                 [m, what, threads = threads](benchmark::State& st) { bm_batch(st, m, what, threads); });
  }
}

}  // namespace

void register_batch_benchmarks() {
  // The f/<name> set of bench_eval.cpp.
  std::vector<std::string> eval_keys = {"lambert", "phong"};
  for (const char* form : {"vector", "angle", "approx"})
    for (const char* norm : {"ward", "duer", "balanced"}) eval_keys.push_back(std::string("ward/") + form + "/" + norm);
  for (const char* k : {"ashikhmin-shirley", "lafortune/matte-steel", "ggx", "metal/gold", "metal/brushed-gold"})
    eval_keys.push_back(k);
  for (const std::string& k : eval_keys) register_one("", k, What::Eval);
  // f/material/<key>: the batch path always dispatches on the material's tag, once per call.
  for (const char* k : {"ward/vector/ward", "lambert"}) {
    const Material m = bench_material(k);
    for (const auto& [name, threads] : {std::pair{std::string("batch/material/"), batch::Threads::One},
                                        std::pair{std::string("batch_mt/material/"), batch::Threads::All}})
      benchmark::RegisterBenchmark((name + k).c_str(),
                                   [m, threads = threads](benchmark::State& st) { bm_batch(st, m, What::Eval, threads); });
  }
  // The sample/<name> and pdf/<name> set of bench_sample.cpp.
  for (const char* k : {"lambert", "phong", "ward/vector/ward", "ashikhmin-shirley", "lafortune/matte-steel", "ggx", "metal/gold",
                        "metal/brushed-gold"}) {
    register_one("sample/", k, What::Sample);
    register_one("pdf/", k, What::Pdf);
  }
}

// --check: the batch path on the benchmark inputs agrees with the scalar f and pdf (1e-4 relative
// where the value exceeds 1e-6: a sanity check; tests/test_batch.cpp holds the 1e-5 comparison).
int check_batch() {
  int failures = 0;
  const BatchInputs& in = batch_inputs();
  const size_t n = bench_wi().size();
  for (const char* k : {"lambert", "phong", "ward/vector/ward", "ward/angle/duer", "ward/approx/balanced", "ashikhmin-shirley",
                        "lafortune/matte-steel", "ggx", "metal/gold", "metal/brushed-gold"}) {
    const Material& m = bench_material(k);
    batch::ColorArray<float> f(n);
    std::vector<float> p(n);
    batch::evaluate(m, in.wi.view(), in.wo.view(), n, f.view());
    batch::pdf(m, in.wi.view(), in.wo.view(), n, p.data());
    size_t bad = 0;
    for (size_t i = 0; i < n; ++i) {
      const RGB ref = m.f(in.wi.get(i), in.wo.get(i));
      const float pref = m.pdf(in.wi.get(i), in.wo.get(i));
      for (int c = 0; c < 3; ++c)
        if (ref[c] > 1e-6f && std::abs(f.get(i)[c] - ref[c]) > 1e-4f * ref[c]) ++bad;
      if (pref > 1e-6f && std::abs(p[i] - pref) > 1e-4f * pref) ++bad;
    }
    std::printf("%s batch/%s (%s): %zu values differ from the scalar path\n", bad ? "FAIL" : "ok  ", k, batch::simd_target(),
                bad);
    failures += bad ? 1 : 0;
  }
  return failures;
}
