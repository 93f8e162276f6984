// python/src/bind_export.cpp: the material in other programs' formats: aniso.export_glsl() and
// aniso.export_brdf() (src/gl, docs/glsl.md), aniso.export() (src/export, docs/export.md), as the
// CLI's export commands.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/export/export.h"
#include "aniso/fit/fit.h"
#include "aniso/gl/glsl_export.h"
#include "aniso/gl/glsl_material.h"
#include "bindings.h"
#include "convert.h"
#include "io/atomic_file.h"
#include "io/text_escape.h"

namespace aniso::python {

void bind_export(py::module_& m) {
  m.def(
      "export_glsl",
      [](const py::object& x, bool full, const py::object& tables_in) {
        const PyMaterial mat = as_material(x);
        std::string tables_path;
        if (!tables_in.is_none()) tables_path = std::string(py::str(py::module_::import("os").attr("fspath")(tables_in)));
        // As `aniso export-glsl --tables` (apps/aniso/cmd_export.cpp): the same checks and messages.
        const std::string tables = gl::export_glsl_tables(mat.desc);
        if (tables.empty() && !tables_in.is_none())
          throw InputError(fmt::format("tables {}: {} is an analytic material, it has no tables", text_escape(tables_path),
                                       text_escape(mat.what)));
        if (!tables.empty() && tables_in.is_none())
          throw InputError(
              fmt::format("{}: a measured material's shader needs its tables file: give tables=PATH (or "
                          "use aniso.glsl_tables() for the array)",
                          text_escape(mat.what)));
        const std::string shader = gl::export_glsl(mat.desc, mat.what, full, tables_path);
        if (!tables.empty()) {
          try {
            io::write_file_atomically(tables_path, tables);
          } catch (const io::FileWriteError& e) {
            PyErr_SetString(PyExc_OSError, terminal_text(e.what()).c_str());
            throw py::error_already_set();
          }
        }
        return shader;
      },
      py::arg("material"), py::kw_only(), py::arg("full") = false, py::arg("tables") = py::none(),
      "The material as one self-contained GLSL source, as `aniso export-glsl` (docs/glsl.md): the library\n"
      "functions it uses, or with full=True the whole library (and aniso_material()), as `--full`. A measured\n"
      "material (.bsdf, .binary) also writes its tables to the file tables (raw float32, as `--tables`), whose\n"
      "name the shader's comment gives; tables is required for it and refused for an analytic material.");
  m.def(
      "glsl_tables",
      [](const py::object& x) -> py::object {
        const PyMaterial mat = as_material(x);
        const std::vector<float> t = gl::glsl_tables(mat.desc);
        if (t.empty()) return py::none();
        // The texture as export_glsl's side file holds it: whole rows of kGlslTablesWidth, zero-padded.
        const py::ssize_t w = gl::kGlslTablesWidth, rows = (py::ssize_t(t.size()) + w - 1) / w;
        py::array_t<float> a({rows, w});
        float* out = a.mutable_data();
        std::fill(out, out + rows * w, 0.f);
        std::copy(t.begin(), t.end(), out);
        return a;
      },
      py::arg("material"),
      "A measured material's tables for the GLSL of export_glsl: a float32 array (rows, 4096), the R32F\n"
      "texture its MeasuredTables_texture reads (docs/glsl.md, \"Measured materials\"); None for an analytic one.");
  m.def(
      "export_brdf",
      [](const py::object& x) {
        const PyMaterial mat = as_material(x);
        return gl::export_brdf(mat.desc, mat.what);
      },
      py::arg("material"), "The material as a Disney BRDF Explorer .brdf file, as `aniso export-brdf`.");
  m.def(
      "export",
      [](const py::object& x, const std::string& to, const py::object& path_in, const std::optional<std::string>& name,
         const std::string& metric, int starts, uint64_t seed, int grid, double blender_version, double tangent_angle_deg,
         bool analytic) {
        const PyMaterial mat = as_material(x);
        std::optional<std::string> path;
        if (!path_in.is_none()) path = std::string(py::str(py::module_::import("os").attr("fspath")(path_in)));
        exporter::ExportOptions o;
        o.target = to;
        if (name) o.name = *name;
        FitOptionText metric_only;
        metric_only.metric = metric;
        o.metric = parse_fit_options(metric_only).metric;
        o.starts = starts;
        o.seed = seed;
        o.grid = grid;
        o.blender_version = blender_version;
        o.tangent_angle_deg = tangent_angle_deg;
        o.analytic = analytic;
        exporter::check_export_options(o);  // before anything is written
        std::string bin_name;
        // A measured source to Mitsuba 3 / pbrt-v4: the tensor file beside path, named from it as the
        // CLI names it from -o (without path, from the material's name).
        if (path && exporter::writes_measured(exporter::find_target(to)->target, mat.desc, o))
          bin_name = exporter::measured_file_name_for_path(exporter::find_target(to)->target, *path);
        if (path && to == "gltf") {
          std::string stem = *path;
          if (const size_t slash = stem.find_last_of('/'); slash != std::string::npos) stem = stem.substr(slash + 1);
          if (const size_t dot = stem.find_last_of('.'); dot != std::string::npos && dot > 0) stem.resize(dot);
          bin_name = stem + ".bin";
          if (std::string_view(*path).substr(path->find_last_of('/') + 1) == bin_name)  // npos + 1 == 0
            throw InputError(
                fmt::format("path {}: to=\"gltf\" writes its buffer beside the .gltf as {}: give a path "
                            "ending in .gltf",
                            text_escape(*path), text_escape(bin_name)));
        }
        exporter::ExportResult r;
        {
          py::gil_scoped_release release;
          r = exporter::export_material(mat.desc, mat.what, o, bin_name);
        }
        py::dict files;
        for (const exporter::ExportFile& f : r.files) {
          if (f.path.empty())
            files[py::str("")] = py::str(f.content);
          else
            files[py::str(f.path)] = py::bytes(f.content);
        }
        if (path) {
          // As the CLI: the .bin first, then the main file; a failed main file takes the .bin with it.
          std::string dir = *path;
          const size_t slash = dir.find_last_of('/');
          dir = slash == std::string::npos ? std::string() : dir.substr(0, slash + 1);
          std::vector<std::string> written;
          try {
            for (size_t i = r.files.size(); i-- > 0;) {
              const std::string target = r.files[i].path.empty() ? *path : dir + r.files[i].path;
              io::write_file_atomically(target, r.files[i].content);
              written.push_back(target);
            }
          } catch (const io::FileWriteError& e) {
            for (const std::string& w : written) std::remove(w.c_str());
            PyErr_SetString(PyExc_OSError, terminal_text(e.what()).c_str());
            throw py::error_already_set();
          }
        }
        py::dict out;
        out["report"] = to_py(r.report.to_json());
        out["text"] = r.report.text();
        out["files"] = files;
        return out;
      },
      py::arg("material"), py::kw_only(), py::arg("to"), py::arg("path") = py::none(), py::arg("name") = py::none(),
      py::arg("metric") = "l2cos", py::arg("starts") = 4, py::arg("seed") = 1, py::arg("grid") = 6,
      py::arg("blender_version") = 4.3, py::arg("tangent_angle_deg") = 0.0, py::arg("analytic") = false,
      "The material in a renderer's own format, as `aniso export --to` (docs/export.md): to = \"blender\",\n"
      "\"mitsuba3\", \"pbrt-v4\", \"materialx\", \"openpbr\" or \"gltf\". Returns {report, text, files}: the report (target\n"
      "model, parameters, exact or fitted, errors, notes) as a dict and as text, and the files (\"\" the main\n"
      "file's text, a glTF's .bin or a measured source's tensor file as bytes under its name). With path, writes\n"
      "them too (atomically; an OSError leaves nothing). A bad material or target raises ValueError. grid,\n"
      "blender_version: as `--grid`, `--blender-version`; tangent_angle_deg: the surface's own turn of the tangent\n"
      "(a scene object's tangent.angle_deg, as `--scene --object`), composed with the material's rotation_deg.\n"
      "A measured source (.bsdf, .binary) to mitsuba3 or pbrt-v4 is the renderer's own measured BSDF with its\n"
      "tensor file beside path, named from path's stem as the CLI names it from -o (STEM_rgb.bsdf, STEM_spec.bsdf);\n"
      "analytic=True writes the fitted analytic material instead, as `--analytic`.");
}

}  // namespace aniso::python
