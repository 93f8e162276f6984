// tests/test_text_input.cpp: the number rule of io/text_input.h (decimal only, underflow to zero,
// overflow and non-finite values rejected; whole decimal integers in range) and the direction lines
// of `aniso eval` (vectors or angles, blank and comment lines, messages naming line and field).
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "aniso/io/input_error.h"
#include "input_error_text.h"
#include "io/text_input.h"

namespace aniso {
namespace {

TEST(NumberRule, DecimalOnlyUnderflowToZeroOverflowRejected) {
  EXPECT_EQ(parse_decimal("010").value(), 10.0);
  EXPECT_EQ(parse_decimal("1e-400").value(), 0.0);
  EXPECT_GT(parse_decimal("1e-310").value(), 0.0);  // subnormal: accepted, not read as 0
  EXPECT_FALSE(std::signbit(parse_decimal("-0").value()));
  for (const char* bad : {"inf", "nan", "-inf", "0x10", "1e999", "", ".", "e5", "1e", "1,5", " 1"})
    EXPECT_FALSE(parse_decimal(bad).has_value()) << bad;
  EXPECT_EQ(parse_decimal("1.").value(), 1.0);
  EXPECT_EQ(parse_decimal(".5").value(), 0.5);
}

TEST(NumberRule, IntegersAreDecimalWholeAndInRange) {
  EXPECT_EQ(parse_unsigned("010", 100, "--count"), 10u);
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("-1", UINT64_MAX, "--seed"); }), "--seed: expected a whole decimal"));
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("18446744073709551616", UINT64_MAX, "--seed"); }), "out of range"));
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("1.5", 100, "--count"); }), "whole decimal number"));
  EXPECT_EQ(parse_unsigned("18446744073709551615", UINT64_MAX, "--seed"), UINT64_MAX);
  EXPECT_EQ(parse_integer("-3", -5, 5, "x"), -3);
}

TEST(NumberRule, DirectionLines) {
  // (1e200, 1e200, 1e200) is non-zero and finite: scaled before normalising, so its squared length
  // does not overflow.
  const DirectionPair d = parse_direction_line("1e200 1e200 1e200 0 0 1e-300", 1, false);
  EXPECT_NEAR(d.wi.z, 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(d.wo, Vec3d(0, 0, 1));
  EXPECT_TRUE(is_blank_or_comment("\f"));
  EXPECT_TRUE(is_blank_or_comment(" \v\t# x"));
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("0 0 0 0 0 1", 7, false); }), "stdin line 7: wi"));
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("0 0 1 0 0 nan", 2, false); }), "field 6"));
  const DirectionPair a = parse_direction_line("30 0 30 180", 1, true);
  EXPECT_NEAR(a.wi.x, 0.5, 1e-15);
  EXPECT_NEAR(a.wo.x, -0.5, 1e-15);
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("91 0 0 0", 3, true); }), "theta must be in [0, 90]"));
}

}  // namespace
}  // namespace aniso
