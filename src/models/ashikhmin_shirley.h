// models/ashikhmin_shirley.h: the Ashikhmin-Shirley model's host side (docs/models/ashikhmin-shirley.md;
// kernel aniso/brdf/ashikhmin_shirley.h). Its lobe rows are also the metal's AS lobe (models/metal.h).
#pragma once

#include "models/model.h"

namespace aniso::models {

template <typename T> inline constexpr Row<T, AshikhminShirleyT<T>> kASColours[] = {
    {reflectance("rd", 0.3, "diffuse reflectance Rd of the coupled 28/(23 pi) term"), ANISO_FIELD(rd)},
    {reflectance("rs", 0.05, "specular reflectance at normal incidence Rs (Schlick's F0)"), ANISO_FIELD(rs)},
    {reflectance("kd", 0.0, "extra Lambertian albedo (kd / pi); 0 in the paper, used by Ngan 2005's fits"), ANISO_FIELD(kd)},
    {{.name = "ks_scale",
      .kind = ParamKind::Color,
      .doc = "scale of the specular term; 1 in the paper, Ngan 2005's specular albedo",
      .min = 0.0,
      .max = kHuge,
      .default_value = 1.0},
     ANISO_FIELD(ks_scale)},
};
template <typename T> inline constexpr Row<T, AshikhminShirleyT<T>> kASLobe[] = {
    {{.name = "n_u",
      .kind = ParamKind::Scalar,
      .doc = "Phong-like exponent along the tangent t",
      .min = 0.0,
      .max = kHuge,
      .default_value = 100.0,
      .partner = "n_v"},
     ANISO_FIELD(lobe.n_u)},
    {{.name = "n_v",
      .kind = ParamKind::Scalar,
      .doc = "Phong-like exponent along the bitangent b",
      .min = 0.0,
      .max = kHuge,
      .default_value = 100.0,
      .partner = "n_u"},
     ANISO_FIELD(lobe.n_v)},
    {{.name = "n",
      .kind = ParamKind::Scalar,
      .doc = "sets n_u = n_v (isotropic); excludes n_u and n_v",
      .min = 0.0,
      .max = kHuge,
      .default_value = NAN,
      .sets = {"n_u", "n_v"}}},
};
inline constexpr auto kASColourParams = specs(kASColours<float>);
inline constexpr auto kASLobeParams = specs(kASLobe<float>);

struct AshikhminShirley {
  static constexpr std::span<const ParamSpec> parts[] = {kASColourParams, kASLobeParams, kOrientation};
  static constexpr ModelSpec spec{"ashikhmin-shirley", "Ashikhmin-Shirley", "Ashikhmin & Shirley 2000, JGT 5(2)", parts};
  template <typename T> static constexpr std::span<const Row<T, AshikhminShirleyT<T>>> bound[] = {kASColours<T>, kASLobe<T>};
  // The lobe alone: the metal's "lobe" of model "ashikhmin-shirley".
  static constexpr std::span<const ParamSpec> lobe_parts[] = {kASLobeParams};
  static constexpr ModelSpec lobe_spec{"ashikhmin-shirley", "Ashikhmin-Shirley lobe", "", lobe_parts};
  // The fit (src/fit): Ngan 2005's form, kd / pi + ks_scale F(rs) f_s without the coupled diffuse
  // (rd = 0), rs grey.
  static constexpr FitKey fit_keys[] = {{"kd", FitKey::Rgb},
                                        {"ks_scale", FitKey::Rgb},
                                        {"rs", FitKey::Grey},
                                        {"n_u", FitKey::One, "n"},
                                        {"n_v", FitKey::One, {}, "n_u"}};
  static constexpr FitFixed fit_fixed[] = {{"rd", 0.0}};
  static constexpr FitDesc fit{fit_keys, fit_fixed, {"n_u", "n_v"}, true};
};
static_assert(rows_match_fields<AshikhminShirley>());

}  // namespace aniso::models
