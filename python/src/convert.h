// python/src/convert.h: JSON <-> Python, for materials, scenes and fit records given or returned
// as dicts.
#pragma once

#include <string>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace aniso::python {

namespace py = pybind11;
using json = nlohmann::json;

// A JSON value as Python: objects as dicts, arrays as lists, numbers, strings, bools, null as None.
py::object to_py(const json& j);

// A dict as the JSON a material or scene file would hold. NumPy arrays and scalars are read as
// their lists and numbers; `where` and `path` name the value in messages ("inline material: ks[1]").
// As parse_json_text (io/json_read.h): nesting deeper than kMaxJsonDepth is an error with the CLI's
// message, which also bounds the recursion here; a dict or list that contains itself is an error of
// its own (it would otherwise be reported as too deep).
json from_py(const py::handle& h, const std::string& where, const std::string& path);

}  // namespace aniso::python
