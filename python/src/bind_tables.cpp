// python/src/bind_tables.cpp: the presets and the parameter tables (src/io/params.cpp) as Python
// data: aniso.presets(), aniso.preset_source(), aniso.models(); and the tables as the Material
// docstring's text.
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/io/params.h"
#include "aniso/io/presets.h"
#include "bindings.h"
#include "io/enum_names.h"

namespace aniso::python {

namespace {

py::list params_py(const ModelSpec& spec);

py::dict param_py(const ParamSpec& p) {
  py::dict d;
  d["name"] = std::string(p.name);
  d["kind"] = std::string(enum_name(p.kind));
  d["range"] = describe_range(p);
  d["default"] = default_text(p);
  d["doc"] = std::string(p.doc);
  d["required"] = p.required;
  py::object value = py::none();  // the default as a value
  if (!p.required && p.sets[0].empty()) {
    if ((p.kind == ParamKind::Scalar || p.kind == ParamKind::Color) && !std::isnan(p.default_value))
      value = py::float_(p.default_value);
    else if (p.kind == ParamKind::Bool)
      value = py::bool_(p.default_value != 0.0);
    else if (p.kind == ParamKind::Choice)
      value = py::str(std::string(p.choices[0]));
  }
  d["default_value"] = value;
  if (p.kind == ParamKind::Scalar || p.kind == ParamKind::Color) {
    d["min"] = p.min;
    d["max"] = p.max;
    d["min_exclusive"] = p.min_exclusive;
  }
  py::list choices;
  for (auto c : p.choices) choices.append(std::string(c));
  d["choices"] = choices;
  d["partner"] = std::string(p.partner);
  py::list sets;
  for (auto s : p.sets)
    if (!s.empty()) sets.append(std::string(s));
  d["sets"] = sets;
  if (p.kind == ParamKind::List) d["max_items"] = p.max_items;
  if (p.sub) d["params"] = params_py(*p.sub);
  if (p.kind == ParamKind::TaggedObject) {
    py::dict by_model;
    for (auto c : p.choices) by_model[py::str(std::string(c))] = params_py(metal_lobe_spec(c));
    d["params"] = by_model;
  }
  return d;
}

py::list params_py(const ModelSpec& spec) {
  py::list l;
  for (const ParamSpec* p : spec.params()) l.append(param_py(*p));
  return l;
}

py::dict models_py() {
  py::dict out;
  for (const ModelSpec* m : model_specs()) {
    py::dict d;
    d["name"] = std::string(m->name);
    d["title"] = std::string(m->title);
    d["citation"] = std::string(m->citation);
    d["params"] = params_py(*m);
    out[py::str(std::string(m->name))] = d;
  }
  return out;
}

}  // namespace

// The tables as text, as `aniso models` prints them: the Material docstring.
std::string tables_text() {
  std::string out;
  const auto key = [&out](const ParamSpec& p, int depth) {
    out += fmt::format("{:{}}    {} : {}, default {}\n{:{}}        {}\n", "", 8 * depth, p.name, describe_range(p),
                       default_text(p), "", 8 * depth, p.doc);
  };
  const auto nested = [&out](const ParamSpec& p, const ModelSpec& sub, int depth) {
    out += fmt::format(
        "{:{}}        keys of {} ({}):\n", "", 8 * depth,
        p.kind == ParamKind::TaggedObject ? fmt::format("{}={{\"model\": \"{}\", ...}}", p.name, sub.name) : std::string(p.name),
        sub.title);
  };
  for (const ModelSpec* m : model_specs()) {
    out += fmt::format("\nmodel=\"{}\": {} ({})\n", m->name, m->title, m->citation);
    walk_params(*m, key, nested);
  }
  return out;
}

void bind_tables(py::module_& m) {
  m.def(
      "presets",
      [] {
        std::vector<std::string> names;
        for (const PresetInfo& p : presets()) names.push_back(p.name);
        return names;
      },
      "The names of the named materials (`aniso presets`), each valid for Material(name).");
  m.def(
      "preset_source",
      [](const std::string& name) {
        for (const PresetInfo& p : presets())
          if (p.name == name) return p.source;
        throw py::value_error(fmt::format("unknown preset \"{}\"", name));
      },
      py::arg("name"), "Where a preset's numbers come from (`aniso presets` lists it beside the name).");
  m.def("models", &models_py,
        "The parameter tables (src/io/params.cpp): {model: {name, title, citation, params: [{name, kind,\n"
        "range, default, default_value, doc, required, min, max, choices, partner, sets, params...}]}}.");
}

}  // namespace aniso::python
