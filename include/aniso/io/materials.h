// aniso/io/materials.h: materials from JSON, presets or files, validated against the parameter tables
// (io/params.h) and built into kernel values (aniso/brdf/material.h).
//
// A material is a JSON object {"model": NAME, ...keys of that model's table}. Unknown keys,
// missing keys, wrong types and values out of range are InputErrors naming the key and the range.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/io/params.h"

namespace aniso {

struct MeasuredData;
namespace rgl {
struct RglData;
}

struct MaterialDesc {
  std::string model;    // the table's name ("ward", ...)
  ParamValues params;   // validated, defaults filled in
  nlohmann::json json;  // the object it was read from
  // model "measured": the loaded table and its sampling tables, which the kernel points into
  // (lifetime rule: include/aniso/measured/measured.h).
  std::shared_ptr<const MeasuredData> measured;
  // model "rgl": the tensor file's tables (the same lifetime rule, include/aniso/rgl/rgl_material.h).
  std::shared_ptr<const rgl::RglData> rgl;
};

// "the number 3", "the string \"x\"", "an array of 2 elements", ...: what a message says it got.
std::string json_type_name(const nlohmann::json& v);

// Validates obj against spec; `where` prefixes error messages ("gold.json", "preset clay").
// `tag_key` ("model") is skipped: the caller has read it.
ParamValues read_params(const nlohmann::json& obj, const ModelSpec& spec, const std::string& where,
                        std::string_view tag_key = {});

// base_dir: the folder a measured material's "file" is relative to ("" = the working directory).
MaterialDesc parse_material(const nlohmann::json& obj, const std::string& where, const std::string& base_dir = {});

// A preset name (`aniso presets`), a path to a JSON file, a path ending in .binary (a MERL BRDF
// file: {"model": "measured", "file": PATH}, docs/measured.md) or .bsdf (an RGL tensor file:
// {"model": "rgl", "file": PATH}, docs/rgl.md), or an inline JSON object ("{...}";
// messages then say "inline material").
MaterialDesc load_material(const std::string& spec);

// A path ending in .binary (any case): load_material reads it as a MERL file.
bool is_measured_file_name(const std::string& spec);

// The material as resolved: every key of its table with defaults filled in and shorthands ("alpha",
// "cxy") expanded. Valid input to parse_material, giving the same material (`aniso presets --show`).
nlohmann::json resolved_json(const MaterialDesc& desc);

template <typename T> MaterialT<T> build_material(const MaterialDesc& desc);
extern template MaterialT<float> build_material<float>(const MaterialDesc&);
extern template MaterialT<double> build_material<double>(const MaterialDesc&);

}  // namespace aniso
