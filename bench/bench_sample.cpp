// bench/bench_sample.cpp: sample(wo, uc, u) and pdf(wi, wo) throughput of the main models, direct
// calls on the model structs, single thread, float (docs/benchmarks.md).
//
// sample() includes what a renderer gets from it: the lobe choice, the direction, and f and pdf at
// that direction (make_sample), so it costs more than f + pdf. Directions wo are bench_eval.cpp's;
// uc, u are precomputed uniforms in [0, 1).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <benchmark/benchmark.h>

#include "aniso/brdf/material.h"
#include "bench_common.h"
#include "stats/rng.h"

using namespace aniso;

namespace {

struct Uniforms {
  std::vector<float> uc;
  std::vector<Vec2> u;
  explicit Uniforms(size_t n) {
    Rng rng(7777);
    uc.resize(n);
    u.resize(n);
    for (size_t i = 0; i < n; ++i) {
      uc[i] = rng.uniform_as<float>();
      u[i] = Vec2(rng.uniform_as<float>(), rng.uniform_as<float>());
    }
  }
};

const Uniforms& uniforms() {
  static const Uniforms un(bench_wo().size());
  return un;
}

template <typename M> const M& alternative(const Material& m) {
  if constexpr (std::is_same_v<M, LambertT<float>>)
    return m.lambert;
  else if constexpr (std::is_same_v<M, PhongT<float>>)
    return m.phong;
  else if constexpr (std::is_same_v<M, WardT<float>>)
    return m.ward;
  else if constexpr (std::is_same_v<M, AshikhminShirleyT<float>>)
    return m.ashikhmin_shirley;
  else if constexpr (std::is_same_v<M, LafortuneT<float>>)
    return m.lafortune;
  else if constexpr (std::is_same_v<M, GGXT<float>>)
    return m.ggx;
  else
    return m.metal;
}

template <typename Model> void bm_sample(benchmark::State& state, const Model model) {
  const std::span<const Vec3> wo = bench_wo();
  const Uniforms& un = uniforms();
  for (auto _ : state) {
    for (size_t i = 0; i < wo.size(); ++i) {
      BSDFSampleT<float> s = model.sample(wo[i], un.uc[i], un.u[i]);
      benchmark::DoNotOptimize(s);
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(wo.size()));
}

template <typename Model> void bm_pdf(benchmark::State& state, const Model model) {
  const std::span<const Vec3> wi = bench_wi(), wo = bench_wo();
  for (auto _ : state) {
    for (size_t i = 0; i < wo.size(); ++i) {
      float p = model.pdf(wi[i], wo[i]);
      benchmark::DoNotOptimize(p);
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(wo.size()));
}

template <typename M> void register_model(const std::string& key) {
  const M model = alternative<M>(bench_material(key));
  benchmark::RegisterBenchmark(("sample/" + key).c_str(), [model](benchmark::State& s) { bm_sample(s, model); });
  benchmark::RegisterBenchmark(("pdf/" + key).c_str(), [model](benchmark::State& s) { bm_pdf(s, model); });
}

// The sampled subset: one material per model; Ward in its default vector form and Ward 1992
// normalisation (sampling itself does not depend on the form).
const char* const kSampled[] = {"lambert", "phong",      "ward/vector/ward",  "ashikhmin-shirley", "lafortune/matte-steel",
                                "ggx",     "metal/gold", "metal/brushed-gold"};

}  // namespace

void register_sample_benchmarks() {
  register_model<LambertT<float>>("lambert");
  register_model<PhongT<float>>("phong");
  register_model<WardT<float>>("ward/vector/ward");
  register_model<AshikhminShirleyT<float>>("ashikhmin-shirley");
  register_model<LafortuneT<float>>("lafortune/matte-steel");
  register_model<GGXT<float>>("ggx");
  register_model<MetalT<float>>("metal/gold");
  register_model<MetalT<float>>("metal/brushed-gold");
}

// --check: every sample is "no sample" or a direction above the horizon with a positive finite pdf
// that pdf() reproduces, and a finite non-negative weight; most samples are valid.
int check_sample() {
  int failures = 0;
  const std::span<const Vec3> wo = bench_wo();
  const Uniforms& un = uniforms();
  for (const char* key : kSampled) {
    const Material& m = bench_material(key);
    size_t valid = 0, bad = 0;
    for (size_t i = 0; i < wo.size(); ++i) {
      const BSDFSampleT<float> s = m.sample(wo[i], un.uc[i], un.u[i]);
      if (!s.valid) continue;
      ++valid;
      const float p = m.pdf(s.wi, wo[i]);
      bool ok = s.wi.z > 0.0f && std::isfinite(s.pdf) && s.pdf > 0.0f && std::abs(p - s.pdf) <= 1e-4f * s.pdf;
      for (int k = 0; k < 3; ++k) ok = ok && std::isfinite(s.weight[k]) && s.weight[k] >= 0.0f;
      if (!ok) ++bad;
    }
    const bool pass = bad == 0 && valid * 2 > wo.size();
    std::printf("%s sample/%s: %zu of %zu valid, %zu bad\n", pass ? "ok  " : "FAIL", key, valid, wo.size(), bad);
    failures += pass ? 0 : 1;
  }
  return failures;
}
