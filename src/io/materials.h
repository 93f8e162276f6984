// io/materials.h: materials from JSON, presets or files, validated against the parameter tables
// (io/params.h) and built into kernel values (aniso/brdf/material.h).
//
// A material is a JSON object {"model": NAME, ...keys of that model's table}. Unknown keys,
// missing keys, wrong types and values out of range are InputErrors naming the key and the range.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "io/params.h"

namespace aniso {

struct MaterialDesc {
  std::string model;    // the table's name ("ward", ...)
  ParamValues params;   // validated, defaults filled in
  nlohmann::json json;  // the object it was read from
};

// "the number 3", "the string \"x\"", "an array of 2 elements", ...: what a message says it got.
std::string json_type_name(const nlohmann::json& v);

// Validates obj against spec; `where` prefixes error messages ("gold.json", "preset clay").
ParamValues read_params(const nlohmann::json& obj, const ModelSpec& spec, const std::string& where);

MaterialDesc parse_material(const nlohmann::json& obj, const std::string& where);

// A preset name (`aniso presets`) or a path to a JSON file.
MaterialDesc load_material(const std::string& name_or_path);

template <typename T> MaterialT<T> build_material(const MaterialDesc& desc);
extern template MaterialT<float> build_material<float>(const MaterialDesc&);
extern template MaterialT<double> build_material<double>(const MaterialDesc&);

}  // namespace aniso
