#include "aniso/data/metals.h"

#include <vector>

#include <fmt/format.h>

#include "io/json_read.h"
#include "io/names.h"

namespace aniso {
namespace {

constexpr MetalData kMetals[] = {
#include "data/metal_table.inc"
};

}  // namespace

std::span<const MetalData> metal_table() { return kMetals; }

const MetalData* find_metal(std::string_view name_in) {
  for (const MetalData& m : kMetals)
    if (m.name == name_in) return &m;
  const std::string name = canonical_spelling(name_in);  // "aluminum" -> "aluminium"
  for (const MetalData& m : kMetals)
    if (m.name == name) return &m;
  return nullptr;
}

std::string metal_names() {
  std::string s;
  for (const MetalData& m : kMetals) s += fmt::format("{}\"{}\"", s.empty() ? "" : ", ", m.name);
  return s;
}

std::string unknown_metal_message(std::string_view name) {
  std::vector<std::string> names;
  for (const MetalData& m : kMetals) names.emplace_back(m.name);
  const std::string near = nearest_names(name, names);
  return fmt::format("unknown metal \"{}\"{}; the metals are {}", text_escape(name),
                     near.empty() ? "" : fmt::format(" (did you mean {}?)", near), metal_names());
}

}  // namespace aniso
