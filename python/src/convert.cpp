// python/src/convert.cpp: JSON <-> Python (convert.h).
#include "convert.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "io/json_read.h"

namespace aniso::python {

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

namespace {

// from_py's conversion (convert.h), with the dicts and lists it is inside for the cycle check.
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

}  // namespace

json from_py(const py::handle& h, const std::string& where, const std::string& path) { return FromPy(where).convert(h, path); }

}  // namespace aniso::python
