// fit/models.cpp: parameter layouts, bounds, materials and starts of every fitted model (models.h).
// The random ranges and the moment formulas are listed in docs/fitting.md ("Starts").
#include "fit/models.h"

#include <algorithm>
#include <cmath>

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

// Ward and GGX share one parameter layout: kd (3), the specular colour (Ward's ks, GGX's f0; 3),
// alpha_x and, when anisotropic, alpha_y. Their starts are the same functions of it.
//   moment start: the peak at the mirror direction at normal incidence is spec / (4 pi alpha^2)
//                 for both (Ward: ks N E with E = 1; GGX: D = 1 / (pi alpha^2), G2 ~ 1);
//   preset start: the nearest material's Ward fit (kd, ks, alpha_x, alpha_y);
//   random start: kd up to twice the data's floor albedo, a grey specular colour, log-uniform alpha.
std::vector<double> alpha_lobe_moment_start(const DataMoments& d, bool anisotropic, const std::vector<ParamDef>& defs) {
  std::vector<double> x(defs.size());
  const double a = alpha_from_exponent(d.mirror_exponent);
  for (int c = 0; c < 3; ++c) x[c] = d.floor_albedo[c], x[3 + c] = d.peak[c] * 4.0 * kPiD * a * a;
  x[6] = a;
  if (anisotropic) x[7] = a;
  clamp_into(x, defs);
  return x;
}

std::vector<double> alpha_lobe_preset_start(const MaterialDesc& desc, bool anisotropic, const std::vector<ParamDef>& defs) {
  std::vector<double> x(defs.size());
  const ParamValues& p = desc.params;
  for (int c = 0; c < 3; ++c) x[c] = p.color("kd")[c], x[3 + c] = p.color("ks")[c];
  x[6] = p.scalar("alpha_x");
  if (anisotropic) x[7] = p.scalar("alpha_y");
  clamp_into(x, defs);
  return x;
}

std::vector<double> alpha_lobe_random_start(Rng& rng, const DataMoments& d, bool anisotropic, const std::vector<ParamDef>& defs) {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[c] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  const double spec = uniform(rng, 0.01, 1.0);
  for (int c = 0; c < 3; ++c) x[3 + c] = spec;
  x[6] = log_uniform(rng, 0.02, 0.6);
  if (anisotropic) x[7] = log_uniform(rng, 0.02, 0.6);
  clamp_into(x, defs);
  return x;
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

// --- Ward --------------------------------------------------------------------------------------

WardFit::WardFit(bool anisotropic, WardNormalization norm) : anisotropic_(anisotropic), norm_(norm) {
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("ward"), "kd", fmt::format("kd.{}", ch[c])));
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("ward"), "ks", fmt::format("ks.{}", ch[c])));
  defs.push_back(table_def(spec("ward"), "alpha_x", anisotropic ? "alpha_x" : "alpha"));
  if (anisotropic) {
    aniso_.push_back(7);
    defs.push_back(table_def(spec("ward"), "alpha_y", "alpha_y"));
    add_rotation(defs);
  }
}

void WardFit::canonicalize(double* x) const {
  if (!anisotropic_) return;
  const bool swap = x[6] > x[7];
  if (swap) std::swap(x[6], x[7]);
  canonical_angle(x, swap);
}

Json WardFit::to_json(const double* x) const {
  const std::string norm(enum_name(norm_));
  return {{"model", "ward"},
          {"kd", rgb_json(x)},
          {"ks", rgb_json(x + 3)},
          {"alpha_x", x[6]},
          {"alpha_y", x[anisotropic_ ? 7 : 6]},
          {"form", "vector"},
          {"normalization", norm}};
}

// ks from the peak: at the mirror direction at normal incidence the lobe is ks / (4 pi alpha^2).
std::vector<double> WardFit::moment_start(const DataMoments& d) const { return alpha_lobe_moment_start(d, anisotropic_, defs); }

std::optional<std::vector<double>> WardFit::from_preset(const MaterialDesc& desc, const DataMoments&) const {
  return alpha_lobe_preset_start(desc, anisotropic_, defs);
}

std::vector<double> WardFit::random_start(Rng& rng, const DataMoments& d) const {
  return alpha_lobe_random_start(rng, d, anisotropic_, defs);
}

// --- Ashikhmin-Shirley ------------------------------------------------------------------------

AshikhminShirleyFit::AshikhminShirleyFit(bool anisotropic) : anisotropic_(anisotropic) {
  const ModelSpec& s = spec("ashikhmin-shirley");
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(s, "kd", fmt::format("kd.{}", ch[c])));
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(s, "ks_scale", fmt::format("ks_scale.{}", ch[c])));
  defs.push_back(table_def(s, "rs", "rs"));
  defs.push_back(table_def(s, "n_u", anisotropic ? "n_u" : "n"));
  if (anisotropic) {
    aniso_.push_back(8);
    defs.push_back(table_def(s, "n_v", "n_v"));
    add_rotation(defs);
  }
}

void AshikhminShirleyFit::canonicalize(double* x) const {
  if (!anisotropic_) return;
  const bool swap = x[7] < x[8];
  if (swap) std::swap(x[7], x[8]);
  canonical_angle(x, swap);
}

Json AshikhminShirleyFit::to_json(const double* x) const {
  return {{"model", "ashikhmin-shirley"},
          {"rd", 0.0},
          {"rs", x[6]},
          {"kd", rgb_json(x)},
          {"ks_scale", rgb_json(x + 3)},
          {"n_u", x[7]},
          {"n_v", x[anisotropic_ ? 8 : 7]}};
}

// The half-vector exponent is about four times the mirror one (theta_h ~ a / 2); the specular peak
// at normal incidence is ks_scale rs (n + 1) / (8 pi).
std::vector<double> AshikhminShirleyFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  const double nh = 4.0 * d.mirror_exponent, rs = 0.05;
  for (int c = 0; c < 3; ++c) x[c] = d.floor_albedo[c], x[3 + c] = d.peak[c] * 8.0 * kPiD / ((nh + 1.0) * rs);
  x[6] = rs;
  x[7] = nh;
  if (anisotropic_) x[8] = nh;
  clamp_into(x, defs);
  return x;
}

std::optional<std::vector<double>> AshikhminShirleyFit::from_preset(const MaterialDesc& desc, const DataMoments&) const {
  std::vector<double> x(defs.size());
  const ParamValues& p = desc.params;
  for (int c = 0; c < 3; ++c) x[c] = p.color("kd")[c], x[3 + c] = p.color("ks_scale")[c];
  x[6] = p.color("rs")[0];
  x[7] = p.scalar("n_u");
  if (anisotropic_) x[8] = p.scalar("n_v");
  clamp_into(x, defs);
  return x;
}

std::vector<double> AshikhminShirleyFit::random_start(Rng& rng, const DataMoments& d) const {
  std::vector<double> x = moment_start(d);
  for (int c = 0; c < 3; ++c) x[c] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  const double scale = log_uniform(rng, 0.2, 5.0);
  for (int c = 0; c < 3; ++c) x[3 + c] *= scale;
  x[6] = uniform(rng, 0.01, 0.5);
  x[7] = log_uniform(rng, 5.0, 5000.0);
  if (anisotropic_) x[8] = log_uniform(rng, 5.0, 5000.0);
  clamp_into(x, defs);
  return x;
}

// --- GGX ---------------------------------------------------------------------------------------

GGXFit::GGXFit(bool anisotropic) : anisotropic_(anisotropic) {
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("ggx"), "kd", fmt::format("kd.{}", ch[c])));
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("ggx"), "f0", fmt::format("f0.{}", ch[c])));
  defs.push_back(table_def(spec("ggx"), "alpha_x", anisotropic ? "alpha_x" : "alpha"));
  if (anisotropic) {
    aniso_.push_back(7);
    defs.push_back(table_def(spec("ggx"), "alpha_y", "alpha_y"));
    add_rotation(defs);
  }
}

void GGXFit::canonicalize(double* x) const {
  if (!anisotropic_) return;
  const bool swap = x[6] > x[7];
  if (swap) std::swap(x[6], x[7]);
  canonical_angle(x, swap);
}

Json GGXFit::to_json(const double* x) const {
  return {
      {"model", "ggx"}, {"kd", rgb_json(x)}, {"f0", rgb_json(x + 3)}, {"alpha_x", x[6]}, {"alpha_y", x[anisotropic_ ? 7 : 6]}};
}

// At normal incidence the specular peak is f0 / (4 pi alpha^2) (D = 1 / (pi alpha^2), G2 ~ 1).
std::vector<double> GGXFit::moment_start(const DataMoments& d) const { return alpha_lobe_moment_start(d, anisotropic_, defs); }

// The nearest material's Ward fit: its kd, its ks as f0, its roughness as alpha.
std::optional<std::vector<double>> GGXFit::from_preset(const MaterialDesc& desc, const DataMoments&) const {
  return alpha_lobe_preset_start(desc, anisotropic_, defs);
}

std::vector<double> GGXFit::random_start(Rng& rng, const DataMoments& d) const {
  return alpha_lobe_random_start(rng, d, anisotropic_, defs);
}

// --- Principled --------------------------------------------------------------------------------

PrincipledFit::PrincipledFit(bool anisotropic) : anisotropic_(anisotropic) {
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("principled"), "base_color", fmt::format("base_color.{}", ch[c])));
  for (const char* key : {"metallic", "specular", "roughness"}) defs.push_back(table_def(spec("principled"), key, key));
  // roughness below 0.0316 clamps alpha = roughness^2 at 0.001 (principled.h): a flat direction
  // for the solver, so the fit stays above it.
  defs.back().lo = 0.04;
  if (anisotropic) {
    aniso_.push_back(6);
    defs.push_back(table_def(spec("principled"), "anisotropic", "anisotropic"));
    add_rotation(defs);
    period_ = 180.0;
  }
}

void PrincipledFit::canonicalize(double* x) const {
  if (anisotropic_) canonical_angle(x, false);
}

Json PrincipledFit::to_json(const double* x) const {
  return {{"model", "principled"}, {"base_color", rgb_json(x)}, {"metallic", x[3]},
          {"specular", x[4]},      {"roughness", x[5]},         {"anisotropic", anisotropic_ ? x[6] : 0.0}};
}

// A dielectric start: the floor albedo as base colour, specular 0.5 (F0 0.04), roughness from the
// mirror lobe's width (alpha = roughness^2), anisotropic 0.2 (inside the range, where the
// derivative of sqrt(1 - 0.9 anisotropic) is moderate).
std::vector<double> PrincipledFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[c] = d.floor_albedo[c];
  x[3] = 0.0, x[4] = 0.5, x[5] = std::sqrt(alpha_from_exponent(d.mirror_exponent));
  if (anisotropic_) x[6] = 0.2;
  clamp_into(x, defs);
  return x;
}

std::vector<double> PrincipledFit::random_start(Rng& rng, const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[c] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  x[3] = uniform(rng, 0.0, 1.0), x[4] = uniform(rng, 0.0, 1.0), x[5] = uniform(rng, 0.1, 0.9);
  if (anisotropic_) x[6] = uniform(rng, 0.0, 0.9);
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

// --- Phong ---------------------------------------------------------------------------------------

PhongFit::PhongFit() {
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("phong"), "kd", fmt::format("kd.{}", ch[c])));
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("phong"), "ks", fmt::format("ks.{}", ch[c])));
  defs.push_back(table_def(spec("phong"), "exponent", "exponent"));
}

Json PhongFit::to_json(const double* x) const {
  return {{"model", "phong"}, {"kd", rgb_json(x)}, {"ks", rgb_json(x + 3)}, {"exponent", x[6]}, {"normalized", true}};
}

// The data's mirror exponent; ks from the peak: at the mirror direction the lobe is ks (s + 2) / (2 pi).
std::vector<double> PhongFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  const double s = d.mirror_exponent;
  for (int c = 0; c < 3; ++c) x[c] = d.floor_albedo[c], x[3 + c] = d.peak[c] * 2.0 * kPiD / (s + 2.0);
  x[6] = s;
  clamp_into(x, defs);
  return x;
}

std::optional<std::vector<double>> PhongFit::from_preset(const MaterialDesc& desc, const DataMoments&) const {
  std::vector<double> x(defs.size());
  const ParamValues& p = desc.params;
  for (int c = 0; c < 3; ++c) x[c] = p.color("kd")[c], x[3 + c] = p.color("ks")[c];
  x[6] = p.scalar("exponent");
  clamp_into(x, defs);
  return x;
}

std::vector<double> PhongFit::random_start(Rng& rng, const DataMoments& d) const {
  std::vector<double> x = moment_start(d);
  for (int c = 0; c < 3; ++c) x[c] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  x[6] = log_uniform(rng, 1.0, 5000.0);
  for (int c = 0; c < 3; ++c) x[3 + c] = d.peak[c] * 2.0 * kPiD / (x[6] + 2.0) * log_uniform(rng, 0.3, 3.0);
  clamp_into(x, defs);
  return x;
}

// --- Lambert -------------------------------------------------------------------------------------

LambertFit::LambertFit() {
  const char* ch = "rgb";
  for (int c = 0; c < 3; ++c) defs.push_back(table_def(spec("lambert"), "kd", fmt::format("kd.{}", ch[c])));
}

Json LambertFit::to_json(const double* x) const { return {{"model", "lambert"}, {"kd", rgb_json(x)}}; }

// The floor albedo plus a share of the peak (a Lambertian surface has no peak: the floor is it).
std::vector<double> LambertFit::moment_start(const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[c] = d.floor_albedo[c];
  clamp_into(x, defs);
  return x;
}

std::vector<double> LambertFit::random_start(Rng& rng, const DataMoments& d) const {
  std::vector<double> x(defs.size());
  for (int c = 0; c < 3; ++c) x[c] = uniform(rng, 0.0, std::min(1.0, 2.0 * d.floor_albedo[c] + 0.05));
  clamp_into(x, defs);
  return x;
}

}  // namespace aniso::fit_detail
