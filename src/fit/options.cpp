// fit/options.cpp: parse_fit_options, the options of a fit from the command line's text (fit.h).
#include "fit/options.h"

#include <cmath>

#include "aniso/fit/fit.h"
#include "io/text_escape.h"
#include "io/text_input.h"

namespace aniso {

using namespace fit_detail;

namespace {

// The model names of the presets and of Ngan 2005 / bbm, accepted by --model with a note
// (docs/presets.md: each maps onto an aniso model exactly).
struct ModelAlias {
  std::string_view alias, model, normalization, note;
};
constexpr ModelAlias kModelAliases[] = {
    {"blinnphong", "phong", "", "Ngan 2005's \"Blinn-Phong\" (bbm's NganBlinnPhong) is the mirror lobe of aniso's phong"},
    {"ashikhminshirley", "ashikhmin-shirley", "", "the Ngan 2005 preset name"},
    {"as", "ashikhmin-shirley", "", "short name"},
    {"wardduer", "ward", "duer", "Ngan 2005's Ward-Duer is ward with --normalization duer"},
    {"disney", "principled", "", "Disney's BRDF Explorer model is aniso's principled"},
};

}  // namespace

FitOptions parse_fit_options(const FitOptionText& a) {
  FitOptions o;
  o.model = a.model;
  o.normalization = a.normalization;
  for (const ModelAlias& alias : kModelAliases)
    if (alias.alias == a.model) {
      o.model = alias.model;
      std::string note = fmt::format("--model {} is read as --model {}", alias.alias, alias.model);
      if (!alias.normalization.empty()) {
        if (a.normalization != "ward" && a.normalization != alias.normalization)
          throw InputError(
              fmt::format("--model {} sets --normalization {}, not {}", alias.alias, alias.normalization, a.normalization));
        o.normalization = alias.normalization;
        note += fmt::format(" --normalization {}", alias.normalization);
      }
      o.notes.push_back(fmt::format("{}: {}", note, alias.note));
    }
  o.lobes = int(parse_integer(a.lobes, 1, kLafortuneMaxLobes, "--lobes"));
  if (a.anisotropic == "auto")
    o.anisotropy = Anisotropy::Auto;
  else if (a.anisotropic == "yes")
    o.anisotropy = Anisotropy::Yes;
  else if (a.anisotropic == "no")
    o.anisotropy = Anisotropy::No;
  else
    throw InputError(fmt::format("--anisotropic: expected auto, yes or no, got \"{}\"", a.anisotropic));
  o.allow_energy_gain = a.allow_energy_gain;
  o.shared_exponents = a.shared_exponents;
  o.metal = a.metal;
  o.metal_lobe = a.metal_lobe;
  o.fresnel = a.fresnel;
  if (a.metric == "l2cos")
    o.metric = FitMetric::L2Cos;
  else if (a.metric == "log")
    o.metric = FitMetric::Log;
  else
    throw InputError(fmt::format("--metric: expected l2cos or log, got \"{}\"", a.metric));
  o.loss = a.loss;
  const std::optional<double> scale = parse_decimal(a.loss_scale);
  if (!scale || !(*scale >= 0.0))
    throw InputError(fmt::format("--loss-scale: expected a finite decimal number >= 0, got \"{}\"", a.loss_scale));
  o.loss_scale = *scale;
  o.starts = int(parse_integer(a.starts, 1, 1000, "--starts"));
  o.seed = parse_unsigned(a.seed, UINT64_MAX, "--seed");
  o.threads = int(parse_integer(a.threads, 0, 256, "--threads"));
  o.max_iterations = int(parse_integer(a.max_iterations, 1, 100000, "--max-iterations"));
  const std::optional<double> theta = parse_decimal(a.max_theta);
  if (!theta || !(*theta > 0.0 && *theta <= 90.0))
    throw InputError(fmt::format("--max-theta: expected degrees in (0, 90], got \"{}\"", text_escape(a.max_theta)));
  o.max_theta_deg = *theta;
  return o;
}

}  // namespace aniso
