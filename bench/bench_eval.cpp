// bench/bench_eval.cpp: f(wi, wo) throughput of every model (docs/benchmarks.md), the shared inputs
// and materials, and main() (with `--check`).
//
// Every benchmark loops over the same kPairs precomputed (wi, wo) pairs, all strictly above the
// horizon, and reports items_per_second = evaluations per second, single thread, float.
// The materials are built at run time from JSON / presets (io/materials.h), as the CLI builds them,
// so the compiler cannot constant-fold their parameters (form, normalisation, tag) into the loop.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/io/materials.h"
#include "bench_common.h"
#include "stats/rng.h"

using namespace aniso;
using nlohmann::json;

namespace {

constexpr size_t kPairs = 4096;

// A direction above the horizon: uniform in solid angle (cos theta uniform in (0, 1]), except that
// one in eight is near grazing, cos theta in [0.001, 0.1).
Vec3 upper_direction(Rng& rng) {
  const float u0 = rng.uniform_as<float>(), u1 = rng.uniform_as<float>(), u2 = rng.uniform_as<float>();
  const float cos_t = u0 < 0.125f ? 0.001f + 0.099f * u1 : 1.0f - u1;  // (0, 1]
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  const float phi = 2.0f * kPi<float> * u2;
  return Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}

struct Inputs {
  std::vector<Vec3> wi, wo;
  Inputs() {
    // Fixed seed: every run, every machine evaluates the same pairs.
    Rng rng(20240601);
    wi.reserve(kPairs);
    wo.reserve(kPairs);
    while (wi.size() < kPairs) {
      const Vec3 o = upper_direction(rng);
      Vec3 i;
      if (rng.uniform_as<float>() < 0.5f) {
        // Half of the pairs near the specular peak, as importance sampling produces them: wo
        // mirrored about a half vector from a Ward lobe of roughness 0.2.
        const Vec2 u(rng.uniform_as<float>(), rng.uniform_as<float>());
        i = reflect_about(o, Ward_SampleHalf(u, 0.2f, 0.2f));
        i = glm::normalize(i);
        if (!(i.z > 0.001f)) continue;  // below or on the horizon: draw the pair again
      } else {
        i = upper_direction(rng);
      }
      wi.push_back(i);
      wo.push_back(o);
    }
  }
};

const Inputs& inputs() {
  static const Inputs in;
  return in;
}

json ward_json(const char* form, const char* norm) {
  return {{"model", "ward"},      {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.1}, {"alpha_y", 0.25}, {"form", form},
          {"normalization", norm}};
}

// Every benchmarked material, by key. Presets where the brief names one, JSON otherwise.
std::map<std::string, Material> build_materials() {
  std::map<std::string, Material> m;
  const auto from_json = [](const json& j, const std::string& key) {
    return build_material<float>(parse_material(j, "bench " + key));
  };
  m["lambert"] = from_json({{"model", "lambert"}, {"kd", 0.5}}, "lambert");
  m["phong"] = from_json({{"model", "phong"}, {"kd", 0.2}, {"ks", 0.4}, {"exponent", 50.0}}, "phong");
  for (const char* form : {"vector", "angle", "approx"})
    for (const char* norm : {"ward", "duer", "balanced"}) {
      const std::string key = std::string("ward/") + form + "/" + norm;
      m[key] = from_json(ward_json(form, norm), key);
    }
  m["ashikhmin-shirley"] =
      from_json({{"model", "ashikhmin-shirley"}, {"rd", 0.3}, {"rs", 0.05}, {"n_u", 20.0}, {"n_v", 500.0}}, "ashikhmin-shirley");
  m["lafortune/matte-steel"] = build_material<float>(load_material("matte-steel"));
  m["ggx"] = from_json({{"model", "ggx"}, {"kd", 0.1}, {"f0", 0.04}, {"alpha_x", 0.1}, {"alpha_y", 0.25}}, "ggx");
  m["metal/gold"] = build_material<float>(load_material("gold"));
  m["metal/brushed-gold"] = build_material<float>(load_material("brushed-gold"));
  return m;
}

const std::map<std::string, Material>& materials() {
  static const std::map<std::string, Material> m = build_materials();
  return m;
}

// The model struct inside a Material, by its static type: the direct (no-dispatch) call.
template <typename M> const M& alternative(const Material& m);
template <> const LambertT<float>& alternative(const Material& m) { return m.lambert; }
template <> const PhongT<float>& alternative(const Material& m) { return m.phong; }
template <> const WardT<float>& alternative(const Material& m) { return m.ward; }
template <> const AshikhminShirleyT<float>& alternative(const Material& m) { return m.ashikhmin_shirley; }
template <> const LafortuneT<float>& alternative(const Material& m) { return m.lafortune; }
template <> const GGXT<float>& alternative(const Material& m) { return m.ggx; }
template <> const MetalT<float>& alternative(const Material& m) { return m.metal; }

// f over all pairs, one DoNotOptimize per result. Model is a model struct (direct call) or
// Material (tag dispatch); either way the object is a run-time value copied into the benchmark.
template <typename Model> void bm_f(benchmark::State& state, const Model model) {
  const Vec3* wi = inputs().wi.data();
  const Vec3* wo = inputs().wo.data();
  for (auto _ : state) {
    for (size_t i = 0; i < kPairs; ++i) {
      RGB r = model.f(wi[i], wo[i]);
      benchmark::DoNotOptimize(r);
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(kPairs));
}

template <typename M> void register_direct(const std::string& key) {
  const M model = alternative<M>(bench_material(key));
  benchmark::RegisterBenchmark(("f/" + key).c_str(), [model](benchmark::State& s) { bm_f(s, model); });
}

void register_dispatch(const std::string& key) {
  const Material model = bench_material(key);
  benchmark::RegisterBenchmark(("f/material/" + key).c_str(), [model](benchmark::State& s) { bm_f(s, model); });
}

void register_eval_benchmarks() {
  register_direct<LambertT<float>>("lambert");
  register_direct<PhongT<float>>("phong");
  for (const char* form : {"vector", "angle", "approx"})
    for (const char* norm : {"ward", "duer", "balanced"}) register_direct<WardT<float>>(std::string("ward/") + form + "/" + norm);
  register_direct<AshikhminShirleyT<float>>("ashikhmin-shirley");
  register_direct<LafortuneT<float>>("lafortune/matte-steel");
  register_direct<GGXT<float>>("ggx");
  register_direct<MetalT<float>>("metal/gold");
  register_direct<MetalT<float>>("metal/brushed-gold");
  // The same Ward vector material through MaterialT::f (tag switch), and the cheapest model, where
  // the dispatch is the largest share of the time.
  register_dispatch("ward/vector/ward");
  register_dispatch("lambert");
}

// --- --check: every benchmarked kernel once over the inputs, instead of timing ---------------

bool finite_nonneg(const RGB& c) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(c[k]) || c[k] < 0.0f) return false;
  return true;
}

int check_eval() {
  int failures = 0;
  const auto& in = inputs();
  for (size_t i = 0; i < kPairs; ++i) {
    if (!(in.wi[i].z > 0.0f) || !(in.wo[i].z > 0.0f) || std::abs(glm::length(in.wi[i]) - 1.0f) > 1e-5f ||
        std::abs(glm::length(in.wo[i]) - 1.0f) > 1e-5f) {
      std::printf("FAIL inputs: pair %zu is not two unit directions above the horizon\n", i);
      return 1;
    }
  }
  for (const auto& [key, m] : materials()) {
    size_t bad = 0, mismatch = 0;
    for (size_t i = 0; i < kPairs; ++i) {
      const RGB via_material = m.f(in.wi[i], in.wo[i]);
      const RGB direct = m.visit([&](const auto& model) { return model.f(in.wi[i], in.wo[i]); });
      if (!finite_nonneg(via_material)) ++bad;
      if (std::memcmp(&via_material, &direct, sizeof(RGB)) != 0) ++mismatch;
    }
    std::printf("%s f/%s: %zu non-finite or negative, %zu dispatch mismatches\n", bad || mismatch ? "FAIL" : "ok  ", key.c_str(),
                bad, mismatch);
    failures += (bad || mismatch) ? 1 : 0;
  }
  // The benchmarked materials are what their names say.
  const auto expect = [&](bool ok, const char* what) {
    std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    failures += ok ? 0 : 1;
  };
  const Material& steel = bench_material("lafortune/matte-steel");
  expect(steel.kind == ModelKind::Lafortune && steel.lafortune.lobe_count == 3, "matte-steel is a 3-lobe Lafortune");
  const Material& brushed = bench_material("metal/brushed-gold");
  expect(brushed.kind == ModelKind::Metal && brushed.metal.lobe_kind == SpecularLobeKind::Ward &&
             brushed.metal.has_directional_diffuse,
         "brushed-gold is a metal with a Ward lobe and directional diffuse");
  const Material& gold = bench_material("metal/gold");
  expect(gold.kind == ModelKind::Metal && gold.metal.lobe_kind == SpecularLobeKind::GGX, "gold is a metal with GGX");
  // Vector and angle forms are the same function: the comparison in docs/benchmarks.md compares
  // like with like. Relative difference of the specular term where it is not negligible.
  for (const char* norm : {"ward", "duer", "balanced"}) {
    const WardT<float>& v = bench_material(std::string("ward/vector/") + norm).ward;
    const WardT<float>& a = bench_material(std::string("ward/angle/") + norm).ward;
    double worst = 0.0;
    for (size_t i = 0; i < kPairs; ++i) {
      const double sv = v.lobe.eval(in.wi[i], in.wo[i]), sa = a.lobe.eval(in.wi[i], in.wo[i]);
      if (sv > 1e-3) worst = std::max(worst, std::abs(sa - sv) / sv);
    }
    std::printf("%s ward/%s: vector vs angle form, max relative difference %.2e\n", worst < 1e-3 ? "ok  " : "FAIL", norm, worst);
    failures += worst < 1e-3 ? 0 : 1;
  }
  return failures;
}

}  // namespace

std::span<const Vec3> bench_wi() { return inputs().wi; }
std::span<const Vec3> bench_wo() { return inputs().wo; }
const Material& bench_material(const std::string& key) { return materials().at(key); }

int main(int argc, char** argv) {
  bool check = false;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--check") == 0)
      check = true;
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  if (check) {
    const int failures = check_eval() + check_sample() + check_batch();
    std::printf("%s: %d failure(s)\n", failures ? "FAILED" : "aniso_bench --check passed", failures);
    return failures ? 1 : 0;
  }
  register_eval_benchmarks();
  register_sample_benchmarks();
  register_batch_benchmarks();
  register_rgl_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
