// models/phong.h: the Phong model's host side (docs/models/phong.md; kernel aniso/brdf/phong.h).
#pragma once

#include "models/model.h"

namespace aniso::models {

template <typename T> inline constexpr Row<T, PhongT<T>> kPhongRows[] = {
    {reflectance("kd", 0.0, "diffuse albedo (kd / pi)"), ANISO_FIELD(kd)},
    {{.name = "ks",
      .kind = ParamKind::Color,
      .doc = "specular colour: scales (r . wo)^s",
      .min = 0.0,
      .max = kHuge,
      .default_value = 0.5},
     ANISO_FIELD(ks)},
    {{.name = "exponent", .kind = ParamKind::Scalar, .doc = "Phong exponent s", .min = 0.0, .max = kHuge, .default_value = 20.0},
     ANISO_FIELD(lobe.exponent)},
    {{.name = "normalized",
      .kind = ParamKind::Bool,
      .doc = "multiply the lobe by (s + 2) / (2 pi) (Lewis 1994)",
      .default_value = 1.0},
     ANISO_FIELD(lobe.normalized)},
};
inline constexpr auto kPhongParams = specs(kPhongRows<float>);

struct Phong {
  static constexpr std::span<const ParamSpec> parts[] = {kPhongParams};
  static constexpr ModelSpec spec{"phong", "Phong", "Phong 1975; Lewis 1994 (normalisation)", parts};
  template <typename T> static constexpr std::span<const Row<T, PhongT<T>>> bound[] = {kPhongRows<T>};
  // The fit (src/fit): the normalised lobe, as Ngan 2005's "Blinn-Phong" fits are (docs/presets.md:
  // bbm's NganBlinnPhong is this mirror lobe).
  static constexpr FitKey fit_keys[] = {{"kd", FitKey::Rgb}, {"ks", FitKey::Rgb}, {"exponent"}};
  static constexpr FitFixed fit_fixed[] = {{"normalized", 1.0}};
  static constexpr FitDesc fit{fit_keys, fit_fixed};
};
static_assert(rows_match_fields<Phong>());

}  // namespace aniso::models
