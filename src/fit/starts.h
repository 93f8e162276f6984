// fit/starts.h (private): the starts of a fit (moments, Ngan 2005's nearest preset, a caller's
// start; the separable grid start is separable.h's) and a start's solution.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/io/presets.h"
#include "fit/costs.h"

namespace aniso::fit_detail {

// The statistics of the data the starts are built from (models.h, DataMoments; starts.cpp).
DataMoments data_moments(const SampleSet& data);

struct StartPoint {
  std::string name;
  std::vector<double> x;
};

// The Ngan 2005 preset of `ngan_model` nearest to the data: the smallest l2cos error on (up to 4096
// of) the samples.
template <class Model>
std::optional<StartPoint> nearest_ngan_start(const Model& model, const std::vector<Prepared>& prep, const DataMoments& dm) {
  const std::string prefix = fmt::format("ngan/{}/", model.ngan_model());
  const size_t stride = std::max<size_t>(1, prep.size() / 4096);
  double best = INFINITY;
  const PresetInfo* best_preset = nullptr;
  for (const PresetInfo& p : presets()) {
    if (p.name.rfind(prefix, 0) != 0) continue;
    const MaterialD m = build_material<double>(parse_material(p.json, p.name));
    double e = 0.0;
    for (size_t i = 0; i < prep.size(); i += stride) {
      const Prepared& s = prep[i];
      const RGBT<double> f = m.f(s.wi, s.wo);
      for (int c = 0; c < 3; ++c) e += sqr(f[c] * s.wi.z - s.target[c]);  // l2cos on the cosine-weighted target
    }
    if (e < best) best = e, best_preset = &p;
  }
  if (!best_preset) return std::nullopt;
  auto x = model.from_preset(parse_material(best_preset->json, best_preset->name), dm);
  if (!x) return std::nullopt;
  return StartPoint{fmt::format("ngan2005 {}", best_preset->name.substr(prefix.size())), *x};
}

// FitOptions::start as a start of this model's parameters (nullopt when none is given).
template <class Model> std::optional<StartPoint> given_start(const Model& model, const DataMoments& dm, const FitOptions& o) {
  if (o.start.empty()) return std::nullopt;
  const auto index = [&](std::string_view name) {
    for (size_t i = 0; i < model.defs.size(); ++i)
      if (model.defs[i].name == name) return int(i);
    return -1;
  };
  std::vector<double> x = model.moment_start(dm);
  std::vector<std::pair<int, double>> pairs;  // the isotropic parameter and one of its pair's values
  for (const auto& [name, value] : o.start) {
    if (!std::isfinite(value)) throw InputError(fmt::format("the fit's start: {} = {} is not a finite number", name, value));
    if (const int i = index(name); i >= 0) {
      x[size_t(i)] = value;
      continue;
    }
    const std::string_view n = name;
    const bool xy = n.size() > 2 && (n.ends_with("_x") || n.ends_with("_y") || n.ends_with("_u") || n.ends_with("_v"));
    if (xy && index(n.substr(0, n.size() - 2)) >= 0) {
      pairs.emplace_back(index(n.substr(0, n.size() - 2)), value);
      continue;
    }
    if (name == "rotation_deg" && model.rotation_index() < 0) continue;  // an isotropic fit has no orientation
    std::string names;
    for (const ParamDef& d : model.defs) names += fmt::format("{}{}", names.empty() ? "" : ", ", d.name);
    throw InputError(fmt::format("the fit's start: \"{}\" is not a parameter of this fit (its parameters: {})", name, names));
  }
  for (size_t i = 0; i < model.defs.size(); ++i) {
    double log_sum = 0.0;
    int count = 0;
    for (const auto& [k, v] : pairs)
      if (size_t(k) == i) log_sum += std::log(std::max(v, 1e-300)), ++count;
    if (count > 0) x[i] = std::exp(log_sum / count);
  }
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], model.defs[i].lo, model.defs[i].hi);
  return StartPoint{"given", x};
}

struct Solved {
  std::vector<double> x;
  double cost = INFINITY;
  int iterations = 0;
  std::string termination;
};

}  // namespace aniso::fit_detail
