// python/src/module.cpp: the `aniso._aniso` extension module (docs/python.md).
//
// Thin bindings over the library: materials are read by io/materials.h (load_material,
// parse_material, build_material), so that Python accepts and rejects exactly what the CLI does,
// with the same messages; evaluation goes through the batch API (aniso/batch/batch.h) on the
// caller's arrays (python/src/arrays.h), the GIL released; scenes are read and rendered by
// src/render, fits run by src/fit (as `aniso fit`), GLSL written by src/gl. The Python package (python/aniso/__init__.py) adds
// the per-model constructors and direction helpers on top.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include "aniso/batch/batch.h"
#include "aniso/brdf/fresnel.h"
#include "aniso/core/frame.h"
#include "aniso/data/metals.h"
#include "aniso/export/export.h"
#include "aniso/fit/fit.h"
#include "aniso/gl/glsl_export.h"
#include "aniso/image/image_io.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/io/presets.h"
#include "aniso/measured/samples.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "aniso/stats/albedo.h"
#include "aniso/version.h"
#include "arrays.h"
#include "io/atomic_file.h"
#include "io/json_read.h"
#include "io/text_input.h"
#include "transpose.h"

namespace py = pybind11;
using nlohmann::json;

namespace aniso::python {
namespace {

// --- JSON <-> Python ---------------------------------------------------------------------------

py::object to_py(const json& j) {
  switch (j.type()) {
    case json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = to_py(v);
      return d;
    }
    case json::value_t::array: {
      py::list l;
      for (const json& v : j) l.append(to_py(v));
      return l;
    }
    case json::value_t::string: return py::str(j.get<std::string>());
    case json::value_t::boolean: return py::bool_(j.get<bool>());
    case json::value_t::number_integer: return py::int_(j.get<int64_t>());
    case json::value_t::number_unsigned: return py::int_(j.get<uint64_t>());
    case json::value_t::number_float: return py::float_(j.get<double>());
    default: return py::none();
  }
}

// A dict as the JSON a material or scene file would hold. NumPy arrays and scalars are read as
// their lists and numbers; `where` and `path` name the value in messages ("inline material: ks[1]").
// As parse_json_text (io/json_read.h): nesting deeper than kMaxJsonDepth is an error with the CLI's
// message, which also bounds the recursion here; a dict or list that contains itself is an error of
// its own (it would otherwise be reported as too deep).
class FromPy {
 public:
  explicit FromPy(std::string where) : where_(std::move(where)) {}

  json convert(const py::handle& h, const std::string& path) {
    if (h.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(h)) return h.cast<bool>();
    if (py::isinstance<py::int_>(h)) {
      int overflow = 0;
      const long long v = PyLong_AsLongLongAndOverflow(h.ptr(), &overflow);
      if (overflow == 0) return int64_t(v);
      const double d = PyLong_AsDouble(h.ptr());  // beyond int64: a (huge) number, which the range check rejects
      if (d == -1.0 && PyErr_Occurred()) {        // beyond double (10**400): OverflowError, cleared
        PyErr_Clear();
        fail(path, fmt::format("expected a number, got an integer of {} decimal digits, beyond the range of a double (1.8e308)",
                               py::len(py::str(py::reinterpret_steal<py::object>(PyNumber_Absolute(h.ptr()))))));
      }
      return d;
    }
    if (py::isinstance<py::float_>(h)) {
      // JSON has no NaN or infinity (RFC 8259 Sec. 6): the same error as any value no file can hold.
      const double v = h.cast<double>();
      if (!std::isfinite(v)) fail(path, fmt::format("expected a finite number, got {}", v));
      return v;
    }
    if (py::isinstance<py::str>(h)) return text(h, path, "a string");
    const bool is_dict = py::isinstance<py::dict>(h), is_list = py::isinstance<py::list>(h) || py::isinstance<py::tuple>(h);
    if (is_dict || is_list) {
      if (std::find(open_.begin(), open_.end(), h.ptr()) != open_.end())
        fail(path, fmt::format("the {} contains itself (a cycle), which JSON cannot hold", is_dict ? "dict" : "list"));
      if (open_.size() >= size_t(kMaxJsonDepth)) throw py::value_error(json_too_deep_message(where_, path));
      open_.push_back(h.ptr());
      json out = is_dict ? json::object() : json::array();
      if (is_dict) {
        for (const auto& [k, v] : h.cast<py::dict>()) {
          if (!py::isinstance<py::str>(k))
            fail(path, fmt::format("expected string keys, got the key {}", std::string(py::repr(k))));
          const std::string key = text(k, path, "a key");
          out[key] = convert(v, path.empty() ? key : path + "." + key);
        }
      } else {
        size_t i = 0;
        for (const py::handle item : h) out.push_back(convert(item, fmt::format("{}[{}]", path, i++)));
      }
      open_.pop_back();
      return out;
    }
    const py::module_ np = py::module_::import("numpy");
    if (py::isinstance(h, np.attr("ndarray"))) return convert(h.attr("tolist")(), path);
    if (py::isinstance(h, np.attr("generic"))) return convert(h.attr("item")(), path);
    fail(path, fmt::format("expected a number, string, bool, list or dict, got {}",
                           std::string(py::str(py::type::of(h).attr("__name__")))));
    return nullptr;
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw py::value_error(fmt::format("{}: {}: {}", where_, path.empty() ? "(top level)" : path, what));
  }
  // A str as UTF-8; one that cannot be written as UTF-8 (an unpaired surrogate, "\ud800") is an
  // error naming it, not pybind11's RuntimeError.
  std::string text(const py::handle& s, const std::string& path, const char* what) const {
    Py_ssize_t size = 0;
    const char* utf8 = PyUnicode_AsUTF8AndSize(s.ptr(), &size);
    if (!utf8) {
      PyErr_Clear();
      fail(path, fmt::format("{} {} is not valid Unicode text (an unpaired surrogate?): JSON text is UTF-8", what,
                             std::string(py::repr(s))));
    }
    return std::string(utf8, size_t(size));
  }

  std::string where_;
  std::vector<PyObject*> open_;  // the dicts and lists being converted, outermost first
};

json from_py(const py::handle& h, const std::string& where, const std::string& path) { return FromPy(where).convert(h, path); }

// --- materials ---------------------------------------------------------------------------------

struct PyMaterial {
  MaterialDesc desc;
  MaterialT<float> mf;
  MaterialT<double> md;
  std::string what;  // how it was given, for the GLSL header ("gold", "inline material")

  PyMaterial(MaterialDesc d, std::string w)
      : desc(std::move(d)), mf(build_material<float>(desc)), md(build_material<double>(desc)), what(std::move(w)) {}
  json resolved() const { return resolved_json(desc); }
};

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
    // A preset name, a file (JSON now; whatever else load_material reads), or inline JSON text.
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

// --- evaluation on chunks ----------------------------------------------------------------------

// Rows per task: 4096 rows of 10 double arrays (wi, wo, f, pdf) are 320 KiB, inside one core's
// L2; and 4096 is the batch API's own block size (docs/performance.md), so a chunk is one block.
constexpr size_t kChunk = 4096;

template <typename Fn> void for_chunks(size_t n, Fn&& fn) {
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, kChunk),
      [&](const tbb::blocked_range<size_t>& r) {
        for (size_t b = r.begin(); b < r.end(); b += kChunk) fn(b, std::min(r.end(), b + kChunk));
      },
      tbb::simple_partitioner());
}

// Scratch arrays of one thread, reused across calls.
template <typename T> T* scratch(size_t arrays) {
  thread_local std::vector<T> buf;
  if (buf.size() < arrays * kChunk) buf.resize(arrays * kChunk);
  return buf.data();
}

template <typename T, typename S> void gather_as(const RowsView& v, size_t begin, size_t len, T* x, T* y, T* z, uint8_t* bad) {
  const py::ssize_t rs = v.single ? 0 : v.row_stride, cs = v.col_stride;
  const char* base = v.data + py::ssize_t(v.single ? 0 : begin) * rs;
  for (size_t i = 0; i < len; ++i) {
    const char* p = base + py::ssize_t(i) * rs;
    S a, b, c;  // memcpy: NumPy buffers need not be aligned
    std::memcpy(&a, p, sizeof a);
    std::memcpy(&b, p + cs, sizeof b);
    std::memcpy(&c, p + 2 * cs, sizeof c);
    x[i] = T(a), y[i] = T(b), z[i] = T(c);
    bad[i] |= uint8_t(!(std::isfinite(a) && std::isfinite(b) && std::isfinite(c)));
  }
}

// Rows [begin, begin + len) of v as three arrays; bad[i] is set where a value is NaN or infinite.
// Contiguous rows (a C-ordered (N, 3) array, aligned) take the vectorised loops of transpose.h.
template <typename T> void gather(const RowsView& v, size_t begin, size_t len, T* x, T* y, T* z, uint8_t* bad) {
  const size_t item = v.f32 ? sizeof(float) : sizeof(double);
  const bool contiguous = !v.single && v.col_stride == py::ssize_t(item) && v.row_stride == py::ssize_t(3 * item) &&
                          reinterpret_cast<uintptr_t>(v.data) % item == 0;
  if (contiguous && v.f32) return deinterleave(reinterpret_cast<const float*>(v.data) + 3 * begin, len, x, y, z, bad);
  if constexpr (std::is_same_v<T, double>)
    if (contiguous) return deinterleave(reinterpret_cast<const double*>(v.data) + 3 * begin, len, x, y, z, bad);
  if (v.f32)
    gather_as<T, float>(v, begin, len, x, y, z, bad);
  else
    gather_as<T, double>(v, begin, len, x, y, z, bad);
}

// The three columns of v as arrays the batch API can read in place: v holds T and each column is
// contiguous (a Fortran-ordered (N, 3) array, or the transpose of a C-ordered (3, N) one). Sets
// bad[i] for NaN / Inf rows, as gather() does; false (nothing done) for any other layout.
template <typename T> bool columns_in_place(const RowsView& v, size_t begin, size_t len, const T** xyz, uint8_t* bad) {
  if (v.single || v.f32 != std::is_same_v<T, float> || v.row_stride != py::ssize_t(sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  for (int c = 0; c < 3; ++c) xyz[c] = reinterpret_cast<const T*>(v.data + c * v.col_stride) + begin;
  mark_nonfinite(xyz[0], xyz[1], xyz[2], len, bad);
  return true;
}

// The columns of v as the batch API's structure of arrays, read in place: v holds T, each column
// contiguous and aligned (Fortran order, or the transpose of a C-ordered (3, N) array). False
// otherwise (nothing set).
template <typename T> bool column_arrays(const RowsView& v, batch::Directions<T>& out) {
  if (v.single || v.f32 != std::is_same_v<T, float> || v.row_stride != py::ssize_t(sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  out = {reinterpret_cast<const T*>(v.data), reinterpret_cast<const T*>(v.data + v.col_stride),
         reinterpret_cast<const T*>(v.data + 2 * v.col_stride)};
  return true;
}

template <typename T> py::array_t<T> rows_out(size_t n, bool single, int columns) {
  if (single) return py::array_t<T>(std::vector<py::ssize_t>{columns});
  return py::array_t<T>(std::vector<py::ssize_t>{py::ssize_t(n), columns});
}

template <typename T> py::object scalar_or_rows(py::array_t<T> a, bool single) {
  if (single) return a[py::int_(0)];  // a NumPy scalar of the array's dtype
  return a;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The caller's `out` array, checked: the dtype the computation runs in, the result's shape,
// C-contiguous and writeable. None: a new array.
template <typename T>
py::array_t<T> out_array(const py::object& out, size_t n, bool single, int columns, const char* name = "out") {
  if (out.is_none()) {
    if (columns == 0) return py::array_t<T>(std::vector<py::ssize_t>{single ? 1 : py::ssize_t(n)});
    return rows_out<T>(n, single, columns);
  }
  const char* dtype = std::is_same_v<T, float> ? "float32" : "float64";
  const std::string shape = columns == 0 ? (single ? "()" : fmt::format("({},)", n))
                                         : (single ? fmt::format("({},)", columns) : fmt::format("({}, {})", n, columns));
  const std::string want = fmt::format(
      "{}: expected a writeable C- or Fortran-contiguous {} array of shape {} (the inputs' dtype and rows)", name, dtype, shape);
  if (!py::isinstance<py::array>(out))
    throw py::value_error(fmt::format("{}, got {}", want, std::string(py::str(py::type::of(out).attr("__name__")))));
  const py::array a = out.cast<py::array>();
  std::vector<py::ssize_t> expected;
  if (columns == 0) {
    if (!single) expected.push_back(py::ssize_t(n));
  } else {
    if (!single) expected.push_back(py::ssize_t(n));
    expected.push_back(columns);
  }
  const bool shape_ok = a.ndim() == py::ssize_t(expected.size()) && std::equal(expected.begin(), expected.end(), a.shape());
  const bool contiguous = (a.flags() & py::array::c_style) || (a.flags() & py::array::f_style);
  if (!py::isinstance<py::array_t<T>>(a) || !shape_ok || !contiguous || !a.writeable())
    throw py::value_error(fmt::format("{}, got {} of shape {}{}{}", want, std::string(py::str(a.dtype())), shape_text(a),
                                      contiguous ? "" : ", not contiguous", a.writeable() ? "" : ", read-only"));
  if (columns == 0 && single) return py::array_t<T>(a.attr("reshape")(1));  // a view of the 0-d array
  return py::reinterpret_borrow<py::array_t<T>>(a);  // as it is (array_t's converting constructor would make it C-ordered)
}

// v as the batch API's interleaved rows (batch::Interleaved): C-ordered rows of T, aligned to T, read
// in place; or a (3,) input, converted into `row` and broadcast (stride 0). False for other layouts
// (Fortran order, slices, another dtype), which take the chunked path below.
template <typename T> bool interleaved_rows(const RowsView& v, T (&row)[3], batch::Interleaved<T>& out) {
  if (v.single) {
    for (int c = 0; c < 3; ++c) row[c] = v.at<T>(0, c);
    out = {row, 0};
    return true;
  }
  if (v.f32 != std::is_same_v<T, float> || v.col_stride != py::ssize_t(sizeof(T)) || v.row_stride != py::ssize_t(3 * sizeof(T)) ||
      reinterpret_cast<uintptr_t>(v.data) % sizeof(T) != 0)
    return false;
  out = {reinterpret_cast<const T*>(v.data), 3};
  return true;
}

template <typename T> py::array_t<T> eval_typed(const MaterialT<T>& m, const RowsView& wi, const RowsView& wo, size_t n,
                                                bool single, const py::object& out_in) {
  py::array_t<T> out = out_array<T>(out_in, n, single, 3);
  T* f = out.mutable_data();
  // A Fortran-ordered `out` (columns contiguous) is written in place, without the interleave.
  const bool out_columns = !single && n > 1 && (out.flags() & py::array::f_style);
  // C-ordered rows in and out (the default layout) go to the batch API as they are: its kernels
  // load and store interleaved rows and write NaN rows themselves, one pass over the memory.
  T row_i[3], row_o[3];
  batch::Interleaved<T> ri, ro;
  if (!out_columns && interleaved_rows(wi, row_i, ri) && interleaved_rows(wo, row_o, ro)) {
    py::gil_scoped_release release;
    batch::evaluate_interleaved(m, ri, ro, n, f, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  // Column-major in and out likewise, through the structure-of-arrays entry point.
  batch::Directions<T> ci, co;
  if (out_columns && column_arrays(wi, ci) && column_arrays(wo, co)) {
    py::gil_scoped_release release;
    batch::evaluate(m, ci, co, n, {f, f + n, f + 2 * n}, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(9);
      uint8_t bad[kChunk] = {};
      const T *a[3] = {s, s + kChunk, s + 2 * kChunk}, *b[3] = {s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk};
      if (!columns_in_place(wi, begin, len, a, bad)) gather(wi, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      if (!columns_in_place(wo, begin, len, b, bad)) gather(wo, begin, len, s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk, bad);
      T* rgb[3] = {s + 6 * kChunk, s + 7 * kChunk, s + 8 * kChunk};
      if (out_columns)
        for (int c = 0; c < 3; ++c) rgb[c] = f + c * n + begin;
      batch::evaluate(m, {a[0], a[1], a[2]}, {b[0], b[1], b[2]}, len, {rgb[0], rgb[1], rgb[2]}, batch::Threads::One);
      // NaN rows for NaN / Inf input (docs/python.md).
      if (out_columns)
        for (int c = 0; c < 3; ++c) mark_bad(rgb[c], len, bad);
      else
        interleave(f + 3 * begin, len, rgb[0], rgb[1], rgb[2], bad);
    });
  }
  return out;
}

template <typename T> py::array_t<T> pdf_typed(const MaterialT<T>& m, const RowsView& wi, const RowsView& wo, size_t n,
                                               bool single, const py::object& out_in) {
  py::array_t<T> out = out_array<T>(out_in, n, single, 0);
  T* p = out.mutable_data();
  T row_i[3], row_o[3];
  batch::Interleaved<T> ri, ro;
  batch::Directions<T> ci, co;
  if (interleaved_rows(wi, row_i, ri) && interleaved_rows(wo, row_o, ro)) {  // as in eval_typed
    py::gil_scoped_release release;
    batch::pdf_interleaved(m, ri, ro, n, p, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  if (column_arrays(wi, ci) && column_arrays(wo, co)) {
    py::gil_scoped_release release;
    batch::pdf(m, ci, co, n, p, batch::Threads::All, batch::Kernels::Simd, batch::NonFinite::NaN);
    return out;
  }
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(6);
      uint8_t bad[kChunk] = {};
      const T *a[3] = {s, s + kChunk, s + 2 * kChunk}, *b[3] = {s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk};
      if (!columns_in_place(wi, begin, len, a, bad)) gather(wi, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      if (!columns_in_place(wo, begin, len, b, bad)) gather(wo, begin, len, s + 3 * kChunk, s + 4 * kChunk, s + 5 * kChunk, bad);
      batch::pdf(m, {a[0], a[1], a[2]}, {b[0], b[1], b[2]}, len, p + begin, batch::Threads::One);
      mark_bad(p + begin, len, bad);
    });
  }
  return out;
}

// Directions as the CLI reads them (io/text_input.h, normalized_direction): normalised, a zero one
// an error naming its row. Rows of unit length already (|w|^2 within kUnitSlack of 1, a few
// roundings of the input's float type) are read as they are, so that the usual input is used in
// place; otherwise a normalised copy (same dtype, C order) replaces the input. Rows with NaN or
// Inf stay as they are (their results are NaN, docs/python.md).
void normalize_rows(RowsView& v, const char* name) {
  const double slack = v.f32 ? 4e-7 : 1e-15;  // ~4 float / ~5 double roundings of |w|^2
  bool unit = true;
  {
    py::gil_scoped_release release;
    for (size_t r = 0; r < v.rows && unit; ++r) {
      const double x = v.at<double>(r, 0), y = v.at<double>(r, 1), z = v.at<double>(r, 2);
      const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);  // NaN, Inf: as they are
      unit = !finite || std::abs(x * x + y * y + z * z - 1.0) <= slack;
    }
  }
  if (unit) return;
  const py::ssize_t rows = py::ssize_t(v.rows);
  py::array copy =
      v.f32 ? py::array(py::array_t<float>({rows, py::ssize_t(3)})) : py::array(py::array_t<double>({rows, py::ssize_t(3)}));
  char* base = static_cast<char*>(copy.mutable_data());
  size_t zero_row = SIZE_MAX;
  {
    py::gil_scoped_release release;
    for (size_t r = 0; r < v.rows; ++r) {
      const Vec3d w(v.at<double>(r, 0), v.at<double>(r, 1), v.at<double>(r, 2));
      Vec3d u = w;
      if (std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) {
        const auto nw = normalized_direction(w);
        if (!nw) {
          zero_row = r;
          break;
        }
        u = *nw;
      }
      for (int c = 0; c < 3; ++c) {
        if (v.f32)
          reinterpret_cast<float*>(base)[3 * r + size_t(c)] = float(u[c]);
        else
          reinterpret_cast<double*>(base)[3 * r + size_t(c)] = u[c];
      }
    }
  }
  if (zero_row != SIZE_MAX)
    throw py::value_error(v.single ? fmt::format("{}: expected a non-zero direction, got (0, 0, 0)", name)
                                   : fmt::format("{}[{}]: expected a non-zero direction, got (0, 0, 0)", name, zero_row));
  const bool single = v.single;
  v = rows_view(single ? copy.attr("reshape")(3) : py::object(copy), name);
}

py::object material_eval(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out) {
  RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}});
  normalize_rows(wi, "wi");
  normalize_rows(wo, "wo");
  const bool single = wi.single && wo.single;
  if (all_f32({&wi, &wo})) return eval_typed<float>(m.mf, wi, wo, n, single, out);
  return eval_typed<double>(m.md, wi, wo, n, single, out);
}

py::object material_pdf(const PyMaterial& m, const py::object& wi_in, const py::object& wo_in, const py::object& out) {
  RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}});
  normalize_rows(wi, "wi");
  normalize_rows(wo, "wo");
  const bool single = wi.single && wo.single;
  if (!out.is_none()) {  // the caller's array, as given (0-d for one pair)
    if (all_f32({&wi, &wo}))
      pdf_typed<float>(m.mf, wi, wo, n, single, out);
    else
      pdf_typed<double>(m.md, wi, wo, n, single, out);
    return out;
  }
  if (all_f32({&wi, &wo})) return scalar_or_rows(pdf_typed<float>(m.mf, wi, wo, n, single, out), single);
  return scalar_or_rows(pdf_typed<double>(m.md, wi, wo, n, single, out), single);
}

// The samplers take uniforms in [0, 1); 1 itself (a float64 uniform rounded to float32 can become 1)
// is taken as the largest number below 1. True when u needs no change.
template <typename T> bool uniforms_ok(const T* uc, const T* u0, const T* u1, size_t len) {
  bool ok = true;
  for (size_t i = 0; i < len; ++i)
    ok &= (uc[i] >= T(0)) & (uc[i] < T(1)) & (u0[i] >= T(0)) & (u0[i] < T(1)) & (u1[i] >= T(0)) & (u1[i] < T(1));
  return ok;
}

template <typename T> py::tuple sample_typed(const MaterialT<T>& m, const RowsView& wo, const RowsView& u, size_t n, bool single,
                                             const py::object& out) {
  py::array_t<T> wi_out, weight_out, pdf_out;
  if (out.is_none()) {
    wi_out = rows_out<T>(n, single, 3), weight_out = rows_out<T>(n, single, 3);
    pdf_out = py::array_t<T>(std::vector<py::ssize_t>{single ? 1 : py::ssize_t(n)});
  } else {
    if (!(py::isinstance<py::tuple>(out) || py::isinstance<py::list>(out)) || py::len(out) != 3)
      throw py::value_error(fmt::format("out: expected a tuple of three arrays (wi, weight, pdf), got {}",
                                        std::string(py::str(py::type::of(out).attr("__name__")))));
    const py::sequence o = out.cast<py::sequence>();
    wi_out = out_array<T>(o[0], n, single, 3, "out[0] (wi)");
    weight_out = out_array<T>(o[1], n, single, 3, "out[1] (weight)");
    pdf_out = out_array<T>(o[2], n, single, 0, "out[2] (pdf)");
  }
  T *wi = wi_out.mutable_data(), *w = weight_out.mutable_data(), *p = pdf_out.mutable_data();
  // Fortran-ordered outputs (columns contiguous) are written in place, as eval's.
  const bool wi_columns = !single && n > 1 && (wi_out.flags() & py::array::f_style);
  const bool weight_columns = !single && n > 1 && (weight_out.flags() & py::array::f_style);
  std::atomic<size_t> first_out_of_range{SIZE_MAX};
  {
    py::gil_scoped_release release;
    for_chunks(n, [&](size_t begin, size_t end) {
      const size_t len = end - begin;
      T* s = scratch<T>(12);
      uint8_t bad[kChunk] = {}, valid[kChunk];
      const T* o[3] = {s, s + kChunk, s + 2 * kChunk};
      T *uc = s + 3 * kChunk, *u0 = s + 4 * kChunk, *u1 = s + 5 * kChunk;
      // Column-major wo and u are read in place (u when it needs no change), as eval reads wi, wo.
      const T* uu[3];
      bool u_in_place = columns_in_place(u, begin, len, uu, bad);
      if (u_in_place && !uniforms_ok(uu[0], uu[1], uu[2], len)) {
        std::fill(bad, bad + len, uint8_t(0));  // gather marks the rows again
        u_in_place = false;
      }
      if (!u_in_place) {
        gather(u, begin, len, uc, u0, u1, bad);
        const T below_one = std::nextafter(T(1), T(0));
        for (size_t i = 0; i < len; ++i) {
          for (T* c : {uc + i, u0 + i, u1 + i}) {
            if (*c >= T(0) && *c < T(1)) continue;
            if (*c == T(1))
              *c = below_one;
            else if (!std::isnan(*c)) {
              size_t cur = first_out_of_range.load();
              while (begin + i < cur && !first_out_of_range.compare_exchange_weak(cur, begin + i)) {}
              *c = T(0);
            }
          }
        }
        uu[0] = uc, uu[1] = u0, uu[2] = u1;
      }
      if (!columns_in_place(wo, begin, len, o, bad)) gather(wo, begin, len, s, s + kChunk, s + 2 * kChunk, bad);
      T* col[6] = {s + 6 * kChunk, s + 7 * kChunk, s + 8 * kChunk, s + 9 * kChunk, s + 10 * kChunk, s + 11 * kChunk};
      if (wi_columns)
        for (int c = 0; c < 3; ++c) col[c] = wi + c * n + begin;
      if (weight_columns)
        for (int c = 0; c < 3; ++c) col[3 + c] = w + c * n + begin;
      batch::Samples<T> r{col[0], col[1], col[2], col[3], col[4], col[5], p + begin, valid};
      batch::sample(m, {o[0], o[1], o[2]}, uu[0], uu[1], uu[2], len, r, batch::Threads::One);
      // NaN rows for NaN / Inf input (docs/python.md).
      if (wi_columns)
        for (int c = 0; c < 3; ++c) mark_bad(col[c], len, bad);
      else
        interleave(wi + 3 * begin, len, col[0], col[1], col[2], bad);
      if (weight_columns)
        for (int c = 0; c < 3; ++c) mark_bad(col[3 + c], len, bad);
      else
        interleave(w + 3 * begin, len, col[3], col[4], col[5], bad);
      mark_bad(p + begin, len, bad);
    });
  }
  if (const size_t row = first_out_of_range.load(); row != SIZE_MAX) {
    double value = 0.0;
    for (int c = 0; c < 3; ++c)
      if (const double x = u.at<double>(row, c); !(x >= 0.0 && x <= 1.0)) value = x;
    throw py::value_error(fmt::format("u: expected uniforms in [0, 1), got {} in row {}", value, u.single ? 0 : row));
  }
  if (!out.is_none()) return py::make_tuple(wi_out, weight_out, out.cast<py::sequence>()[2]);
  return py::make_tuple(wi_out, weight_out, scalar_or_rows(pdf_out, single));
}

py::tuple material_sample(const PyMaterial& m, const py::object& wo_in, const py::object& u_in, const py::object& out) {
  RowsView wo = rows_view(wo_in, "wo");
  const RowsView u = rows_view(u_in, "u");
  const size_t n = common_rows({{"wo", &wo}, {"u", &u}});
  normalize_rows(wo, "wo");
  const bool single = wo.single && u.single;
  if (all_f32({&wo, &u})) return sample_typed<float>(m.mf, wo, u, n, single, out);
  return sample_typed<double>(m.md, wo, u, n, single, out);
}

// The largest albedo sample count, as `aniso albedo --samples` allows.
constexpr int64_t kMaxAlbedoSamples = 1'000'000'000;

py::object material_albedo(const PyMaterial& m, const py::object& theta_in, double phi, int64_t samples, uint64_t seed,
                           bool return_error) {
  if (samples < 1 || samples > kMaxAlbedoSamples)
    throw py::value_error(fmt::format("samples: expected a whole number in [1, {}], got {}", kMaxAlbedoSamples, samples));
  if (!std::isfinite(phi)) throw py::value_error(fmt::format("phi: expected a finite angle in radians, got {}", phi));
  const py::module_ np = py::module_::import("numpy");
  // Numbers only: NumPy would read the text "0.3" as 0.3 (the CLI's --theta-deg takes text; a
  // Python argument is a number). Real dtypes as rows_view reads them (arrays.h).
  const py::array given = np.attr("asarray")(theta_in);
  const char kind = given.dtype().kind();
  if (!(kind == 'f' || kind == 'i' || kind == 'u') || (kind == 'f' && given.dtype().itemsize() > 8))
    throw py::value_error(
        fmt::format("theta: expected a number or an array of float16, float32, float64 or integers (radians), got {} of dtype {}",
                    std::string(py::str(py::type::of(theta_in).attr("__name__"))), std::string(py::str(given.dtype()))));
  const py::array_t<double, py::array::c_style | py::array::forcecast> theta = np.attr("asarray")(given, "float64");
  if (theta.ndim() > 1)
    throw py::value_error(fmt::format("theta: expected a number or an array of shape (N,), got shape {}", shape_text(theta)));
  const size_t n = size_t(theta.size());
  const double* t = theta.data();
  for (size_t i = 0; i < n; ++i)
    if (!(t[i] >= 0.0 && t[i] <= M_PI / 2) && !std::isnan(t[i]))
      throw py::value_error(fmt::format("theta: expected viewing angles in [0, pi/2] radians from the normal, got {}", t[i]));
  const bool single = theta.ndim() == 0;
  py::array_t<double> mean = rows_out<double>(n, single, 3), err = rows_out<double>(n, single, 3);
  double *pm = mean.mutable_data(), *pe = err.mutable_data();
  {
    py::gil_scoped_release release;
    for (size_t i = 0; i < n; ++i) {
      if (std::isnan(t[i])) {
        for (int c = 0; c < 3; ++c) pm[3 * i + c] = pe[3 * i + c] = kNaN;
        continue;
      }
      // As `aniso albedo` (direction_from_degrees, src/io/text_input.cpp), in radians.
      const Vec3d wo(std::sin(t[i]) * std::cos(phi), std::sin(t[i]) * std::sin(phi), std::cos(t[i]));
      const AlbedoEstimate a = albedo_importance(m.md, wo, samples, seed);
      for (int c = 0; c < 3; ++c) pm[3 * i + c] = a.mean[c], pe[3 * i + c] = a.std_error[c];
    }
  }
  if (return_error) return py::make_tuple(mean, err);
  return mean;
}

// --- parameter tables --------------------------------------------------------------------------

const char* kind_name(ParamKind k) {
  switch (k) {
    case ParamKind::Scalar: return "scalar";
    case ParamKind::Color: return "color";
    case ParamKind::Bool: return "bool";
    case ParamKind::Choice: return "choice";
    case ParamKind::String: return "string";
    case ParamKind::Object: return "object";
    case ParamKind::List: return "list";
    case ParamKind::TaggedObject: return "tagged-object";
  }
  return "";
}

py::list params_py(const ModelSpec& spec);

py::dict param_py(const ParamSpec& p) {
  py::dict d;
  d["name"] = std::string(p.name);
  d["kind"] = kind_name(p.kind);
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

// --- frames ------------------------------------------------------------------------------------

Vec3d vec3_arg(const py::object& obj, const char* name) {
  const RowsView v = rows_view(obj, name);
  if (!v.single) throw py::value_error(fmt::format("{}: expected one direction of shape (3,), got {} rows", name, v.rows));
  const Vec3d w(v.at<double>(0, 0), v.at<double>(0, 1), v.at<double>(0, 2));
  if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)))
    throw py::value_error(fmt::format("{}: expected finite values, got ({}, {}, {})", name, w.x, w.y, w.z));
  return w;
}

Vec3d unit_arg(const py::object& obj, const char* name) {
  const Vec3d w = vec3_arg(obj, name);
  const double len = glm::length(w);
  if (!(len > 0.0)) throw py::value_error(fmt::format("{}: expected a non-zero direction, got (0, 0, 0)", name));
  return w / len;
}

py::array_t<double> vec3_py(const Vec3d& v) {
  py::array_t<double> a(3);
  a.mutable_at(0) = v.x, a.mutable_at(1) = v.y, a.mutable_at(2) = v.z;
  return a;
}

// w as rows, each mapped by fn (double precision), returned in the input's precision and shape.
template <typename Fn> py::array map_rows(const py::object& w_in, const char* name, Fn fn) {
  const RowsView w = rows_view(w_in, name);
  const size_t n = w.single ? 1 : w.rows;
  py::array_t<double> out = rows_out<double>(n, w.single, 3);
  double* o = out.mutable_data();
  for (size_t i = 0; i < n; ++i) {
    const Vec3d r = fn(Vec3d(w.at<double>(i, 0), w.at<double>(i, 1), w.at<double>(i, 2)));
    o[3 * i] = r.x, o[3 * i + 1] = r.y, o[3 * i + 2] = r.z;
  }
  if (w.f32) return out.attr("astype")("float32");
  return out;
}

// --- fresnel -----------------------------------------------------------------------------------

glm::dvec3 rgb_arg(const py::object& obj, const char* name, double lo, bool lo_exclusive, double hi) {
  const py::module_ np = py::module_::import("numpy");
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = np.attr("asarray")(obj, "float64");
  } catch (py::error_already_set& e) {
    throw py::value_error(fmt::format("{}: expected a number or [r, g, b] ({})", name, e.what()));
  }
  if (!(a.size() == 1 || (a.ndim() == 1 && a.size() == 3)))
    throw py::value_error(fmt::format("{}: expected a number or [r, g, b], got shape {}", name, shape_text(a)));
  glm::dvec3 c;
  for (int i = 0; i < 3; ++i) {
    c[i] = a.data()[a.size() == 1 ? 0 : i];
    if (!((lo_exclusive ? c[i] > lo : c[i] >= lo) && c[i] <= hi))
      throw py::value_error(
          fmt::format("{}: channel {}: expected a number in {}{}, {}], got {}", name, i, lo_exclusive ? "(" : "[", lo, hi, c[i]));
  }
  return c;
}

py::array fresnel_py(const py::object& cos_in, const py::object& metal, const py::object& eta_in, const py::object& k_in,
                     bool schlick) {
  glm::dvec3 eta, k;
  if (!metal.is_none()) {
    if (!eta_in.is_none() || !k_in.is_none()) throw py::value_error("give either metal or eta and k, not both");
    const std::string name = py::str(metal);
    const MetalData* md = find_metal(name);
    if (!md) throw py::value_error(fmt::format("metal: {}", unknown_metal_message(name)));
    eta = md->eta, k = md->k;
  } else {
    if (eta_in.is_none() || k_in.is_none())
      throw py::value_error(fmt::format("give metal=NAME (one of {}) or both eta=[r, g, b] and k=[r, g, b]", metal_names()));
    eta = rgb_arg(eta_in, "eta", 0.0, true, 100.0);  // the ranges of `aniso fresnel --eta --k`
    k = rgb_arg(k_in, "k", 0.0, false, 100.0);
  }
  const py::module_ np = py::module_::import("numpy");
  const py::array_t<double, py::array::c_style | py::array::forcecast> c = np.attr("asarray")(cos_in, "float64");
  std::vector<py::ssize_t> shape(c.shape(), c.shape() + c.ndim());
  shape.push_back(3);
  py::array_t<double> out(shape);
  double* o = out.mutable_data();
  const double* ci = c.data();
  const RGBT<double> e(eta), kk(k);
  for (py::ssize_t i = 0; i < c.size(); ++i) {
    RGBT<double> F(kNaN);  // NaN cosines give NaN rows
    if (!std::isnan(ci[i])) F = schlick ? F_Schlick(F_Conductor(1.0, e, kk), ci[i]) : F_Conductor(ci[i], e, kk);
    o[3 * i] = F.x, o[3 * i + 1] = F.y, o[3 * i + 2] = F.z;
  }
  return out;
}

// --- render ------------------------------------------------------------------------------------

std::atomic<bool> g_render_interrupted{false};
extern "C" void on_render_sigint(int) { g_render_interrupted.store(true); }

int int_arg(const std::optional<int>& v, const char* name, int lo, int hi, int fallback) {
  if (!v) return fallback;
  if (*v < lo || *v > hi) throw py::value_error(fmt::format("{}: expected a whole number in [{}, {}], got {}", name, lo, hi, *v));
  return *v;
}

py::array_t<float> render_py(const py::object& scene_in, const py::object& material, std::optional<int> spp,
                             std::optional<int> width, std::optional<int> height, uint64_t seed, int threads,
                             std::optional<int> max_depth, std::optional<std::string> strategy, std::optional<bool> progress) {
  using namespace aniso::render;
  if (!scene_in.is_none() && !material.is_none()) throw py::value_error("give either a scene or material=, not both");
  Scene scene;
  if (!material.is_none()) {
    // The preview scene of `aniso render --material`, with the material as resolved.
    scene = parse_scene(preview_scene(as_material(material).resolved()), "preview scene", "");
  } else if (py::isinstance<py::dict>(scene_in)) {
    scene = parse_scene(from_py(scene_in, "scene dict", ""), "scene dict", "");
  } else if (py::isinstance<py::str>(scene_in) || py::hasattr(scene_in, "__fspath__")) {
    scene = load_scene(py::str(py::module_::import("os").attr("fspath")(scene_in)));
  } else {
    throw py::value_error("render(): expected a scene (a dict or a path to a scene file) or material=");
  }
  scene.film.spp = int_arg(spp, "spp", 1, 1 << 20, scene.film.spp);
  // One of width and height alone keeps the scene's aspect ratio, as `aniso render --width`.
  resize_film(scene.film, int_arg(width, "width", 16, 16384, 0), int_arg(height, "height", 16, 16384, 0));
  scene.integrator.max_depth = int_arg(max_depth, "max_depth", 1, 1024, scene.integrator.max_depth);
  if (strategy) {
    if (*strategy == "mis")
      scene.integrator.strategy = Strategy::Mis;
    else if (*strategy == "bsdf")
      scene.integrator.strategy = Strategy::Bsdf;
    else if (*strategy == "light")
      scene.integrator.strategy = Strategy::Light;
    else
      throw py::value_error(fmt::format("strategy: expected one of \"mis\", \"bsdf\", \"light\", got \"{}\"", *strategy));
  }
  if (threads < 0 || threads > 1024)
    throw py::value_error(fmt::format("threads: expected 0 (all cores) to 1024, got {}", threads));
  RenderOptions ro;
  ro.threads = threads;
  ro.seed = seed;
  // Ctrl-C stops the render at the end of a pass and raises KeyboardInterrupt (Python's own
  // handler cannot run while this thread is in C++); only the main thread may take SIGINT over.
  const bool main_thread =
      py::module_::import("threading").attr("current_thread")().is(py::module_::import("threading").attr("main_thread")());
  // Renders in other threads get a flag of their own that nothing sets (Ctrl-C goes to the main thread).
  std::atomic<bool> never_cancelled{false};
  if (main_thread) g_render_interrupted.store(false);
  ro.cancel = main_thread ? &g_render_interrupted : &never_cancelled;
  const bool show = progress ? *progress : isatty(STDERR_FILENO) != 0;
  const std::string what = scene.source;
  if (show) ro.progress = [&what](double f) { std::fprintf(stderr, "\raniso.render: %s %3.0f%%", what.c_str(), 100.0 * f); };
  struct sigaction old_action {};
  if (main_thread) {
    struct sigaction action {};
    action.sa_handler = on_render_sigint;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_action);
  }
  Image img;
  {
    py::gil_scoped_release release;
    img = aniso::render::render(scene, ro);
  }
  if (main_thread) sigaction(SIGINT, &old_action, nullptr);
  if (show) std::fprintf(stderr, "\r\033[K");
  if (main_thread && g_render_interrupted.load()) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  auto* owned = new std::vector<float>(std::move(img.rgb));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(3)}, owned->data(), free_when_done);
}

// render()'s image (or any (H, W, 3) linear RGB array) to a file, by the CLI's writer
// (render/image.h, write_image): .png tone-mapped as `aniso render` does (exposure in stops, the
// aces or clamp curve, sRGB), .exr and .pfm linear as they are; written atomically. exposure and
// tonemap apply to PNG only, as the CLI's --exposure and --tonemap.
void save_image_py(const py::object& img_in, const py::object& path_in, std::optional<double> exposure,
                   std::optional<std::string> tonemap) {
  const py::module_ np = py::module_::import("numpy");
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_in));
  const py::array given = np.attr("asarray")(img_in);
  const char kind = given.dtype().kind();
  if (!((kind == 'f' && given.dtype().itemsize() <= 8) || kind == 'i' || kind == 'u'))
    throw py::value_error(fmt::format("img: expected a (height, width, 3) array of float32 or float64 (linear RGB), got dtype {}",
                                      std::string(py::str(given.dtype()))));
  if (given.ndim() != 3 || given.shape(2) != 3 || given.shape(0) < 1 || given.shape(1) < 1)
    throw py::value_error(fmt::format("img: expected a (height, width, 3) array (linear RGB), got shape {}", shape_text(given)));
  if (given.shape(0) > 65536 || given.shape(1) > 65536)
    throw py::value_error(fmt::format("img: expected at most 65536 x 65536 pixels, got shape {}", shape_text(given)));
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".exr" && ext != ".pfm")
    throw py::value_error(fmt::format("path {}: expected a .png, .exr or .pfm file name", path));
  if ((exposure || tonemap) && ext != ".png")
    throw py::value_error(
        fmt::format("exposure and tonemap apply to PNG output only; {} holds linear radiance, written as given", path));
  render::ToneMapOptions tm;
  if (exposure) {
    if (!(std::isfinite(*exposure) && *exposure >= -30.0 && *exposure <= 30.0))
      throw py::value_error(fmt::format("exposure: expected a finite number of stops in [-30, 30], got {}", *exposure));
    tm.exposure_stops = float(*exposure);
  }
  if (tonemap) {
    if (*tonemap != "aces" && *tonemap != "clamp")
      throw py::value_error(fmt::format("tonemap: expected \"aces\" or \"clamp\", got \"{}\"", *tonemap));
    tm.curve = *tonemap == "clamp" ? render::ToneMap::Clamp : render::ToneMap::Aces;
  }
  const py::array_t<float, py::array::c_style | py::array::forcecast> a = np.attr("ascontiguousarray")(given, "float32");
  render::Image img(int(a.shape(1)), int(a.shape(0)));
  std::copy(a.data(), a.data() + img.rgb.size(), img.rgb.begin());
  for (size_t i = 0; i < img.rgb.size(); ++i)
    if (!std::isfinite(img.rgb[i]))
      throw py::value_error(fmt::format("img[{}, {}, {}]: expected finite radiance, got {}", i / 3 / size_t(img.width),
                                        i / 3 % size_t(img.width), i % 3, img.rgb[i]));
  try {
    py::gil_scoped_release release;
    render::write_image(path, img, tm);
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    PyErr_SetString(PyExc_OSError, e.what());
    throw py::error_already_set();
  }
}

// --- fit ---------------------------------------------------------------------------------------

// Samples from the caller's arrays: wi, wo (N, 3) unit directions above the horizon (one of them
// may be (3,), used for every row), value (N, 3) the BRDF in 1/sr, weight (N,) or None. Checked as
// the CSV reader checks its rows (measured/samples.cpp), each message naming the argument and row.
SampleSet samples_from_arrays(const py::object& wi_in, const py::object& wo_in, const py::object& value_in,
                              const py::object& weight_in) {
  if (wi_in.is_none() || wo_in.is_none() || value_in.is_none())
    throw py::value_error(
        "fit(): expected data (a path to a .binary, .brdf, .bsdf or .csv file) or all of the arrays wi=, wo= "
        "and value= (and optionally weight=)");
  const RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo"), value = rows_view(value_in, "value");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}, {"value", &value}});
  std::vector<double> weight;
  if (!weight_in.is_none()) {
    const py::module_ np = py::module_::import("numpy");
    py::array_t<double, py::array::c_style | py::array::forcecast> w;
    try {
      w = np.attr("asarray")(weight_in, "float64");
    } catch (py::error_already_set& e) {
      throw py::value_error(fmt::format("weight: expected an array of shape (N,) of numbers > 0 ({})", e.what()));
    }
    if (w.ndim() != 1 || size_t(w.shape(0)) != n)
      throw py::value_error(
          fmt::format("weight: expected an array of shape ({},) (the rows of wi, wo and value), got shape {}", n, shape_text(w)));
    weight.assign(w.data(), w.data() + n);
  }
  SampleSet set;
  set.source = "arrays";
  set.format = "arrays";
  set.samples.resize(n);
  // A unit direction: length 1 within 1e-5 (a float32 unit vector is within 1e-7; the fit takes z as
  // cos(theta) and does not normalise), strictly above the horizon (z > 0) as the CSV's theta < 90 deg.
  const auto direction = [](const RowsView& v, const char* name, size_t i) {
    const Vec3d w(v.at<double>(i, 0), v.at<double>(i, 1), v.at<double>(i, 2));
    if (!(std::abs(glm::length(w) - 1.0) <= 1e-5 && w.z > 0.0))
      throw py::value_error(
          fmt::format("{}: row {}: expected a unit direction above the horizon (length 1 within 1e-5, z > 0), "
                      "got ({}, {}, {})",
                      name, v.single ? 0 : i, w.x, w.y, w.z));
    return w;
  };
  for (size_t i = 0; i < n; ++i) {
    MeasuredSample& s = set.samples[i];
    s.wi = direction(wi, "wi", i);
    s.wo = direction(wo, "wo", i);
    for (int c = 0; c < 3; ++c) s.value[c] = value.at<double>(i, c);
    if (!(std::isfinite(s.value.x) && std::isfinite(s.value.y) && std::isfinite(s.value.z)) ||
        !(s.value.x >= 0.0 && s.value.y >= 0.0 && s.value.z >= 0.0))
      throw py::value_error(fmt::format("value: row {}: expected finite BRDF values >= 0 (1/sr), got ({}, {}, {})",
                                        value.single ? 0 : i, s.value.x, s.value.y, s.value.z));
    s.value += 0.0;  // -0 as 0, as the CSV reader
    if (!weight.empty()) {
      s.weight = weight[i];
      if (!(std::isfinite(s.weight) && s.weight > 0.0))
        throw py::value_error(fmt::format("weight: row {}: expected a finite number > 0, got {}", i, s.weight));
    }
  }
  return set;
}

// A measured data file as arrays (aniso.read_measured): what `aniso fit DATA` fits.
py::dict read_measured_py(const py::object& path_in) {
  if (!(py::isinstance<py::str>(path_in) || py::hasattr(path_in, "__fspath__")))
    throw py::value_error(
        fmt::format("path: expected a path to a .binary (MERL), .brdf (Cornell), .bsdf (RGL) or .csv file, got {}",
                    std::string(py::str(py::type::of(path_in).attr("__name__")))));
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_in));
  SampleSet set;
  {
    py::gil_scoped_release release;
    set = read_measured(path);
  }
  const size_t n = set.samples.size();
  py::array_t<double> wi = rows_out<double>(n, false, 3), wo = rows_out<double>(n, false, 3),
                      value = rows_out<double>(n, false, 3);
  py::array_t<double> weight(std::vector<py::ssize_t>{py::ssize_t(n)});
  double *pi = wi.mutable_data(), *po = wo.mutable_data(), *pv = value.mutable_data(), *pw = weight.mutable_data();
  for (size_t i = 0; i < n; ++i) {
    const MeasuredSample& s = set.samples[i];
    for (int c = 0; c < 3; ++c) pi[3 * i + c] = s.wi[c], po[3 * i + c] = s.wo[c], pv[3 * i + c] = s.value[c];
    pw[i] = s.weight;
  }
  py::dict d;
  d["wi"] = wi, d["wo"] = wo, d["value"] = value, d["weight"] = weight;
  d["source"] = set.source, d["format"] = set.format, d["description"] = set.description, d["warnings"] = set.warnings;
  return d;
}

// What aniso.fit returns: the fitted material, its error figures and the fit's record (the "fit"
// object of the CLI's fitted.json).
struct PyFitResult {
  PyMaterial material;
  json material_json;  // as fit_samples returned it (fitted.json without "fit")
  json provenance;     // fit_provenance: fitted.json's "fit"
  FitResult result;
};

std::atomic<bool> g_fit_interrupted{false};
extern "C" void on_fit_sigint(int) { g_fit_interrupted.store(true); }

// Python's numbers as the CLI's option text: the same parser, so the same checks and messages.
std::string option_text(const py::object& v, const char* name) {
  if (py::isinstance<py::bool_>(v) ||
      !(py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v) || py::isinstance<py::str>(v)))
    throw py::value_error(
        fmt::format("{}: expected a number, got {}", name, std::string(py::str(py::type::of(v).attr("__name__")))));
  return py::str(v);
}

PyFitResult fit_py(const py::object& data_in, const py::object& wi, const py::object& wo, const py::object& value,
                   const py::object& weight, const std::string& model, const py::object& lobes, const py::object& anisotropic,
                   bool allow_energy_gain, bool shared_exponents, const std::string& normalization, const py::object& metal,
                   const std::string& metal_lobe, const std::string& metric, const std::string& loss,
                   const py::object& loss_scale, const py::object& starts, const py::object& seed, const py::object& threads,
                   const py::object& max_iterations, const py::object& progress) {
  FitOptionText t;
  t.model = model;
  t.lobes = option_text(lobes, "lobes");
  // anisotropic: "auto" | "yes" | "no" as the CLI's --anisotropic, or True / False for yes / no.
  if (py::isinstance<py::bool_>(anisotropic))
    t.anisotropic = anisotropic.cast<bool>() ? "yes" : "no";
  else if (py::isinstance<py::str>(anisotropic))
    t.anisotropic = anisotropic.cast<std::string>();
  else
    throw py::value_error(fmt::format("anisotropic: expected \"auto\", \"yes\", \"no\", True or False, got {}",
                                      std::string(py::str(py::type::of(anisotropic).attr("__name__")))));
  t.allow_energy_gain = allow_energy_gain;
  t.shared_exponents = shared_exponents;
  t.normalization = normalization;
  t.metal = metal.is_none() ? "" : std::string(py::str(metal));
  t.metal_lobe = metal_lobe;
  t.metric = metric;
  t.loss = loss;
  t.loss_scale = option_text(loss_scale, "loss_scale");
  t.starts = option_text(starts, "starts");
  t.seed = option_text(seed, "seed");
  t.threads = option_text(threads, "threads");
  t.max_iterations = option_text(max_iterations, "max_iterations");
  FitOptions o = parse_fit_options(t);

  SampleSet data;
  if (!data_in.is_none()) {
    if (!wi.is_none() || !wo.is_none() || !value.is_none() || !weight.is_none())
      throw py::value_error("fit(): give either data (a file) or the arrays wi=, wo=, value=, not both");
    if (!(py::isinstance<py::str>(data_in) || py::hasattr(data_in, "__fspath__")))
      throw py::value_error(
          fmt::format("data: expected a path to a .binary (MERL), .brdf (Cornell), .bsdf (RGL) or .csv file, got {}",
                      std::string(py::str(py::type::of(data_in).attr("__name__")))));
    const std::string path = py::str(py::module_::import("os").attr("fspath")(data_in));
    py::gil_scoped_release release;
    data = read_measured(path);
  } else {
    data = samples_from_arrays(wi, wo, value, weight);
  }
  for (const std::string& w : data.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();

  // Progress: None shows a line on stderr as `aniso fit` does (when stderr is a terminal, once the fit
  // has run a second), True always, False never; a callable gets a dict per solver iteration.
  const bool call = !progress.is_none() && PyCallable_Check(progress.ptr()) && !py::isinstance<py::bool_>(progress);
  if (!progress.is_none() && !call && !py::isinstance<py::bool_>(progress))
    throw py::value_error(fmt::format("progress: expected None, True, False or a callable, got {}",
                                      std::string(py::str(py::type::of(progress).attr("__name__")))));
  const bool print = !call && (progress.is_none() ? isatty(STDERR_FILENO) != 0 : progress.cast<bool>());
  const double print_after = progress.is_none() ? 1.0 : 0.0;
  std::optional<py::error_already_set> callback_error;
  double last_print = -1.0;
  bool printed = false;
  // Ctrl-C (SIGINT, in the main thread) stops the fit at the solver's next iteration and raises
  // KeyboardInterrupt, as render does; a progress callback that raises stops it too.
  std::atomic<bool> stop{false};
  const py::module_ threading = py::module_::import("threading");
  const bool main_thread = threading.attr("current_thread")().is(threading.attr("main_thread")());
  struct SigintScope {
    bool active;
    struct sigaction old {};
    explicit SigintScope(bool on) : active(on) {
      if (!active) return;
      g_fit_interrupted.store(false);
      struct sigaction action {};
      action.sa_handler = on_fit_sigint;
      sigemptyset(&action.sa_mask);
      sigaction(SIGINT, &action, &old);
    }
    ~SigintScope() {
      if (active) sigaction(SIGINT, &old, nullptr);
    }
  };
  o.cancel = &stop;
  o.progress = [&](const FitProgress& p) {
    if (main_thread && g_fit_interrupted.load()) stop.store(true);
    if (call) {
      py::gil_scoped_acquire gil;
      try {
        py::dict d;
        d["stage"] = p.stage;
        d["iteration"] = p.iteration;
        d["cost"] = p.cost;
        d["elapsed_s"] = p.elapsed_s;
        d["remaining_s"] = p.remaining_s;
        progress(d);
      } catch (py::error_already_set& e) {
        if (!callback_error) callback_error.emplace(std::move(e));
        stop.store(true);
      }
    } else if (print && p.elapsed_s >= print_after && p.elapsed_s - last_print >= 0.1) {
      last_print = p.elapsed_s;
      std::fprintf(stderr, "\raniso.fit: %-90s",
                   fmt::format("{} iteration {} cost {:.4g}  {:.1f} s, about {:.0f} s left", p.stage, p.iteration, p.cost,
                               p.elapsed_s, p.remaining_s)
                       .c_str());
      printed = true;
    }
  };
  std::optional<FitResult> r;
  bool cancelled = false;
  {
    const SigintScope sigint(main_thread);
    py::gil_scoped_release release;
    try {
      r = fit_samples(data, o);
    } catch (const FitCancelled&) {
      cancelled = true;
    }
  }
  if (printed) std::fprintf(stderr, "\r\033[K");
  if (callback_error) throw std::move(*callback_error);
  if (cancelled) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  json provenance = fit_provenance(*r, data, o);
  PyMaterial mat(parse_material(r->material, "fitted material"), "fitted material");
  return PyFitResult{std::move(mat), r->material, std::move(provenance), std::move(*r)};
}

}  // namespace
}  // namespace aniso::python

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
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

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
  m.def(
      "metals",
      [] {
        py::dict out;
        for (const MetalData& md : metal_table()) {
          py::dict d;
          d["symbol"] = std::string(md.symbol);
          d["eta"] = vec3_py(md.eta);
          d["k"] = vec3_py(md.k);
          d["f0"] = vec3_py(F_Conductor(1.0, RGBT<double>(md.eta), RGBT<double>(md.k)));
          d["source"] = std::string(md.source);
          out[py::str(std::string(md.name))] = d;
        }
        return out;
      },
      "The measured metals (`aniso metals`): {name: {symbol, eta, k, f0, source}}, RGB eta and k.");
  m.def("fresnel", &fresnel_py, py::arg("cos_theta"), py::arg("metal") = py::none(), py::kw_only(), py::arg("eta") = py::none(),
        py::arg("k") = py::none(), py::arg("schlick") = false,
        "Unpolarised conductor Fresnel reflectance from air, RGB, as `aniso fresnel`: of a named metal\n"
        "(aniso.metals()) or of given eta and k (a number or [r, g, b] each). cos_theta: any shape;\n"
        "returns that shape + (3,). schlick=True: Schlick's approximation from the exact F0.");

  py::class_<FrameT<double>>(m, "Frame",
                             "An orthonormal tangent frame (t, b = n x t, n) that orients anisotropy (aniso/core/frame.h).\n\n"
                             "Frame(n, t=None): from a normal and an approximate tangent (Gram-Schmidt), or any frame\n"
                             "about n without t (Duff et al. 2017). n and t need not be unit; t parallel to n is a ValueError.")
      .def(py::init([](const py::object& n, const py::object& t) {
             const Vec3d nn = unit_arg(n, "n");
             if (t.is_none()) return FrameT<double>::from_normal(nn);
             // from_normal_tangent falls back to an arbitrary frame when t is (nearly) parallel to n:
             // here that is an error, as the caller asked for a tangent direction.
             const Vec3d tu = unit_arg(t, "t"), t_perp = tu - glm::dot(tu, nn) * nn;
             if (!(glm::dot(t_perp, t_perp) > 1e-12))
               throw py::value_error(
                   fmt::format("t: ({:.6g}, {:.6g}, {:.6g}) is parallel to n, so it gives no tangent direction "
                               "(its part perpendicular to n is below 1e-6 of its length); give a t "
                               "across n, or no t for any frame about n",
                               tu.x, tu.y, tu.z));
             return FrameT<double>::from_normal_tangent(nn, tu);
           }),
           py::arg("n") = py::make_tuple(0.0, 0.0, 1.0), py::arg("t") = py::none())
      .def_property_readonly(
          "t", [](const FrameT<double>& f) { return vec3_py(f.t); }, "tangent (x of the local frame)")
      .def_property_readonly(
          "b", [](const FrameT<double>& f) { return vec3_py(f.b); }, "bitangent n x t (y)")
      .def_property_readonly(
          "n", [](const FrameT<double>& f) { return vec3_py(f.n); }, "normal (z)")
      .def_property_readonly(
          "matrix",
          [](const FrameT<double>& f) {
            py::array_t<double> a({3, 3});
            for (int c = 0; c < 3; ++c) a.mutable_at(0, c) = f.t[c], a.mutable_at(1, c) = f.b[c], a.mutable_at(2, c) = f.n[c];
            return a;
          },
          "rows t, b, n: matrix @ w is to_local(w)")
      .def(
          "to_local",
          [](const FrameT<double>& f, const py::object& w) {
            return map_rows(w, "w", [&](const Vec3d& v) { return f.to_local(v); });
          },
          py::arg("w"), "World directions (N, 3) or (3,) into this frame: (w.t, w.b, w.n).")
      .def(
          "to_world",
          [](const FrameT<double>& f, const py::object& w) {
            return map_rows(w, "w", [&](const Vec3d& v) { return f.to_world(v); });
          },
          py::arg("w"), "Local directions (N, 3) or (3,) into world space: x t + y b + z n.")
      .def("rotated", &FrameT<double>::rotated, py::arg("psi"),
           "The frame with t and b rotated about n by psi radians (the scenes' angle_deg): t' = cos psi t + sin psi b.")
      .def("__repr__", [](const FrameT<double>& f) {
        return fmt::format("aniso.Frame(t=({:.6g}, {:.6g}, {:.6g}), b=({:.6g}, {:.6g}, {:.6g}), n=({:.6g}, {:.6g}, {:.6g}))",
                           f.t.x, f.t.y, f.t.z, f.b.x, f.b.y, f.b.z, f.n.x, f.n.y, f.n.z);
      });

  m.def("render", &render_py, py::arg("scene") = py::none(), py::kw_only(), py::arg("material") = py::none(),
        py::arg("spp") = py::none(), py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("seed") = uint64_t(1),
        py::arg("threads") = 0, py::arg("max_depth") = py::none(), py::arg("strategy") = py::none(),
        py::arg("progress") = py::none(),
        "Renders a scene (a dict with the keys of a scene file, or a path: docs/scenes.md) or, with\n"
        "material=, the preview scene of `aniso render --material`. Returns linear RGB radiance,\n"
        "(height, width, 3) float32, row 0 at the top. spp, width, height, max_depth, strategy override\n"
        "the scene's; the same seed gives the same image. Progress on stderr when it is a terminal;\n"
        "Ctrl-C stops it (KeyboardInterrupt).");
  m.def("save_image", &save_image_py, py::arg("img"), py::arg("path"), py::kw_only(), py::arg("exposure") = py::none(),
        py::arg("tonemap") = py::none(),
        "Writes an image such as render()'s ((height, width, 3) linear RGB) as `aniso render -o` does:\n"
        ".png tone-mapped (exposure in stops, tonemap \"aces\" (default) or \"clamp\", sRGB 8-bit), .exr (32-bit\n"
        "float) or .pfm linear as given. Written to a temporary file renamed into place. exposure and\n"
        "tonemap apply to PNG only (ValueError otherwise); a write failure is an OSError.");
  m.def(
      "export_glsl",
      [](const py::object& x, bool full) {
        const PyMaterial mat = as_material(x);
        return gl::export_glsl(mat.desc, mat.what, full);
      },
      py::arg("material"), py::kw_only(), py::arg("full") = false,
      "The material as one self-contained GLSL source, as `aniso export-glsl` (docs/glsl.md): the library\n"
      "functions it uses, or with full=True the whole library (and aniso_material()), as `--full`.");
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
         const std::string& metric, int starts, uint64_t seed) {
        const PyMaterial mat = as_material(x);
        std::optional<std::string> path;
        if (!path_in.is_none()) path = std::string(py::str(py::module_::import("os").attr("fspath")(path_in)));
        exporter::ExportOptions o;
        o.target = to;
        if (name) o.name = *name;
        FitOptionText metric_only;
        metric_only.metric = metric;
        o.metric = parse_fit_options(metric_only).metric;
        if (starts < 1 || starts > 100) throw InputError(fmt::format("starts: expected 1 to 100, got {}", starts));
        o.starts = starts;
        o.seed = seed;
        std::string bin_name;
        if (path && to == "gltf") {
          std::string stem = *path;
          if (const size_t slash = stem.find_last_of('/'); slash != std::string::npos) stem = stem.substr(slash + 1);
          if (const size_t dot = stem.find_last_of('.'); dot != std::string::npos && dot > 0) stem.resize(dot);
          bin_name = stem + ".bin";
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
            PyErr_SetString(PyExc_OSError, e.what());
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
      py::arg("metric") = "l2cos", py::arg("starts") = 4, py::arg("seed") = 1,
      "The material in a renderer's own format, as `aniso export --to` (docs/export.md): to = \"blender\",\n"
      "\"mitsuba3\", \"pbrt-v4\", \"materialx\" or \"gltf\". Returns {report, text, files}: the report (target\n"
      "model, parameters, exact or fitted, errors, notes) as a dict and as text, and the files (\"\" the main\n"
      "file's text, a glTF's .bin as bytes under its name). With path, writes them too (atomically; an\n"
      "OSError leaves nothing). A bad material or target raises ValueError.");
  py::class_<PyFitResult>(m, "FitResult",
                          "What aniso.fit returns: the fitted Material and its error figures (iterable as\n"
                          "material, errors), the fitted parameters and the record `aniso fit` stores in fitted.json.")
      .def_property_readonly(
          "material", [](const PyFitResult& r) { return r.material; }, "the fitted Material")
      .def_property_readonly(
          "errors", [](const PyFitResult& r) { return to_py(r.provenance["error"]); },
          "{l2cos, l2cos_rgb, log, log_rgb, relative_l2cos} over every sample (docs/fitting.md, \"Metrics\"),\n"
          "as `aniso fit` prints them: \"all\" is the RMS of the three channels")
      .def_property_readonly(
          "parameters",
          [](const PyFitResult& r) {
            py::dict d;
            for (size_t i = 0; i < r.result.parameters.size(); ++i)
              d[py::str(r.result.parameter_names[i])] = r.result.parameters[i];
            return d;
          },
          "the solver's parameter vector by name (\"kd.r\", \"alpha\", ...)")
      .def_property_readonly(
          "best_start", [](const PyFitResult& r) { return r.result.best_start; },
          "the start the result came from: \"moments\", \"ngan2005 NAME\", \"random K\"")
      .def_property_readonly("iterations", [](const PyFitResult& r) { return r.result.iterations; })
      .def_property_readonly("seconds", [](const PyFitResult& r) { return r.result.seconds; })
      .def_property_readonly("samples", [](const PyFitResult& r) { return r.result.samples_total; })
      .def_property_readonly("samples_in_solver", [](const PyFitResult& r) { return r.result.samples_used; })
      .def_property_readonly("termination", [](const PyFitResult& r) { return r.result.termination; })
      .def_property_readonly(
          "anisotropic", [](const PyFitResult& r) { return r.result.anisotropic; },
          "whether the fitted model is anisotropic (with its rotation_deg)")
      .def_property_readonly(
          "anisotropy_reason", [](const PyFitResult& r) { return r.result.anisotropy_reason; },
          "why: the auto rule's decision and figures, or the option")
      .def_property_readonly(
          "tied", [](const PyFitResult& r) { return r.result.tied; },
          "parameters the data did not constrain, tied to their isotropic partner (docs/fitting.md)")
      .def_property_readonly("weakly_constrained", [](const PyFitResult& r) { return r.result.weakly_constrained; })
      .def_property_readonly(
          "largest_albedo", [](const PyFitResult& r) { return r.result.largest_albedo; },
          "the fitted material's largest directional albedo over the grid of docs/fitting.md")
      .def_property_readonly(
          "fit", [](const PyFitResult& r) { return to_py(r.provenance); },
          "the \"fit\" object of `aniso fit`'s fitted.json (data, options, errors, solver)")
      .def(
          "to_dict",
          [](const PyFitResult& r) {
            json j = r.material_json;
            j["fit"] = r.provenance;
            return to_py(j);
          },
          "fitted.json as `aniso fit -o` writes it: the material's keys plus the \"fit\" object.")
      .def(
          "to_json",
          [](const PyFitResult& r, int indent) {
            json j = r.material_json;
            j["fit"] = r.provenance;
            return j.dump(indent) + "\n";
          },
          py::arg("indent") = 2, "to_dict() as JSON text, the file `aniso fit -o` writes (every tool reads it).")
      .def("__iter__",
           [](const PyFitResult& r) { return py::iter(py::make_tuple(py::cast(r.material), to_py(r.provenance["error"]))); })
      .def("__repr__", [](const PyFitResult& r) {
        return fmt::format("aniso.FitResult(model={}, l2cos={:.5g}, log={:.5g}, relative_l2cos={:.4g}, best_start={})",
                           r.material_json.value("model", ""), r.result.errors.l2cos_all, r.result.errors.log_all,
                           r.result.errors.relative_l2cos, json(r.result.best_start).dump());
      });

  m.def("fit", &fit_py, py::arg("data") = py::none(), py::kw_only(), py::arg("wi") = py::none(), py::arg("wo") = py::none(),
        py::arg("value") = py::none(), py::arg("weight") = py::none(), py::arg("model") = "lafortune", py::arg("lobes") = 1,
        py::arg("anisotropic") = "auto", py::arg("allow_energy_gain") = false, py::arg("shared_exponents") = false,
        py::arg("normalization") = "ward", py::arg("metal") = py::none(), py::arg("metal_lobe") = "ggx",
        py::arg("metric") = "l2cos", py::arg("loss") = "none", py::arg("loss_scale") = 0.0, py::arg("starts") = 6,
        py::arg("seed") = 1, py::arg("threads") = 0, py::arg("max_iterations") = 200, py::arg("progress") = py::none(),
        "Fits a model to measured data, as `aniso fit` (docs/fitting.md): the same solver, options, starts\n"
        "and error figures; the same data, options and seed give the same material.\n\n"
        "data: a path to a MERL .binary, Cornell .brdf, RGL tensor .bsdf or CSV file of samples (what `aniso fit\n"
        "DATA` reads);\n"
        "or instead wi, wo: (N, 3) unit directions above the horizon (one of them may be (3,)), value: (N, 3)\n"
        "f(wi, wo) in 1/sr (no cosine), weight: (N,) or None. The keywords are `aniso fit`'s options:\n"
        "model (lafortune | ward | ashikhmin-shirley | ggx | metal | principled), lobes (Lafortune, 1 to 8),\n"
        "anisotropic (\"auto\": when the data show it, \"yes\" / True, \"no\" / False; an anisotropic fit fits\n"
        "rotation_deg too), allow_energy_gain (else every directional albedo stays <= 1), shared_exponents, normalization (Ward: "
        "ward | duer | balanced), metal (a named metal; None fits eta\n"
        "and k), metal_lobe (ggx | ward | ashikhmin-shirley), metric (l2cos | log), loss (none | huber |\n"
        "cauchy | soft_l1), loss_scale, starts, seed, threads (0: all cores), max_iterations.\n"
        "progress: None (a line on stderr when it is a terminal, as the CLI), True, False, or a callable\n"
        "given {stage, iteration, cost, elapsed_s, remaining_s} each iteration. The GIL is released while\n"
        "fitting; Ctrl-C stops the fit (KeyboardInterrupt). Returns a FitResult: `m, errors = aniso.fit(...)`.\n"
        "Bad data or options raise ValueError with the CLI's message.");
  m.def(
      "read_measured", &read_measured_py, py::arg("path"),
      "Reads measured reflectance as `aniso fit DATA` does (a MERL .binary, Cornell .brdf, RGL tensor .bsdf\n"
      "or CSV file of samples; Cornell spectra reduced to linear sRGB; an RGL file sampled on a grid of\n"
      "directions): {wi, wo: (N, 3) unit directions, value: (N, 3) f in 1/sr, weight: (N,), source, format,\n"
      "description (what was sampled, for an RGL file; else empty), warnings}. aniso.fit(wi=..., wo=..., value=..., weight=...)\n"
      "on them fits what aniso.fit(path) fits.");
  m.def(
      "simd_target", [] { return std::string(batch::simd_target()); },
      "The SIMD target the batch path runs on this machine (\"AVX3\", \"AVX2\", ...).");
}
