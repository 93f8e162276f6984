// apps/aniso/cmd_sample.cpp: `aniso sample -m MATERIAL --wo X Y Z -n N`, N draws of the material's
// importance sampling for one viewing direction (docs/cli.md), one line
// 'wi.x wi.y wi.z weight_r weight_g weight_b pdf' each.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/io/materials.h"
#include "commands.h"
#include "io/text_input.h"
#include "stats/rng.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

// Largest count: 1e9 sample lines is ~60 GB of text (minutes).
constexpr uint64_t kMaxCount = 1'000'000'000;

// Streams N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf' in 1 MiB blocks (bounded memory).
int cmd_sample(const std::string& material, const std::vector<double>& wo_in, uint64_t count, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const auto wo = normalized_direction(Vec3d(wo_in[0], wo_in[1], wo_in[2]));
  if (!wo) throw InputError("--wo: expected a non-zero direction, got (0, 0, 0)");
  Rng rng(seed);
  std::string out;
  for (uint64_t i = 0; i < count; ++i) {
    const double uc = rng.uniform();
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    const BSDFSampleT<double> s = m.sample(*wo, uc, u);
    if (!s.valid) {
      out += "0 0 0 0 0 0 0\n";
    } else {
      out += fmt::format("{} {} {} {} {} {} {}\n", num(s.wi.x), num(s.wi.y), num(s.wi.z), num(s.weight.x), num(s.weight.y),
                         num(s.weight.z), num(s.pdf));
    }
    if (out.size() > (size_t(1) << 20)) {
      write_stdout(out);
      out.clear();
    }
  }
  write_stdout(out);
  return 0;
}

}  // namespace

void add_sample_command(CLI::App& app) {
  struct Args {
    std::string material;
    std::vector<double> wo;
    std::string count_text = "1", seed_text = "1";
  };
  auto a = std::make_shared<Args>();
  auto* sample = app.add_subcommand("sample", "write N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf'");
  sample->add_option("--material,-m", a->material, kMaterialHelp)->required();
  sample->add_option("--wo", a->wo, "viewing direction x y z (local frame; normalised)")
      ->required()
      ->expected(3)
      ->check(decimal_value());
  // --samples counts the same thing as albedo's --samples (draws of sample()); --count is kept.
  sample
      ->add_option("--count,-n,--samples", a->count_text,
                   fmt::format("number of samples (draws of sample(): output lines), 0 to {}", kMaxCount))
      ->type_name("INT")
      ->capture_default_str();
  sample->add_option("--seed", a->seed_text, "random seed, 0 to 2^64-1")->type_name("UINT64")->capture_default_str();
  sample->callback([a] {
    run_command([&] {
      return cmd_sample(a->material, a->wo, parse_unsigned(a->count_text, kMaxCount, "--count"),
                        parse_unsigned(a->seed_text, UINT64_MAX, "--seed"));
    });
  });
}

}  // namespace aniso
