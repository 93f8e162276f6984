// io/materials.cpp: the JSON reader (generic, driven by the tables) and one builder per model.
#include "aniso/io/materials.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "aniso/io/presets.h"
#include "aniso/measured/measured.h"
#include "aniso/rgl/rgl_material.h"
#include "io/enum_names.h"
#include "io/json_read.h"

namespace aniso {

std::string json_type_name(const nlohmann::json& v) {
  if (v.is_number()) return fmt::format("the number {}", v.dump());
  if (v.is_string()) return fmt::format("the string {}", v.dump());
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_array()) return fmt::format("an array of {} elements", v.size());
  if (v.is_object()) return "an object";
  return "null";
}

namespace {

using nlohmann::json;

bool in_range(const ParamSpec& p, double x) {
  if (!std::isfinite(x)) return false;
  if (p.min_exclusive ? !(x > p.min) : !(x >= p.min)) return false;
  return x <= p.max;
}

[[noreturn]] void fail(const std::string& where, std::string_view key, const std::string& what) {
  throw InputError(fmt::format("{}: key \"{}\": {}", where, key, what));
}

ParamValue read_value(const json& v, const ParamSpec& p, const std::string& where) {
  const auto expected = [&] { return fmt::format("expected {}, got {}", describe_range(p), json_type_name(v)); };
  switch (p.kind) {
    case ParamKind::Scalar:
      if (!v.is_number() || !in_range(p, v.get<double>())) fail(where, p.name, expected());
      return v.get<double>() + 0.0;  // + 0.0 turns -0 into +0 (docs/conventions.md, "Numbers")
    case ParamKind::Color: {
      if (v.is_number()) {
        if (!in_range(p, v.get<double>())) fail(where, p.name, expected());
        return glm::dvec3(v.get<double>() + 0.0);
      }
      if (!v.is_array() || v.size() != 3) fail(where, p.name, expected());
      glm::dvec3 c;
      for (int i = 0; i < 3; ++i) {
        if (!v[i].is_number() || !in_range(p, v[i].get<double>()))
          fail(where, p.name, fmt::format("element {}: expected {}, got {}", i, describe_range(p), json_type_name(v[i])));
        c[i] = v[i].get<double>() + 0.0;
      }
      return c;
    }
    case ParamKind::Bool:
      if (!v.is_boolean()) fail(where, p.name, expected());
      return v.get<bool>();
    case ParamKind::Choice:
    case ParamKind::String: {
      if (!v.is_string()) fail(where, p.name, expected());
      const std::string s = v.get<std::string>();
      if (p.kind == ParamKind::Choice) {
        bool ok = false;
        for (auto c : p.choices) ok = ok || c == s;
        if (!ok) fail(where, p.name, expected());
      }
      return s;
    }
    case ParamKind::Object:
      if (!v.is_object()) fail(where, p.name, expected());
      return std::make_shared<ParamValues>(read_params(v, *p.sub, fmt::format("{}: {}", where, p.name)));
    case ParamKind::TaggedObject: {
      if (!v.is_object()) fail(where, p.name, expected());
      const auto it = v.find("model");
      if (it == v.end() || !it->is_string()) fail(where, fmt::format("{}.model", p.name), expected());
      const std::string model = it->get<std::string>();
      bool ok = false;
      for (auto c : p.choices) ok = ok || c == model;
      if (!ok) fail(where, fmt::format("{}.model", p.name), expected());
      auto out =
          std::make_shared<ParamValues>(read_params(v, metal_lobe_spec(model), fmt::format("{}: {}", where, p.name), "model"));
      out->values["model"] = model;
      return out;
    }
    case ParamKind::List: {
      if (!v.is_array() || v.empty() || static_cast<int>(v.size()) > p.max_items) fail(where, p.name, expected());
      std::vector<ParamValues> items;
      for (size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_object())
          fail(where, fmt::format("{}[{}]", p.name, i), fmt::format("expected an object, got {}", json_type_name(v[i])));
        items.push_back(read_params(v[i], *p.sub, fmt::format("{}: {}[{}]", where, p.name, i)));
      }
      return items;
    }
  }
  fail(where, p.name, "unsupported parameter kind");
}

std::string allowed_keys(const ModelSpec& spec) {
  std::string s;
  for (const ParamSpec* p : spec.params()) s += fmt::format("{}\"{}\"", s.empty() ? "" : ", ", p->name);
  return s;
}

// Anisotropic pairs and their shorthands (docs/conventions.md, "Anisotropic pairs"): a shorthand
// ("alpha", "n", "cxy") sets both halves and excludes them; a half given without its partner is an
// error naming the partner (a default the user never sees would make the material anisotropic).
void resolve_pairs(ParamValues& pv, const json& obj, const ModelSpec& spec) {
  for (const ParamSpec* p : spec.params()) {
    if (p->sets[0].empty() || !obj.contains(p->name)) continue;
    for (const std::string_view half : p->sets)
      if (obj.contains(half))
        pv.fail(p->name,
                fmt::format("sets \"{}\" and \"{}\": cannot be given together with \"{}\"", p->sets[0], p->sets[1], half));
    const ParamValue v = pv.values.at(std::string(p->name));
    pv.values[std::string(p->sets[0])] = v;
    pv.values[std::string(p->sets[1])] = v;
    pv.values.erase(std::string(p->name));
  }
  for (const ParamSpec* p : spec.params()) {
    if (p->partner.empty() || !obj.contains(p->name) || obj.contains(p->partner)) continue;
    std::string shorthand;
    for (const ParamSpec* q : spec.params())
      if (q->sets[0] == p->name || q->sets[1] == p->name)
        shorthand = fmt::format(", or \"{}\" alone for an isotropic value", q->name);
    pv.fail(p->name, fmt::format("given without its partner \"{}\": give both{}", p->partner, shorthand));
  }
}

}  // namespace

ParamValues read_params(const json& obj, const ModelSpec& spec, const std::string& where, std::string_view tag_key) {
  ParamValues pv;
  pv.where = where;
  if (!obj.is_object()) throw InputError(fmt::format("{}: expected a JSON object, got {}", where, json_type_name(obj)));
  for (const auto& [key, value] : obj.items()) {
    if (key == tag_key) continue;  // "model": read by the caller
    // rotation_deg on a model without it: an isotropic model, where turning the tangent changes nothing.
    if (!spec.find(key) && key == "rotation_deg" && tag_key == "model") {
      std::string oriented;
      for (const ModelSpec* m : model_specs())
        if (m->find("rotation_deg")) oriented += fmt::format("{}{}", oriented.empty() ? "" : ", ", m->name);
      if (spec.name == "rgl")
        throw InputError(
            fmt::format("{}: key \"rotation_deg\": a tensor file is tabulated in its own frame and has no "
                        "rotation key; turn the surface's tangent instead (a scene's tangent.angle_deg)",
                        where));
      throw InputError(
          fmt::format("{}: key \"rotation_deg\": {} is isotropic, so turning its tangent has no effect; remove "
                      "the key (the anisotropic models take it: {})",
                      where, spec.name, oriented));
    }
    if (!spec.find(key))
      throw InputError(
          fmt::format("{}: unknown key \"{}\" for {}; allowed keys: {}", where, text_escape(key), spec.name, allowed_keys(spec)));
  }
  for (const ParamSpec* p : spec.params()) {
    const auto it = obj.find(p->name);
    if (it != obj.end()) {
      pv.values[std::string(p->name)] = read_value(*it, *p, where);
      continue;
    }
    if (p->required) fail(where, p->name, fmt::format("missing (required; {})", describe_range(*p)));
    switch (p->kind) {
      case ParamKind::Scalar:
        if (!std::isnan(p->default_value)) pv.values[std::string(p->name)] = p->default_value;
        break;
      case ParamKind::Color:
        if (!std::isnan(p->default_value)) pv.values[std::string(p->name)] = glm::dvec3(p->default_value);
        break;
      case ParamKind::Bool: pv.values[std::string(p->name)] = p->default_value != 0.0; break;
      case ParamKind::Choice: pv.values[std::string(p->name)] = std::string(p->choices[0]); break;
      default: break;  // optional objects, strings and lists have no default: absent
    }
  }
  resolve_pairs(pv, obj, spec);
  return pv;
}

MaterialDesc parse_material(const json& obj, const std::string& where, const std::string& base_dir) {
  if (!obj.is_object()) throw InputError(fmt::format("{}: expected a JSON object, got {}", where, json_type_name(obj)));
  const auto it = obj.find("model");
  std::string models;
  for (const ModelSpec* m : model_specs()) models += fmt::format("{}\"{}\"", models.empty() ? "" : ", ", m->name);
  if (it == obj.end()) throw InputError(fmt::format("{}: key \"model\": missing; expected one of {}", where, models));
  if (!it->is_string() || !find_model_spec(it->get<std::string>()))
    throw InputError(fmt::format("{}: key \"model\": expected one of {}, got {}", where, models, json_type_name(*it)));
  MaterialDesc d;
  d.model = it->get<std::string>();
  // "fit": the error figures and provenance `aniso fit` writes beside the material
  // (docs/fitting.md). Accepted (an object) and ignored: it does not change the material.
  const auto fit = obj.find("fit");
  if (fit != obj.end() && !fit->is_object())
    throw InputError(fmt::format("{}: key \"fit\": expected an object (the provenance `aniso fit` writes), got {}", where,
                                 json_type_name(*fit)));
  if (fit != obj.end()) {
    json body = obj;
    body.erase("fit");
    d.params = read_params(body, *find_model_spec(d.model), where, "model");
  } else {
    d.params = read_params(obj, *find_model_spec(d.model), where, "model");
  }
  d.json = obj;
  // Cross-key rules the tables cannot express.
  if (d.model == "lafortune") {
    // A lobe's value is at most scale max|C|^n (the base is C . (wi * wo) <= max|C| by
    // Cauchy-Schwarz); beyond 1e30 the float kernels overflow (float max 3.4e38, with room for the
    // sums and the sampling weights).
    const auto& lobes = d.params.list("lobes");
    for (size_t i = 0; i < lobes.size(); ++i) {
      const ParamValues& l = lobes[i];
      for (int c = 0; c < 3; ++c) {
        const double cmax = std::max({std::abs(l.color("cx")[c]), std::abs(l.color("cy")[c]), std::abs(l.color("cz")[c])});
        const double log10_peak =
            l.color("n")[c] * std::log10(std::max(cmax, 1e-300)) + std::log10(std::max(l.color("scale")[c], 1e-300));
        if (log10_peak > 30.0)
          l.fail("n", fmt::format("with max|C| = {:g} and scale {:g}, channel {} reaches {:g}^{:g}, beyond the float range "
                                  "(the peak scale max|C|^n must stay below 1e30: lower n or |C|)",
                                  cmax, l.color("scale")[c], c, cmax, l.color("n")[c]));
      }
    }
  }
  if (d.model == "measured") {
    const std::string& file = d.params.text("file");
    if (file.empty()) d.params.fail("file", "expected the path of a MERL .binary file, got an empty string");
    namespace fs = std::filesystem;
    const fs::path p = base_dir.empty() || fs::path(file).is_absolute() ? fs::path(file) : fs::path(base_dir) / file;
    d.measured = load_measured(p.string());  // InputError naming the file and the byte offset
  }
  if (d.model == "rgl") {
    const std::string& file = d.params.text("file");
    if (file.empty()) d.params.fail("file", "expected the path of an RGL .bsdf tensor file, got an empty string");
    namespace fs = std::filesystem;
    const fs::path p = base_dir.empty() || fs::path(file).is_absolute() ? fs::path(file) : fs::path(base_dir) / file;
    d.rgl = rgl::load_rgl(p.string());  // InputError naming the file, the field and the problem
  }
  if (d.model == "metal") {
    const bool named = d.params.has("metal"), custom = d.params.has("eta") || d.params.has("k");
    if (named && custom) d.params.fail("metal", "give either \"metal\" or \"eta\" and \"k\", not both");
    if (!named && !(d.params.has("eta") && d.params.has("k")))
      d.params.fail(d.params.has("eta") ? "k" : (d.params.has("k") ? "eta" : "metal"),
                    "missing: a metal needs \"metal\" (a name) or both \"eta\" and \"k\"");
    if (named && !find_metal(d.params.text("metal"))) d.params.fail("metal", unknown_metal_message(d.params.text("metal")));
  }
  return d;
}

MaterialDesc load_material(const std::string& spec) {
  // An inline JSON object (scripts, and users of Mitsuba's dict API, pass materials this way).
  const size_t first = spec.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && spec[first] == '{')
    return parse_material(parse_json_text(spec, "inline material"), "inline material");
  if (const auto preset = find_preset(spec)) return parse_material(*preset, fmt::format("preset {}", spec));
  if (spec.empty()) throw InputError("material: empty name; expected a preset name, a JSON file or an inline JSON object");
  namespace fs = std::filesystem;
  // A MERL file: read_merl names the file and the problem (missing, a directory, a bad header...).
  if (is_measured_file_name(spec)) return parse_material(json{{"model", "measured"}, {"file", spec}}, spec);
  if (rgl::is_rgl_file_name(spec)) return parse_material(json{{"model", "rgl"}, {"file", spec}}, spec);
  std::error_code ec;
  if (!fs::exists(spec, ec)) {
    // Neither a preset nor a file: suggest the nearest preset names.
    const std::string near = nearest_preset_names(spec);
    throw InputError(fmt::format("material \"{}\": neither a preset (see `aniso presets`) nor an existing file{}",
                                 text_escape(spec), near.empty() ? "" : fmt::format("; did you mean {}?", near)));
  }
  return parse_material(read_json_file(spec), spec, fs::path(spec).parent_path().string());
}

bool is_measured_file_name(const std::string& spec) {
  const size_t n = spec.size();
  if (n < 7) return false;
  std::string ext = spec.substr(n - 7);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".binary";
}

namespace {

json values_to_json(const ParamValues& pv) {
  json out = json::object();
  for (const auto& [key, v] : pv.values) {
    if (const double* d = std::get_if<double>(&v))
      out[key] = *d;
    else if (const glm::dvec3* c = std::get_if<glm::dvec3>(&v)) {
      if (c->x == c->y && c->y == c->z)
        out[key] = c->x;  // grey: one number, as the presets write it
      else
        out[key] = {c->x, c->y, c->z};
    } else if (const bool* b = std::get_if<bool>(&v))
      out[key] = *b;
    else if (const std::string* s = std::get_if<std::string>(&v))
      out[key] = *s;
    else if (const auto* o = std::get_if<std::shared_ptr<ParamValues>>(&v))
      out[key] = values_to_json(**o);
    else if (const auto* l = std::get_if<std::vector<ParamValues>>(&v)) {
      json arr = json::array();
      for (const ParamValues& item : *l) arr.push_back(values_to_json(item));
      out[key] = std::move(arr);
    }
  }
  return out;
}

}  // namespace

json resolved_json(const MaterialDesc& d) {
  json out = values_to_json(d.params);
  out["model"] = d.model;
  return out;
}

// --- builders: one per model, each a plain copy from the validated values --------------------

namespace {

template <typename T> RGBT<T> rgb(const glm::dvec3& c) { return RGBT<T>(T(c.x), T(c.y), T(c.z)); }

template <typename T> WardLobeT<T> build_ward_lobe(const ParamValues& p) {
  WardLobeT<T> l;
  l.alpha_x = T(p.scalar("alpha_x"));
  l.alpha_y = T(p.scalar("alpha_y"));
  // The reader checked the names against the same tables (params.cpp: the choices).
  l.form = *enum_from_name<WardForm>(p.text("form"));
  l.normalization = *enum_from_name<WardNormalization>(p.text("normalization"));
  return l;
}

template <typename T> LafortuneLobeT<T> build_lafortune_lobe(const ParamValues& p) {
  LafortuneLobeT<T> l;
  l.cx = rgb<T>(p.color("cx"));
  l.cy = rgb<T>(p.color("cy"));
  l.cz = rgb<T>(p.color("cz"));
  l.n = rgb<T>(p.color("n"));
  l.scale = rgb<T>(p.color("scale"));
  return l;
}

template <typename T> MetalT<T> build(ModelType<MetalT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  MetalT<T> m;
  if (p.has("metal")) {
    const MetalData* md = find_metal(p.text("metal"));
    m.eta = rgb<T>(md->eta);
    m.k = rgb<T>(md->k);
  } else {
    m.eta = rgb<T>(p.color("eta"));
    m.k = rgb<T>(p.color("k"));
  }
  const ParamValues& lobe = p.object("lobe");
  m.lobe_kind = *enum_from_name<SpecularLobeKind>(lobe.text("model"));
  switch (m.lobe_kind) {
    case SpecularLobeKind::Ward: m.ward = build_ward_lobe<T>(lobe); break;
    case SpecularLobeKind::AshikhminShirley:
      m.ashikhmin_shirley.n_u = T(lobe.scalar("n_u"));
      m.ashikhmin_shirley.n_v = T(lobe.scalar("n_v"));
      break;
    case SpecularLobeKind::GGX:
      m.ggx.alpha_x = T(lobe.scalar("alpha_x"));
      m.ggx.alpha_y = T(lobe.scalar("alpha_y"));
      break;
  }
  if (p.has("directional_diffuse")) {
    // Ngan et al. 2005's Lafortune normalisation, (n + 2) / (2 pi max|C|^n), folded in: dividing C by
    // max|C| keeps the lobe's peak at 1 without computing max|C|^n (which underflows for large n),
    // and the scale becomes albedo F0 (n + 2) / (2 pi), coloured by the metal's F0.
    const ParamValues& dd = p.object("directional_diffuse");
    const double cx = dd.scalar("cx"), cy = dd.scalar("cy"), cz = dd.scalar("cz"), n = dd.scalar("n");
    const double cmax = std::max({std::abs(cx), std::abs(cy), std::abs(cz)});
    if (!(cmax > 0.0)) dd.fail("cz", "the lobe needs at least one non-zero coefficient");
    const RGBT<T> f0 = F_Conductor(T(1), m.eta, m.k);
    m.has_directional_diffuse = true;
    m.directional_diffuse.cx = RGBT<T>(T(cx / cmax));
    m.directional_diffuse.cy = RGBT<T>(T(cy / cmax));
    m.directional_diffuse.cz = RGBT<T>(T(cz / cmax));
    m.directional_diffuse.n = RGBT<T>(T(n));
    m.directional_diffuse.scale = rgb<T>(dd.color("albedo")) * f0 * T((n + 2.0) / (2.0 * M_PI));
    // The directional lobe's energy is taken from the specular lobe: (1 - albedo) F spec + albedo F0
    // lobe keeps the albedo <= 1 whenever both lobes are bounded (docs/models/metal.md).
    m.specular_weight = RGBT<T>(T(1)) - rgb<T>(dd.color("albedo"));
  }
  return m;
}

template <typename T> LambertT<T> build(ModelType<LambertT<T>>, const MaterialDesc& d) {
  LambertT<T> m;
  m.kd = rgb<T>(d.params.color("kd"));
  return m;
}

template <typename T> PhongT<T> build(ModelType<PhongT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  PhongT<T> m;
  m.kd = rgb<T>(p.color("kd"));
  m.ks = rgb<T>(p.color("ks"));
  m.lobe.exponent = T(p.scalar("exponent"));
  m.lobe.normalized = p.boolean("normalized");
  return m;
}

template <typename T> WardT<T> build(ModelType<WardT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  WardT<T> m;
  m.kd = rgb<T>(p.color("kd"));
  m.ks = rgb<T>(p.color("ks"));
  m.lobe = build_ward_lobe<T>(p);
  return m;
}

template <typename T> AshikhminShirleyT<T> build(ModelType<AshikhminShirleyT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  AshikhminShirleyT<T> m;
  m.rd = rgb<T>(p.color("rd"));
  m.rs = rgb<T>(p.color("rs"));
  m.kd = rgb<T>(p.color("kd"));
  m.ks_scale = rgb<T>(p.color("ks_scale"));
  m.lobe.n_u = T(p.scalar("n_u"));
  m.lobe.n_v = T(p.scalar("n_v"));
  return m;
}

template <typename T> LafortuneT<T> build(ModelType<LafortuneT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  LafortuneT<T> m;
  m.rho_d = rgb<T>(p.color("rho_d"));
  const auto& lobes = p.list("lobes");
  m.lobe_count = static_cast<int>(lobes.size());
  for (size_t i = 0; i < lobes.size(); ++i) m.lobes[i] = build_lafortune_lobe<T>(lobes[i]);
  return m;
}

template <typename T> GGXT<T> build(ModelType<GGXT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  GGXT<T> m;
  m.kd = rgb<T>(p.color("kd"));
  m.f0 = rgb<T>(p.color("f0"));
  m.lobe.alpha_x = T(p.scalar("alpha_x"));
  m.lobe.alpha_y = T(p.scalar("alpha_y"));
  return m;
}

template <typename T> PrincipledT<T> build(ModelType<PrincipledT<T>>, const MaterialDesc& d) {
  const ParamValues& p = d.params;
  PrincipledT<T> m;
  m.base_color = rgb<T>(p.color("base_color"));
  m.metallic = T(p.scalar("metallic"));
  m.subsurface = T(p.scalar("subsurface"));
  m.specular = T(p.scalar("specular"));
  m.roughness = T(p.scalar("roughness"));
  m.specular_tint = T(p.scalar("specular_tint"));
  m.anisotropic = T(p.scalar("anisotropic"));
  m.sheen = T(p.scalar("sheen"));
  m.sheen_tint = T(p.scalar("sheen_tint"));
  m.clearcoat = T(p.scalar("clearcoat"));
  m.clearcoat_gloss = T(p.scalar("clearcoat_gloss"));
  return m;
}

template <typename T> RglT<T> build(ModelType<RglT<T>>, const MaterialDesc& d) {
  if (!d.rgl) throw InputError(fmt::format("{}: rgl material without its tensor file", d.params.where));
  return rgl::rgl_kernel<T>(*d.rgl);
}

template <typename T> MeasuredT<T> build(ModelType<MeasuredT<T>>, const MaterialDesc& d) {
  if (!d.measured) throw InputError(fmt::format("{}: measured material without its table", d.params.where));
  return measured_kernel<T>(*d.measured);
}

}  // namespace

// One builder per registry row: build(ModelType<Type<T>>, desc) above (a row without one does
// not compile).
template <typename T> MaterialT<T> build_material(const MaterialDesc& d) {
  const std::optional<ModelKind> kind = find_model_kind(d.model);
  if (!kind) throw InputError(fmt::format("{}: model \"{}\" is not a registered model", d.params.where, d.model));
  MaterialT<T> m = visit_kind<T>(*kind, [&](auto type) { return MaterialT<T>(build(type, d)); });
  // The anisotropic models' orientation (kOrientation in params.cpp), computed in double.
  if (d.params.has("rotation_deg")) {
    const FrameRotationT<double> r = frame_rotation_deg(d.params.scalar("rotation_deg"));
    m.rotation = FrameRotationT<T>{T(r.c), T(r.s)};
  }
  return m;
}

template MaterialT<float> build_material<float>(const MaterialDesc&);
template MaterialT<double> build_material<double>(const MaterialDesc&);

}  // namespace aniso
