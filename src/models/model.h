// models/model.h: what a model file (src/models/<member>.h) is made of, in the shape of a Mitsuba 3
// plugin (one file: its parameters, its checks, its construction). A model file defines, in
// namespace aniso::models, a struct named like its registry row's Tag (aniso/brdf/registry.h) with
//   spec              its parameter table (ModelSpec): what the JSON reader validates against, what
//                     `aniso models`, docs/models/<name>.md, the Python keywords, the GLSL slots and
//                     the explorer's sliders are made from
//   bound<T>          the table's rows, each with the kernel field it sets (Row: a ParamSpec and a
//                     Field), as spans in table order; from them the material builder, the GLSL
//                     builder and the fit layout are generated. Only for a model whose keys map one
//                     to one onto fields of its kernel Type<T>.
// and, where the model needs them,
//   check(d, dir)     the cross-key rules the table cannot express, run by parse_material after
//                     the table's validation (dir: the folder a file key is relative to)
//   build<T>(d)       a hand-written builder, in place of the generated one, where the keys do not
//                     map one to one (a list of lobes, a name looked up, a file)
//   glsl(pv, P)       its GLSL twin: the body of aniso_model(), filling the kernel struct `m` from
//                     the slots (P(slot name) is the slot's GLSL expression)
// src/models/all.h lists the model files; src/models/models.cpp (the tables' registry, the reader
// and builder of materials), src/gl/glsl_material.cpp and src/fit read them. Adding a model:
// docs/architecture.md, "Adding a model".
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "aniso/brdf/material.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "io/enum_names.h"

namespace aniso::models {

// --- a row's binding: the kernel field it sets ------------------------------------------------

// What a field of a kernel can be, for the scalar type T (float, double, ceres::Jet): a number, an
// RGB triple, a flag or one of the enumerations a user spells (io/enum_names.h).
template <typename T> using FieldPtr = std::variant<T*, RGBT<T>*, bool*, WardForm*, WardNormalization*>;

template <typename T, typename F> constexpr ParamKind field_kind() {
  if constexpr (std::is_same_v<F, T>) return ParamKind::Scalar;
  if constexpr (std::is_same_v<F, RGBT<T>>) return ParamKind::Color;
  if constexpr (std::is_same_v<F, bool>) return ParamKind::Bool;
  if constexpr (std::is_enum_v<F>) return ParamKind::Choice;
}
template <typename F> constexpr std::span<const std::string_view> field_choices() {
  if constexpr (std::is_enum_v<F>) return enum_names<F>();
  return {};
}

// The field of the kernel M (= Type<T>) that a row sets: its path, which is the same in C++ and in
// the GLSL twin's struct ("lobe.alpha_x"), and its address in a given kernel value. Written
// ANISO_FIELD(lobe.alpha_x).
template <typename T, typename M> struct Field {
  std::string_view path;
  FieldPtr<T> (*get)(M&) = nullptr;
  ParamKind kind = ParamKind::Scalar;         // the table kind the field's type takes
  std::span<const std::string_view> choices;  // an enumeration's names

  constexpr Field() = default;
  template <typename L> constexpr Field(std::string_view p, L)
      : path(p),
        get(+[](M& m) -> FieldPtr<T> { return L{}(m); }),
        kind(field_kind<T, std::remove_pointer_t<decltype(L{}(std::declval<M&>()))>>()),
        choices(field_choices<std::remove_pointer_t<decltype(L{}(std::declval<M&>()))>>()) {}
};
#define ANISO_FIELD(path)                  \
  {                                        \
#path, [](auto& m) { return &m.path; } \
  }

// A row of a model's table and the kernel field it sets. A row without a field is resolved by the
// host before the kernel sees it: a shorthand (ParamSpec::sets: the reader copies it into its pair)
// or the orientation (kOrientation: MaterialT's rotation).
template <typename T, typename M> struct Row {
  using Kernel = M;
  ParamSpec spec;
  Field<T, M> field = {};
};

// The table rows of a part of bound rows (ModelSpec::parts are spans of ParamSpec).
template <typename R, size_t N> constexpr std::array<ParamSpec, N> specs(const R (&rows)[N]) {
  std::array<ParamSpec, N> out{};
  for (size_t i = 0; i < N; ++i) out[i] = rows[i].spec;
  return out;
}

// Every row of a generated model is bound to a field whose type is the row's kind (an enumeration
// with the row's choices), or is a shorthand. Checked by a static_assert in each model file.
template <typename P> consteval bool rows_match_fields() {
  for (const auto& part : P::template bound<float>)
    for (const auto& r : part) {
      if (!r.field.get) {
        if (r.spec.sets[0].empty()) return false;  // a key no field takes
        continue;
      }
      if (r.field.kind != r.spec.kind) return false;
      if (r.spec.kind == ParamKind::Choice) {
        if (r.field.choices.size() != r.spec.choices.size()) return false;
        for (size_t i = 0; i < r.spec.choices.size(); ++i)
          if (r.field.choices[i] != r.spec.choices[i]) return false;
      }
    }
  return true;
}

template <typename P>
concept Generated = requires {
  P::template bound<float>;
};

// The kernel type Type<T> of a generated model.
template <typename P, typename T> using KernelOf = typename std::remove_cvref_t<decltype(P::template bound<T>[0][0])>::Kernel;

// --- the fit of a generated model -----------------------------------------------------------

// A key of the table the fitter solves for (src/fit/models.h, BoundFit), in the order of its
// vector. Its entries are named "<key>.r", "<key>.g", "<key>.b" (Rgb), or "<key>" (Grey: one
// entry for the three channels; One: a number).
struct FitKey {
  enum Shape { One, Rgb, Grey };
  std::string_view key;
  Shape shape = One;
  // An anisotropic pair in an isotropic fit: the first half's entry takes this name ("alpha")
  // and the second half shares it (iso_tie: its first half), or a key only an anisotropic fit
  // solves for is held at iso_value.
  std::string_view iso_name = {};
  std::string_view iso_tie = {};
  double iso_value = NAN;
  double lo = NAN;  // a lower bound above the table's (the reason at the row)
  // A key the fit solves for only when its options free it (FitOptions::fresnel "free-f90": GGX's
  // f90); else it is held at the table's default, and the fitted material does not name it.
  bool optional = false;
};
// A key the fitter holds at a value (a number; a choice's or string's text).
struct FitFixed {
  std::string_view key;
  double number = 0.0;
  std::string_view text = {};
};
struct FitDesc {
  std::span<const FitKey> keys;
  std::span<const FitFixed> fixed = {};
  // An anisotropic fit's pair, ordered by canonicalize() with the lobe narrower along the tangent:
  // the smaller value first (alpha), or the larger (narrower_is_larger: AS exponents). None:
  // the rotation alone is canonical (principled), repeating after rotation_period degrees.
  std::array<std::string_view, 2> pair = {};
  bool narrower_is_larger = false;
  double rotation_period = 90.0;
};

// --- the generated builder and GLSL twin ------------------------------------------------------

template <typename T> RGBT<T> rgb(const glm::dvec3& c) { return RGBT<T>(T(c.x), T(c.y), T(c.z)); }

// The kernel from the validated values: each bound row's value into its field, in table order.
template <typename T, typename M, typename P> M build_generated(const ParamValues& p) {
  M m;
  for (const auto& part : P::template bound<T>)
    for (const auto& r : part) {
      if (!r.field.get) continue;
      const std::string_view key = r.spec.name;
      std::visit(
          [&](auto* f) {
            using F = std::remove_pointer_t<decltype(f)>;
            if constexpr (std::is_same_v<F, T>)
              *f = T(p.scalar(key));
            else if constexpr (std::is_same_v<F, RGBT<T>>)
              *f = rgb<T>(p.color(key));
            else if constexpr (std::is_same_v<F, bool>)
              *f = p.boolean(key);
            else  // the reader checked the name against the same choices
              *f = *enum_from_name<F>(p.text(key));
          },
          r.field.get(m));
    }
  return m;
}

// A slot's GLSL expression by its name (src/gl/glsl_material.cpp hands it out and checks that the
// builder used every slot).
using SlotFn = std::function<std::string(const std::string& slot)>;

// The GLSL twin of build_generated: "  m.<field> = <slot>;" per bound row, in table order.
template <typename P> std::string glsl_generated(const SlotFn& slot) {
  std::string b;
  for (const auto& part : P::template bound<float>)
    for (const auto& r : part)
      if (r.field.get) b += fmt::format("  m.{} = {};\n", r.field.path, slot(std::string(r.spec.name)));
  return b;
}

// --- rows the tables share ------------------------------------------------------------------

// Upper bound of exponents and scales: far beyond any fit (Ngan's sharpest is 45800), and the
// normalisations (n + 2) / (2 pi) stay far inside the float range.
inline constexpr double kHuge = 1e6;

// Reflectances (albedos) of energy-conserving terms live in [0, 1].
constexpr ParamSpec reflectance(std::string_view name, double def, std::string_view doc) {
  return ParamSpec{.name = name, .kind = ParamKind::Color, .doc = doc, .min = 0.0, .max = 1.0, .default_value = def};
}
// Roughness alpha: [0.001, 1]. 0 is a mirror (a delta the models cannot represent) and below 1e-3
// the lobe's peak 1 / (pi alpha^2) and the exponent (h.t / alpha)^2 leave the float range near
// the horizon; above 1 the Gaussian / GGX lobes no longer describe a surface (Ward: "mostly
// diffuse" past 0.2).
constexpr ParamSpec roughness(std::string_view name, double def, std::string_view doc, std::string_view partner) {
  return ParamSpec{
      .name = name, .kind = ParamKind::Scalar, .doc = doc, .min = 1e-3, .max = 1.0, .default_value = def, .partner = partner};
}
// "alpha": the isotropic shorthand for alpha_x = alpha_y.
constexpr ParamSpec roughness_shorthand() {
  return ParamSpec{.name = "alpha",
                   .kind = ParamKind::Scalar,
                   .doc = "sets alpha_x = alpha_y (isotropic); excludes alpha_x and alpha_y",
                   .min = 1e-3,
                   .max = 1.0,
                   .default_value = NAN,
                   .sets = {"alpha_x", "alpha_y"}};
}
// A number in [0, 1].
constexpr ParamSpec unit(std::string_view name, double def, std::string_view doc) {
  return ParamSpec{.name = name, .kind = ParamKind::Scalar, .doc = doc, .min = 0.0, .max = 1.0, .default_value = def};
}

// The anisotropic models' orientation (material.h, FrameRotationT): the tangent turned about the
// normal, t' = cos a t + sin a b, composed with a scene's tangent.angle_deg. [-360, 360] like that
// key; the isotropic models have no such key (their reader says it would have no effect).
inline constexpr ParamSpec kOrientation[] = {
    {.name = "rotation_deg",
     .kind = ParamKind::Scalar,
     .doc = "turns the tangent about the normal by this angle, degrees (t' = cos a t + sin a b), as a scene's "
            "tangent.angle_deg does and added to it",
     .min = -360.0,
     .max = 360.0,
     .default_value = 0.0},
};

// A measured file key given relative to the folder of the JSON naming it (else the working directory).
std::string resolve_file(const std::string& file, const std::string& base_dir);

}  // namespace aniso::models
