// models/ggx.h: the anisotropic GGX model's host side (docs/models/ggx.md; kernel aniso/brdf/ggx.h).
// Its lobe rows are also the metal's GGX lobe (models/metal.h).
#pragma once

#include "models/model.h"

namespace aniso::models {

template <typename T> inline constexpr Row<T, GGXT<T>> kGGXColours[] = {
    {reflectance("kd", 0.0, "Lambertian albedo added to the specular term (kd / pi)"), ANISO_FIELD(kd)},
    {reflectance("f0", 0.04, "Schlick's reflectance at normal incidence"), ANISO_FIELD(f0)},
    {reflectance("f90", 1.0, "the reflectance at grazing incidence: 1 in Schlick's form; below 1 a flatter Fresnel"),
     ANISO_FIELD(f90)},
};
template <typename T> inline constexpr Row<T, GGXT<T>> kGGXLobe[] = {
    {roughness("alpha_x", 0.2, "GGX roughness along the tangent t", "alpha_y"), ANISO_FIELD(lobe.alpha_x)},
    {roughness("alpha_y", 0.2, "GGX roughness along the bitangent b", "alpha_x"), ANISO_FIELD(lobe.alpha_y)},
    {roughness_shorthand()},
};
inline constexpr auto kGGXColourParams = specs(kGGXColours<float>);
inline constexpr auto kGGXLobeParams = specs(kGGXLobe<float>);

struct GGX {
  static constexpr std::span<const ParamSpec> parts[] = {kGGXColourParams, kGGXLobeParams, kOrientation};
  static constexpr ModelSpec spec{"ggx", "Anisotropic GGX",
                                  "Walter et al. 2007; Heitz 2014 (Smith G2); Heitz 2018 (visible normals)", parts};
  template <typename T> static constexpr std::span<const Row<T, GGXT<T>>> bound[] = {kGGXColours<T>, kGGXLobe<T>};
  // The lobe alone: the metal's "lobe" of model "ggx".
  static constexpr std::span<const ParamSpec> lobe_parts[] = {kGGXLobeParams};
  static constexpr ModelSpec lobe_spec{"ggx", "GGX lobe", "", lobe_parts};
  // The fit (src/fit).
  static constexpr FitKey fit_keys[] = {{"kd", FitKey::Rgb},
                                        {"f0", FitKey::Rgb},
                                        {.key = "f90", .shape = FitKey::Rgb, .optional = true},
                                        {"alpha_x", FitKey::One, "alpha"},
                                        {"alpha_y", FitKey::One, {}, "alpha_x"}};
  static constexpr FitDesc fit{fit_keys, {}, {"alpha_x", "alpha_y"}};
};
static_assert(rows_match_fields<GGX>());

}  // namespace aniso::models
