// apps/aniso/cmd_metals.cpp: `aniso metals`, the measured metals' table: RGB eta, k, the F0 they
// give and the data source (src/data/metals.cpp, docs/cli.md).
#include <string>

#include <fmt/format.h>

#include "aniso/brdf/fresnel.h"
#include "aniso/data/metals.h"
#include "commands.h"

namespace aniso {
namespace {

int cmd_metals() {
  std::string out =
      fmt::format("{:<10} {:<4} {:<32} {:<32} {:<32} {}\n", "# name", "sym", "eta (r g b)", "k (r g b)", "F0 (r g b)", "source");
  for (const MetalData& md : metal_table()) {
    const RGBT<double> f0 = F_Conductor(1.0, RGBT<double>(md.eta), RGBT<double>(md.k));
    const auto rgb = [](const glm::dvec3& v) { return fmt::format("{:.4f} {:.4f} {:.4f}", v.x, v.y, v.z); };
    out += fmt::format("{:<10} {:<4} {:<32} {:<32} {:<32} {}\n", md.name, md.symbol, rgb(md.eta), rgb(md.k), rgb(f0), md.source);
  }
  write_stdout(out);
  return 0;
}

}  // namespace

void add_metals_command(CLI::App& app) {
  auto* metals_cmd = app.add_subcommand("metals", "list the measured metals: RGB eta, k, F0 and the data source");
  metals_cmd->callback([] { run_command([] { return cmd_metals(); }); });
}

}  // namespace aniso
