// tests/test_materials.cpp: the presets (every one parses, builds in float and double, and
// evaluates to finite, non-negative values; the size of each preset family; how Ngan 2005's models
// map onto ours; sampling efficiency and energy of the presets), the parameter tables (well-formed:
// docs, ranges, defaults) and the reader (error messages name the key and the range; accepted
// values evaluate to finite numbers; files that do not parse are InputErrors; anisotropic pairs
// and their shorthand; the JSON rules of io/json_read.h: duplicate keys, nesting depth, escaped
// keys, file kinds; inline materials, names and the resolved form).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/io/presets.h"
#include "aniso/stats/albedo.h"
#include "input_error_text.h"
#include "io/json_read.h"
#include "test_util.h"

namespace aniso {
namespace {

using nlohmann::json;

// --- helpers -----------------------------------------------------------------------------------

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// The message of the InputError that parsing `j` raises ("" if it raises none).
std::string parse_error_of(const json& j) {
  try {
    (void)parse_material(j, "test.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A few directions in the upper hemisphere, including the mirror configuration (h = n), normal
// incidence and grazing angles, plus random ones.
template <typename T> std::vector<std::pair<Vec3T<T>, Vec3T<T>>> probe_directions() {
  std::vector<std::pair<Vec3T<T>, Vec3T<T>>> out;
  const auto d = [](double theta, double phi) {
    const Vec3d v = test::spherical(theta, phi);
    return Vec3T<T>(T(v.x), T(v.y), T(v.z));
  };
  out.push_back({d(0, 0), d(0, 0)});       // normal incidence and view
  out.push_back({d(30, 0), d(30, 180)});   // mirror: h = n
  out.push_back({d(60, 90), d(60, 270)});  // mirror along the bitangent
  out.push_back({d(45, 20), d(10, 150)});
  out.push_back({d(89.5, 0), d(89.5, 180)});  // grazing mirror
  out.push_back({d(89.9, 45), d(5, 300)});    // grazing light
  out.push_back({d(20, 10), d(20, 10)});      // retro-reflection
  Rng rng(7);
  for (int i = 0; i < 16; ++i) out.push_back({test::random_upper<T>(rng), test::random_upper<T>(rng)});
  return out;
}

// --- presets -------------------------------------------------------------------------------------

template <typename T> void check_preset_builds_and_evaluates(const PresetInfo& p) {
  SCOPED_TRACE(p.name);
  MaterialT<T> m;
  ASSERT_NO_THROW(m = build_material<T>(load_material(p.name)));
  for (const auto& [wi, wo] : probe_directions<T>()) {
    const RGBT<T> f = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(double(f[c]))) << "channel " << c << " at wi (" << wi.x << ", " << wi.y << ", " << wi.z
                                               << "), wo (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
      ASSERT_GE(f[c], T(0)) << "channel " << c;
    }
    const T pdf = m.pdf(wi, wo);
    ASSERT_TRUE(std::isfinite(double(pdf)));
    ASSERT_GE(pdf, T(0));
  }
  // Below the horizon: zero.
  const Vec3T<T> up(T(0), T(0), T(1)), down(T(0.6), T(0), T(-0.8));
  EXPECT_EQ(m.f(down, up), RGBT<T>(T(0)));
  EXPECT_EQ(m.f(up, down), RGBT<T>(T(0)));
}

TEST(MaterialPresets, EveryPresetParsesAndBuildsInDouble) {
  for (const PresetInfo& p : presets()) check_preset_builds_and_evaluates<double>(p);
}

TEST(MaterialPresets, EveryPresetParsesAndBuildsInFloat) {
  for (const PresetInfo& p : presets()) check_preset_builds_and_evaluates<float>(p);
}

TEST(MaterialPresets, NamesAreUniqueAndFindPresetReturnsTheListedJson) {
  std::set<std::string> names;
  for (const PresetInfo& p : presets()) {
    EXPECT_TRUE(names.insert(p.name).second) << "duplicate preset " << p.name;
    EXPECT_FALSE(p.source.empty()) << p.name << " has no source";
    const auto j = find_preset(p.name);
    ASSERT_TRUE(j.has_value()) << p.name;
    EXPECT_EQ(*j, p.json) << p.name;
  }
  EXPECT_FALSE(find_preset("no-such-preset").has_value());
}

TEST(MaterialPresets, FamilySizes) {
  std::map<std::string, int> ngan;
  int matte_steel = 0, pbrt_v1 = 0, metals = 0, brushed = 0, principled = 0;
  const std::set<std::string> pbrt_names = {"bluepaint", "clay", "felt", "primer", "skin", "brushedmetal"};
  std::set<std::string> metal_names;
  for (const MetalData& md : metal_table()) metal_names.insert(std::string(md.name));
  ASSERT_EQ(metal_names.size(), 12u);

  for (const PresetInfo& p : presets()) {
    if (p.name == "matte-steel") {
      ++matte_steel;
    } else if (pbrt_names.count(p.name)) {
      ++pbrt_v1;
      EXPECT_EQ(p.json.at("model"), "lafortune") << p.name;
    } else if (metal_names.count(p.name)) {
      ++metals;
      EXPECT_EQ(p.json.at("model"), "metal") << p.name;
    } else if (starts_with(p.name, "brushed-") && metal_names.count(p.name.substr(8))) {
      ++brushed;
      EXPECT_EQ(p.json.at("model"), "metal") << p.name;
    } else if (starts_with(p.name, "ngan/")) {
      const size_t slash = p.name.find('/', 5);
      ASSERT_NE(slash, std::string::npos) << p.name;
      ++ngan[p.name.substr(5, slash - 5)];
    } else if (starts_with(p.name, "principled/")) {
      ++principled;
      EXPECT_EQ(p.json.at("model"), "principled") << p.name;
    } else {
      ADD_FAILURE() << "preset " << p.name << " belongs to no known family";
    }
  }
  EXPECT_EQ(matte_steel, 1);
  EXPECT_EQ(pbrt_v1, 6);
  EXPECT_EQ(metals, 12);
  EXPECT_EQ(brushed, 12);
  EXPECT_EQ(principled, 4);
  // Ngan et al. 2005 fitted 86 MERL materials per model; cooktorrance and he are not provided.
  const std::map<std::string, int> expected_ngan = {
      {"ward", 86}, {"wardduer", 86}, {"blinnphong", 86}, {"lafortune", 86}, {"ashikhminshirley", 86}};
  EXPECT_EQ(ngan, expected_ngan);
  EXPECT_EQ(presets().size(), 1u + 6u + 24u + 5u * 86u + 4u);
}

TEST(MaterialPresets, NganModelsMapOntoOurs) {
  const auto model_of = [](const std::string& name) { return find_preset(name)->at("model").get<std::string>(); };
  EXPECT_EQ(model_of("ngan/ward/nickel"), "ward");
  EXPECT_EQ(find_preset("ngan/ward/nickel")->at("normalization"), "ward");
  EXPECT_EQ(find_preset("ngan/wardduer/nickel")->at("normalization"), "duer");
  EXPECT_EQ(find_preset("ngan/ward/nickel")->at("form"), "vector");
  EXPECT_EQ(model_of("ngan/blinnphong/nickel"), "phong");
  EXPECT_EQ(find_preset("ngan/blinnphong/nickel")->at("normalized"), true);
  EXPECT_EQ(model_of("ngan/lafortune/nickel"), "lafortune");
  EXPECT_EQ(model_of("ngan/ashikhminshirley/nickel"), "ashikhmin-shirley");
  EXPECT_EQ(find_preset("ngan/ashikhminshirley/nickel")->at("rd"), 0.0);  // no coupled diffuse term
  EXPECT_FALSE(find_preset("ngan/cooktorrance/nickel").has_value());
  EXPECT_FALSE(find_preset("ngan/he/nickel").has_value());
}

// Lafortune lobes whose axis a = (Cx wo.x, Cy wo.y, Cz wo.z) points below the horizon (Cz < 0, as
// in pbrt-v1's clay, felt and skin) hold (nearly) all of their mass below the horizon (at wo = n
// all of it: the lobe is 0 in the upper hemisphere). A sampler that weighted them by
// scale |a|^n 2 pi / (n + 1) would pick them almost always and return "no sample" (clay at wo = n:
// 0 valid samples in 10000, an importance-sampled albedo with 500 times the standard error of
// uniform sampling): unbiased, but useless for a material that reflects 28% of the light. For
// every preset at least a quarter of the draws give a sample.
TEST(MaterialPresets, SamplingRarelyReturnsNoSample) {
  for (const PresetInfo& p : presets()) {
    const MaterialD m = build_material<double>(load_material(p.name));
    for (double theta : {0.0, 30.0, 60.0}) {
      const Vec3d wo = test::spherical(theta, 37.0);
      Rng rng(1);
      const int n = 2000;
      int valid = 0;
      for (int i = 0; i < n; ++i) {
        const double uc = rng.uniform();
        const Vec2T<double> u(rng.uniform(), rng.uniform());
        valid += m.sample(wo, uc, u).valid ? 1 : 0;
      }
      EXPECT_GE(valid, n / 4) << p.name << " at theta " << theta << ": " << valid << " of " << n << " draws give a sample";
    }
  }
}

// The brushed-<metal> presets add a directional-diffuse lobe (albedo 0.1 x F0) to a balanced Ward
// lobe whose albedo approaches F itself: without energy coupling brushed-silver would reflect 1.04
// and brushed-gold (red) 1.046 of the incident light at normal incidence. A metal preset must not
// reflect more than it receives: directional albedo <= 1 in every channel.
TEST(MaterialPresets, MetalPresetsDoNotGainEnergy) {
  for (const MetalData& md : metal_table()) {
    for (const std::string& name : {std::string(md.name), "brushed-" + std::string(md.name)}) {
      const MaterialD m = build_material<double>(load_material(name));
      for (double theta : {0.0, 30.0, 60.0}) {
        for (double phi : {0.0, 90.0}) {
          const AlbedoEstimate a = albedo_importance(m, test::spherical(theta, phi), 1 << 14, 5);
          for (int c = 0; c < 3; ++c) {
            EXPECT_LE(a.mean[c], 1.0 + 4.0 * a.std_error[c] + 1e-3) << name << " theta " << theta << " phi " << phi << " channel "
                                                                    << c << ": albedo " << a.mean[c] << " +- " << a.std_error[c];
          }
        }
      }
    }
  }
}

// Ngan's Lafortune lobe ks (n + 2) / (2 pi max(|Cz|, |Cxy|)^n) max(C . (wi * wo), 0)^n, folded into
// C / max|C| and scale = ks (n + 2) / (2 pi): the lobe's largest coefficient is +-1.
TEST(MaterialPresets, NganLafortuneCoefficientsAreNormalised) {
  for (const PresetInfo& p : presets()) {
    if (!starts_with(p.name, "ngan/lafortune/")) continue;
    SCOPED_TRACE(p.name);
    const json& lobe = p.json.at("lobes").at(0);
    const double cxy = lobe.at("cxy").get<double>(), cz = lobe.at("cz").get<double>();
    EXPECT_NEAR(std::max(std::abs(cxy), std::abs(cz)), 1.0, 1e-12);
  }
}

// --- parameter tables ----------------------------------------------------------------------------

bool default_in_range(const ParamSpec& p) {
  const double x = p.default_value;
  if (!std::isfinite(x)) return false;
  if (p.min_exclusive ? !(x > p.min) : !(x >= p.min)) return false;
  return x <= p.max;
}

void check_table(const ModelSpec& spec, std::set<const ModelSpec*>& seen) {
  if (!seen.insert(&spec).second) return;
  SCOPED_TRACE(std::string(spec.name));
  EXPECT_FALSE(spec.name.empty());
  EXPECT_FALSE(spec.title.empty());
  std::set<std::string_view> names;
  for (const ParamSpec* p : spec.params()) {
    SCOPED_TRACE(std::string(p->name));
    EXPECT_FALSE(p->name.empty());
    EXPECT_TRUE(names.insert(p->name).second) << "duplicate parameter";
    EXPECT_FALSE(p->doc.empty()) << "parameter without documentation";
    EXPECT_EQ(spec.find(p->name), p);
    switch (p->kind) {
      case ParamKind::Scalar:
      case ParamKind::Color:
        EXPECT_LE(p->min, p->max);
        if (p->min_exclusive) {
          EXPECT_LT(p->min, p->max);
        }
        // A default, where the parameter has one (not required, not NaN), lies in the range.
        if (!p->required && !std::isnan(p->default_value)) {
          EXPECT_TRUE(default_in_range(*p)) << "default " << p->default_value << " outside " << describe_range(*p);
        }
        break;
      case ParamKind::Bool: EXPECT_TRUE(p->default_value == 0.0 || p->default_value == 1.0); break;
      case ParamKind::Choice: EXPECT_FALSE(p->choices.empty()); break;
      case ParamKind::String: break;
      case ParamKind::Object:
        ASSERT_NE(p->sub, nullptr);
        check_table(*p->sub, seen);
        break;
      case ParamKind::List:
        ASSERT_NE(p->sub, nullptr);
        EXPECT_GT(p->max_items, 0);
        check_table(*p->sub, seen);
        break;
      case ParamKind::TaggedObject:
        EXPECT_FALSE(p->choices.empty());
        for (auto c : p->choices) {
          EXPECT_EQ(metal_lobe_spec(c).name, c);
          check_table(metal_lobe_spec(c), seen);
        }
        break;
    }
    EXPECT_FALSE(describe_range(*p).empty());
  }
}

TEST(MaterialParamTables, EveryTableIsWellFormed) {
  std::set<const ModelSpec*> seen;
  for (const ModelSpec* m : model_specs()) {
    EXPECT_FALSE(m->citation.empty()) << m->name;
    check_table(*m, seen);
  }
  check_table(lafortune_lobe_spec(), seen);
  check_table(directional_diffuse_spec(), seen);
  EXPECT_GE(seen.size(), model_specs().size() + 5);  // + lafortune lobe, directional diffuse, 3 metal lobes
}

TEST(MaterialParamTables, EveryModelIsListedAndFound) {
  std::vector<std::string> names;
  for (const ModelSpec* m : model_specs()) {
    names.emplace_back(m->name);
    EXPECT_EQ(find_model_spec(m->name), m);
  }
  const std::vector<std::string> expected = {"lambert", "phong", "ward",       "ashikhmin-shirley", "lafortune",
                                             "ggx",     "metal", "principled", "measured",          "rgl"};
  EXPECT_EQ(names, expected);
  EXPECT_EQ(find_model_spec("cooktorrance"), nullptr);
}

// The smallest valid material of each model: the required keys only.
json minimal_material(std::string_view model) {
  if (model == "lafortune") return {{"model", "lafortune"}, {"lobes", json::array({{{"n", 10.0}}})}};
  if (model == "metal") return {{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}}}};
  return {{"model", std::string(model)}};
}

TEST(MaterialParamTables, DefaultsBuildAValidMaterial) {
  for (const ModelSpec* m : model_specs()) {
    if (m->name == "measured" || m->name == "rgl") continue;  // one key, a file: test_measured.cpp, test_rgl.cpp
    SCOPED_TRACE(std::string(m->name));
    const json j = minimal_material(m->name);
    MaterialDesc d;
    ASSERT_NO_THROW(d = parse_material(j, "test.json"));
    // Every optional key with a default is filled in.
    for (const ParamSpec* p : m->params()) {
      const bool has_default =
          !p->required && (((p->kind == ParamKind::Scalar || p->kind == ParamKind::Color) && !std::isnan(p->default_value)) ||
                           p->kind == ParamKind::Bool || p->kind == ParamKind::Choice);
      if (has_default) {
        EXPECT_TRUE(d.params.has(p->name)) << p->name;
      }
    }
    const MaterialD md = build_material<double>(d);
    const RGBT<double> f = md.f(test::spherical(30, 0), test::spherical(30, 180));
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(f[c]));
      EXPECT_GE(f[c], 0.0);
    }
  }
}

// --- error messages ------------------------------------------------------------------------------

TEST(MaterialErrors, MessagesNameTheKeyAndTheRange) {
  struct Case {
    json j;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {{{"model", "ward"}, {"alpha_x", 0.0}}, {"test.json", "\"alpha_x\"", "[0.001, 1]", "got the number 0"}},
      {{{"model", "ward"}, {"alpha_x", -0.1}}, {"\"alpha_x\"", "[0.001, 1]"}},
      {{{"model", "ward"}, {"alpha_y", 1.5}}, {"\"alpha_y\"", "[0.001, 1]"}},
      {{{"model", "ward"}, {"alpha_x", "big"}}, {"\"alpha_x\"", "[0.001, 1]", "got the string \"big\""}},
      {{{"model", "ward"}, {"form", "fast"}}, {"\"form\"", "\"vector\" \"angle\" \"approx\"", "\"fast\""}},
      {{{"model", "lambert"}, {"kd", 1.5}}, {"\"kd\"", "[0, 1]", "1.5"}},
      {{{"model", "lambert"}, {"kd", {0.1, 0.2}}}, {"\"kd\"", "[r, g, b]", "an array of 2 elements"}},
      {{{"model", "lambert"}, {"kd", {0.1, 0.2, -1.0}}}, {"\"kd\"", "element 2", "[0, 1]"}},
      {{{"model", "lambert"}, {"kd", 0.5}, {"foo", 1}}, {"unknown key \"foo\"", "\"kd\""}},
      {{{"kd", 0.5}}, {"\"model\"", "missing", "\"lambert\""}},
      {{{"model", "cooktorrance"}}, {"\"model\"", "\"cooktorrance\""}},
      {{{"model", "phong"}, {"normalized", 1}}, {"\"normalized\"", "true or false"}},
      {{{"model", "lafortune"}}, {"\"lobes\"", "missing", "required"}},
      {{{"model", "lafortune"}, {"lobes", json::array()}}, {"\"lobes\"", "1 to 8"}},
      {{{"model", "lafortune"}, {"lobes", json::array({{{"cz", 1.0}}})}}, {"lobes[0]", "\"n\"", "missing"}},
      {{{"model", "lafortune"}, {"lobes", json::array({{{"n", 2.0}}, {{"n", 3.0}, {"cx", 1.0}, {"cxy", 1.0}}})}},
       {"lobes[1]", "\"cxy\"", "\"cx\""}},
      {{{"model", "lafortune"}, {"lobes", json::array({{{"n", -1.0}}})}}, {"lobes[0]", "\"n\"", "[0, "}},
      {{{"model", "metal"}, {"metal", "unobtainium"}, {"lobe", {{"model", "ggx"}}}},
       {"\"metal\"", "unknown metal \"unobtainium\"", "\"gold\""}},
      {{{"model", "metal"}, {"metal", "gold"}, {"eta", 1.0}, {"k", 2.0}, {"lobe", {{"model", "ggx"}}}},
       {"\"metal\"", "not both"}},
      {{{"model", "metal"}, {"eta", 1.0}, {"lobe", {{"model", "ggx"}}}}, {"\"k\"", "missing"}},
      {{{"model", "metal"}, {"metal", "gold"}}, {"\"lobe\"", "missing"}},
      {{{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "phong"}}}}, {"lobe.model", "\"ggx\""}},
      {{{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ward"}, {"alpha_y", 2.0}}}},
       {"lobe", "\"alpha_y\"", "[0.001, 1]"}},
      {{{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}, {"kd", 0.1}}}}, {"lobe", "unknown key \"kd\""}},
      {{{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}}}, {"directional_diffuse", {{"albedo", 2.0}}}},
       {"directional_diffuse", "\"albedo\"", "[0, 1]"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.j.dump());
    const std::string msg = parse_error_of(c.j);
    ASSERT_FALSE(msg.empty()) << "accepted";
    for (const std::string& s : c.expect) EXPECT_NE(msg.find(s), std::string::npos) << "\"" << s << "\" not in: " << msg;
  }
}

// Generic: for every numeric key of every model, a value below the minimum, above a finite maximum,
// and of the wrong type are rejected with a message naming the key and stating the range.
TEST(MaterialErrors, EveryNumericKeyIsRangeChecked) {
  for (const ModelSpec* m : model_specs()) {
    for (const ParamSpec* p : m->params()) {
      if (p->kind != ParamKind::Scalar && p->kind != ParamKind::Color) continue;
      SCOPED_TRACE(std::string(m->name) + "." + std::string(p->name));
      const std::string range = describe_range(*p);
      const std::string key = "\"" + std::string(p->name) + "\"";
      std::vector<json> bad = {p->min_exclusive ? p->min : p->min - 1.0, "0.5"};
      if (p->max < 1e6) bad.push_back(p->max + 1.0);
      for (const json& v : bad) {
        json j = minimal_material(m->name);
        j[std::string(p->name)] = v;
        const std::string msg = parse_error_of(j);
        ASSERT_FALSE(msg.empty()) << "value " << v.dump() << " accepted";
        EXPECT_NE(msg.find(key), std::string::npos) << msg;
        EXPECT_NE(msg.find(range), std::string::npos) << msg;
      }
    }
  }
}

// Parameters with max = kHuge (1e6: exponents, scales): a rejected finite value is never told that
// the range is unbounded (a message 'expected number in [0, inf), got the number 2000000.0' would
// contradict itself, and `aniso models` would advertise a range the reader does not accept).
TEST(MaterialErrors, RejectedValueIsOutsideTheStatedRange) {
  for (const ModelSpec* m : model_specs()) {
    for (const ParamSpec* p : m->params()) {
      if ((p->kind != ParamKind::Scalar && p->kind != ParamKind::Color) || p->max < 1e6) continue;
      SCOPED_TRACE(std::string(m->name) + "." + std::string(p->name));
      json j = minimal_material(m->name);
      j[std::string(p->name)] = 2.0 * p->max;
      const std::string msg = parse_error_of(j);
      if (!msg.empty()) {
        EXPECT_EQ(msg.find("inf)"), std::string::npos) << msg;
      }
    }
  }
}

// Every value the tables accept evaluates to finite numbers, as no model returns Inf or NaN
// (docs/conventions.md), at both ends of every range: for example roughness 1e-200, where
// alpha_x alpha_y would underflow to 0 and the Ward / GGX normalisation become Inf (Inf at the
// peak, 0 * Inf = NaN beside it), and a Lafortune lobe with cz = 100 and n = 1000 (100^1000 = Inf).
// The reader rejects what the kernels cannot evaluate, or the kernels stay finite.
TEST(MaterialErrors, EveryAcceptedExtremeValueEvaluatesFinite) {
  std::vector<json> extremes;
  for (const ModelSpec* m : model_specs()) {
    for (const ParamSpec* p : m->params()) {
      if (p->kind != ParamKind::Scalar && p->kind != ParamKind::Color) continue;
      for (double v : {p->min_exclusive ? 1e-200 : p->min, std::min(p->max, 1e6)}) {
        json j = minimal_material(m->name);
        j[std::string(p->name)] = v;
        extremes.push_back(j);
      }
    }
  }
  extremes.push_back({{"model", "lafortune"}, {"lobes", json::array({{{"cz", 100.0}, {"n", 1000.0}}})}});
  extremes.push_back({{"model", "ward"}, {"alpha_x", 1e-200}, {"alpha_y", 1e-200}});
  extremes.push_back({{"model", "ggx"}, {"alpha_x", 1e-200}, {"alpha_y", 1e-200}});
  extremes.push_back(
      {{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ward"}, {"alpha_x", 1e-200}, {"alpha_y", 1e-200}}}});
  for (const json& j : extremes) {
    MaterialDesc d;
    try {
      d = parse_material(j, "test.json");
    } catch (const InputError&) {
      continue;  // rejected: fine
    }
    SCOPED_TRACE(j.dump());
    const MaterialD md = build_material<double>(d);
    bool finite = true;
    for (const auto& [wi, wo] : probe_directions<double>()) {
      const RGBT<double> f = md.f(wi, wo);
      for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(f[c]);
    }
    EXPECT_TRUE(finite) << "accepted, but f is not finite everywhere";
  }
}

TEST(MaterialErrors, DirectionalDiffuseNeedsANonZeroCoefficient) {
  const json j = {{"model", "metal"},
                  {"metal", "gold"},
                  {"lobe", {{"model", "ggx"}}},
                  {"directional_diffuse", {{"cx", 0.0}, {"cy", 0.0}, {"cz", 0.0}}}};
  // The metal's rule (src/models/metal.h) refuses it, when the material is built or (with the rules
  // as table data, branch models-host) already when it is read.
  try {
    (void)build_material<double>(parse_material(j, "test.json"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("non-zero"), std::string::npos) << e.what();
  }
}

// Files: a fresh directory per test.
class MaterialFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (std::filesystem::temp_directory_path() / "aniso-mat-XXXXXX").string();
    ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::string load_error(const std::string& path) {
    try {
      (void)load_material(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(MaterialFiles, ValidFileLoads) {
  const std::string path =
      write("m.json", R"({"model": "ward", "kd": 0.1, "ks": [0.2, 0.3, 0.4], "alpha_x": 0.05, "alpha_y": 0.3})");
  const MaterialDesc d = load_material(path);
  EXPECT_EQ(d.model, "ward");
  EXPECT_DOUBLE_EQ(d.params.scalar("alpha_y"), 0.3);
  EXPECT_EQ(d.params.text("form"), "vector");  // default: the first choice
}

TEST_F(MaterialFiles, MissingFileAndUnknownPreset) {
  const std::string msg = load_error((dir_ / "nope.json").string());
  EXPECT_NE(msg.find("nope.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("neither a preset"), std::string::npos) << msg;
  EXPECT_NE(load_error("no-such-preset").find("no-such-preset"), std::string::npos);
}

TEST_F(MaterialFiles, InvalidJsonNamesTheFile) {
  const std::string path = write("bad.json", R"({"model": "lambert")");
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("invalid JSON"), std::string::npos) << msg;
}

// A number that overflows a double is an InputError naming the file and the number, like any other
// bad JSON: nlohmann::json throws out_of_range (406, "number overflow parsing '1e999'") for it, not
// parse_error, and no other exception may escape (the CLI would abort instead of exiting 2).
TEST_F(MaterialFiles, OverflowingNumberIsAnInputError) {
  const std::string path = write("huge.json", R"({"model": "lambert", "kd": 1e999})");
  std::string msg;
  try {
    (void)load_material(path);
    FAIL() << "1e999 accepted";
  } catch (const InputError& e) {
    msg = e.what();
  } catch (const std::exception& e) {
    FAIL() << "not an InputError: " << e.what();
  }
  EXPECT_NE(msg.find("huge.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1e999"), std::string::npos) << msg;
}

// --- anisotropic pairs (docs/conventions.md, "Anisotropic pairs") -------------------------------

TEST(AnisotropicPairs, HalfAPairNamesThePartner) {
  // Half a pair is an error naming the missing half, never evaluated with the other half's default.
  EXPECT_TRUE(contains(parse_error_of({{"model", "ashikhmin-shirley"}, {"rd", 0.1}, {"rs", 0.2}, {"n_u", 10}}),
                       "key \"n_u\": given without its partner \"n_v\""));
  EXPECT_TRUE(contains(parse_error_of({{"model", "ward"}, {"alpha_y", 0.2}}), "partner \"alpha_x\""));
  EXPECT_TRUE(contains(parse_error_of({{"model", "ggx"}, {"alpha_x", 0.2}}), "partner \"alpha_y\""));
  EXPECT_TRUE(
      contains(parse_error_of({{"model", "lafortune"}, {"lobes", json::array({{{"cx", -1}, {"n", 5}}})}}), "partner \"cy\""));
  EXPECT_TRUE(contains(parse_error_of({{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}, {"alpha_x", 0.1}}}}),
                       "partner \"alpha_y\""));
  EXPECT_TRUE(
      contains(parse_error_of(
                   {{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ward"}}}, {"directional_diffuse", {{"cy", -1}}}}),
               "partner \"cx\""));
  // The message offers the shorthand.
  EXPECT_TRUE(contains(parse_error_of({{"model", "ward"}, {"alpha_x", 0.2}}), "or \"alpha\" alone"));
}

TEST(AnisotropicPairs, ShorthandSetsBothAndExcludesThem) {
  const MaterialDesc w = parse_material({{"model", "ward"}, {"alpha", 0.3}}, "m");
  EXPECT_EQ(w.params.scalar("alpha_x"), 0.3);
  EXPECT_EQ(w.params.scalar("alpha_y"), 0.3);
  EXPECT_FALSE(w.params.has("alpha"));
  const MaterialDesc a = parse_material({{"model", "ashikhmin-shirley"}, {"n", 40}}, "m");
  EXPECT_EQ(a.params.scalar("n_u"), 40.0);
  EXPECT_EQ(a.params.scalar("n_v"), 40.0);
  EXPECT_TRUE(contains(parse_error_of({{"model", "ward"}, {"alpha", 0.3}, {"alpha_x", 0.2}}), "cannot be given together"));
  // Both halves, or neither (both defaults), stay accepted.
  EXPECT_NO_THROW(parse_material({{"model", "ward"}, {"alpha_x", 0.1}, {"alpha_y", 0.3}}, "m"));
  EXPECT_NO_THROW(parse_material({{"model", "ward"}}, "m"));
}

// --- JSON documents -------------------------------------------------------------------------------

TEST(JsonRead, DuplicateKeysAreErrorsNamingKeyAndPath) {
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"alpha_x": 0.1, "alpha_x": 0.5})", "f.json"); }),
                       "f.json: alpha_x: duplicate key \"alpha_x\""));
  // An error whichever of the two values comes first (so neither is checked against the range alone).
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"kd": 2, "kd": 0.5})", "f"); }), "duplicate key \"kd\""));
  EXPECT_TRUE(
      contains(error_of([] { parse_json_text(R"({"model": "ward", "model": "lambert"})", "f"); }), "duplicate key \"model\""));
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"lobes": [{"n": 1}, {"n": 2, "n": 3}]})", "f"); }),
                       "lobes[1].n: duplicate key"));
  // The same key in different objects is fine.
  EXPECT_NO_THROW(parse_json_text(R"({"a": {"n": 1}, "b": {"n": 2}, "c": [{"n": 1}, {"n": 2}]})", "f"));
}

TEST(JsonRead, DeepNestingIsRejectedNotACrash) {
  // 200,000 levels of arrays: an error naming the depth, not a stack overflow in a recursive copy
  // (fuzz/corpus/material/defect-deep-nesting.json).
  std::string deep = R"({"model": "lambert", "zz": )";
  deep += std::string(200000, '[') + std::string(200000, ']') + "}";
  const std::string msg = error_of([&] { load_material(deep); });
  EXPECT_TRUE(contains(msg, "inline material")) << msg;
  EXPECT_TRUE(contains(msg, "nested deeper than 64 levels")) << msg;
  // 60 levels are still read (and then rejected as an unknown key, by the material reader).
  std::string ok = R"({"model": "lambert", "zz": )" + std::string(60, '[') + std::string(60, ']') + "}";
  EXPECT_TRUE(contains(error_of([&] { load_material(ok); }), "unknown key \"zz\""));
}

TEST(JsonRead, ControlCharactersInKeysAreEscaped) {
  const std::string msg = parse_error_of(json::parse("{\"model\": \"lambert\", \"a\\u0000b\\u001b[31m\": 1}"));
  EXPECT_TRUE(contains(msg, "a\\u0000b\\u001b[31m")) << msg;  // the whole key, escaped
  EXPECT_EQ(msg.find('\x1b'), std::string::npos);
}

TEST(JsonRead, FileKindsHaveTheirOwnMessages) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("aniso-json-read-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  EXPECT_TRUE(contains(error_of([&] { read_json_file((dir / "missing.json").string()); }), "no such file"));
  EXPECT_TRUE(contains(error_of([&] { read_json_file(dir.string()); }), "is a directory"));
  std::ofstream(dir / "bad.json") << "{\"model\": ";
  EXPECT_TRUE(contains(error_of([&] { read_json_file((dir / "bad.json").string()); }), "invalid JSON"));
  // A FIFO is read like a file (`-m <(...)` passes /dev/fd/N, a pipe).
  const std::filesystem::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << R"({"model": "lambert", "kd": 0.25})"; });
  const MaterialDesc d = load_material(fifo.string());
  writer.join();
  EXPECT_EQ(d.params.color("kd"), glm::dvec3(0.25));
  std::filesystem::remove_all(dir);
}

// --- materials: inline, names, resolved form ---------------------------------------------------

TEST(MaterialSpec, InlineJsonAndNames) {
  const MaterialDesc d = load_material(R"({"model": "ward", "alpha_x": 0.1, "alpha_y": 0.3})");
  EXPECT_EQ(d.params.scalar("alpha_y"), 0.3);
  EXPECT_TRUE(contains(error_of([] { load_material(R"({"model": "ward", "alpha": 7})"); }), "inline material: key \"alpha\""));
  EXPECT_TRUE(contains(error_of([] { load_material("gld"); }), "did you mean \"gold\""));
  EXPECT_TRUE(contains(error_of([] { load_material(""); }), "empty name"));
  // The American spelling is an alias (docs/presets.md).
  EXPECT_NO_THROW(load_material("aluminum"));
  EXPECT_NO_THROW(load_material("brushed-aluminum"));
  EXPECT_NO_THROW(parse_material({{"model", "metal"}, {"metal", "aluminum"}, {"lobe", {{"model", "ggx"}}}}, "m"));
  EXPECT_TRUE(
      contains(parse_error_of({{"model", "metal"}, {"metal", "gld"}, {"lobe", {{"model", "ggx"}}}}), "did you mean \"gold\""));
}

TEST(MaterialSpec, ResolvedJsonIsValidInputGivingTheSameMaterial) {
  Rng rng(11);
  for (const PresetInfo& p : presets()) {
    const MaterialDesc d = load_material(p.name);
    const json r = resolved_json(d);
    const MaterialDesc again = parse_material(r, "resolved " + p.name);
    const MaterialD a = build_material<double>(d), b = build_material<double>(again);
    for (int i = 0; i < 8; ++i) {
      const Vec3d wi = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() + 0.05));
      const Vec3d wo = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() + 0.05));
      ASSERT_EQ(a.f(wi, wo), b.f(wi, wo)) << p.name;
    }
    ASSERT_EQ(resolved_json(again), r) << p.name;  // a fixed point
  }
}

TEST(MaterialSpec, NegativeZeroReadsAsZero) {
  const MaterialDesc d = parse_material({{"model", "lambert"}, {"kd", -0.0}}, "m");
  EXPECT_FALSE(std::signbit(d.params.color("kd").x));
}

}  // namespace
}  // namespace aniso
