#include "aniso/data/metals.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "io/json_read.h"
#include "io/names.h"

namespace aniso {
namespace {

constexpr MetalData kMetals[] = {
#include "data/metal_table.inc"
};

struct MetalSpectrumRow {
  std::string_view name;
  double n[kMetalSpectrumSamples], k[kMetalSpectrumSamples];
};
constexpr MetalSpectrumRow kSpectra[] = {
#include "data/metal_spectra.inc"
};
static_assert(std::size(kSpectra) == std::size(kMetals), "metal_spectra.inc has one row per metal_table.inc row");

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

glm::dvec2 metal_nk(const MetalData& m, double lambda_nm) {
  size_t row = 0;
  while (row < std::size(kMetals) && kMetals[row].name != m.name) ++row;
  if (row == std::size(kMetals) || kSpectra[row].name != m.name)
    throw std::invalid_argument(fmt::format("metal_nk: \"{}\" is not a row of metal_table()", m.name));
  const MetalSpectrumRow& s = kSpectra[row];
  const double x = std::clamp((lambda_nm - kMetalSpectrumFirstNm) / kMetalSpectrumStepNm, 0.0, double(kMetalSpectrumSamples - 1));
  const int i = std::min(int(x), kMetalSpectrumSamples - 2);
  const double t = x - i;
  return {(1.0 - t) * s.n[i] + t * s.n[i + 1], (1.0 - t) * s.k[i] + t * s.k[i + 1]};
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
