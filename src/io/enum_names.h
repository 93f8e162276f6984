// io/enum_names.h: the one name table of each enumeration a user spells in JSON or on the command
// line, or reads in the exported parameter tables. The parameter tables' choices (params.cpp), the
// material builders (materials.cpp), the fitter (src/fit) and the GLSL slots (the choice's index is
// the enumerator's value, which the GLSL twins' constants repeat) all read these; the kinds of the
// tables' keys are named here for `aniso web-data` (apps/aniso/cmd_web.cpp) and aniso.models()
// (python/src/bind_tables.cpp).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "aniso/brdf/metal.h"
#include "aniso/brdf/ward.h"
#include "aniso/io/params.h"

namespace aniso {

// EnumNames<E>::kNames[i] is the name of the enumerator with value i (the enumerators are 0..n-1).
template <typename E> struct EnumNames;

template <> struct EnumNames<WardForm> {
  static constexpr std::string_view kNames[] = {"vector", "angle", "approx"};
  static_assert(int(WardForm::Approx) + 1 == std::size(kNames));
};
template <> struct EnumNames<WardNormalization> {
  static constexpr std::string_view kNames[] = {"ward", "duer", "balanced"};
  static_assert(int(WardNormalization::Balanced) + 1 == std::size(kNames));
};
// The metal's specular lobe: the names are those of the models the lobe comes from.
template <> struct EnumNames<SpecularLobeKind> {
  static constexpr std::string_view kNames[] = {"ward", "ashikhmin-shirley", "ggx"};
  static_assert(int(SpecularLobeKind::GGX) + 1 == std::size(kNames));
};

// The kind of a parameter table's key, as the browser explorer (web/explorer.js, web/validate.js)
// and aniso.models() (docs/python.md) read it.
template <> struct EnumNames<ParamKind> {
  static constexpr std::string_view kNames[] = {"scalar", "color", "bool", "choice", "string", "object", "list", "tagged-object"};
  static_assert(int(ParamKind::TaggedObject) + 1 == std::size(kNames));
};

// The kinds of a table's cross-key rules, as `aniso web-data` exports them (web/validate.js applies them).
template <> struct EnumNames<ParamRule::Kind> {
  static constexpr std::string_view kNames[] = {"exclusive", "key-or-all", "non-zero", "peak-below"};
  static_assert(int(ParamRule::Kind::PeakBelow) + 1 == std::size(kNames));
};

template <typename E> constexpr std::span<const std::string_view> enum_names() { return EnumNames<E>::kNames; }
template <typename E> constexpr std::string_view enum_name(E e) { return EnumNames<E>::kNames[static_cast<int>(e)]; }
template <typename E> constexpr std::optional<E> enum_from_name(std::string_view s) {
  for (size_t i = 0; i < std::size(EnumNames<E>::kNames); ++i)
    if (EnumNames<E>::kNames[i] == s) return static_cast<E>(i);
  return std::nullopt;
}
// The names joined by sep ("ward | duer | balanced"): the help texts and docstrings that list
// the choices list them from here.
template <typename E> std::string enum_names_text(std::string_view sep = " | ") {
  std::string out;
  for (const std::string_view n : enum_names<E>()) (out += out.empty() ? "" : sep) += n;
  return out;
}

}  // namespace aniso
