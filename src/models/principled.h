// models/principled.h: the Disney principled model's host side (docs/models/principled.md; kernel
// aniso/brdf/principled.h).
#pragma once

#include "models/model.h"

namespace aniso::models {

// Disney's BRDF Explorer, src/brdfs/disney.brdf lines 21-33: every parameter in [0, 1] with the
// file's defaults (base colour: ours is linear, the file's .82 .67 .16 is a display colour; a grey
// default here). Roughness 0 is allowed: the kernel clamps alpha to 0.001 (principled.h).
template <typename T> inline constexpr Row<T, PrincipledT<T>> kPrincipledRows[] = {
    {reflectance("base_color", 0.5, "base colour C (linear RGB): diffuse albedo, metallic specular colour"),
     ANISO_FIELD(base_color)},
    {unit("metallic", 0.0, "0 dielectric, 1 metallic (mixes the specular colour to C, removes the diffuse)"),
     ANISO_FIELD(metallic)},
    {unit("subsurface", 0.0, "blend from the diffuse to Hanrahan-Krueger's subsurface approximation"), ANISO_FIELD(subsurface)},
    {unit("specular", 0.5, "dielectric specular amount: F0 = 0.08 specular (0.5: F0 = 0.04, IOR 1.5)"), ANISO_FIELD(specular)},
    {unit("roughness", 0.5, "alpha = roughness^2 (split by anisotropic); also the diffuse retro-reflection"),
     ANISO_FIELD(roughness)},
    {unit("specular_tint", 0.0, "tints the dielectric F0 towards the hue of C"), ANISO_FIELD(specular_tint)},
    {unit("anisotropic", 0.0, "aspect = sqrt(1 - 0.9 anisotropic), alpha_x = alpha / aspect, alpha_y = alpha aspect"),
     ANISO_FIELD(anisotropic)},
    {unit("sheen", 0.0, "grazing sheen amount (for cloth)"), ANISO_FIELD(sheen)},
    {unit("sheen_tint", 0.5, "tints the sheen towards the hue of C"), ANISO_FIELD(sheen_tint)},
    {unit("clearcoat", 0.0, "second, GTR1 specular lobe (F0 0.04, fixed alpha 0.25 masking), scaled 0.25 clearcoat"),
     ANISO_FIELD(clearcoat)},
    {unit("clearcoat_gloss", 1.0, "clearcoat alpha = 0.1 (0, satin) to 0.001 (1, gloss)"), ANISO_FIELD(clearcoat_gloss)},
};
inline constexpr auto kPrincipledParams = specs(kPrincipledRows<float>);

struct Principled {
  static constexpr std::span<const ParamSpec> parts[] = {kPrincipledParams, kOrientation};
  static constexpr ModelSpec spec{"principled", "Disney principled",
                                  "Burley 2012, Physically-Based Shading at Disney (BRDF Explorer's disney.brdf)", parts};
  template <typename T> static constexpr std::span<const Row<T, PrincipledT<T>>> bound[] = {kPrincipledRows<T>};
  // The fit (src/fit): base_color, metallic, specular, roughness and, when anisotropic,
  // anisotropic; subsurface, sheen and clearcoat keep their defaults (0). roughness stays above
  // 0.04: below 0.0316 alpha = roughness^2 clamps at 0.001 (principled.h), a flat direction for the
  // solver. No pair to swap (anisotropic >= 0 always makes alpha_x >= alpha_y): the lobe repeats
  // after a half turn.
  static constexpr FitKey fit_keys[] = {{"base_color", FitKey::Rgb},
                                        {"metallic"},
                                        {"specular"},
                                        {"roughness", FitKey::One, {}, {}, NAN, 0.04},
                                        {"anisotropic", FitKey::One, {}, {}, 0.0}};
  static constexpr FitDesc fit{fit_keys, {}, {}, false, 180.0};
};
static_assert(rows_match_fields<Principled>());

}  // namespace aniso::models
