// python/src/module.cpp: the `aniso._aniso` extension module (docs/python.md).
//
// Thin bindings over the library: materials are read by io/materials.h (load_material,
// parse_material, build_material), so that Python accepts and rejects exactly what the CLI does,
// with the same messages; evaluation goes through the batch API (aniso/batch/batch.h) on the
// caller's arrays (python/src/arrays.h), the GIL released; scenes are read and rendered by
// src/render, fits run by src/fit (as `aniso fit`), GLSL written by src/gl. The Python package (python/aniso/__init__.py) adds
// the per-model constructors and direction helpers on top.
//
// One file per concept, each with its bind_<concept>(module) (bindings.h: pybind11's pattern for
// large modules); the conversions between JSON and Python in convert.h, NumPy's arrays of
// directions in arrays.h.

#include <pybind11/pybind11.h>

#include <exception>
#include <string>

#include "aniso/io/input_error.h"
#include "aniso/version.h"
#include "bindings.h"
#include "io/text_escape.h"

PYBIND11_MODULE(_aniso, m) {
  using namespace aniso;
  using namespace aniso::python;
  m.doc() = "aniso: anisotropic and measured reflectance (the compiled part; import aniso)";
  m.attr("__version__") = ANISO_VERSION;  // aniso/version.h, from project(aniso VERSION ...)

  // Every input error of the library (InputError: a bad material, scene or argument) is a
  // ValueError with the message the CLI prints after "aniso: error: ".
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, terminal_text(e.what()).c_str());
    }
  });

  // The definitions in this order: help(aniso) and the stub (python/tools/make_stub.py) list them
  // as defined.
  bind_material(m);
  bind_tables(m);
  bind_metals(m);
  bind_frame(m);
  bind_render(m);
  bind_export(m);
  bind_fit(m);
  bind_batch(m);
}
