// aniso/io/presets.h: named materials, usable wherever a material is (`--material NAME`).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace aniso {

struct PresetInfo {
  std::string name;     // "ngan/ward/nickel"
  std::string source;   // where the numbers come from
  nlohmann::json json;  // the material object
};

// All presets, in listing order: the lecture's matte steel, pbrt-v1's Lafortune fits, the metals,
// Ngan et al. 2005's fits of the MERL materials.
const std::vector<PresetInfo>& presets();
// Exact name, or an accepted alternative spelling (io/names.h: "aluminum").
std::optional<nlohmann::json> find_preset(std::string_view name);
// "\"gold\", \"brushed-gold\"": the presets nearest to a mistyped name, for "did you mean" messages.
std::string nearest_preset_names(std::string_view name);

}  // namespace aniso
