// models/lafortune.h: the Lafortune model's host side (docs/models/lafortune.md; kernel
// aniso/brdf/lafortune.h). Hand-written builders: its lobes are a list (up to 8), each lobe's keys
// the fields of one LafortuneLobeT.
#pragma once

#include <algorithm>
#include <cmath>

#include "models/model.h"

namespace aniso::models {

// C coefficients: fitted values lie within |C| < 3; 100 is a generous bound that keeps |a|^n finite
// for moderate n.
inline constexpr ParamSpec kLafortuneLobe[] = {
    {.name = "cx",
     .kind = ParamKind::Color,
     .doc = "C_x: weight of wi.x wo.x (per channel)",
     .min = -100.0,
     .max = 100.0,
     .default_value = -1.0,
     .partner = "cy"},
    {.name = "cy",
     .kind = ParamKind::Color,
     .doc = "C_y: weight of wi.y wo.y (per channel)",
     .min = -100.0,
     .max = 100.0,
     .default_value = -1.0,
     .partner = "cx"},
    {.name = "cxy",
     .kind = ParamKind::Color,
     .doc = "sets C_x = C_y (isotropic); excludes cx and cy",
     .min = -100.0,
     .max = 100.0,
     .default_value = NAN,
     .sets = {"cx", "cy"}},
    {.name = "cz",
     .kind = ParamKind::Color,
     .doc = "C_z: weight of wi.z wo.z (per channel)",
     .min = -100.0,
     .max = 100.0,
     .default_value = 1.0},
    {.name = "n", .kind = ParamKind::Color, .doc = "lobe exponent (per channel)", .min = 0.0, .max = kHuge, .required = true},
    {.name = "scale",
     .kind = ParamKind::Color,
     .doc = "per-lobe scale k_s (the lecture's optional factor)",
     .min = 0.0,
     .max = kHuge,
     .default_value = 1.0},
};

// A lobe's value is at most scale max|C|^n (the base is C . (wi * wo) <= max|C| by Cauchy-Schwarz);
// beyond 1e30 the float kernels overflow (float max 3.4e38, with room for the sums and the
// sampling weights).
inline constexpr ParamRule kLafortuneLobeRules[] = {
    {.kind = ParamRule::Kind::PeakBelow,
     .key = "n",
     .keys = {"cx", "cy", "cz"},
     .message = "with max|C| = {cmax:g} and scale {scale:g}, channel {channel} reaches {cmax:g}^{n:g}, beyond the float range "
                "(the peak scale max|C|^n must stay below 1e30: lower n or |C|)",
     .exponent = "n",
     .scale = "scale",
     .limit = 30.0},
};

struct Lafortune {
  static constexpr std::span<const ParamSpec> lobe_parts[] = {kLafortuneLobe};
  static constexpr ModelSpec lobe_spec{"lobes[i]", "Lafortune lobe", "", lobe_parts, kLafortuneLobeRules};
  static constexpr ParamSpec params[] = {
      reflectance("rho_d", 0.0, "diffuse albedo (rho_d / pi)"),
      {.name = "lobes",
       .kind = ParamKind::List,
       .doc = "generalised cosine lobes",
       .required = true,
       .sub = &lobe_spec,
       .max_items = 8},
  };
  static constexpr std::span<const ParamSpec> parts[] = {params, kOrientation};
  static constexpr ModelSpec spec{"lafortune", "Lafortune", "Lafortune et al. 1997, SIGGRAPH", parts};

  template <typename T> static LafortuneT<T> build(const MaterialDesc& d) {
    const ParamValues& p = d.params;
    LafortuneT<T> m;
    m.rho_d = rgb<T>(p.color("rho_d"));
    const auto& lobes = p.list("lobes");
    m.lobe_count = static_cast<int>(lobes.size());
    for (size_t i = 0; i < lobes.size(); ++i) {
      const ParamValues& l = lobes[i];
      m.lobes[i].cx = rgb<T>(l.color("cx"));
      m.lobes[i].cy = rgb<T>(l.color("cy"));
      m.lobes[i].cz = rgb<T>(l.color("cz"));
      m.lobes[i].n = rgb<T>(l.color("n"));
      m.lobes[i].scale = rgb<T>(l.color("scale"));
    }
    return m;
  }

  static std::string glsl(const ParamValues& pv, const SlotFn& P) {
    const int count = int(pv.list("lobes").size());
    std::string b = fmt::format("  m.rho_d = {};\n  m.lobe_count = {};\n", P("rho_d"), count);
    for (int i = 0; i < count; ++i) {
      const std::string l = fmt::format("lobes{}_", i);
      b += fmt::format(
          "  m.lobes[{0}].cx = {1};\n  m.lobes[{0}].cy = {2};\n  m.lobes[{0}].cz = {3};\n"
          "  m.lobes[{0}].n = {4};\n  m.lobes[{0}].scale = {5};\n",
          i, P(l + "cx"), P(l + "cy"), P(l + "cz"), P(l + "n"), P(l + "scale"));
    }
    return b;
  }
};

}  // namespace aniso::models
