// examples/cpp/fit.cpp: fitting a model to measured samples from C++ (CMake aniso::fit).
//
// The samples here are "measured" from a known anisotropic Ward material (turned by 30 degrees)
// with 1% multiplicative noise, on a grid of incident and viewing directions; fit_samples
// (include/aniso/fit/fit.h, docs/fitting.md) fits the Ward model to them and must recover the
// material's parameters: alpha_x and alpha_y within 3%, rotation_deg within 1 degree, kd and ks
// within 0.02. Real data come from a file instead: aniso::read_measured(path) reads a CSV of
// samples, a Cornell .brdf file or a MERL .binary table into the same SampleSet
// (include/aniso/measured/samples.h). Exit status 1 when a parameter is not recovered.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include <aniso/fit/fit.h>
#include <aniso/io/materials.h>
#include <aniso/measured/samples.h>

int main() {
  // The material that made the data, as JSON (the fit returns its result in the same form).
  const char* truth_json =
      R"({"model": "ward", "kd": [0.1, 0.08, 0.05], "ks": [0.5, 0.4, 0.3], "alpha_x": 0.08, "alpha_y": 0.25,
          "rotation_deg": 30})";
  const aniso::MaterialDesc truth_desc = aniso::load_material(truth_json);
  const aniso::MaterialD truth = aniso::build_material<double>(truth_desc);

  // A SampleSet: directions in the local frame (z = normal, x = tangent), value = f(wi, wo) in 1/sr
  // without the cosine, weight 1. Incidence and view 10 to 70 degrees, azimuths every 30 degrees:
  // half vectors at every azimuth, which an anisotropic fit needs (docs/fitting.md, "Anisotropy").
  aniso::SampleSet data;
  data.source = "synthetic ward";
  data.format = "synthetic";
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  const auto radians = [](int degrees) { return degrees * std::numbers::pi / 180.0; };
  for (int theta_i = 10; theta_i <= 70; theta_i += 15)
    for (int phi_i = 0; phi_i < 360; phi_i += 30)
      for (int theta_o = 10; theta_o <= 70; theta_o += 15)
        for (int phi_o = 0; phi_o < 360; phi_o += 30) {
          aniso::MeasuredSample s;
          s.wi = aniso::direction_from_angles(radians(theta_i), radians(phi_i));
          s.wo = aniso::direction_from_angles(radians(theta_o), radians(phi_o));
          s.value = glm::dvec3(truth.f(s.wi, s.wo)) * (1.0 + noise(rng));
          data.samples.push_back(s);
        }

  // The options of `aniso fit --model ward --anisotropic yes --normalization ward` (FitOptions
  // holds every one of them; parse_fit_options reads them from text as the CLI does).
  aniso::FitOptions options;
  options.model = "ward";
  options.normalization = "ward";
  options.anisotropy = aniso::Anisotropy::Yes;
  options.seed = 1;  // the same input and options give the same fit, on any number of threads

  const aniso::FitResult result = aniso::fit_samples(data, options);

  // result.material is a valid material (load_material / parse_material accept it), in the
  // canonical orientation: rotation_deg in [0, 180) and alpha_x <= alpha_y.
  std::printf("%zu samples, best start \"%s\", %d iterations, %.2f s\n", data.samples.size(), result.best_start.c_str(),
              result.iterations, result.seconds);
  std::printf("fitted: %s\n", result.material.dump().c_str());
  std::printf("relative l2cos error %.4f\n", result.errors.relative_l2cos);

  int failures = 0;
  const auto expect = [&](const char* key, double got, double want, double tolerance) {
    const bool ok = std::abs(got - want) <= tolerance;
    std::printf("  %-14s fitted %9.5f  true %9.5f  %s\n", key, got, want, ok ? "ok" : "MISMATCH");
    failures += ok ? 0 : 1;
  };
  const nlohmann::json& m = result.material;
  expect("alpha_x", m["alpha_x"].get<double>(), 0.08, 0.03 * 0.08);
  expect("alpha_y", m["alpha_y"].get<double>(), 0.25, 0.03 * 0.25);
  expect("rotation_deg", m["rotation_deg"].get<double>(), 30.0, 1.0);
  // Colours are written as one number when grey, else [r, g, b].
  const auto channel = [](const nlohmann::json& c, int i) { return c.is_array() ? c[i].get<double>() : c.get<double>(); };
  const double kd[3] = {0.1, 0.08, 0.05}, ks[3] = {0.5, 0.4, 0.3};
  for (int c = 0; c < 3; ++c) {
    expect(("kd[" + std::to_string(c) + "]").c_str(), channel(m["kd"], c), kd[c], 0.02);
    expect(("ks[" + std::to_string(c) + "]").c_str(), channel(m["ks"], c), ks[c], 0.02);
  }

  // The fitted material as a kernel value, like any other material.
  const aniso::MaterialD fitted = aniso::build_material<double>(aniso::parse_material(result.material, "fitted"));
  const aniso::Vec3d wi = aniso::direction_from_angles(0.5, 0.3), wo = aniso::direction_from_angles(0.6, 3.3);
  std::printf("f at one pair: fitted %.5f, true %.5f (green)\n", fitted.f(wi, wo).y, truth.f(wi, wo).y);
  return failures ? 1 : 0;
}
