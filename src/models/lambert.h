// models/lambert.h: the Lambert model's host side (docs/models/lambert.md; kernel aniso/brdf/lambert.h).
#pragma once

#include "models/model.h"

namespace aniso::models {

template <typename T> inline constexpr Row<T, LambertT<T>> kLambertRows[] = {
    {reflectance("kd", 0.5, "diffuse albedo: f = kd / pi"), ANISO_FIELD(kd)},
};
inline constexpr auto kLambertParams = specs(kLambertRows<float>);

struct Lambert {
  static constexpr std::span<const ParamSpec> parts[] = {kLambertParams};
  static constexpr ModelSpec spec{"lambert", "Lambert", "Lambert 1760", parts};
  template <typename T> static constexpr std::span<const Row<T, LambertT<T>>> bound[] = {kLambertRows<T>};
  // The fit (src/fit): kd.
  static constexpr FitKey fit_keys[] = {{"kd", FitKey::Rgb}};
  static constexpr FitDesc fit{fit_keys};
};
static_assert(rows_match_fields<Lambert>());

}  // namespace aniso::models
