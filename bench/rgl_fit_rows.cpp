// bench/rgl_fit_rows.cpp: docs/fitting.md's "RGL tensor files" table. Each known material is
// written with export_rgl at the default grids (RGB, and the first also spectral), read back as
// data (read_measured: the file's f on its half/difference grid) and fitted with the default
// options (as `aniso fit FILE --model M`: 6 starts, --anisotropic auto, all cores); printed: the
// fitted material, the fit's relative l2cos against the samples, the source material's (the
// truth's) against the same samples, the file size and the fit's time. Not a ctest: about a
// minute of fitting.
//
//   aniso_rgl_fit_rows [DIR]   (the files are written to DIR, default the current folder)
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "aniso/fit/fit.h"
#include "aniso/io/materials.h"
#include "aniso/measured/samples.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"

namespace aniso {
namespace {

struct Row {
  const char* name;
  const char* material;  // JSON
  const char* model;     // the fitted model
  const char* normalization;
  bool spectral;
};

int run(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  const Row rows[] = {
      {"ggx_turned_rgb", R"({"model":"ggx","kd":0.1,"f0":[0.9,0.6,0.3],"alpha_x":0.08,"alpha_y":0.3,"rotation_deg":30})", "ggx",
       "ward", false},
      {"ggx_turned_spectral", R"({"model":"ggx","kd":0.1,"f0":[0.9,0.6,0.3],"alpha_x":0.08,"alpha_y":0.3,"rotation_deg":30})",
       "ggx", "ward", true},
      {"ward_turned_rgb",
       R"({"model":"ward","kd":[0.2,0.15,0.1],"ks":0.3,"alpha_x":0.05,"alpha_y":0.3,"normalization":"balanced","rotation_deg":120})",
       "ward", "balanced", false},
      {"ggx_iso_rgb", R"({"model":"ggx","kd":0.1,"f0":[0.9,0.6,0.3],"alpha":0.15})", "ggx", "ward", false},
  };
  for (const Row& r : rows) {
    const MaterialDesc desc = parse_material(nlohmann::json::parse(r.material), r.name);
    const MaterialD m = build_material<double>(desc);
    rgl::BrdfSource src = rgl::brdf_source(m);
    src.description = r.material;
    rgl::ExportOptions eo;
    eo.spectral = r.spectral;
    const std::vector<uint8_t> bytes = rgl::serialize_tensor(rgl::export_rgl(src, eo));
    const std::string path = dir + "/" + r.name + ".bsdf";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    const auto t0 = std::chrono::steady_clock::now();
    const SampleSet data = read_measured(path);
    FitOptions o;
    o.model = r.model;
    o.normalization = r.normalization;
    const FitResult f = fit_samples(data, o);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double truth = fit_errors(m, data).relative_l2cos;
    std::printf("%-20s %.1f MB  fit %s\n  relative l2cos: fit %.4f, truth %.4f; %.1f s wall (read + fit)\n", r.name,
                double(bytes.size()) / 1e6, f.material.dump().c_str(), f.errors.relative_l2cos, truth, wall);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) { return aniso::run(argc, argv); }
