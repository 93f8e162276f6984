// fit/options.h (private): the names of an enumeration option in messages and its parsing.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "aniso/io/input_error.h"
#include "io/enum_names.h"

namespace aniso::fit_detail {

// "ward, duer or balanced": the names of an enumeration (io/enum_names.h) for an error message.
template <typename E> std::string name_list() {
  const auto names = enum_names<E>();
  std::string s;
  for (size_t i = 0; i < names.size(); ++i)
    s += fmt::format("{}{}", i == 0 ? "" : i + 1 == names.size() ? " or " : ", ", names[i]);
  return s;
}

template <typename E> E option_enum(const std::string& s, std::string_view option) {
  const std::optional<E> e = enum_from_name<E>(s);
  if (!e) throw InputError(fmt::format("{}: expected {}, got \"{}\"", option, name_list<E>(), s));
  return *e;
}

}  // namespace aniso::fit_detail
