// fit/models.h: how each model's parameters map to a flat vector for the solver (internal to
// src/fit). A generated model (one whose table rows are bound to its kernel's fields, src/models)
// has BoundFit, made from its model file's FitDesc by name; Lafortune and metal have their own
// classes. Each gives (the concept FitLayout)
//   defs            name and bounds of every entry (bounds from the parameter tables, src/models)
//   build<T>(x)     the kernel (include/aniso/brdf/*.h) for the vector x, T = double or ceres::Jet
//   to_json(x)      the material, as `aniso` reads it
//   moment_start    a start from the data's moments (DataMoments)
//   from_preset     a start from a published fit (the Ngan 2005 presets), or nothing
//   random_start    a random start, drawn from documented ranges (docs/fitting.md)
#pragma once

#include <cmath>
#include <concepts>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/fit/fit.h"
#include "aniso/io/materials.h"
#include "models/all.h"
#include "stats/rng.h"

namespace aniso::fit_detail {

struct ParamDef {
  std::string name;
  double lo, hi;
};

// What the starts are built from (fit.cpp, data_moments()).
struct DataMoments {
  glm::dvec3 floor_albedo{0.0};   // pi x the 5th percentile of each channel: the diffuse floor
  glm::dvec3 peak{0.0};           // the largest value above the floor, per channel (1/sr)
  double mirror_exponent = 10.0;  // n of a cosine lobe about the mirror direction fitted to the excess
};

using Json = nlohmann::json;

// Bounds of a key of a table (min_exclusive: see each use).
ParamDef table_def(const ModelSpec& spec, std::string_view key, std::string name);

// The orientation of an anisotropic fit (docs/fitting.md, "Orientation"): rotation_deg, the last
// entry of the vector. The model's kernel never sees it: the residuals turn the directions by it
// (fit.cpp, as MaterialT does with FrameRotationT), so the derivative comes through the same Jet.
// Every anisotropic lobe is symmetric under a half turn, and the Gaussian / GGX / AS / Lafortune
// lobes under a quarter turn with their pair swapped: canonicalize() writes the one form with the
// rotation in [0, 180) and the lobe narrower along the tangent (alpha_x <= alpha_y, n_u >= n_v,
// |C_x| >= |C_y| summed over lobes and channels); principled has no swap (its anisotropic >= 0
// always makes alpha_x >= alpha_y).
class Orientation {
 public:
  // No penalty residuals unless a model has them (LafortuneFit's).
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  int rotation_index() const { return rotation_; }
  // The entries that exist only because the fit is anisotropic: the second half of each pair and
  // the rotation (what the identifiability check ties when the data do not constrain them).
  const std::vector<int>& anisotropy_indices() const { return aniso_; }
  // The turn after which the lobe repeats itself with its pair swapped (90 degrees), or repeats
  // only itself (180: principled). The orientation starts spread over it.
  double rotation_period() const { return period_; }

 protected:
  void add_rotation(std::vector<ParamDef>& defs) {
    rotation_ = int(defs.size());
    aniso_.push_back(rotation_);
    defs.push_back({"rotation_deg", -360.0, 360.0});  // the table's range (params.cpp, kOrientation)
  }
  // Adds a quarter turn when the caller swapped the pair, then wraps the angle into [0, 180).
  void canonical_angle(double* x, bool quarter_turn) const {
    if (rotation_ < 0) return;
    double a = x[rotation_] + (quarter_turn ? 90.0 : 0.0);
    a = std::fmod(a, 180.0);
    if (a < 0.0) a += 180.0;
    if (a >= 180.0) a -= 180.0;  // fmod of a value just below 0 rounds up to 180
    x[rotation_] = a;
  }
  int rotation_ = -1;
  double period_ = 90.0;
  std::vector<int> aniso_;
};

class LafortuneFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  LafortuneFit(int lobes, bool anisotropic, bool shared_exponents);
  std::vector<ParamDef> defs;
  int rho(int c) const { return c; }
  int cx(int k, int c) const { return base(k) + c; }
  int cy(int k, int c) const { return anisotropic_ ? base(k) + 3 + c : cx(k, c); }
  int cz(int k, int c) const { return base(k) + (anisotropic_ ? 6 : 3) + c; }
  int n(int k, int c) const { return base(k) + (anisotropic_ ? 9 : 6) + (shared_ ? 0 : c); }

  template <typename T> LafortuneT<T> build(const T* x) const {
    LafortuneT<T> m;
    m.rho_d = RGBT<T>(x[0], x[1], x[2]);
    m.lobe_count = lobes_;
    for (int k = 0; k < lobes_; ++k)
      for (int c = 0; c < 3; ++c) {
        m.lobes[k].cx[c] = x[cx(k, c)];
        m.lobes[k].cy[c] = x[cy(k, c)];
        m.lobes[k].cz[c] = x[cz(k, c)];
        m.lobes[k].n[c] = x[n(k, c)];
        m.lobes[k].scale[c] = T(1);
      }
    return m;
  }
  // The material reader bounds each lobe's peak, scale max|C|^n <= 1e30 (models/lafortune.h: beyond it
  // the float kernels overflow), which box bounds cannot express. One residual per lobe and
  // channel keeps the fit inside: max(0, n ln max|C| - kPeakLog), kPeakLog = 66 < ln(1e30) = 69.08
  // (a margin), weighted 1: a unit of excess costs far more than the whole data term (~1e-3). The
  // max is exact (its derivative follows the largest coefficient), not a smooth bound: sharp lobes
  // need |C| within 1e-3 of 1 and n in the thousands, which sqrt(cx^2 + cy^2 + cz^2) would forbid.
  static constexpr double kPeakLog = 66.0;
  int penalty_count() const { return 3 * lobes_; }
  template <typename T> void penalties(const T* x, T* out) const {
    using std::log;
    const auto absolute = [](const T& v) { return v < T(0) ? -v : v; };
    for (int k = 0; k < lobes_; ++k)
      for (int c = 0; c < 3; ++c) {
        T m = absolute(x[cx(k, c)]);
        const T y = absolute(x[cy(k, c)]), z = absolute(x[cz(k, c)]);
        if (y > m) m = y;
        if (z > m) m = z;
        const T excess = m > T(1) ? x[n(k, c)] * log(m) - T(kPeakLog) : T(-1);
        out[3 * k + c] = excess > T(0) ? excess : T(0);
      }
  }
  // f is a sum of parts that share no parameter but the rotation: the diffuse term (part 0, rho_d)
  // and each lobe (part k + 1). The Jacobian is assembled part by part (fit.cpp, ChunkCost), each part the same
  // kernel with only that term, on a Jet as wide as the part's parameters (at most 12) instead of
  // all of them (up to 99): the derivatives are the same, the Jet arithmetic a fraction.
  static constexpr bool kHasParts = true;
  static constexpr int kMaxPartSize = 13;  // an anisotropic lobe (12) and the rotation
  int part_count() const { return lobes_ + 1; }
  std::vector<int> part_indices(int part) const {
    std::vector<int> out;
    const int first = part == 0 ? 0 : base(part - 1), size = part == 0 ? 3 : stride_;
    for (int i = 0; i < size; ++i) out.push_back(first + i);
    // Every lobe turns with the rotation: each lobe's part adds its share of df/d(rotation).
    if (part > 0 && rotation_ >= 0) out.push_back(rotation_);
    return out;
  }
  template <typename T> LafortuneT<T> build_part(int part, const T* x) const {
    LafortuneT<T> m = build(x);
    if (part == 0) {
      m.lobe_count = 0;
      return m;
    }
    m.rho_d = RGBT<T>(T(0));
    m.lobes[0] = m.lobes[part - 1];
    m.lobe_count = 1;
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "lafortune"; }

 private:
  int base(int k) const { return 3 + k * stride_; }
  int lobes_;
  bool anisotropic_, shared_;
  int stride_;
};

// A conductor (metal.h): named eta, k (fixed) or fitted ones, and a Ward, AS or GGX lobe.
class MetalFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  MetalFit(bool anisotropic, const std::string& metal, SpecularLobeKind lobe);
  std::vector<ParamDef> defs;
  template <typename T> MetalT<T> build(const T* x) const {
    MetalT<T> m;
    int i = 0;
    if (named_) {
      m.eta = RGBT<T>(T(eta_.x), T(eta_.y), T(eta_.z));
      m.k = RGBT<T>(T(k_.x), T(k_.y), T(k_.z));
    } else {
      m.eta = RGBT<T>(x[0], x[1], x[2]);
      m.k = RGBT<T>(x[3], x[4], x[5]);
      i = 6;
    }
    m.lobe_kind = lobe_;
    const T a = x[i], b = x[anisotropic_ ? i + 1 : i];
    m.ward.alpha_x = a, m.ward.alpha_y = b;
    m.ggx.alpha_x = a, m.ggx.alpha_y = b;
    m.ashikhmin_shirley.n_u = a, m.ashikhmin_shirley.n_v = b;
    m.ward.form = WardForm::Vector;
    m.ward.normalization = WardNormalization::Ward1992;
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return lobe_ == SpecularLobeKind::AshikhminShirley ? "ashikhminshirley" : "ward"; }

 private:
  bool anisotropic_, named_;
  std::string metal_;
  glm::dvec3 eta_{0.0}, k_{0.0};
  SpecularLobeKind lobe_;
};

// The fit of a generated model P (src/models: a table whose rows are bound to the kernel's
// fields): the entries of P::fit's keys in order, then rotation_deg when anisotropic; every bound
// field is set from its entry, from a held value (P::fit's fixed keys, or the command's options)
// or from its table default. The starts are each model's (models.cpp, Starts<P>), by key.
template <class P> class BoundFit : public Orientation {
 public:
  // options: keys held at a value the command chose (Ward's --normalization); freed: the optional
  // keys (models::FitKey::optional) the command asks the fit to solve for.
  explicit BoundFit(bool anisotropic = false, std::vector<models::FitFixed> options = {},
                    std::vector<std::string_view> freed = {});
  std::vector<ParamDef> defs;

  template <typename T> models::KernelOf<P, T> build(const T* x) const {
    models::KernelOf<P, T> m;
    size_t r = 0;
    for (const auto& part : P::template bound<T>)
      for (const auto& row : part) {
        const Source& s = sources_[r++];
        if (!row.field.get) continue;
        std::visit(
            [&](auto* f) {
              using F = std::remove_pointer_t<decltype(f)>;
              if constexpr (std::is_same_v<F, T>)
                *f = s.entry >= 0 ? x[s.entry] : T(s.number);
              else if constexpr (std::is_same_v<F, RGBT<T>>)
                *f = s.entry < 0 ? RGBT<T>(T(s.number))
                     : s.rgb     ? RGBT<T>(x[s.entry], x[s.entry + 1], x[s.entry + 2])
                                 : RGBT<T>(x[s.entry]);
              else if constexpr (std::is_same_v<F, bool>)
                *f = s.number != 0.0;
              else
                *f = static_cast<F>(int(s.number));  // a choice's index
            },
            row.field.get(m));
      }
    return m;
  }
  void canonicalize(double* x) const;
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const;

  // The entry of a key (channel c of an Rgb key; a tied key's partner), -1 when not solved for.
  int at(std::string_view key, int c = 0) const;
  bool solves(std::string_view key) const { return entries_.count(std::string(key)) > 0; }
  bool anisotropic() const { return anisotropic_; }
  // The text a key is held at (a fixed choice), "" when none.
  std::string_view held_text(std::string_view key) const;

 private:
  // Where each bound row's field comes from, in the order of P::bound<T>'s rows.
  struct Source {
    int entry = -1;     // the first entry, or -1: held at `number`
    bool rgb = false;   // three entries (else one for all channels)
    double number = 0;  // a held value (a choice's index)
  };
  std::vector<Source> sources_;
  std::map<std::string, std::pair<int, bool>> entries_;  // key -> its first entry, three of them (Rgb)
  std::vector<models::FitFixed> held_;
  bool anisotropic_;
};

using LambertFit = BoundFit<models::Lambert>;
using PhongFit = BoundFit<models::Phong>;
using GGXFit = BoundFit<models::GGX>;
using AshikhminShirleyFit = BoundFit<models::AshikhminShirley>;
using PrincipledFit = BoundFit<models::Principled>;
// f = kd / pi + ks N E (ward.h), vector form, the chosen normalisation.
struct WardFit : BoundFit<models::Ward> {
  WardFit(bool anisotropic, WardNormalization norm)
      : BoundFit(anisotropic, {{.key = "normalization", .text = enum_name(norm)}}) {}
};

// What fit.cpp's fit_with asks of a model's layout (the members the header comment lists).
template <class M>
concept FitLayout = requires(const M& m, double* x, Rng& rng, const DataMoments& d, const MaterialDesc& desc) {
  { m.defs } -> std::convertible_to<std::vector<ParamDef>>;
  m.template build<double>(x);
  m.canonicalize(x);
  { m.to_json(x) } -> std::same_as<Json>;
  { m.moment_start(d) } -> std::same_as<std::vector<double>>;
  { m.from_preset(desc, d) } -> std::same_as<std::optional<std::vector<double>>>;
  { m.random_start(rng, d) } -> std::same_as<std::vector<double>>;
  { m.ngan_model() } -> std::convertible_to<std::string>;
  { m.penalty_count() } -> std::same_as<int>;
  { m.rotation_index() } -> std::same_as<int>;
};
static_assert(FitLayout<LafortuneFit> && FitLayout<MetalFit> && FitLayout<WardFit> && FitLayout<GGXFit> &&
              FitLayout<AshikhminShirleyFit> && FitLayout<PrincipledFit> && FitLayout<PhongFit> && FitLayout<LambertFit>);

// For tests: the largest relative difference between the Lafortune Jacobian assembled by parts
// and the one from a single Jet over every parameter (fit.cpp), residuals included, at x.
double lafortune_parts_jacobian_difference(int lobes, bool anisotropic, bool shared, FitMetric metric, const SampleSet& data,
                                           const std::vector<double>& x);

}  // namespace aniso::fit_detail
