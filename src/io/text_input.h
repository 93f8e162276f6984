// io/text_input.h: numbers and direction pairs as the CLI reads them (stdin lines, options).
// One rule for numbers everywhere (docs/conventions.md, "Numbers"):
//  - decimal only ("010" is ten, not octal eight; no hex, no "inf", no "nan");
//  - a value is rounded to the nearest double; magnitudes below the smallest subnormal (4.9e-324)
//    round to 0, and -0 is read as +0; magnitudes above the largest double (1.8e308) are an error;
//  - integers must be whole, in range, and are never wrapped or saturated.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "aniso/core/math.h"

namespace aniso {

// A finite decimal number, or nullopt (with `why` set) when the token is not one.
std::optional<double> parse_decimal(std::string_view token, std::string* why = nullptr);

// A decimal integer in [lo, hi]; throws InputError naming `what` ("--count") and the range.
int64_t parse_integer(std::string_view token, int64_t lo, int64_t hi, std::string_view what);
uint64_t parse_unsigned(std::string_view token, uint64_t hi, std::string_view what);

// Blank (only spaces, tabs, CR, form feeds, vertical tabs) or a comment line ('#' first).
bool is_blank_or_comment(std::string_view line);

// A unit direction from a non-zero finite vector (scaled by its largest component first, so that
// (1e200, 1e200, 1e200) and (1e-300, 0, 0) normalise without overflow or underflow); nullopt for
// zero vectors.
std::optional<Vec3d> normalized_direction(const Vec3d& v);

// Unit direction from spherical angles in degrees: theta from the normal, phi from the tangent.
Vec3d direction_from_degrees(double theta_deg, double phi_deg);

// A file name's extension in lower case, with its dot (".png"); "" without one.
std::string lower_extension(const std::string& path);

struct DirectionPair {
  Vec3d wi, wo;
};

// One `aniso eval` input line: "wi.x wi.y wi.z wo.x wo.y wo.z" (vectors, normalised here), or with
// `angles` "theta_i phi_i theta_o phi_o" in degrees (theta in [0, 90], phi any finite value).
// Throws InputError "stdin line N: ..." naming the field and what was expected.
DirectionPair parse_direction_line(std::string_view line, size_t line_no, bool angles);

}  // namespace aniso
