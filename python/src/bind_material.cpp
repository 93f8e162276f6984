// python/src/bind_material.cpp: aniso.Material: made from a preset name, a dict, a file, inline
// JSON or another Material (with keyword arguments on top), as the CLI reads materials
// (io/materials.h), so that Python accepts and rejects exactly what the CLI does.
#include <optional>
#include <string>

#include <fmt/format.h>

#include "aniso/io/params.h"
#include "bindings.h"
#include "convert.h"

namespace aniso::python {

namespace {

// The resolved keys of `base` with `overrides` applied: a shorthand ("alpha") replaces both halves
// of its pair, None removes a key (its default applies again).
json apply_overrides(json base, const py::kwargs& overrides, const std::string& where) {
  const ModelSpec* spec = find_model_spec(base.value("model", ""));
  for (const auto& [k, v] : overrides) {
    const std::string key = k.cast<std::string>();
    if (key == "model") {
      if (v.cast<py::object>().equal(py::str(base.value("model", "")))) continue;
      throw py::value_error(
          fmt::format("{}: model: cannot be changed by a keyword argument (got \"{}\"); start from "
                      "Material(model=..., ...) or a dict",
                      where, std::string(py::str(v))));
    }
    if (spec)
      if (const ParamSpec* p = spec->find(key); p && !p->sets[0].empty())
        for (std::string_view half : p->sets) base.erase(std::string(half));
    if (v.is_none())
      base.erase(key);
    else
      base[key] = from_py(v, where, key);
  }
  return base;
}

}  // namespace

PyMaterial make_material(const py::object& x, const py::kwargs& kw) {
  // Dicts are inline materials: the same messages as `aniso eval -m '{...}'`.
  const std::string inline_where = "inline material";
  if (x.is_none()) {
    if (kw.empty())
      throw py::value_error(
          "Material(): expected a preset name, a dict, a file path, inline JSON, or keyword "
          "arguments with \"model\" (aniso.presets() lists the presets)");
    py::dict d;
    for (const auto& [k, v] : kw) d[k] = v;
    return PyMaterial(parse_material(from_py(d, inline_where, ""), inline_where), inline_where);
  }
  std::optional<PyMaterial> base;
  if (py::isinstance<PyMaterial>(x)) {
    base.emplace(x.cast<const PyMaterial&>());
  } else if (py::isinstance<py::dict>(x)) {
    base.emplace(parse_material(from_py(x, inline_where, ""), inline_where), inline_where);
  } else if (py::isinstance<py::str>(x) || py::hasattr(x, "__fspath__")) {
    // A preset name, a file (whatever load_material reads: JSON), or inline JSON text.
    const std::string spec = py::str(py::module_::import("os").attr("fspath")(x));
    base.emplace(load_material(spec), spec);
  } else {
    throw py::value_error(fmt::format("Material(): expected a preset name, a dict, a file path or inline JSON, got {}",
                                      std::string(py::str(py::type::of(x).attr("__name__")))));
  }
  if (kw.empty()) return std::move(*base);
  const std::string where =
      fmt::format("{} with keyword arguments", base->desc.params.where.empty() ? base->what : base->desc.params.where);
  return PyMaterial(parse_material(apply_overrides(base->resolved(), kw, where), where), base->what);
}

// Anything Material() accepts, as a material.
PyMaterial as_material(const py::object& x) {
  if (py::isinstance<PyMaterial>(x)) return x.cast<const PyMaterial&>();
  return make_material(x, py::kwargs());
}

void bind_material(py::module_& m) {
  static const std::string material_doc = fmt::format(
      "A material: one of the models with its parameters, validated as the JSON files are.\n\n"
      "Material(x) takes a preset name (aniso.presets()), a dict with the keys of a material JSON file,\n"
      "a path to a material file, inline JSON text, or another Material; keyword arguments are JSON keys\n"
      "(Material(model=\"ward\", alpha_x=0.05, alpha_y=0.3), or Material(\"gold\", lobe=...) to change a\n"
      "preset's keys; None removes a key). A bad material raises ValueError with the CLI's message.\n\n"
      "Parameters of each model (aniso.models() has them as dicts):\n{}",
      tables_text());

  py::class_<PyMaterial>(m, "Material", material_doc.c_str())
      .def(py::init(&make_material), py::arg("x") = py::none(), py::pos_only())
      .def_property_readonly(
          "model", [](const PyMaterial& self) { return self.desc.model; }, "the model's name (\"ward\", \"metal\", ...)")
      .def(
          "to_dict", [](const PyMaterial& self) { return to_py(self.resolved()); },
          "The material as resolved: every key of its table, defaults filled in; Material(m.to_dict()) == m.")
      .def(
          "to_json", [](const PyMaterial& self, int indent) { return self.resolved().dump(indent); }, py::arg("indent") = 2,
          "to_dict() as JSON text: a material file the CLI reads.")
      .def("__eq__", [](const PyMaterial& a, const PyMaterial& b) { return a.resolved() == b.resolved(); })
      .def("__repr__", [](const PyMaterial& self) { return fmt::format("aniso.Material({})", self.resolved().dump()); })
      .def("eval", &material_eval, py::arg("wi"), py::arg("wo"), py::kw_only(), py::arg("out") = py::none(),
           "f(wi, wo), the BRDF without the cosine, per RGB channel.\n\n"
           "wi (towards the light) and wo (towards the viewer) are unit directions in the local frame\n"
           "(z = normal, x = tangent), arrays of shape (N, 3) or (3,) (a (3,) argument is used for every\n"
           "row of the other). Returns (N, 3), or (3,) when both are (3,). float32 when both are float32,\n"
           "else float64. Rows with a NaN or infinite input are NaN. out: an array to write the result\n"
           "into (C- or Fortran-contiguous, that dtype and shape), returned; saves allocating one per call.")
      .def("pdf", &material_pdf, py::arg("wi"), py::arg("wo"), py::kw_only(), py::arg("out") = py::none(),
           "The solid-angle density of sample() producing wi for this wo: (N,) (a scalar for (3,) inputs).\n"
           "out: as for eval(), of shape (N,) (0-d for (3,) inputs).")
      .def("sample", &material_sample, py::arg("wo"), py::arg("u"), py::kw_only(), py::arg("out") = py::none(),
           "Importance-samples wi for the viewing direction wo.\n\n"
           "wo: (N, 3) or (3,); u: uniforms in [0, 1), (N, 3) or (3,): u[:, 0] picks the lobe, u[:, 1:] the\n"
           "direction. Returns (wi, weight, pdf): (N, 3), (N, 3), (N,), weight = f cos(theta_i) / pdf.\n"
           "Where there is no sample (wo below the horizon, wi below it) all three are 0. out: a tuple of\n"
           "three arrays (wi, weight, pdf) to write into (C- or Fortran-contiguous, the result's dtype and\n"
           "shapes; pdf 0-d for (3,) inputs), returned.")
      .def("albedo", &material_albedo, py::arg("theta"), py::arg("phi") = 0.0, py::arg("samples") = int64_t(1) << 20,
           py::arg("seed") = uint64_t(1), py::arg("return_error") = false,
           "Directional albedo: integral of f cos(theta_i) over the hemisphere, for the viewing direction\n"
           "(theta, phi) in radians (theta from the normal, in [0, pi/2]; phi from the tangent), by the\n"
           "model's importance sampling with `samples` draws, as `aniso albedo`. theta may be an array (N,):\n"
           "returns (3,) or (N, 3); with return_error=True also the standard errors.")
      .def(py::pickle([](const PyMaterial& self) { return py::make_tuple(to_py(self.resolved())); },
                      [](const py::tuple& t) { return make_material(t[0], py::kwargs()); }));
}

}  // namespace aniso::python
