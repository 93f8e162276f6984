// models/metal.h: the metal's host side (docs/models/metal.md; kernel aniso/brdf/metal.h): a
// conductor's Fresnel with measured or given eta and k, one of three specular lobes (the lobe rows
// of models/ward.h, ashikhmin_shirley.h, ggx.h) and an optional directional-diffuse lobe.
// Hand-written builders: the metal's name is looked up, the lobe is chosen by its "model" key and
// the directional lobe's keys are folded into the kernel's.
#pragma once

#include <algorithm>
#include <cmath>

#include "aniso/data/metals.h"
#include "models/ashikhmin_shirley.h"
#include "models/ggx.h"
#include "models/model.h"
#include "models/ward.h"

namespace aniso::models {

inline constexpr ParamSpec kDirectionalDiffuse[] = {
    {.name = "albedo",
     .kind = ParamKind::Color,
     .doc = "lobe albedo at normal incidence, multiplied by the metal's F0 colour",
     .min = 0.0,
     .max = 1.0,
     .default_value = 0.1},
    {.name = "cx",
     .kind = ParamKind::Scalar,
     .doc = "C_x of the lobe",
     .min = -100.0,
     .max = 100.0,
     .default_value = -1.0,
     .partner = "cy"},
    {.name = "cy",
     .kind = ParamKind::Scalar,
     .doc = "C_y of the lobe",
     .min = -100.0,
     .max = 100.0,
     .default_value = -1.0,
     .partner = "cx"},
    {.name = "cxy",
     .kind = ParamKind::Scalar,
     .doc = "sets C_x = C_y; excludes cx and cy",
     .min = -100.0,
     .max = 100.0,
     .default_value = NAN,
     .sets = {"cx", "cy"}},
    {.name = "cz", .kind = ParamKind::Scalar, .doc = "C_z of the lobe", .min = -100.0, .max = 100.0, .default_value = 1.0},
    {.name = "n",
     .kind = ParamKind::Scalar,
     .doc = "lobe exponent (broad: 1 to 20)",
     .min = 0.0,
     .max = kHuge,
     .default_value = 5.0},
};

// The lobe divides C by max|C| (Metal::build): one coefficient at least is non-zero.
inline constexpr ParamRule kDirectionalDiffuseRules[] = {
    {.kind = ParamRule::Kind::NonZero,
     .key = "cz",
     .keys = {"cx", "cy", "cz"},
     .message = "the lobe needs at least one non-zero coefficient"},
};
// Either a metal's name or both eta and k.
inline constexpr ParamRule kMetalRules[] = {
    {.kind = ParamRule::Kind::Exclusive,
     .key = "metal",
     .keys = {"eta", "k"},
     .message = "give either \"metal\" or \"eta\" and \"k\", not both"},
    {.kind = ParamRule::Kind::KeyOrAll,
     .key = "metal",
     .keys = {"eta", "k"},
     .message = "missing: a metal needs \"metal\" (a name) or both \"eta\" and \"k\""},
};

struct Metal {
  static constexpr std::span<const ParamSpec> directional_diffuse_parts[] = {kDirectionalDiffuse};
  static constexpr ModelSpec directional_diffuse_spec{"directional_diffuse", "Directional-diffuse lobe",
                                                      "Lafortune 1997 lobe with Ngan 2005's normalisation",
                                                      directional_diffuse_parts, kDirectionalDiffuseRules};
  // The lobe's table for each of its "model" choices (enum_names<SpecularLobeKind>, in that order).
  static constexpr const ModelSpec* lobe_specs[] = {&Ward::lobe_spec, &AshikhminShirley::lobe_spec, &GGX::lobe_spec};
  static constexpr ParamSpec params[] = {
      {.name = "metal",
       .kind = ParamKind::String,
       .doc = "measured metal: gold silver copper aluminium chromium iron nickel titanium platinum tungsten "
              "zinc brass (or give eta and k)"},
      {.name = "eta",
       .kind = ParamKind::Color,
       .doc = "real part of the complex index of refraction (RGB)",
       .min = 0.0,
       .max = 100.0,
       .min_exclusive = true,
       .default_value = NAN},
      {.name = "k",
       .kind = ParamKind::Color,
       .doc = "imaginary part (extinction coefficient, RGB)",
       .min = 0.0,
       .max = 100.0,
       .default_value = NAN},
      {.name = "lobe",
       .kind = ParamKind::TaggedObject,
       .doc = "the specular lobe: {\"model\": \"ward\" | \"ashikhmin-shirley\" | \"ggx\", and that lobe's keys "
              "(roughness, form, normalization), no colours",
       .required = true,
       .choices = enum_names<SpecularLobeKind>(),
       .tagged = lobe_specs},
      {.name = "directional_diffuse",
       .kind = ParamKind::Object,
       .doc = "optional broad lobe coloured by the metal",
       .sub = &directional_diffuse_spec},
  };
  static constexpr std::span<const ParamSpec> parts[] = {params, kOrientation};
  static constexpr ModelSpec spec{"metal", "Metal", "Cook & Torrance 1982; Born & Wolf (conductor Fresnel)", parts, kMetalRules};
  // Keys the host resolves before the GPU sees them (no GLSL slot): the metal's name, whose eta
  // and k the host looks up (glsl_material).
  static constexpr std::string_view host_keys[] = {"metal"};

  // A metal's name is one of the table's (the page checks it against the metals `aniso web-data`
  // exports).
  static void check(MaterialDesc& d, const std::string&) {
    if (d.params.has("metal") && !find_metal(d.params.text("metal")))
      d.params.fail("metal", unknown_metal_message(d.params.text("metal")));
  }

  template <typename T> static MetalT<T> build(const MaterialDesc& d) {
    const ParamValues& p = d.params;
    MetalT<T> m;
    if (p.has("metal")) {
      const MetalData* md = find_metal(p.text("metal"));
      m.eta = rgb<T>(md->eta);
      m.k = rgb<T>(md->k);
    } else {
      m.eta = rgb<T>(p.color("eta"));
      m.k = rgb<T>(p.color("k"));
    }
    const ParamValues& lobe = p.object("lobe");
    m.lobe_kind = *enum_from_name<SpecularLobeKind>(lobe.text("model"));
    switch (m.lobe_kind) {
      case SpecularLobeKind::Ward:
        m.ward.alpha_x = T(lobe.scalar("alpha_x"));
        m.ward.alpha_y = T(lobe.scalar("alpha_y"));
        // The reader checked the names against the same tables (the rows' choices).
        m.ward.form = *enum_from_name<WardForm>(lobe.text("form"));
        m.ward.normalization = *enum_from_name<WardNormalization>(lobe.text("normalization"));
        break;
      case SpecularLobeKind::AshikhminShirley:
        m.ashikhmin_shirley.n_u = T(lobe.scalar("n_u"));
        m.ashikhmin_shirley.n_v = T(lobe.scalar("n_v"));
        break;
      case SpecularLobeKind::GGX:
        m.ggx.alpha_x = T(lobe.scalar("alpha_x"));
        m.ggx.alpha_y = T(lobe.scalar("alpha_y"));
        break;
    }
    if (p.has("directional_diffuse")) {
      // Ngan et al. 2005's Lafortune normalisation, (n + 2) / (2 pi max|C|^n), folded in: dividing C by
      // max|C| keeps the lobe's peak at 1 without computing max|C|^n (which underflows for large n),
      // and the scale becomes albedo F0 (n + 2) / (2 pi), coloured by the metal's F0.
      const ParamValues& dd = p.object("directional_diffuse");
      const double cx = dd.scalar("cx"), cy = dd.scalar("cy"), cz = dd.scalar("cz"), n = dd.scalar("n");
      const double cmax = std::max({std::abs(cx), std::abs(cy), std::abs(cz)});
      if (!(cmax > 0.0)) dd.fail("cz", "the lobe needs at least one non-zero coefficient");  // kDirectionalDiffuseRules
      const RGBT<T> f0 = F_Conductor(T(1), m.eta, m.k);
      m.has_directional_diffuse = true;
      m.directional_diffuse.cx = RGBT<T>(T(cx / cmax));
      m.directional_diffuse.cy = RGBT<T>(T(cy / cmax));
      m.directional_diffuse.cz = RGBT<T>(T(cz / cmax));
      m.directional_diffuse.n = RGBT<T>(T(n));
      m.directional_diffuse.scale = rgb<T>(dd.color("albedo")) * f0 * T((n + 2.0) / (2.0 * M_PI));
      // The directional lobe's energy is taken from the specular lobe: (1 - albedo) F spec + albedo F0
      // lobe keeps the albedo <= 1 whenever both lobes are bounded (docs/models/metal.md).
      m.specular_weight = RGBT<T>(T(1)) - rgb<T>(dd.color("albedo"));
    }
    return m;
  }

  // What the host resolves before the GPU sees the values: a named metal's eta and k (as build()
  // does), which then have their slots.
  static void host_values(ParamValues& pv) {
    if (!pv.has("metal")) return;
    const MetalData* md = find_metal(pv.text("metal"));
    if (!md) pv.fail("metal", "unknown metal");
    pv.values["eta"] = glm::dvec3(md->eta);
    pv.values["k"] = glm::dvec3(md->k);
  }

  // pv: with host_values() applied.
  static std::string glsl(const ParamValues& pv, const SlotFn& P) {
    std::string b = fmt::format("  m.eta = {};\n  m.k = {};\n", P("eta"), P("k"));
    // Every lobe member gets a value, so that no field of the struct is read uninitialised.
    b += "  m.ward = WardLobe(0.15, 0.15, WardForm_Vector, WardNormalization_Ward1992);\n"
         "  m.ashikhmin_shirley = AshikhminShirleyLobe(100.0, 100.0);\n  m.ggx = GGXLobe(0.2, 0.2);\n";
    switch (*enum_from_name<SpecularLobeKind>(pv.object("lobe").text("model"))) {
      case SpecularLobeKind::Ward:
        b += "  m.lobe_kind = SpecularLobeKind_Ward;\n";
        b += fmt::format("  m.ward.alpha_x = {};\n  m.ward.alpha_y = {};\n  m.ward.form = {};\n  m.ward.normalization = {};\n",
                         P("lobe_alpha_x"), P("lobe_alpha_y"), P("lobe_form"), P("lobe_normalization"));
        break;
      case SpecularLobeKind::AshikhminShirley:
        b += fmt::format(
            "  m.lobe_kind = SpecularLobeKind_AshikhminShirley;\n  m.ashikhmin_shirley.n_u = {};\n"
            "  m.ashikhmin_shirley.n_v = {};\n",
            P("lobe_n_u"), P("lobe_n_v"));
        break;
      case SpecularLobeKind::GGX:
        b += fmt::format("  m.lobe_kind = SpecularLobeKind_GGX;\n  m.ggx.alpha_x = {};\n  m.ggx.alpha_y = {};\n",
                         P("lobe_alpha_x"), P("lobe_alpha_y"));
        break;
    }
    b += "  m.specular_weight = vec3(1.0);\n"
         "  m.directional_diffuse = LafortuneLobe(vec3(-1.0), vec3(-1.0), vec3(1.0), vec3(10.0), vec3(0.0));\n";
    if (pv.has("directional_diffuse")) {
      // build(): Ngan et al. 2005's normalisation folded in, C / max|C| and
      // scale = albedo F0 (n + 2) / (2 pi); the directional lobe takes its energy from the specular one.
      b += fmt::format(
          "  m.has_directional_diffuse = true;\n"
          "  float dd_cx = {}, dd_cy = {}, dd_cz = {}, dd_n = {};\n"
          "  vec3 dd_albedo = {};\n"
          "  float dd_cmax = max(max(abs(dd_cx), abs(dd_cy)), abs(dd_cz));\n"
          "  // The host rejects an all-zero C; a slider can reach it: the lobe is then 0, not 0 / 0.\n"
          "  float dd_inv = dd_cmax > 0.0 ? 1.0 / dd_cmax : 0.0;\n"
          "  m.directional_diffuse.cx = vec3(dd_cx * dd_inv);\n"
          "  m.directional_diffuse.cy = vec3(dd_cy * dd_inv);\n"
          "  m.directional_diffuse.cz = vec3(dd_cz * dd_inv);\n"
          "  m.directional_diffuse.n = vec3(dd_n);\n"
          "  m.directional_diffuse.scale = dd_albedo * F_Conductor(1.0, m.eta, m.k) * ((dd_n + 2.0) * kInv2Pi);\n"
          "  m.specular_weight = vec3(1.0) - dd_albedo;\n",
          P("directional_diffuse_cx"), P("directional_diffuse_cy"), P("directional_diffuse_cz"), P("directional_diffuse_n"),
          P("directional_diffuse_albedo"));
    } else {
      b += "  m.has_directional_diffuse = false;\n";
    }
    return b;
  }
};

}  // namespace aniso::models
