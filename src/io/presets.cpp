#include "aniso/io/presets.h"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "aniso/brdf/fresnel.h"
#include "aniso/data/fits.h"
#include "aniso/data/metals.h"
#include "aniso/io/params.h"
#include "io/names.h"

namespace aniso {
namespace {

using nlohmann::json;

double to_double(const std::string& s, std::string_view where) {
  try {
    size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw InputError(fmt::format("{}: expected a number, got \"{}\"", where, s));
  }
}

json rgb(const CsvRow& r, size_t first, std::string_view where) {
  return json::array({to_double(r[first], where), to_double(r[first + 1], where), to_double(r[first + 2], where)});
}

// The lecture's "matte steel" (VGP352 week 5, from Lafortune et al. 1997); no diffuse term given.
json matte_steel() {
  const double t[9][3] = {{-1.11954, 1.01272, 15.8708}, {-1.11845, 1.01469, 15.6489},  {-1.11999, 1.01942, 15.4571},
                          {-1.05334, 0.69541, 111.267}, {-1.06409, 0.662178, 88.9222}, {-1.08378, 0.626672, 65.2179},
                          {-1.01684, 1.00132, 180.181}, {-1.01635, 1.00112, 184.152},  {-1.01529, 1.00108, 195.773}};
  json lobes = json::array();
  for (int lobe = 0; lobe < 3; ++lobe) {
    json cxy = json::array(), cz = json::array(), n = json::array();
    for (int c = 0; c < 3; ++c) {
      cxy.push_back(t[3 * lobe + c][0]);
      cz.push_back(t[3 * lobe + c][1]);
      n.push_back(t[3 * lobe + c][2]);
    }
    lobes.push_back({{"cxy", cxy}, {"cz", cz}, {"n", n}});
  }
  return {{"model", "lafortune"}, {"rho_d", 0.0}, {"lobes", lobes}};
}

void add_pbrt_v1(std::vector<PresetInfo>& out) {
  std::map<std::string, json> by_name;
  std::vector<std::string> order;
  for (const CsvRow& r : pbrt_v1_lafortune_rows()) {
    const std::string where = fmt::format("pbrt-v1 fit {} {}", r[0], r[1]);
    if (!by_name.count(r[0])) {
      order.push_back(r[0]);
      by_name[r[0]] = {{"model", "lafortune"}, {"lobes", json::array()}};
    }
    json& m = by_name[r[0]];
    if (r[1] == "R_diffuse") {
      m["rho_d"] = rgb(r, 3, where);
      continue;
    }
    const size_t lobe = static_cast<size_t>(to_double(r[2], where));
    while (m["lobes"].size() <= lobe) m["lobes"].push_back(json::object());
    const std::string key = r[1] == "Cxy" ? "cxy" : (r[1] == "Cz" ? "cz" : "n");
    m["lobes"][lobe][key] = rgb(r, 3, where);
  }
  for (const auto& name : order)
    out.push_back({name, "pbrt-v1 Lafortune fit of a Cornell measurement (data/fits/lafortune-pbrt-v1)", by_name[name]});
}

std::map<std::string, double> parse_params(const std::string& s, std::string_view where) {
  std::map<std::string, double> out;
  size_t start = 0;
  while (start < s.size()) {
    const size_t semi = s.find(';', start);
    const std::string kv = s.substr(start, semi == std::string::npos ? std::string::npos : semi - start);
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) throw InputError(fmt::format("{}: expected key=value, got \"{}\"", where, kv));
    out[kv.substr(0, eq)] = to_double(kv.substr(eq + 1), where);
    if (semi == std::string::npos) break;
    start = semi + 1;
  }
  return out;
}

// Ngan, Durand & Matusik 2005 as evaluated by bbm (include/bsdfmodel/ngan.h): a Lambertian kd / pi
// plus one specular model scaled by ks, all isotropic (docs/presets.md gives each formula).
void add_ngan(std::vector<PresetInfo>& out) {
  for (const CsvRow& r : ngan2005_rows()) {
    const std::string where = fmt::format("Ngan 2005 fit {}/{}", r[0], r[1]);
    const json kd = rgb(r, 2, where), ks = rgb(r, 5, where);
    const auto p = parse_params(r[8], where);
    const auto param = [&](const char* key) {
      const auto it = p.find(key);
      if (it == p.end()) throw InputError(fmt::format("{}: parameter {} missing", where, key));
      return it->second;
    };
    json m;
    if (r[0] == "ward" || r[0] == "wardduer") {
      m = {{"model", "ward"},
           {"kd", kd},
           {"ks", ks},
           {"alpha_x", param("roughness")},
           {"alpha_y", param("roughness")},
           {"form", "vector"},
           {"normalization", r[0] == "ward" ? "ward" : "duer"}};
    } else if (r[0] == "blinnphong") {
      // bbm's NganBlinnPhong is the modified Phong about the mirror direction, (n + 2) / (2 pi).
      m = {{"model", "phong"}, {"kd", kd}, {"ks", ks}, {"exponent", param("sharpness")}, {"normalized", true}};
    } else if (r[0] == "lafortune") {
      // Ngan's lobe: ks (n + 2) / (2 pi max(|Cz|, |Cxy|)^n) max(C . (wi * wo), 0)^n. Folded into our
      // lobe as C / max|C| and scale ks (n + 2) / (2 pi): equal, without max|C|^n underflowing.
      const double cxy = param("Cxy"), cz = param("Cz"), n = param("sharpness");
      const double cmax = std::max(std::abs(cxy), std::abs(cz));
      const double norm = (n + 2.0) / (2.0 * M_PI);
      json scale = json::array();
      for (int c = 0; c < 3; ++c) scale.push_back(ks[c].get<double>() * norm);
      m = {{"model", "lafortune"},
           {"rho_d", kd},
           {"lobes", json::array({{{"cxy", cxy / cmax}, {"cz", cz / cmax}, {"n", n}, {"scale", scale}}})}};
    } else if (r[0] == "ashikhminshirley") {
      // Lambertian kd plus ks times the AS specular term with Schlick F0; no coupled diffuse term.
      m = {{"model", "ashikhmin-shirley"},
           {"rd", 0.0},
           {"rs", param("fresnelReflectance")},
           {"kd", kd},
           {"ks_scale", ks},
           {"n_u", param("sharpness")},
           {"n_v", param("sharpness")}};
    } else {
      continue;  // cooktorrance, he: models aniso does not implement (yet); see docs/presets.md
    }
    out.push_back({fmt::format("ngan/{}/{}", r[0], r[1]), "Ngan, Durand & Matusik 2005 fit of MERL (via bbm)", m});
  }
}

void add_metals(std::vector<PresetInfo>& out) {
  for (const MetalData& md : metal_table()) {
    const std::string name(md.name);
    out.push_back({name,
                   fmt::format("polished {}: GGX alpha 0.1, measured n, k ({})", name, md.source),
                   {{"model", "metal"}, {"metal", name}, {"lobe", {{"model", "ggx"}, {"alpha_x", 0.1}, {"alpha_y", 0.1}}}}});
    out.push_back({"brushed-" + name,
                   fmt::format("{} brushed along the tangent: balanced Ward 0.05 x 0.3 + directional diffuse", name),
                   {{"model", "metal"},
                    {"metal", name},
                    {"lobe", {{"model", "ward"}, {"alpha_x", 0.05}, {"alpha_y", 0.3}, {"normalization", "balanced"}}},
                    {"directional_diffuse", {{"albedo", 0.1}, {"n", 4.0}}}}});
  }
}

// A few Disney principled materials (docs/presets.md, "Disney principled"); base colours linear.
void add_principled(std::vector<PresetInfo>& out) {
  out.push_back({"principled/red-plastic",
                 "Disney principled: glossy red plastic (dielectric, F0 0.04)",
                 {{"model", "principled"}, {"base_color", {0.6, 0.05, 0.04}}, {"roughness", 0.3}, {"specular", 0.5}}});
  out.push_back({"principled/car-paint",
                 "Disney principled: blue paint under a glossy clearcoat",
                 {{"model", "principled"},
                  {"base_color", {0.03, 0.08, 0.35}},
                  {"roughness", 0.45},
                  {"metallic", 0.2},
                  {"clearcoat", 1.0},
                  {"clearcoat_gloss", 0.95}}});
  // The base colour of a metal is its F0: aluminium's, from the measured eta and k (metals.md).
  const MetalData* al = find_metal("aluminium");
  const glm::dvec3 f0 = F_Conductor(1.0, RGBT<double>(al->eta), RGBT<double>(al->k));
  out.push_back({"principled/brushed-aluminium",
                 "Disney principled: aluminium (F0 from the metal table) brushed along the tangent",
                 {{"model", "principled"},
                  {"base_color", {f0.x, f0.y, f0.z}},
                  {"metallic", 1.0},
                  {"roughness", 0.35},
                  {"anisotropic", 0.8}}});
  out.push_back({"principled/velvet",
                 "Disney principled: dark red velvet (sheen, subsurface, rough)",
                 {{"model", "principled"},
                  {"base_color", {0.3, 0.02, 0.06}},
                  {"roughness", 0.9},
                  {"specular", 0.2},
                  {"subsurface", 0.5},
                  {"sheen", 1.0},
                  {"sheen_tint", 0.5}}});
}

std::vector<PresetInfo> build_presets() {
  std::vector<PresetInfo> out;
  out.push_back({"matte-steel", "the lecture's 3-lobe Lafortune fit (VGP352 week 5; Lafortune et al. 1997)", matte_steel()});
  add_pbrt_v1(out);
  add_metals(out);
  add_ngan(out);
  add_principled(out);
  return out;
}

}  // namespace

const std::vector<PresetInfo>& presets() {
  static const std::vector<PresetInfo> all = build_presets();
  return all;
}

std::optional<json> find_preset(std::string_view name_in) {
  for (const PresetInfo& p : presets())
    if (p.name == name_in) return p.json;
  const std::string name = canonical_spelling(name_in);  // "aluminum" -> "aluminium" (io/names.h)
  for (const PresetInfo& p : presets())
    if (p.name == name) return p.json;
  return std::nullopt;
}

std::string nearest_preset_names(std::string_view name) {
  std::vector<std::string> names;
  for (const PresetInfo& p : presets()) names.push_back(p.name);
  return nearest_names(name, names);
}

}  // namespace aniso
