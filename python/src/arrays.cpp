// python/src/arrays.cpp: reading NumPy arguments (python/src/arrays.h).
#include "arrays.h"

#include <fmt/format.h>

namespace aniso::python {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += fmt::format("{}{}", d ? ", " : "", a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

RowsView rows_view(const py::handle& obj, const char* name, int columns) {
  const py::module_ np = py::module_::import("numpy");
  const std::string expected = fmt::format("an array of shape (N, {0}) or ({0},)", columns);
  py::array a;
  try {
    a = np.attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    // Ragged lists, objects NumPy cannot read as an array.
    throw py::value_error(fmt::format("{}: expected {}, got {} ({})", name, expected,
                                      std::string(py::str(py::type::of(obj).attr("__name__"))), e.what()));
  }
  const char kind = a.dtype().kind();
  const py::ssize_t itemsize = a.dtype().itemsize();
  RowsView v;
  if (kind == 'f' && (itemsize == 4 || itemsize == 8)) {
    v.f32 = itemsize == 4;
  } else if ((kind == 'f' && itemsize < 8) || kind == 'i' || kind == 'u') {
    a = a.attr("astype")(np.attr("float64"));  // integers and float16 (exactly representable): computed in double
  } else if (kind == 'f') {
    // long double (float96, float128): rounding it to double would lose its extra digits unasked.
    throw py::value_error(
        fmt::format("{}: expected {} of float32 or float64 (or float16, integers), got dtype {}: "
                    "convert it with .astype(numpy.float64) if double precision is enough",
                    name, expected, std::string(py::str(a.dtype()))));
  } else {
    throw py::value_error(fmt::format("{}: expected {} of float32 or float64 (or integers), got dtype {}", name, expected,
                                      std::string(py::str(a.dtype()))));
  }
  if (a.ndim() == 1 && a.shape(0) == columns) {
    v.single = true;
    v.rows = 1;
    v.row_stride = 0;
    v.col_stride = a.strides(0);
  } else if (a.ndim() == 2 && a.shape(1) == columns) {
    v.rows = size_t(a.shape(0));
    v.row_stride = a.strides(0);
    v.col_stride = a.strides(1);
  } else {
    throw py::value_error(fmt::format("{}: expected {}, got shape {}", name, expected, shape_text(a)));
  }
  v.data = static_cast<const char*>(a.data());
  v.keep = std::move(a);
  return v;
}

size_t common_rows(std::initializer_list<std::pair<const char*, const RowsView*>> inputs) {
  size_t n = 1;
  const char* first = nullptr;
  for (const auto& [name, v] : inputs) {
    if (v->single) continue;
    if (!first) {
      first = name;
      n = v->rows;
    } else if (v->rows != n) {
      throw py::value_error(
          fmt::format("{} and {}: expected the same number of rows N (or one of them of shape (3,)), "
                      "got {} and {}",
                      first, name, n, v->rows));
    }
  }
  return n;
}

}  // namespace aniso::python
