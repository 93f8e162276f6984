// python/src/bindings.h: what the files of the `aniso._aniso` module share (module.cpp calls the
// bind_* functions in order): the Material type, the evaluation functions its methods are, the
// tables' text for its docstring, and one bind_<concept>(module) per file, pybind11's pattern for
// large modules.
#pragma once

#include <cstdint>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "aniso/brdf/material.h"
#include "aniso/core/math.h"
#include "aniso/io/materials.h"
#include "arrays.h"
#include "convert.h"

namespace aniso::python {

// --- materials (bind_material.cpp) -------------------------------------------------------------

struct PyMaterial {
  MaterialDesc desc;
  MaterialT<float> mf;
  MaterialT<double> md;
  std::string what;  // how it was given, for the GLSL header ("gold", "inline material")

  PyMaterial(MaterialDesc d, std::string w)
      : desc(std::move(d)), mf(build_material<float>(desc)), md(build_material<double>(desc)), what(std::move(w)) {}
  json resolved() const { return resolved_json(desc); }
};

// Material(x, **kw): a preset name, a dict, a file path, inline JSON or a Material, with keyword
// arguments as JSON keys on top.
PyMaterial make_material(const py::object& x, const py::kwargs& kw);
// Anything Material() accepts, as a material.
PyMaterial as_material(const py::object& x);

// --- Material's methods on arrays (bind_batch.cpp) ---------------------------------------------

py::object material_eval(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out);
py::object material_pdf(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out);
py::tuple material_sample(const PyMaterial& m, const py::object& wo_in, const py::object& u_in, const py::object& out);
py::object material_albedo(const PyMaterial& m, const py::object& theta_in, double phi, int64_t samples, uint64_t seed,
                           bool return_error);

// The tables as text, as `aniso models` prints them: the Material docstring (bind_tables.cpp).
std::string tables_text();

// A (3,) float64 array (bind_frame.cpp).
py::array_t<double> vec3_py(const Vec3d& v);

// --- the module's parts, in the order module.cpp calls them ------------------------------------

void bind_material(py::module_& m);  // Material
void bind_tables(py::module_& m);    // presets, preset_source, models
void bind_metals(py::module_& m);    // metals, fresnel
void bind_frame(py::module_& m);     // Frame
void bind_render(py::module_& m);    // render, save_image
void bind_export(py::module_& m);    // export_glsl, export_brdf, export
void bind_fit(py::module_& m);       // FitResult, fit, read_measured
void bind_batch(py::module_& m);     // simd_target

}  // namespace aniso::python
