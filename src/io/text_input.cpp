// io/text_input.cpp: the CLI's number rule and its stdin line parser (io/text_input.h).
#include "io/text_input.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "aniso/io/params.h"
#include "io/json_read.h"

namespace aniso {

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '\n'; }

// Decimal syntax: [+-] digits [. digits] [e|E [+-] digits], at least one digit in the mantissa.
bool decimal_syntax(std::string_view t) {
  size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  size_t digits = 0;
  while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  if (i < t.size() && t[i] == '.') {
    ++i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    size_t e = 0;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++e;
    if (e == 0) return false;
  }
  return i == t.size();
}
}  // namespace

std::optional<double> parse_decimal(std::string_view token, std::string* why) {
  if (!decimal_syntax(token)) {
    if (why) *why = "not a decimal number";
    return std::nullopt;
  }
  const std::string s(token);
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  // ERANGE with a finite result is underflow (rounded to a subnormal or 0): accepted by the rule.
  if (!std::isfinite(v)) {
    if (why) *why = "beyond the largest double (1.8e308)";
    return std::nullopt;
  }
  return v + 0.0;  // -0 -> +0
}

int64_t parse_integer(std::string_view token, int64_t lo, int64_t hi, std::string_view what) {
  int64_t v = 0;
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v, 10);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && p == token.data() + token.size() && (v < lo || v > hi)))
    throw InputError(
        fmt::format("{}: {} is out of range; expected a whole number in [{}, {}]", what, text_escape(token), lo, hi));
  if (ec != std::errc() || p != token.data() + token.size() || token.empty())
    throw InputError(
        fmt::format("{}: expected a whole decimal number in [{}, {}], got \"{}\"", what, lo, hi, text_escape(token)));
  return v;
}

uint64_t parse_unsigned(std::string_view token, uint64_t hi, std::string_view what) {
  uint64_t v = 0;
  if (!token.empty() && token[0] == '-')
    throw InputError(fmt::format("{}: expected a whole decimal number in [0, {}], got \"{}\"", what, hi, text_escape(token)));
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v, 10);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && p == token.data() + token.size() && v > hi))
    throw InputError(fmt::format("{}: {} is out of range; expected a whole number in [0, {}]", what, text_escape(token), hi));
  if (ec != std::errc() || p != token.data() + token.size() || token.empty())
    throw InputError(fmt::format("{}: expected a whole decimal number in [0, {}], got \"{}\"", what, hi, text_escape(token)));
  return v;
}

bool is_blank_or_comment(std::string_view line) {
  size_t i = 0;
  while (i < line.size() && is_space(line[i])) ++i;
  return i == line.size() || line[i] == '#';
}

std::optional<Vec3d> normalized_direction(const Vec3d& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0.0) || !std::isfinite(m)) return std::nullopt;
  const Vec3d s = v / m;  // largest component +-1: the length is in [1, sqrt 3]
  return s / std::sqrt(glm::dot(s, s));
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

Vec3d direction_from_degrees(double theta_deg, double phi_deg) {
  // phi is any finite number of degrees: reduced to (-360, 360) first (fmod is exact), because
  // phi * pi / 180 overflows to inf above about 5.7e307 degrees and cos(inf) is NaN ("30 1e300 30
  // -1e308": tests/test_cli.cpp, CliEval.AnglesHugePhiIsReducedNotNaN).
  const double t = theta_deg * M_PI / 180.0, p = std::fmod(phi_deg, 360.0) * M_PI / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

DirectionPair parse_direction_line(std::string_view line, size_t line_no, bool angles) {
  const int want = angles ? 4 : 6;
  const char* layout = angles ? "theta_i phi_i theta_o phi_o, degrees" : "wi.x wi.y wi.z wo.x wo.y wo.z";
  // A NUL byte (binary input, a C string cut short) is named, not taken for the end of the line.
  if (const size_t nul = line.find('\0'); nul != std::string_view::npos)
    throw InputError(fmt::format("stdin line {}: column {}: a NUL byte; expected text ({})", line_no, nul + 1, layout));
  double v[6] = {};
  int count = 0;
  size_t i = 0;
  while (true) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size()) break;
    size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    const std::string_view tok = line.substr(i, j - i);
    if (count == want)
      throw InputError(fmt::format("stdin line {}: expected {} numbers ({}), got more (\"{}\")", line_no, want, layout,
                                   text_escape(tok.substr(0, 40))));
    std::string why;
    const auto x = parse_decimal(tok, &why);
    if (!x)
      throw InputError(fmt::format("stdin line {}: field {}: expected a finite decimal number, got \"{}\" ({})", line_no,
                                   count + 1, text_escape(tok.substr(0, 40)), why));
    v[count++] = *x;
    i = j;
  }
  if (count < want)
    throw InputError(fmt::format("stdin line {}: expected {} numbers ({}), got {}", line_no, want, layout, count));
  if (angles) {
    for (int k : {0, 2})
      if (v[k] < 0.0 || v[k] > 90.0)
        throw InputError(fmt::format("stdin line {}: field {}: theta must be in [0, 90] degrees, got {}", line_no, k + 1, v[k]));
    return {direction_from_degrees(v[0], v[1]), direction_from_degrees(v[2], v[3])};
  }
  const auto wi = normalized_direction(Vec3d(v[0], v[1], v[2]));
  const auto wo = normalized_direction(Vec3d(v[3], v[4], v[5]));
  if (!wi) throw InputError(fmt::format("stdin line {}: wi: expected a non-zero direction, got (0, 0, 0)", line_no));
  if (!wo) throw InputError(fmt::format("stdin line {}: wo: expected a non-zero direction, got (0, 0, 0)", line_no));
  return {*wi, *wo};
}

}  // namespace aniso
