// fit/models.cpp: parameter layouts, bounds, materials and starts of every fitted model (models.h).
// The random ranges and the moment formulas are listed in docs/fitting.md ("Starts").
#include "fit/models.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "io/enum_names.h"

namespace aniso::fit_detail {
namespace {

constexpr double kPiD = 3.14159265358979323846;

double uniform(Rng& rng, double lo, double hi) { return lo + (hi - lo) * rng.uniform(); }
double log_uniform(Rng& rng, double lo, double hi) { return std::exp(uniform(rng, std::log(lo), std::log(hi))); }

Json rgb_json(const double* x) {
  if (x[0] == x[1] && x[1] == x[2]) return x[0] + 0.0;
  return Json::array({x[0] + 0.0, x[1] + 0.0, x[2] + 0.0});
}

// Roughness alpha of a Gaussian / GGX lobe whose width matches a cosine lobe of exponent n about
// the mirror direction: (cos a)^n ~ exp(-n a^2 / 2) against exp(-tan^2 theta_h / alpha^2) with
// theta_h ~ a / 2, so alpha^2 ~ 8 / n... a start, not a conversion; clamped to the table's range.
double alpha_from_exponent(double n) { return std::clamp(std::sqrt(8.0 / std::max(n, 1.0)) / 2.0, 0.01, 0.8); }

const ModelSpec& spec(std::string_view name) { return *find_model_spec(name); }

void clamp_into(std::vector<double>& x, const std::vector<ParamDef>& defs) {
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], defs[i].lo, defs[i].hi);
}

}  // namespace

ParamDef table_def(const ModelSpec& s, std::string_view key, std::string name) {
  const ParamSpec* p = s.find(key);
  return {std::move(name), p->min, p->max};
}

// --- Lafortune ---------------------------------------------------------------------------------

LafortuneFit::LafortuneFit(int lobes, bool anisotropic, bool shared_exponents)
    : lobes_(lobes),
      anisotropic_(anisotropic),
      shared_(shared_exponents),
      stride_((anisotropic ? 9 : 6) + (shared_exponents ? 1 : 3)) {
  const ModelSpec& lobe = lafortune_lobe_spec();
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("lafortune"), "rho_d", fmt::format("rho_d.{}", ch[c])));
  for (int k = 0; k < lobes; ++k) {
    for (int c = 0; c < 3; ++c)
      defs.push_back(table_def(lobe, "cx", fmt::format("lobe{}.{}.{}", k, anisotropic ? "cx" : "cxy", ch[c])));
    if (anisotropic)
      for (int c = 0; c < 3; ++c) defs.push_back(table_def(lobe, "cy", fmt::format("lobe{}.cy.{}", k, ch[c])));
    for (int c = 0; c < 3; ++c) defs.push_back(table_def(lobe, "cz", fmt::format("lobe{}.cz.{}", k, ch[c])));
    if (shared_exponents)
      defs.push_back(table_def(lobe, "n", fmt::format("lobe{}.n", k)));
    else
      for (int c = 0; c < 3; ++c) defs.push_back(table_def(lobe, "n", fmt::format("lobe{}.n.{}", k, ch[c])));
  }
  if (anisotropic) {
    for (int k = 0; k < lobes; ++k)
      for (int c = 0; c < 3; ++c) aniso_.push_back(cy(k, c));
    add_rotation(defs);
  }
}

void LafortuneFit::canonicalize(double* x) const {
  // The lobes are interchangeable (f is their sum): the sharpest first, by the mean exponent over
  // the channels, so that the same material is written the same way whichever start found it.
  std::vector<int> order(static_cast<size_t>(lobes_));
  for (int k = 0; k < lobes_; ++k) order[size_t(k)] = k;
  const auto mean_n = [&](int k) { return (x[n(k, 0)] + x[n(k, 1)] + x[n(k, 2)]) / 3.0; };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return mean_n(a) > mean_n(b); });
  std::vector<double> lobes(x + base(0), x + base(0) + size_t(lobes_ * stride_));
  for (int k = 0; k < lobes_; ++k) std::copy_n(lobes.begin() + long(order[size_t(k)] * stride_), stride_, x + base(k));
  if (!anisotropic_) return;
  double sx = 0.0, sy = 0.0;
  for (int k = 0; k < lobes_; ++k)
    for (int c = 0; c < 3; ++c) sx += std::abs(x[cx(k, c)]), sy += std::abs(x[cy(k, c)]);
  const bool swap = sx < sy;
  if (swap)
    for (int k = 0; k < lobes_; ++k)
      for (int c = 0; c < 3; ++c) std::swap(x[cx(k, c)], x[cy(k, c)]);
  canonical_angle(x, swap);
}

Json LafortuneFit::to_json(const double* x) const {
  Json lobes = Json::array();
  for (int k = 0; k < lobes_; ++k) {
    double cxv[3], cyv[3], czv[3], nv[3];
    for (int c = 0; c < 3; ++c) cxv[c] = x[cx(k, c)], cyv[c] = x[cy(k, c)], czv[c] = x[cz(k, c)], nv[c] = x[n(k, c)];
    lobes.push_back({{"cx", rgb_json(cxv)}, {"cy", rgb_json(cyv)}, {"cz", rgb_json(czv)}, {"n", rgb_json(nv)}, {"scale", 1.0}});
  }
  return {{"model", "lafortune"}, {"rho_d", rgb_json(x)}, {"lobes", lobes}};
}

// Lobe k of the moment start: the data's mirror exponent for lobe 0, each further lobe four times
// broader and 0.3 times as high, all about the mirror direction (C = (-s, -s, s)): s^n is the
// lobe's peak, the data's peak above the floor.
std::vector<double> LafortuneFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[rho(c)] = d.floor_albedo[c];
  for (int k = 0; k < lobes_; ++k) {
    const double nk = std::max(1.0, d.mirror_exponent / std::pow(4.0, k));
    for (int c = 0; c < 3; ++c) {
      const double peak = std::max(d.peak[c] * std::pow(0.3, k), 1e-6);
      const double s = std::pow(peak, 1.0 / nk);
      x[cx(k, c)] = -s;
      x[cy(k, c)] = -s;
      x[cz(k, c)] = s;
      x[n(k, c)] = nk;
    }
  }
  clamp_into(x, defs);
  return x;
}

// Ngan's one-lobe fit as lobe 0 (its scale folded into C: scale base^n = (scale^(1/n) base)^n, so
// the fitted lobes keep scale 1 as pbrt-v1's do), the moment start's lobes after it.
std::optional<std::vector<double>> LafortuneFit::from_preset(const MaterialDesc& desc, const DataMoments& m) const {
  std::vector<double> x = moment_start(m);
  const ParamValues& p = desc.params;
  const ParamValues& l = p.list("lobes")[0];
  for (int c = 0; c < 3; ++c) {
    x[rho(c)] = p.color("rho_d")[c];
    const double nn = std::max(l.color("n")[c], 1e-3);
    const double f = std::pow(std::max(l.color("scale")[c], 1e-300), 1.0 / nn);
    x[cx(0, c)] = l.color("cx")[c] * f;
    x[cy(0, c)] = l.color("cy")[c] * f;
    x[cz(0, c)] = l.color("cz")[c] * f;
    x[n(0, c)] = nn;  // shared exponents: the last channel's (Ngan's are grey)
  }
  clamp_into(x, defs);
  return x;
}

std::vector<double> LafortuneFit::random_start(Rng& rng, const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[rho(c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  for (int k = 0; k < lobes_; ++k) {
    const double nk = log_uniform(rng, 1.0, 500.0);
    const bool retro = k > 0 && rng.uniform() < 0.2;  // a lobe towards the light (C_xy > 0)
    const double xy = uniform(rng, 0.9, 1.1), z = uniform(rng, 0.6, 1.1), aniso = uniform(rng, 0.8, 1.25);
    for (int c = 0; c < 3; ++c) {
      const double s = std::pow(std::max(d.peak[c], 1e-6) * uniform(rng, 0.1, 1.0), 1.0 / nk);
      x[cx(k, c)] = (retro ? s : -s) * xy;
      x[cy(k, c)] = x[cx(k, c)] * (anisotropic_ ? aniso : 1.0);
      x[cz(k, c)] = s * z;
      x[n(k, c)] = nk;
    }
  }
  clamp_into(x, defs);
  return x;
}

// --- Metal -------------------------------------------------------------------------------------

MetalFit::MetalFit(bool anisotropic, const std::string& metal, SpecularLobeKind lobe)
    : anisotropic_(anisotropic), named_(!metal.empty()), metal_(metal), lobe_(lobe) {
  const char* ch = "rgb";
  if (named_) {
    const MetalData* md = find_metal(metal);
    if (!md) throw InputError(fmt::format("--metal: {}", unknown_metal_message(metal)));
    eta_ = md->eta;
    k_ = md->k;
  } else {
    // eta is in (0, 100] in the table; 1e-3 keeps the bound closed (Ceres' bounds are inclusive)
    // and is below every measured metal's (silver's 0.05 is the smallest in docs/metals.md).
    for (int c = 0; c < 3; ++c) {
      ParamDef d = table_def(spec("metal"), "eta", fmt::format("eta.{}", ch[c]));
      d.lo = 1e-3;
      defs.push_back(d);
    }
    for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("metal"), "k", fmt::format("k.{}", ch[c])));
  }
  const ModelSpec& ls = metal_lobe_spec(enum_name(lobe));
  const bool as = lobe == SpecularLobeKind::AshikhminShirley;
  defs.push_back(table_def(ls, as ? "n_u" : "alpha_x", anisotropic ? (as ? "n_u" : "alpha_x") : (as ? "n" : "alpha")));
  if (anisotropic) {
    aniso_.push_back(int(defs.size()));
    defs.push_back(table_def(ls, as ? "n_v" : "alpha_y", as ? "n_v" : "alpha_y"));
    add_rotation(defs);
  }
}

void MetalFit::canonicalize(double* x) const {
  if (!anisotropic_) return;
  const int i = named_ ? 0 : 6;
  // The narrower direction along the tangent: the smaller alpha, or the larger AS exponent.
  const bool swap = lobe_ == SpecularLobeKind::AshikhminShirley ? x[i] < x[i + 1] : x[i] > x[i + 1];
  if (swap) std::swap(x[i], x[i + 1]);
  canonical_angle(x, swap);
}

Json MetalFit::to_json(const double* x) const {
  Json out = {{"model", "metal"}};
  int i = 0;
  if (named_) {
    out["metal"] = metal_;
  } else {
    out["eta"] = rgb_json(x);
    out["k"] = rgb_json(x + 3);
    i = 6;
  }
  const double a = x[i], b = x[anisotropic_ ? i + 1 : i];
  if (lobe_ == SpecularLobeKind::AshikhminShirley)
    out["lobe"] = {{"model", "ashikhmin-shirley"}, {"n_u", a}, {"n_v", b}};
  else if (lobe_ == SpecularLobeKind::Ward)
    out["lobe"] = {{"model", "ward"}, {"alpha_x", a}, {"alpha_y", b}, {"form", "vector"}, {"normalization", "ward"}};
  else
    out["lobe"] = {{"model", "ggx"}, {"alpha_x", a}, {"alpha_y", b}};
  return out;
}

// eta, k of a grey mirror-like metal with F0 ~ 0.9 (aluminium-like: eta 1.2, k 7) as the start.
std::vector<double> MetalFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  int i = 0;
  if (!named_) {
    for (int c = 0; c < 3; ++c) x[c] = 1.2, x[3 + c] = 7.0;
    i = 6;
  }
  const double v = lobe_ == SpecularLobeKind::AshikhminShirley ? 4.0 * d.mirror_exponent : alpha_from_exponent(d.mirror_exponent);
  x[i] = v;
  if (anisotropic_) x[i + 1] = v;
  clamp_into(x, defs);
  return x;
}

std::optional<std::vector<double>> MetalFit::from_preset(const MaterialDesc& desc, const DataMoments& m) const {
  std::vector<double> x = moment_start(m);
  const int i = named_ ? 0 : 6;
  const ParamValues& p = desc.params;
  const bool as = lobe_ == SpecularLobeKind::AshikhminShirley;
  x[i] = p.scalar(as ? "n_u" : "alpha_x");
  if (anisotropic_) x[i + 1] = p.scalar(as ? "n_v" : "alpha_y");
  clamp_into(x, defs);
  return x;
}

std::vector<double> MetalFit::random_start(Rng& rng, const DataMoments&) const {
  std::vector<double> x(defs.size());
  int i = 0;
  if (!named_) {
    for (int c = 0; c < 3; ++c) x[c] = log_uniform(rng, 0.1, 3.0), x[3 + c] = uniform(rng, 1.0, 8.0);
    i = 6;
  }
  const bool as = lobe_ == SpecularLobeKind::AshikhminShirley;
  x[i] = as ? log_uniform(rng, 5.0, 5000.0) : log_uniform(rng, 0.02, 0.6);
  if (anisotropic_) x[i + 1] = as ? log_uniform(rng, 5.0, 5000.0) : log_uniform(rng, 0.02, 0.6);
  clamp_into(x, defs);
  return x;
}

// --- the generated models (BoundFit) -----------------------------------------------------------

template <class P>
BoundFit<P>::BoundFit(bool anisotropic, std::vector<models::FitFixed> options, std::vector<std::string_view> freed)
    : held_(std::begin(P::fit.fixed), std::end(P::fit.fixed)), anisotropic_(anisotropic) {
  const ModelSpec& s = P::spec;
  if (anisotropic && !s.find("rotation_deg"))
    throw std::logic_error(fmt::format("{} has no anisotropic fit (no rotation_deg)", s.name));
  held_.insert(held_.end(), options.begin(), options.end());
  const char* ch = "rgb";
  for (const models::FitKey& k : P::fit.keys) {
    const bool aniso_only = !k.iso_tie.empty() || !std::isnan(k.iso_value);
    if (aniso_only && !anisotropic) continue;
    if (k.optional && std::find(freed.begin(), freed.end(), k.key) == freed.end()) continue;
    if (aniso_only) aniso_.push_back(int(defs.size()));
    entries_[std::string(k.key)] = {int(defs.size()), k.shape == models::FitKey::Rgb};
    const std::string name(!anisotropic && !k.iso_name.empty() ? k.iso_name : k.key);
    if (k.shape == models::FitKey::Rgb)
      for (int c = 0; c < 3; ++c) defs.push_back(table_def(s, k.key, fmt::format("{}.{}", name, ch[c])));
    else
      defs.push_back(table_def(s, k.key, name));
    if (!std::isnan(k.lo)) defs.back().lo = k.lo;
  }
  // An isotropic fit: the pair's second half shares its first half's entry.
  for (const models::FitKey& k : P::fit.keys)
    if (!anisotropic && !k.iso_tie.empty()) entries_[std::string(k.key)] = entries_.at(std::string(k.iso_tie));
  if (anisotropic) {
    add_rotation(defs);
    period_ = P::fit.rotation_period;
  }
  // Where each bound field comes from: its entries, a held value, or its table default.
  for (const auto& part : P::template bound<double>)
    for (const auto& row : part) {
      Source src;
      const ParamSpec& p = row.spec;
      const auto e = entries_.find(std::string(p.name));
      const auto key =
          std::find_if(std::begin(P::fit.keys), std::end(P::fit.keys), [&](const auto& k) { return k.key == p.name; });
      const auto held = std::find_if(held_.begin(), held_.end(), [&](const auto& h) { return h.key == p.name; });
      if (e != entries_.end()) {
        src.entry = e->second.first;
        src.rgb = e->second.second;
      } else if (key != std::end(P::fit.keys) && !std::isnan(key->iso_value)) {
        src.number = key->iso_value;
      } else if (held != held_.end() && p.kind == ParamKind::Choice) {
        const auto it = std::find(p.choices.begin(), p.choices.end(), held->text);
        if (it == p.choices.end())
          throw std::logic_error(fmt::format("{}: \"{}\" is not a choice of {}", s.name, held->text, p.name));
        src.number = double(it - p.choices.begin());
      } else if (held != held_.end()) {
        src.number = held->number;
      } else {
        src.number = p.kind == ParamKind::Choice ? 0.0 : p.default_value;
      }
      sources_.push_back(src);
    }
}

template <class P> int BoundFit<P>::at(std::string_view key, int c) const {
  const auto e = entries_.find(std::string(key));
  if (e == entries_.end()) throw std::logic_error(fmt::format("{}: \"{}\" is not solved for", P::spec.name, key));
  return e->second.first + (e->second.second ? c : 0);
}

template <class P> std::string_view BoundFit<P>::held_text(std::string_view key) const {
  for (const models::FitFixed& h : held_)
    if (h.key == key) return h.text;
  return {};
}

template <class P> void BoundFit<P>::canonicalize(double* x) const {
  if (!anisotropic_) return;
  bool swap = false;
  if (!P::fit.pair[0].empty()) {
    // The narrower direction along the tangent: the smaller alpha, or the larger AS exponent.
    const int a = at(P::fit.pair[0]), b = at(P::fit.pair[1]);
    swap = P::fit.narrower_is_larger ? x[a] < x[b] : x[a] > x[b];
    if (swap) std::swap(x[a], x[b]);
  }
  canonical_angle(x, swap);
}

template <class P> Json BoundFit<P>::to_json(const double* x) const {
  Json out = {{"model", std::string(P::spec.name)}};
  for (const models::FitKey& k : P::fit.keys) {
    const auto e = entries_.find(std::string(k.key));
    if (e == entries_.end() && k.optional) continue;  // held at the table's default
    if (e == entries_.end())
      out[std::string(k.key)] = k.iso_value;
    else if (e->second.second)
      out[std::string(k.key)] = rgb_json(x + e->second.first);
    else
      out[std::string(k.key)] = x[e->second.first];
  }
  for (const models::FitFixed& h : held_) {
    const ParamSpec* p = P::spec.find(h.key);
    if (p->kind == ParamKind::Choice || p->kind == ParamKind::String)
      out[std::string(h.key)] = std::string(h.text);
    else if (p->kind == ParamKind::Bool)
      out[std::string(h.key)] = h.number != 0.0;
    else
      out[std::string(h.key)] = h.number;
  }
  return out;
}

namespace {

// Each generated model's starts (docs/fitting.md, "Starts"), by key: a start from the data's
// moments, from a published fit (the Ngan 2005 presets) or nothing, a random one; and the Ngan
// model whose presets are tried.
template <class P> struct Starts;

// Ward and GGX share their layout's shape: kd (3), the specular colour (Ward's ks, GGX's f0; 3),
// alpha_x and, when anisotropic, alpha_y. Their starts are the same functions of it.
//   moment start: the peak at the mirror direction at normal incidence is spec / (4 pi alpha^2)
//                 for both (Ward: ks N E with E = 1; GGX: D = 1 / (pi alpha^2), G2 ~ 1);
//   preset start: the nearest material's Ward fit (kd, ks, alpha_x, alpha_y);
//   random start: kd up to twice the data's floor albedo, a grey specular colour, log-uniform alpha.
template <class P> struct AlphaLobeStarts {
  static std::vector<double> moment(const BoundFit<P>& f, std::string_view spec, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    const double a = alpha_from_exponent(d.mirror_exponent);
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = d.floor_albedo[c], x[f.at(spec, c)] = d.peak[c] * 4.0 * kPiD * a * a;
    x[f.at("alpha_x")] = a;
    if (f.anisotropic()) x[f.at("alpha_y")] = a;
    clamp_into(x, f.defs);
    return x;
  }
  static std::optional<std::vector<double>> preset(const BoundFit<P>& f, std::string_view spec, const MaterialDesc& desc) {
    std::vector<double> x(f.defs.size());
    const ParamValues& p = desc.params;
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = p.color("kd")[c], x[f.at(spec, c)] = p.color("ks")[c];
    x[f.at("alpha_x")] = p.scalar("alpha_x");
    if (f.anisotropic()) x[f.at("alpha_y")] = p.scalar("alpha_y");
    clamp_into(x, f.defs);
    return x;
  }
  static std::vector<double> random(const BoundFit<P>& f, std::string_view spec, Rng& rng, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
    const double s = uniform(rng, 0.01, 1.0);
    for (int c = 0; c < 3; ++c) x[f.at(spec, c)] = s;
    x[f.at("alpha_x")] = log_uniform(rng, 0.02, 0.6);
    if (f.anisotropic()) x[f.at("alpha_y")] = log_uniform(rng, 0.02, 0.6);
    clamp_into(x, f.defs);
    return x;
  }
};

// f = kd / pi + ks N E (ward.h): ks from the peak, the lobe is ks / (4 pi alpha^2) at the mirror
// direction at normal incidence.
template <> struct Starts<models::Ward> : AlphaLobeStarts<models::Ward> {
  using F = BoundFit<models::Ward>;
  static std::vector<double> moment(const F& f, const DataMoments& d) { return AlphaLobeStarts::moment(f, "ks", d); }
  static std::optional<std::vector<double>> preset(const F& f, const MaterialDesc& desc, const DataMoments&) {
    return AlphaLobeStarts::preset(f, "ks", desc);
  }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    return AlphaLobeStarts::random(f, "ks", rng, d);
  }
  static std::string ngan(const F& f) { return f.held_text("normalization") == "duer" ? "wardduer" : "ward"; }
};

// At normal incidence the specular peak is f0 / (4 pi alpha^2) (D = 1 / (pi alpha^2), G2 ~ 1). The
// preset start is the nearest material's Ward fit: its kd, its ks as f0, its roughness as alpha.
template <> struct Starts<models::GGX> : AlphaLobeStarts<models::GGX> {
  using F = BoundFit<models::GGX>;
  // A free f90 starts at Schlick's 1 (the linear solve at every start then moves it).
  static std::vector<double> schlick_f90(const F& f, std::vector<double> x) {
    if (f.solves("f90"))
      for (int c = 0; c < 3; ++c) x[f.at("f90", c)] = 1.0;
    return x;
  }
  static std::vector<double> moment(const F& f, const DataMoments& d) {
    return schlick_f90(f, AlphaLobeStarts::moment(f, "f0", d));
  }
  static std::optional<std::vector<double>> preset(const F& f, const MaterialDesc& desc, const DataMoments&) {
    const std::optional<std::vector<double>> x = AlphaLobeStarts::preset(f, "f0", desc);
    return x ? std::optional(schlick_f90(f, *x)) : std::nullopt;
  }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    return schlick_f90(f, AlphaLobeStarts::random(f, "f0", rng, d));
  }
  static std::string ngan(const F&) { return "ward"; }  // the nearest material's Ward roughness
};

// Ngan 2005's form of Ashikhmin-Shirley. The half-vector exponent is about four times the mirror
// one (theta_h ~ a / 2); the specular peak at normal incidence is ks_scale rs (n + 1) / (8 pi).
template <> struct Starts<models::AshikhminShirley> {
  using F = BoundFit<models::AshikhminShirley>;
  static std::vector<double> moment(const F& f, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    const double nh = 4.0 * d.mirror_exponent, rs = 0.05;
    for (int c = 0; c < 3; ++c)
      x[f.at("kd", c)] = d.floor_albedo[c], x[f.at("ks_scale", c)] = d.peak[c] * 8.0 * kPiD / ((nh + 1.0) * rs);
    x[f.at("rs")] = rs;
    x[f.at("n_u")] = nh;
    if (f.anisotropic()) x[f.at("n_v")] = nh;
    clamp_into(x, f.defs);
    return x;
  }
  static std::optional<std::vector<double>> preset(const F& f, const MaterialDesc& desc, const DataMoments&) {
    std::vector<double> x(f.defs.size());
    const ParamValues& p = desc.params;
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = p.color("kd")[c], x[f.at("ks_scale", c)] = p.color("ks_scale")[c];
    x[f.at("rs")] = p.color("rs")[0];
    x[f.at("n_u")] = p.scalar("n_u");
    if (f.anisotropic()) x[f.at("n_v")] = p.scalar("n_v");
    clamp_into(x, f.defs);
    return x;
  }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    std::vector<double> x = moment(f, d);
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
    const double scale = log_uniform(rng, 0.2, 5.0);
    for (int c = 0; c < 3; ++c) x[f.at("ks_scale", c)] *= scale;
    x[f.at("rs")] = uniform(rng, 0.01, 0.5);
    x[f.at("n_u")] = log_uniform(rng, 5.0, 5000.0);
    if (f.anisotropic()) x[f.at("n_v")] = log_uniform(rng, 5.0, 5000.0);
    clamp_into(x, f.defs);
    return x;
  }
  static std::string ngan(const F&) { return "ashikhminshirley"; }
};

// A dielectric start: the floor albedo as base colour, specular 0.5 (F0 0.04), roughness from the
// mirror lobe's width (alpha = roughness^2), anisotropic 0.2 (inside the range, where the
// derivative of sqrt(1 - 0.9 anisotropic) is moderate). No Ngan fit of this model.
template <> struct Starts<models::Principled> {
  using F = BoundFit<models::Principled>;
  static std::vector<double> moment(const F& f, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    for (int c = 0; c < 3; ++c) x[f.at("base_color", c)] = d.floor_albedo[c];
    x[f.at("metallic")] = 0.0, x[f.at("specular")] = 0.5,
    x[f.at("roughness")] = std::sqrt(alpha_from_exponent(d.mirror_exponent));
    if (f.anisotropic()) x[f.at("anisotropic")] = 0.2;
    clamp_into(x, f.defs);
    return x;
  }
  static std::optional<std::vector<double>> preset(const F&, const MaterialDesc&, const DataMoments&) { return std::nullopt; }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    for (int c = 0; c < 3; ++c) x[f.at("base_color", c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
    x[f.at("metallic")] = uniform(rng, 0.0, 1.0), x[f.at("specular")] = uniform(rng, 0.0, 1.0),
    x[f.at("roughness")] = uniform(rng, 0.1, 0.9);
    if (f.anisotropic()) x[f.at("anisotropic")] = uniform(rng, 0.0, 0.9);
    clamp_into(x, f.defs);
    return x;
  }
  static std::string ngan(const F&) { return "ward"; }  // unused: the start comes from moments
};

// Phong's lobe about the mirror direction: the data's mirror exponent; ks from the peak, at the
// mirror direction the lobe is ks (s + 2) / (2 pi).
template <> struct Starts<models::Phong> {
  using F = BoundFit<models::Phong>;
  static std::vector<double> moment(const F& f, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    const double s = d.mirror_exponent;
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = d.floor_albedo[c], x[f.at("ks", c)] = d.peak[c] * 2.0 * kPiD / (s + 2.0);
    x[f.at("exponent")] = s;
    clamp_into(x, f.defs);
    return x;
  }
  static std::optional<std::vector<double>> preset(const F& f, const MaterialDesc& desc, const DataMoments&) {
    std::vector<double> x(f.defs.size());
    const ParamValues& p = desc.params;
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = p.color("kd")[c], x[f.at("ks", c)] = p.color("ks")[c];
    x[f.at("exponent")] = p.scalar("exponent");
    clamp_into(x, f.defs);
    return x;
  }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    std::vector<double> x = moment(f, d);
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
    const int e = f.at("exponent");
    x[e] = log_uniform(rng, 1.0, 5000.0);
    for (int c = 0; c < 3; ++c) x[f.at("ks", c)] = d.peak[c] * 2.0 * kPiD / (x[e] + 2.0) * log_uniform(rng, 0.3, 3.0);
    clamp_into(x, f.defs);
    return x;
  }
  static std::string ngan(const F&) { return "blinnphong"; }
};

// f = kd / pi: the floor albedo (a Lambertian surface has no peak: the floor is it).
template <> struct Starts<models::Lambert> {
  using F = BoundFit<models::Lambert>;
  static std::vector<double> moment(const F& f, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = d.floor_albedo[c];
    clamp_into(x, f.defs);
    return x;
  }
  static std::optional<std::vector<double>> preset(const F&, const MaterialDesc&, const DataMoments&) { return std::nullopt; }
  static std::vector<double> random(const F& f, Rng& rng, const DataMoments& d) {
    std::vector<double> x(f.defs.size());
    for (int c = 0; c < 3; ++c) x[f.at("kd", c)] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
    clamp_into(x, f.defs);
    return x;
  }
  static std::string ngan(const F&) { return "ward"; }  // unused: no preset start
};

}  // namespace

template <class P> std::vector<double> BoundFit<P>::moment_start(const DataMoments& d) const {
  return Starts<P>::moment(*this, d);
}
template <class P>
std::optional<std::vector<double>> BoundFit<P>::from_preset(const MaterialDesc& desc, const DataMoments& m) const {
  return Starts<P>::preset(*this, desc, m);
}
template <class P> std::vector<double> BoundFit<P>::random_start(Rng& rng, const DataMoments& d) const {
  return Starts<P>::random(*this, rng, d);
}
template <class P> std::string BoundFit<P>::ngan_model() const { return Starts<P>::ngan(*this); }

template class BoundFit<models::Lambert>;
template class BoundFit<models::Phong>;
template class BoundFit<models::Ward>;
template class BoundFit<models::AshikhminShirley>;
template class BoundFit<models::GGX>;
template class BoundFit<models::Principled>;

}  // namespace aniso::fit_detail
