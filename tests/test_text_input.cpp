// tests/test_text_input.cpp: the number rule of io/text_input.h (decimal only, underflow to zero,
// overflow and non-finite values rejected; whole decimal integers in range) and the direction lines
// of `aniso eval` (vectors or angles, blank and comment lines, messages naming line and field);
// the size limit of every whole-file read (io/json_read.h).
#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/io/input_error.h"
#include "input_error_text.h"
#include "io/json_read.h"
#include "io/text_input.h"
#include "temp_dir.h"

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

// Issue 40 item 5: `-m /dev/zero` grew to 16.8 GB, `-m /dev/urandom` never ended. A regular file
// over the limit is refused by its size before it is read (a sparse file: no disk used); a device
// or a FIFO is read up to one byte past the limit (here 1 MiB, to stay fast), then refused.
TEST(ReadTextFile, SizeLimitNamesTheFileAndTheLimit) {
  const test::TempDir dir;
  const std::string big = dir.path("big.json");
  { std::ofstream(big) << "{}"; }
  std::filesystem::resize_file(big, kMaxJsonFileBytes + 1);
  EXPECT_EQ(error_of([&] { (void)read_json_file(big); }),
            fmt::format("{}: {} bytes: larger than 64 MiB, the limit for a JSON file (docs/cli.md, \"Size limits\")", big,
                        kMaxJsonFileBytes + 1));
  std::filesystem::resize_file(big, 1 << 20);  // at the limit given: read whole (zeros: not JSON, but read)
  EXPECT_EQ(read_text_file(big, "a test file", size_t(1) << 20).size(), size_t(1) << 20);
  if (::access("/dev/zero", R_OK) == 0) {
    EXPECT_EQ(error_of([] { (void)read_text_file("/dev/zero", "a test file", size_t(1) << 20); }),
              "/dev/zero: larger than 1 MiB, the limit for a test file (docs/cli.md, \"Size limits\")");
  }
  if (::access("/dev/urandom", R_OK) == 0) {
    EXPECT_TRUE(contains(error_of([] { (void)read_text_file("/dev/urandom", "a test file", size_t(1) << 20); }),
                         "/dev/urandom: larger than 1 MiB"));
  }
  // A FIFO fed 2 MiB: refused after 1 MiB. The writer blocks SIGPIPE (sent to the writing
  // thread), so that the reader's close ends its write with EPIPE instead of the process.
  const std::string fifo = dir.path("fifo.json");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] {
    sigset_t pipe;
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    ::pthread_sigmask(SIG_BLOCK, &pipe, nullptr);
    const int fd = ::open(fifo.c_str(), O_WRONLY);
    if (fd < 0) return;
    const std::string block(1 << 16, ' ');
    for (int i = 0; i < 32; ++i)
      if (::write(fd, block.data(), block.size()) < 0) break;
    ::close(fd);
  });
  EXPECT_TRUE(contains(error_of([&] { (void)read_text_file(fifo, "a test file", size_t(1) << 20); }), "larger than 1 MiB"));
  writer.join();
}

}  // namespace
}  // namespace aniso
