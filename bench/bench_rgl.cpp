// bench/bench_rgl.cpp: an RGL tensor file read back (RglT, pbrt-v4's MeasuredBxDF: docs/rgl.md)
// against nothing but itself: f, pdf and sample per call, single thread, float, on the bench's
// directions (bench_eval.cpp), for the materials of docs/rgl.md's "Speed" table; the analytic
// models' rows are bench_eval.cpp's f/... benchmarks. Each file is written (RGB, default grids)
// the first time one of its benchmarks runs, outside the timed loop: a filter that skips them
// costs nothing.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/rgl/tensor.h"
#include "bench_common.h"
#include "stats/rng.h"

using namespace aniso;

namespace {

// The benchmarked materials: name and material (preset name or inline JSON), docs/rgl.md's rows.
const std::vector<std::pair<std::string, std::string>>& rgl_materials() {
  static const std::vector<std::pair<std::string, std::string>> m = {
      {"gold", "gold"},
      {"matte-steel", "matte-steel"},
      {"brushed-gold", "brushed-gold"},
      {"ward-aniso",
       R"({"model":"ward","kd":0.1,"ks":0.3,"alpha_x":0.05,"alpha_y":0.3,"form":"approx","normalization":"balanced"})"}};
  return m;
}

// The file of one material, written once and read back as `aniso eval --material file.bsdf` reads it.
const rgl::RglData& rgl_file(const std::string& spec) {
  static std::map<std::string, std::shared_ptr<rgl::RglData>> files;
  auto it = files.find(spec);
  if (it == files.end()) {
    const MaterialDesc desc = load_material(spec);
    const MetalData* metal = desc.model == "metal" && desc.params.has("metal") ? find_metal(desc.params.text("metal")) : nullptr;
    rgl::ExportOptions opt;
    opt.spectral = false;
    const std::vector<uint8_t> bytes =
        rgl::serialize_tensor(rgl::export_rgl(rgl::brdf_source(build_material<double>(desc), metal), opt));
    it = files.emplace(spec, rgl::rgl_from_tensor(rgl::parse_tensor(bytes, spec + ".bsdf"))).first;
  }
  return *it->second;
}

enum class What { F, Pdf, Sample };

void bm_rgl(benchmark::State& state, const std::string& spec, What what) {
  const RglT<float> k = rgl::rgl_kernel<float>(rgl_file(spec));
  const auto wi = bench_wi(), wo = bench_wo();
  Rng rng(5);
  std::vector<float> u(2 * wo.size());
  for (float& x : u) x = rng.uniform_as<float>();
  size_t i = 0;
  for (auto _ : state) {
    if (what == What::F)
      benchmark::DoNotOptimize(k.f(wi[i], wo[i]));
    else if (what == What::Pdf)
      benchmark::DoNotOptimize(k.pdf(wi[i], wo[i]));
    else
      benchmark::DoNotOptimize(k.sample(wo[i], 0.5f, Vec2(u[2 * i], u[2 * i + 1])));
    i = i + 1 == wo.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

void register_rgl_benchmarks() {
  for (const auto& [name, spec] : rgl_materials())
    for (const auto& [label, what] : {std::pair{"f", What::F}, std::pair{"pdf", What::Pdf}, std::pair{"sample", What::Sample}})
      benchmark::RegisterBenchmark((std::string("rgl/") + label + "/" + name).c_str(),
                                   [spec = spec, what = what](benchmark::State& s) { bm_rgl(s, spec, what); });
}
