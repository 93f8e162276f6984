// fit/models.h: how each model's parameters map to a flat vector for the solver (internal to
// src/fit). Each model class gives
//   defs            name and bounds of every entry (bounds from the parameter tables, params.cpp)
//   build<T>(x)     the kernel (include/aniso/brdf/*.h) for the vector x, T = double or ceres::Jet
//   to_json(x)      the material, as `aniso` reads it
//   moment_start    a start from the data's moments (DataMoments)
//   from_preset     a start from a published fit (the Ngan 2005 presets), or nothing
//   random_start    a random start, drawn from documented ranges (docs/fitting.md)
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/fit/fit.h"
#include "aniso/io/materials.h"
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
  // The material reader bounds each lobe's peak, scale max|C|^n <= 1e30 (materials.cpp: beyond it
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

// f = kd / pi + ks N E (ward.h), vector form, the chosen normalisation.
class WardFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  WardFit(bool anisotropic, WardNormalization norm);
  std::vector<ParamDef> defs;
  template <typename T> WardT<T> build(const T* x) const {
    WardT<T> m;
    m.kd = RGBT<T>(x[0], x[1], x[2]);
    m.ks = RGBT<T>(x[3], x[4], x[5]);
    m.lobe.alpha_x = x[6];
    m.lobe.alpha_y = x[anisotropic_ ? 7 : 6];
    m.lobe.form = WardForm::Vector;
    m.lobe.normalization = norm_;
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return norm_ == WardNormalization::Duer ? "wardduer" : "ward"; }

 private:
  bool anisotropic_;
  WardNormalization norm_;
};

// Ngan 2005's form of Ashikhmin-Shirley: kd / pi + ks_scale F(rs) f_s, no coupled diffuse (rd = 0).
class AshikhminShirleyFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  explicit AshikhminShirleyFit(bool anisotropic);
  std::vector<ParamDef> defs;
  template <typename T> AshikhminShirleyT<T> build(const T* x) const {
    AshikhminShirleyT<T> m;
    m.rd = RGBT<T>(T(0));
    m.kd = RGBT<T>(x[0], x[1], x[2]);
    m.ks_scale = RGBT<T>(x[3], x[4], x[5]);
    m.rs = RGBT<T>(x[6]);
    m.lobe.n_u = x[7];
    m.lobe.n_v = x[anisotropic_ ? 8 : 7];
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "ashikhminshirley"; }

 private:
  bool anisotropic_;
};

class GGXFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  explicit GGXFit(bool anisotropic);
  std::vector<ParamDef> defs;
  template <typename T> GGXT<T> build(const T* x) const {
    GGXT<T> m;
    m.kd = RGBT<T>(x[0], x[1], x[2]);
    m.f0 = RGBT<T>(x[3], x[4], x[5]);
    m.lobe.alpha_x = x[6];
    m.lobe.alpha_y = x[anisotropic_ ? 7 : 6];
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "ward"; }  // the nearest material's Ward roughness

 private:
  bool anisotropic_;
};

// A conductor (metal.h): named eta, k (fixed) or fitted ones, and a Ward, AS or GGX lobe.
class MetalFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
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

// The Disney principled BRDF (principled.h): base_color (3), metallic, specular, roughness and,
// when anisotropic, anisotropic; subsurface, sheen and clearcoat stay 0 (their keys' defaults).
class PrincipledFit : public Orientation {
 public:
  void canonicalize(double* x) const;
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  explicit PrincipledFit(bool anisotropic);
  std::vector<ParamDef> defs;
  template <typename T> PrincipledT<T> build(const T* x) const {
    PrincipledT<T> m;
    m.base_color = RGBT<T>(x[0], x[1], x[2]);
    m.metallic = x[3];
    m.specular = x[4];
    m.roughness = x[5];
    m.anisotropic = anisotropic_ ? x[6] : T(0);
    m.subsurface = T(0), m.specular_tint = T(0), m.sheen = T(0), m.sheen_tint = T(0.5);
    m.clearcoat = T(0), m.clearcoat_gloss = T(1);
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc&, const DataMoments&) const { return std::nullopt; }
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "ward"; }  // no Ngan fit of this model: the start comes from moments

 private:
  bool anisotropic_;
};

// Phong's lobe about the mirror direction (phong.h), normalised (Lewis 1994), as Ngan 2005's
// "Blinn-Phong" fits are (docs/presets.md: bbm's NganBlinnPhong is this mirror lobe): kd (3),
// ks (3), exponent. Isotropic: no orientation.
class PhongFit : public Orientation {
 public:
  void canonicalize(double*) const {}
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  PhongFit();
  std::vector<ParamDef> defs;
  template <typename T> PhongT<T> build(const T* x) const {
    PhongT<T> m;
    m.kd = RGBT<T>(x[0], x[1], x[2]);
    m.ks = RGBT<T>(x[3], x[4], x[5]);
    m.lobe.exponent = x[6];
    m.lobe.normalized = true;
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc& d, const DataMoments& m) const;
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "blinnphong"; }
};

// f = kd / pi: kd (3). The start is the data's albedo over the hemisphere's samples.
class LambertFit : public Orientation {
 public:
  void canonicalize(double*) const {}
  int penalty_count() const { return 0; }
  template <typename T> void penalties(const T*, T*) const {}
  LambertFit();
  std::vector<ParamDef> defs;
  template <typename T> LambertT<T> build(const T* x) const {
    LambertT<T> m;
    m.kd = RGBT<T>(x[0], x[1], x[2]);
    return m;
  }
  Json to_json(const double* x) const;
  std::vector<double> moment_start(const DataMoments& d) const;
  std::optional<std::vector<double>> from_preset(const MaterialDesc&, const DataMoments&) const { return std::nullopt; }
  std::vector<double> random_start(Rng& rng, const DataMoments& d) const;
  std::string ngan_model() const { return "ward"; }  // unused: no preset start
};

// For tests: the largest relative difference between the Lafortune Jacobian assembled by parts
// and the one from a single Jet over every parameter (fit.cpp), residuals included, at x.
double lafortune_parts_jacobian_difference(int lobes, bool anisotropic, bool shared, FitMetric metric, const SampleSet& data,
                                           const std::vector<double>& x);

}  // namespace aniso::fit_detail
