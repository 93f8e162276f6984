// apps/aniso/cmd_fresnel.cpp: `aniso fresnel`, the unpolarised conductor Fresnel reflectance 'r g b'
// of a measured metal (`aniso metals`) or of a given complex index eta + i k (docs/cli.md).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/brdf/fresnel.h"
#include "aniso/data/metals.h"
#include "commands.h"

namespace aniso {
namespace {

struct FresnelArgs {
  std::string metal;
  std::vector<double> eta, k;
  double theta = 0.0;
  bool schlick = false;
};

int cmd_fresnel(const FresnelArgs& a) {
  RGBT<double> eta, k;
  if (!a.metal.empty()) {
    if (!a.eta.empty() || !a.k.empty()) throw InputError("give either --metal or --eta and --k, not both");
    const MetalData* md = find_metal(a.metal);
    if (!md) throw InputError(fmt::format("--metal: {}", unknown_metal_message(a.metal)));
    eta = md->eta;
    k = md->k;
  } else {
    if (a.eta.empty() || a.k.empty())
      throw InputError(fmt::format("give --metal NAME (one of {}) or both --eta R G B and --k R G B", metal_names()));
    for (int c = 0; c < 3; ++c) {
      if (!(a.eta[c] > 0.0 && a.eta[c] <= 100.0))
        throw InputError(fmt::format("--eta: channel {}: expected a number in (0, 100], got {}", c, a.eta[c]));
      if (!(a.k[c] >= 0.0 && a.k[c] <= 100.0))
        throw InputError(fmt::format("--k: channel {}: expected a number in [0, 100], got {}", c, a.k[c]));
      eta[c] = a.eta[c];
      k[c] = a.k[c];
    }
  }
  const double c = std::cos(a.theta * M_PI / 180.0);
  // --schlick: Schlick's approximation with the exact F0 of the same metal, for comparison.
  const RGBT<double> F = a.schlick ? F_Schlick(F_Conductor(1.0, eta, k), c) : F_Conductor(c, eta, k);
  write_stdout(fmt::format("{} {} {}\n", num(F.x), num(F.y), num(F.z)));
  return 0;
}

}  // namespace

void add_fresnel_command(CLI::App& app) {
  auto fa = std::make_shared<FresnelArgs>();
  auto* fresnel = app.add_subcommand("fresnel", "conductor Fresnel reflectance 'r g b' of a measured metal or of a given eta, k");
  fresnel->add_option("--metal", fa->metal, "metal name (`aniso metals` lists them)");
  fresnel->add_option("--eta", fa->eta, "real part of the complex index, R G B, each in (0, 100]")
      ->expected(3)
      ->check(decimal_value());
  fresnel->add_option("--k", fa->k, "extinction coefficient, R G B, each in [0, 100]")->expected(3)->check(decimal_value());
  fresnel->add_option("--theta-deg", fa->theta, "angle of incidence")->check(finite_range(0.0, 90.0))->capture_default_str();
  fresnel->add_flag("--schlick", fa->schlick, "Schlick's approximation from the metal's F0 instead of the exact equations");
  fresnel->callback([fa] { run_command([&] { return cmd_fresnel(*fa); }); });
}

}  // namespace aniso
