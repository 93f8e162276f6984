// models/models.cpp: the model files together (models/all.h): the tables in the registry's order,
// the material reader's model-specific steps (the rules, the files) and the builder, each
// dispatched to the row's model file.
#include <filesystem>

#include <fmt/format.h>

#include "aniso/io/presets.h"
#include "aniso/rgl/rgl_material.h"
#include "io/json_read.h"
#include "io/text_escape.h"
#include "models/all.h"

namespace aniso {
namespace {

// One table per registry row, in the registry's order.
constexpr const ModelSpec* kAllModels[] = {
#define ANISO_X(Tag, Type, member, name, batch, glsl) &models::Tag::spec,
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
};

}  // namespace

std::span<const ModelSpec* const> model_specs() { return kAllModels; }

const ModelSpec* find_model_spec(std::string_view name) {
  for (const ModelSpec* m : kAllModels)
    if (m->name == name) return m;
  return nullptr;
}

std::optional<ModelKind> find_model_kind(std::string_view name) {
  for (const ModelInfo& m : kModels)
    if (m.name == name) return m.kind;
  return std::nullopt;
}

const ModelSpec& lafortune_lobe_spec() { return models::Lafortune::lobe_spec; }
const ModelSpec& directional_diffuse_spec() { return models::Metal::directional_diffuse_spec; }
const ModelSpec& metal_lobe_spec(std::string_view model) {
  const auto kind = enum_from_name<SpecularLobeKind>(model).value_or(SpecularLobeKind::GGX);
  return *models::Metal::lobe_specs[static_cast<int>(kind)];
}

std::string models::resolve_file(const std::string& file, const std::string& base_dir) {
  namespace fs = std::filesystem;
  const fs::path p = base_dir.empty() || fs::path(file).is_absolute() ? fs::path(file) : fs::path(base_dir) / file;
  return p.string();
}

namespace {

// rotation_deg on a model without it: an isotropic model, where turning the tangent changes
// nothing, or a tensor file (its own frame). Raised where the reader would name the first key the
// table does not have, if that key is rotation_deg.
template <typename P> void check_rotation(const nlohmann::json& obj, const std::string& where) {
  const ModelSpec& spec = P::spec;
  for (const auto& [key, value] : obj.items()) {
    if (key == "model" || spec.find(key)) continue;
    if (key != "rotation_deg") return;  // read_params names the unknown key
    if constexpr (requires { P::no_rotation; })
      throw InputError(fmt::format("{}: key \"rotation_deg\": {}", where, P::no_rotation));
    std::string oriented;
    for (const ModelSpec* m : model_specs())
      if (m->find("rotation_deg")) oriented += fmt::format("{}{}", oriented.empty() ? "" : ", ", m->name);
    throw InputError(
        fmt::format("{}: key \"rotation_deg\": {} is isotropic, so turning its tangent has no effect; remove "
                    "the key (the anisotropic models take it: {})",
                    where, spec.name, oriented));
  }
}

}  // namespace

MaterialDesc parse_material(const nlohmann::json& obj, const std::string& where, const std::string& base_dir) {
  if (!obj.is_object()) throw InputError(fmt::format("{}: expected a JSON object, got {}", where, json_type_name(obj)));
  const auto it = obj.find("model");
  std::string names;
  for (const ModelSpec* m : model_specs()) names += fmt::format("{}\"{}\"", names.empty() ? "" : ", ", m->name);
  if (it == obj.end()) throw InputError(fmt::format("{}: key \"model\": missing; expected one of {}", where, names));
  if (!it->is_string() || !find_model_kind(it->get<std::string>()))
    throw InputError(fmt::format("{}: key \"model\": expected one of {}, got {}", where, names, json_type_name(*it)));
  MaterialDesc d;
  d.model = it->get<std::string>();
  // "fit": the error figures and provenance `aniso fit` writes beside the material
  // (docs/fitting.md). Accepted (an object) and ignored: it does not change the material.
  const auto fit = obj.find("fit");
  if (fit != obj.end() && !fit->is_object())
    throw InputError(fmt::format("{}: key \"fit\": expected an object (the provenance `aniso fit` writes), got {}", where,
                                 json_type_name(*fit)));
  nlohmann::json body;
  if (fit != obj.end()) {
    body = obj;
    body.erase("fit");
  }
  const nlohmann::json& keys = fit != obj.end() ? body : obj;
  models::visit_model(*find_model_kind(d.model), [&](auto file) {
    using P = typename decltype(file)::plugin;
    check_rotation<P>(keys, where);
    d.params = read_params(keys, P::spec, where, "model");
    d.json = obj;
    // The rules the table cannot express, and the files a measured material names.
    if constexpr (requires { P::check(d, base_dir); }) P::check(d, base_dir);
  });
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
  if (is_measured_file_name(spec)) return parse_material(nlohmann::json{{"model", "measured"}, {"file", spec}}, spec);
  if (rgl::is_rgl_file_name(spec)) return parse_material(nlohmann::json{{"model", "rgl"}, {"file", spec}}, spec);
  std::error_code ec;
  if (!fs::exists(spec, ec)) {
    // Neither a preset nor a file: suggest the nearest preset names.
    const std::string near = nearest_preset_names(spec);
    throw InputError(fmt::format("material \"{}\": neither a preset (see `aniso presets`) nor an existing file{}",
                                 text_escape(spec), near.empty() ? "" : fmt::format("; did you mean {}?", near)));
  }
  return parse_material(read_json_file(spec), spec, fs::path(spec).parent_path().string());
}

// Each row's builder: its model file's hand-written build<T>, or the one generated from its bound
// rows (models/model.h, build_generated).
template <typename T> MaterialT<T> build_material(const MaterialDesc& d) {
  const std::optional<ModelKind> kind = find_model_kind(d.model);
  if (!kind) throw InputError(fmt::format("{}: model \"{}\" is not a registered model", d.params.where, d.model));
  MaterialT<T> m = models::visit_model(*kind, [&](auto file) {
    using P = typename decltype(file)::plugin;
    using M = typename decltype(file)::template kernel<T>;
    if constexpr (requires { P::template build<T>(d); })
      return MaterialT<T>(P::template build<T>(d));
    else
      return MaterialT<T>(models::build_generated<T, M, P>(d.params));
  });
  // The anisotropic models' orientation (models::kOrientation), computed in double.
  if (d.params.has("rotation_deg")) {
    const FrameRotationT<double> r = frame_rotation_deg(d.params.scalar("rotation_deg"));
    m.rotation = FrameRotationT<T>{T(r.c), T(r.s)};
  }
  return m;
}

template MaterialT<float> build_material<float>(const MaterialDesc&);
template MaterialT<double> build_material<double>(const MaterialDesc&);

}  // namespace aniso
