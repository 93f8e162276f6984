#include "data/metals.h"

#include <fmt/format.h>

namespace aniso {
namespace {

constexpr MetalData kMetals[] = {
#include "data/metal_table.inc"
};

}  // namespace

std::span<const MetalData> metal_table() { return kMetals; }

const MetalData* find_metal(std::string_view name) {
  for (const MetalData& m : kMetals)
    if (m.name == name) return &m;
  return nullptr;
}

std::string metal_names() {
  std::string s;
  for (const MetalData& m : kMetals) s += fmt::format("{}\"{}\"", s.empty() ? "" : ", ", m.name);
  return s;
}

}  // namespace aniso
