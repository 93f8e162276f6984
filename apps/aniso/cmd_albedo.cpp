// apps/aniso/cmd_albedo.cpp: `aniso albedo -m MATERIAL --theta-deg T`, the directional albedo
// 'r g b' for one viewing direction by the material's importance sampling (docs/cli.md).
#include <cstdint>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "aniso/io/materials.h"
#include "aniso/stats/albedo.h"
#include "commands.h"
#include "io/text_input.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

// Largest count: 1e9 albedo samples ~1 minute.
constexpr uint64_t kMaxSamples = 1'000'000'000;

int cmd_albedo(const std::string& material, double theta, double phi, uint64_t samples, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  // theta = 90 is on the horizon (cos rounds to 6e-17 < the double horizon cosine 1e-12): albedo 0
  // (docs/conventions.md, "The horizon").
  const AlbedoEstimate a = albedo_importance(m, direction_from_degrees(theta, phi), int64_t(samples), seed);
  write_stdout(fmt::format("{} {} {}\n", num(a.mean.x), num(a.mean.y), num(a.mean.z)));
  return 0;
}

}  // namespace

void add_albedo_command(CLI::App& app) {
  struct Args {
    std::string material;
    double theta = 0.0, phi = 0.0;
    std::string samples_text = "1048576", seed_text = "1";
  };
  auto a = std::make_shared<Args>();
  auto* albedo = app.add_subcommand("albedo", "directional albedo 'r g b' for the viewing direction (theta, phi)");
  albedo->add_option("--material,-m", a->material, kMaterialHelp)->required();
  albedo->add_option("--theta-deg", a->theta, "viewing angle from the normal; 90 is the horizon (albedo 0)")
      ->required()
      ->check(finite_range(0.0, 90.0));
  albedo->add_option("--phi-deg", a->phi, "azimuth from the tangent")->check(finite_range(-360.0, 360.0))->capture_default_str();
  albedo->add_option("--samples", a->samples_text, fmt::format("importance samples, 1 to {}", kMaxSamples))
      ->type_name("INT")
      ->capture_default_str();
  albedo->add_option("--seed", a->seed_text, "random seed, 0 to 2^64-1")->type_name("UINT64")->capture_default_str();
  albedo->callback([a] {
    run_command([&] {
      const uint64_t n = parse_unsigned(a->samples_text, kMaxSamples, "--samples");
      if (n == 0) throw InputError(fmt::format("--samples: expected a whole number in [1, {}], got 0", kMaxSamples));
      return cmd_albedo(a->material, a->theta, a->phi, n, parse_unsigned(a->seed_text, UINT64_MAX, "--seed"));
    });
  });
}

}  // namespace aniso
