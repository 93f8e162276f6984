// aniso: the command-line tool. Scripting commands (exact formats; other tools and tests depend on
// them, docs/cli.md): eval, sample, albedo, fresnel; and presets, models for discovery.
// Numbers are computed in double precision and printed with 9 significant digits.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "data/metals.h"
#include "io/materials.h"
#include "io/presets.h"
#include "stats/albedo.h"
#include "stats/rng.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

Vec3d normalized_or_throw(const Vec3d& v, const std::string& what) {
  const double len = glm::length(v);
  if (!std::isfinite(len) || !(len > 0.0))
    throw InputError(fmt::format("{}: expected a non-zero, finite direction, got ({}, {}, {})", what, v.x, v.y, v.z));
  return v / len;
}

std::string num(double x) { return fmt::format("{:.9g}", x); }

// Reads "wi.x wi.y wi.z wo.x wo.y wo.z" lines; all lines are checked before anything is printed,
// so a bad line leaves no half-written output.
int cmd_eval(const std::string& material) {
  const Mat m = build_material<double>(load_material(material));
  std::string out, line;
  size_t line_no = 0;
  while (std::getline(std::cin, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;  // blank lines and comments
    std::istringstream in(line);
    double v[6];
    for (int i = 0; i < 6; ++i) {
      std::string tok;
      if (!(in >> tok))
        throw InputError(fmt::format("stdin line {}: expected 6 numbers (wi.x wi.y wi.z wo.x wo.y wo.z), got {}",
                                     line_no, i));
      try {
        size_t used = 0;
        v[i] = std::stod(tok, &used);
        if (used != tok.size() || !std::isfinite(v[i])) throw std::invalid_argument(tok);
      } catch (const std::exception&) {
        throw InputError(fmt::format("stdin line {}: field {}: expected a finite number, got \"{}\"", line_no, i + 1, tok));
      }
    }
    std::string extra;
    if (in >> extra) throw InputError(fmt::format("stdin line {}: expected 6 numbers, got more (\"{}\")", line_no, extra));
    const Vec3d wi = normalized_or_throw(Vec3d(v[0], v[1], v[2]), fmt::format("stdin line {}: wi", line_no));
    const Vec3d wo = normalized_or_throw(Vec3d(v[3], v[4], v[5]), fmt::format("stdin line {}: wo", line_no));
    const RGBT<double> f = m.f(wi, wo);
    out += fmt::format("{} {} {} {}\n", num(f.x), num(f.y), num(f.z), num(m.pdf(wi, wo)));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

int cmd_sample(const std::string& material, const std::vector<double>& wo_in, int64_t count, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const Vec3d wo = normalized_or_throw(Vec3d(wo_in[0], wo_in[1], wo_in[2]), "--wo");
  Rng rng(seed);
  std::string out;
  for (int64_t i = 0; i < count; ++i) {
    const double uc = rng.uniform();
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    const BSDFSampleT<double> s = m.sample(wo, uc, u);
    if (!s.valid) {
      out += "0 0 0 0 0 0 0\n";
      continue;
    }
    out += fmt::format("{} {} {} {} {} {} {}\n", num(s.wi.x), num(s.wi.y), num(s.wi.z), num(s.weight.x),
                       num(s.weight.y), num(s.weight.z), num(s.pdf));
    if (out.size() > (1u << 20)) {
      std::fwrite(out.data(), 1, out.size(), stdout);
      out.clear();
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

Vec3d direction_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

int cmd_albedo(const std::string& material, double theta, double phi, int64_t samples, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const AlbedoEstimate a = albedo_importance(m, direction_deg(theta, phi), samples, seed);
  fmt::print("{} {} {}\n", num(a.mean.x), num(a.mean.y), num(a.mean.z));
  return 0;
}

int cmd_fresnel(const std::string& metal, double theta, bool schlick) {
  const MetalData* md = find_metal(metal);
  if (!md) throw InputError(fmt::format("--metal: unknown metal \"{}\"; expected one of {}", metal, metal_names()));
  const double c = std::cos(theta * M_PI / 180.0);
  const RGBT<double> eta(md->eta), k(md->k);
  // --schlick: Schlick's approximation with the exact F0 of the same metal, for comparison.
  const RGBT<double> F = schlick ? F_Schlick(F_Conductor(1.0, eta, k), c) : F_Conductor(c, eta, k);
  fmt::print("{} {} {}\n", num(F.x), num(F.y), num(F.z));
  return 0;
}

int cmd_presets(const std::string& show) {
  if (!show.empty()) {
    const auto p = find_preset(show);
    if (!p) throw InputError(fmt::format("--show: unknown preset \"{}\" (run `aniso presets` for the list)", show));
    fmt::print("{}\n", p->dump(2));
    return 0;
  }
  for (const PresetInfo& p : presets()) fmt::print("{:<40} {}\n", p.name, p.source);
  return 0;
}

int cmd_models(bool markdown, const std::string& only) {
  if (!only.empty() && !find_model_spec(only)) {
    std::string names;
    for (const ModelSpec* m : model_specs()) names += fmt::format(" {}", m->name);
    throw InputError(fmt::format("--model: unknown model \"{}\"; expected one of{}", only, names));
  }
  if (markdown) {
    for (const ModelSpec* m : model_specs())
      if (only.empty() || m->name == only) fmt::print("{}\n", markdown_table(*m));
    return 0;
  }
  for (const ModelSpec* m : model_specs()) {
    if (!only.empty() && m->name != only) continue;
    fmt::print("{} ({}) -- {}\n", m->name, m->title, m->citation);
    for (const ParamSpec* p : m->params()) {
      fmt::print("  {:<20} {:<55} {}{}\n", p->name, describe_range(*p), p->doc, p->required ? " [required]" : "");
    }
  }
  return 0;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) {
  using namespace aniso;
  CLI::App app{"aniso: anisotropic and measured reflectance (models, sampling, metals)"};
  app.require_subcommand(1);

  std::string material;
  auto* eval = app.add_subcommand("eval", "read 'wi.x wi.y wi.z wo.x wo.y wo.z' lines on stdin, write 'f_r f_g f_b pdf'");
  eval->add_option("--material,-m", material, "preset name or JSON file")->required();

  std::vector<double> wo;
  int64_t count = 1;
  uint64_t seed = 1;
  auto* sample = app.add_subcommand("sample", "write N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf'");
  sample->add_option("--material,-m", material, "preset name or JSON file")->required();
  sample->add_option("--wo", wo, "viewing direction x y z (local frame)")->required()->expected(3);
  sample->add_option("--count,-n", count, "number of samples")->check(CLI::Range(int64_t(0), int64_t(1) << 40));
  sample->add_option("--seed", seed, "random seed");

  double theta = 0.0, phi = 0.0;
  int64_t samples = 1 << 20;
  auto* albedo = app.add_subcommand("albedo", "directional albedo 'r g b' for the viewing direction (theta, phi)");
  albedo->add_option("--material,-m", material, "preset name or JSON file")->required();
  albedo->add_option("--theta-deg", theta, "viewing angle from the normal")->required()->check(CLI::Range(0.0, 90.0));
  albedo->add_option("--phi-deg", phi, "azimuth from the tangent")->check(CLI::Range(-360.0, 360.0));
  albedo->add_option("--samples", samples, "importance samples")->check(CLI::Range(int64_t(1), int64_t(1) << 34));
  albedo->add_option("--seed", seed, "random seed");

  std::string metal;
  auto* fresnel = app.add_subcommand("fresnel", "conductor Fresnel reflectance 'r g b' of a measured metal");
  fresnel->add_option("--metal", metal, "metal name (aniso presets lists them)")->required();
  fresnel->add_option("--theta-deg", theta, "angle of incidence")->check(CLI::Range(0.0, 90.0));
  bool schlick = false;
  fresnel->add_flag("--schlick", schlick, "Schlick's approximation from the metal's F0 instead of the exact equations");

  std::string show;
  auto* presets_cmd = app.add_subcommand("presets", "list the named materials");
  presets_cmd->add_option("--show", show, "print one preset's JSON");

  auto* models = app.add_subcommand("models", "list the models and their parameter tables");
  bool markdown = false;
  std::string only_model;
  models->add_flag("--markdown", markdown, "print the tables as markdown (as docs/models/*.md quote them)");
  models->add_option("--model", only_model, "only this model");

  // An unknown command would otherwise be reported by CLI11 as "A subcommand is required".
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names += fmt::format(" {}", sub->get_name());
      known = known || sub->check_name(argv[1]);
    }
    if (!known) {
      fmt::print(stderr, "aniso: error: unknown command \"{}\"; expected one of{}\n", argv[1], names);
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help); every command-line error exits 2, like input errors.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (eval->parsed()) return cmd_eval(material);
    if (sample->parsed()) return cmd_sample(material, wo, count, seed);
    if (albedo->parsed()) return cmd_albedo(material, theta, phi, samples, seed);
    if (fresnel->parsed()) return cmd_fresnel(metal, theta, schlick);
    if (presets_cmd->parsed()) return cmd_presets(show);
    if (models->parsed()) return cmd_models(markdown, only_model);
  } catch (const InputError& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    return 2;
  }
  return 1;
}
