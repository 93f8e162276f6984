// io/materials.cpp: the JSON reader, driven by a table (read_params), and the resolved JSON of a
// material. What depends on the model, its table, its rules and its builder, is in its model file
// (src/models/<member>.h; parse_material, load_material and build_material: src/models/models.cpp).
#include "aniso/io/materials.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

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
      const size_t choice = size_t(std::find(p.choices.begin(), p.choices.end(), model) - p.choices.begin());
      auto out = std::make_shared<ParamValues>(read_params(v, *p.tagged[choice], fmt::format("{}: {}", where, p.name), "model"));
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

// A key's value in channel c: a number, or a colour's channel.
double channel(const ParamValues& pv, std::string_view key, int c) {
  const auto it = pv.values.find(key);
  if (it != pv.values.end())
    if (const glm::dvec3* v = std::get_if<glm::dvec3>(&it->second)) return (*v)[c];
  return pv.scalar(key);
}

// The table's cross-key rules (ParamRule), in order; web/validate.js applyRule is their twin.
void apply_rule(const ParamRule& r, const ParamValues& pv) {
  const auto given = [&](std::string_view k) { return !k.empty() && pv.has(k); };
  switch (r.kind) {
    case ParamRule::Kind::Exclusive:
      if (given(r.key) && (given(r.keys[0]) || given(r.keys[1]) || given(r.keys[2]))) pv.fail(r.key, r.message);
      return;
    case ParamRule::Kind::KeyOrAll: {
      if (given(r.key)) return;
      std::string_view missing;
      bool some = false;
      for (const std::string_view k : r.keys) {
        if (k.empty()) continue;
        if (given(k))
          some = true;
        else if (missing.empty())
          missing = k;
      }
      if (!missing.empty()) pv.fail(some ? missing : r.key, r.message);
      return;
    }
    case ParamRule::Kind::NonZero: {
      double largest = 0.0;
      for (const std::string_view k : r.keys)
        if (!k.empty())
          for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(channel(pv, k, c)));
      if (!(largest > 0.0)) pv.fail(r.key, r.message);
      return;
    }
    case ParamRule::Kind::PeakBelow:
      for (int c = 0; c < 3; ++c) {
        double cmax = 0.0;
        for (const std::string_view k : r.keys)
          if (!k.empty()) cmax = std::max(cmax, std::abs(channel(pv, k, c)));
        const double n = channel(pv, r.exponent, c), scale = channel(pv, r.scale, c);
        if (n * std::log10(std::max(cmax, 1e-300)) + std::log10(std::max(scale, 1e-300)) > r.limit)
          pv.fail(r.key, fmt::format(fmt::runtime(r.message), fmt::arg("cmax", cmax), fmt::arg("scale", scale),
                                     fmt::arg("channel", c), fmt::arg("n", n)));
      }
      return;
  }
}

}  // namespace

ParamValues read_params(const json& obj, const ModelSpec& spec, const std::string& where, std::string_view tag_key) {
  ParamValues pv;
  pv.where = where;
  if (!obj.is_object()) throw InputError(fmt::format("{}: expected a JSON object, got {}", where, json_type_name(obj)));
  for (const auto& [key, value] : obj.items()) {
    if (key == tag_key) continue;  // "model": read by the caller
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
  for (const ParamRule& r : spec.rules) apply_rule(r, pv);
  return pv;
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

}  // namespace aniso
