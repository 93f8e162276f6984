// tests/test_image.cpp: render/image: the sRGB curve, tone mapping, readers and writers (round
// trips, PFM orientation, atomic writes, errors on bad input), and the label text.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/input_error.h"
#include "temp_dir.h"

namespace aniso::render {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::string pfm_bytes(const std::string& header, const std::vector<float>& values) {
  std::string s = header;
  for (float v : values) {
    unsigned char b[4];
    std::memcpy(b, &v, 4);  // the test machines are little endian, as the "-1.0" scale says
    s.append(reinterpret_cast<const char*>(b), 4);
  }
  return s;
}

// Expects read_image(path, where) to throw an InputError whose message names `where`, the path
// and contains `problem`.
void expect_read_error(const std::string& path, const std::string& problem) {
  const std::string where = "scene.json: environment.file";
  try {
    read_image(path, where);
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(where + ": " + path + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << msg << "\n  expected to contain: " << problem;
  }
}

Image test_image(int w, int h) {
  Image img(w, h);
  const float values[] = {0.0f, 1e-3f, 123.5f, 0.25f, 7.0f, 1e-30f, 3.0e5f, 0.5f, 1.0f / 3.0f};
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = values[i % 9] * float(1 + i / 9);
  return img;
}

// ---------------------------------------------------------------------------------------------

TEST(ImageSrgb, KnownValuesAndKnee) {
  EXPECT_EQ(srgb_encode(0.0f), 0.0f);
  EXPECT_EQ(srgb_encode(1.0f), 1.0f);
  EXPECT_NEAR(srgb_encode(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(srgb_decode(0.735357f), 0.5f, 1e-5f);
  // The knee: linear 0.0031308 <-> encoded 0.04045, continuous from both sides.
  EXPECT_NEAR(srgb_encode(0.0031308f), 0.04045f, 1e-5f);
  EXPECT_NEAR(srgb_encode(0.0031307f), 12.92f * 0.0031307f, 1e-7f);
  EXPECT_NEAR(srgb_encode(0.0031309f), srgb_encode(0.0031308f), 1e-5f);
  EXPECT_NEAR(srgb_decode(0.04045f), 0.0031308f, 1e-6f);
  EXPECT_NEAR(srgb_decode(0.01f), 0.01f / 12.92f, 1e-8f);
  // Out of range and NaN.
  EXPECT_EQ(srgb_encode(-1.0f), 0.0f);
  EXPECT_EQ(srgb_encode(2.0f), 1.0f);
  EXPECT_EQ(srgb_encode(std::nanf("")), 0.0f);
  EXPECT_EQ(srgb_decode(std::nanf("")), 0.0f);
}

TEST(ImageSrgb, RoundTrip) {
  for (int i = 0; i <= 1000; ++i) {
    const float x = float(i) / 1000.0f;
    EXPECT_NEAR(srgb_decode(srgb_encode(x)), x, 2e-6f) << x;
    EXPECT_NEAR(srgb_encode(srgb_decode(x)), x, 2e-6f) << x;
  }
}

// ---------------------------------------------------------------------------------------------

uint8_t tonemap1(float v, ToneMap curve, float stops = 0.0f) {
  Image img(1, 1);
  img.set(0, 0, RGB(v));
  return tonemap(img, {stops, curve}).rgb[0];
}

TEST(ImageToneMap, BlackWhiteAndGarbage) {
  for (ToneMap c : {ToneMap::Aces, ToneMap::Clamp}) {
    EXPECT_EQ(tonemap1(0.0f, c), 0);
    EXPECT_EQ(tonemap1(1e30f, c), 255);
    EXPECT_EQ(tonemap1(std::numeric_limits<float>::infinity(), c), 255);
    EXPECT_EQ(tonemap1(std::nanf(""), c), 0);
    EXPECT_EQ(tonemap1(-5.0f, c), 0);
    EXPECT_EQ(tonemap1(-std::numeric_limits<float>::infinity(), c), 0);
    EXPECT_EQ(tonemap1(1.0f, c, 1e6f), 255);  // 2^1e6 = inf
    EXPECT_EQ(tonemap1(1.0f, c, -1e6f), 0);
  }
}

TEST(ImageToneMap, ClampCurve) {
  // 0.5 -> sRGB 0.735357 -> 187.5 -> 188.
  EXPECT_EQ(tonemap1(0.5f, ToneMap::Clamp), 188);
  EXPECT_EQ(tonemap1(1.0f, ToneMap::Clamp), 255);
  EXPECT_EQ(tonemap1(2.0f, ToneMap::Clamp), 255);
  for (int b = 0; b < 256; ++b) EXPECT_EQ(tonemap1(srgb_decode(float(b) / 255.0f), ToneMap::Clamp), b);
}

TEST(ImageToneMap, AcesCurve) {
  // Narkowicz 2015 at x = 0.5, then sRGB.
  const float x = 0.5f;
  const float aces = x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
  EXPECT_EQ(tonemap1(x, ToneMap::Aces), uint8_t(std::lround(srgb_encode(aces) * 255.0f)));
  // Monotone.
  uint8_t prev = 0;
  for (float v = 0.0f; v < 20.0f; v += 0.01f) {
    const uint8_t b = tonemap1(v, ToneMap::Aces);
    EXPECT_GE(b, prev) << v;
    prev = b;
  }
}

TEST(ImageToneMap, ExposureDoublesBeforeTheCurve) {
  for (ToneMap c : {ToneMap::Aces, ToneMap::Clamp})
    for (float v : {0.01f, 0.1f, 0.25f, 0.4f, 2.0f}) {
      EXPECT_EQ(tonemap1(v, c, 1.0f), tonemap1(2.0f * v, c)) << v;
      EXPECT_EQ(tonemap1(v, c, -2.0f), tonemap1(0.25f * v, c)) << v;
    }
  // Channels and pixels are mapped independently.
  Image img(2, 1);
  img.set(0, 0, RGB(0.5f, 0.0f, 1.0f));
  img.set(1, 0, RGB(0.0f, 0.5f, 0.0f));
  const DisplayImage d = tonemap(img, {0.0f, ToneMap::Clamp});
  EXPECT_EQ(d.rgb, (std::vector<uint8_t>{188, 0, 255, 0, 188, 0}));
}

// ---------------------------------------------------------------------------------------------

TEST(ImageIo, FloatRoundTripsAreExact) {
  TempDir dir;
  const Image img = test_image(7, 5);
  for (const char* name : {"a.pfm", "a.exr", "UPPER.PFM", "UPPER.EXR"}) {
    SCOPED_TRACE(name);
    write_image(dir.path(name), img);
    const Image back = read_image(dir.path(name), "test");
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    for (size_t i = 0; i < img.rgb.size(); ++i) ASSERT_EQ(back.rgb[i], img.rgb[i]) << i;  // bit-exact
  }
  // Overwriting an existing file works, and nothing is left behind.
  write_image(dir.path("a.pfm"), test_image(2, 3));
  EXPECT_EQ(read_image(dir.path("a.pfm"), "test").height, 3);
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"UPPER.EXR", "UPPER.PFM", "a.exr", "a.pfm"}));
}

TEST(ImageIo, PngRoundTrip) {
  TempDir dir;
  DisplayImage d(6, 4);
  for (size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] = uint8_t(i * 37 % 256);
  write_png(dir.path("d.png"), d);
  const Image lin = read_image(dir.path("d.png"), "test", /*linear_8bit=*/true);
  ASSERT_EQ(lin.width, 6);
  ASSERT_EQ(lin.height, 4);
  for (size_t i = 0; i < d.rgb.size(); ++i) ASSERT_EQ(lin.rgb[i], float(d.rgb[i]) / 255.0f) << i;
  const Image srgb = read_image(dir.path("d.png"), "test");
  for (size_t i = 0; i < d.rgb.size(); ++i) ASSERT_NEAR(srgb.rgb[i], srgb_decode(float(d.rgb[i]) / 255.0f), 1e-6f);

  // write_image(.png) = tonemap + write_png; reading back (sRGB-decoded) is within one 8-bit step.
  Image img(5, 3);
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = float(i) / float(img.rgb.size());
  write_image(dir.path("i.png"), img, {0.0f, ToneMap::Clamp});
  const Image back = read_image(dir.path("i.png"), "test");
  const DisplayImage expected = tonemap(img, {0.0f, ToneMap::Clamp});
  const Image bytes = read_image(dir.path("i.png"), "test", true);
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    ASSERT_EQ(bytes.rgb[i], float(expected.rgb[i]) / 255.0f) << i;
    ASSERT_NEAR(srgb_encode(back.rgb[i]), srgb_encode(img.rgb[i]), 0.5f / 255.0f + 1e-6f) << i;
  }
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"d.png", "i.png"}));
}

TEST(ImageIo, PfmTopRowStaysOnTop) {
  TempDir dir;
  Image img(3, 4);
  img.set(1, 0, RGB(1.0f, 2.0f, 3.0f));  // top row
  write_image(dir.path("t.pfm"), img);
  const Image back = read_image(dir.path("t.pfm"), "test");
  EXPECT_EQ(back.at(1, 0), RGB(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(back.at(1, 3), RGB(0.0f));
  // In the file the top row comes last.
  std::ifstream in(dir.path("t.pfm"), std::ios::binary);
  const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string header = "PF\n3 4\n-1.0\n";
  ASSERT_EQ(s.substr(0, header.size()), header);
  ASSERT_EQ(s.size(), header.size() + 3 * 4 * 3 * 4);
  float last_row_x1[3];
  std::memcpy(last_row_x1, s.data() + header.size() + (3 * 3 * 3 + 3) * 4, 12);
  EXPECT_EQ(last_row_x1[0], 1.0f);
  EXPECT_EQ(last_row_x1[2], 3.0f);
}

TEST(ImageIo, HandWrittenPfmIsReadTheRightWayUp) {
  TempDir dir;
  // 2 x 2, bottom row first: bottom = (1, 2), top = (3, 4) in every channel.
  write_bytes(dir.path("rgb.pfm"), pfm_bytes("PF\n2 2\n-1.0\n", {1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4}));
  const Image rgb = read_image(dir.path("rgb.pfm"), "test");
  EXPECT_EQ(rgb.at(0, 0), RGB(3.0f));
  EXPECT_EQ(rgb.at(1, 0), RGB(4.0f));
  EXPECT_EQ(rgb.at(0, 1), RGB(1.0f));
  EXPECT_EQ(rgb.at(1, 1), RGB(2.0f));
  // Greyscale "Pf", header on one line with extra spaces: expanded to RGB.
  write_bytes(dir.path("grey.pfm"), pfm_bytes("Pf  2 2 -2.5\n", {1, 2, 3, 4}));
  const Image grey = read_image(dir.path("grey.pfm"), "test");
  EXPECT_EQ(grey.at(0, 0), RGB(3.0f));
  EXPECT_EQ(grey.at(1, 1), RGB(2.0f));
  // Big endian (positive scale).
  std::string be = "PF\n1 1\n1.0\n";
  for (float v : {0.5f, 2.0f, 8.0f}) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int k = 3; k >= 0; --k) be.push_back(char((bits >> (8 * k)) & 0xFF));
  }
  write_bytes(dir.path("be.pfm"), be);
  EXPECT_EQ(read_image(dir.path("be.pfm"), "test").at(0, 0), RGB(0.5f, 2.0f, 8.0f));
}

TEST(ImageIo, HdrIsReadLinear) {
  TempDir dir;
  // Radiance RGBE, 2 x 1, flat (no run-length encoding below 8 pixels a row): value = m * 2^(e - 136).
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
  for (int b : {128, 64, 0, 129, 128, 128, 128, 130}) hdr.push_back(char(b));
  write_bytes(dir.path("a.HDR"), hdr);
  const Image img = read_image(dir.path("a.HDR"), "test");
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  EXPECT_EQ(img.at(0, 0), RGB(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(img.at(1, 0), RGB(2.0f));
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// stb_image's Radiance decoder reads zeros past the end of the data: a truncated run-length
// scanline looped for ever and a truncated flat file gave black pixels. Every cut must be an
// error that names the file (a hang here is a ctest timeout).
TEST(ImageIo, TruncatedOrCorruptRadianceHdrIsRefused) {
  TempDir dir;
  write_bytes(dir.path("49.hdr"), std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n\x02\x02\x00\x08", 49));
  expect_read_error(dir.path("49.hdr"), "truncated Radiance HDR: scanline 0 of 2 ends past the end of the file (49 bytes");

  // examples/assets/studio.hdr: 512 x 256, run-length encoded. Whole, it reads; cut anywhere
  // inside its pixels, it is refused.
  const std::string studio = file_bytes(std::string(ANISO_SOURCE_DIR) + "/examples/assets/studio.hdr");
  ASSERT_GT(studio.size(), 20000u);
  write_bytes(dir.path("studio.hdr"), studio);
  const Image whole = read_image(dir.path("studio.hdr"), "test");
  EXPECT_EQ(whole.width, 512);
  EXPECT_EQ(whole.height, 256);
  for (size_t cut : {size_t(200), size_t(1000), studio.size() / 2, studio.size() - 1}) {
    write_bytes(dir.path("cut.hdr"), studio.substr(0, cut));
    expect_read_error(dir.path("cut.hdr"), "truncated Radiance HDR: scanline ");
  }
  write_bytes(dir.path("header.hdr"), studio.substr(0, 60));
  expect_read_error(dir.path("header.hdr"), "corrupt or unsupported image");

  // The first scanline's marker, then a row length that is not the image's width; then a run that
  // reaches past the end of its row.
  const size_t data_start = studio.find("+X 512\n") + 7;
  std::string bad = studio;
  bad[data_start + 3] = 1;  // 512 -> 513
  write_bytes(dir.path("len.hdr"), bad);
  expect_read_error(dir.path("len.hdr"), "scanline 0 of 256 (byte 95) claims 513 pixels, the image is 512 wide");
  std::string run = studio.substr(0, data_start + 4);
  for (int i = 0; i < 5; ++i) run += "\xff\x80";  // 5 runs of 127 > 512
  write_bytes(dir.path("run.hdr"), run + studio.substr(data_start + 4));
  expect_read_error(dir.path("run.hdr"), "scanline 0 of 256 (byte 107) has a run past its end");

  // Flat rows (fewer than 8 pixels) cut to 10 %: refused, not black.
  std::string flat = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 40 +X 4\n";
  const size_t header = flat.size();
  for (int i = 0; i < 160; ++i) flat += "\x80\x40\x20\x81";
  write_bytes(dir.path("flat.hdr"), flat);
  EXPECT_EQ(read_image(dir.path("flat.hdr"), "test").at(3, 39), RGB(1.0f, 0.5f, 0.25f));
  write_bytes(dir.path("flat10.hdr"), flat.substr(0, header + 64));
  expect_read_error(dir.path("flat10.hdr"), "truncated Radiance HDR: scanline 4 of 40 ends past the end of the file");
}

// The size limit is checked from the header, before decoding: a PNG header claiming 16384 x 16384
// pixels (a valid such file compresses to 32 KB) is refused at once.
TEST(ImageIo, ImagesBeyondTheSizeLimitAreRefusedFromTheHeader) {
  TempDir dir;
  auto png_header = [](uint32_t w, uint32_t h) {
    std::string s("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
    for (uint32_t v : {w, h})
      for (int b = 3; b >= 0; --b) s.push_back(char((v >> (8 * b)) & 0xff));
    s += std::string("\x08\x02\0\0\0", 5) + std::string(4, '\0');  // 8-bit RGB; CRC unchecked by stb_image
    return s + std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  };
  write_bytes(dir.path("big.png"), png_header(16384, 16384));
  expect_read_error(
      dir.path("big.png"),
      "image too large (16384 x 16384 = 268435456 pixels; at most 67108864 pixels, e.g. 8192 x 8192 or 16384 x 4096)");
  write_bytes(dir.path("wide.png"), png_header(16384, 4097));
  expect_read_error(dir.path("wide.png"), "image too large (16384 x 4097");
  // At the limit the header passes and decoding starts (and fails on the missing pixel data).
  write_bytes(dir.path("limit.png"), png_header(16384, 4096));
  expect_read_error(dir.path("limit.png"), "more than a file of");
}

TEST(ImageIo, BadInputIsAnInputErrorNamingWhereAndPath) {
  TempDir dir;
  expect_read_error(dir.path("missing.hdr"), "cannot open (No such file or directory)");
  fs::create_directory(dir.path("dir.png"));
  expect_read_error(dir.path("dir.png"), "is a directory");
  write_bytes(dir.path("empty.exr"), "");
  expect_read_error(dir.path("empty.exr"), "empty file");
  write_bytes(dir.path("trunc.pfm"), pfm_bytes("PF\n4 4\n-1.0\n", std::vector<float>(20, 1.0f)));
  expect_read_error(dir.path("trunc.pfm"), "truncated PFM");
  write_bytes(dir.path("header.pfm"), "PF\n4");
  expect_read_error(dir.path("header.pfm"), "truncated PFM header");
  write_bytes(dir.path("magic.pfm"), "P6\n1 1\n255\nabc");
  expect_read_error(dir.path("magic.pfm"), "not a PFM file");
  write_bytes(dir.path("scale.pfm"), pfm_bytes("PF\n1 1\n0\n", {1, 1, 1}));
  expect_read_error(dir.path("scale.pfm"), "bad PFM scale");
  write_bytes(dir.path("zero.pfm"), "PF\n0 3\n-1.0\n");
  expect_read_error(dir.path("zero.pfm"), "zero-size image");
  write_bytes(dir.path("huge.pfm"), "PF\n99999999999 99999999999\n-1.0\n");
  expect_read_error(dir.path("huge.pfm"), "bad PFM width");
  write_bytes(dir.path("big.pfm"), "PF\n100000 100000\n-1.0\n");
  expect_read_error(dir.path("big.pfm"), "image too large");
  write_bytes(dir.path("garbage.png"), "this is not a PNG file at all");
  expect_read_error(dir.path("garbage.png"), "not a PNG file (no PNG signature)");
  write_bytes(dir.path("garbage.jpg"), "this is not a JPEG file at all");
  expect_read_error(dir.path("garbage.jpg"), "not a JPEG file (no JPEG signature)");
  // fuzz/corpus/image/regression-tga-as-png: 118 bytes that stb_image decoded as a run-length TGA
  // of 6168 x 6168 pixels (31 s); only PNG, JPEG and HDR decoders are compiled in, and the
  // signature must match the extension.
  std::string tga = std::string("\0\0\n", 3) + std::string(104, '\x18') + std::string("\0\0\xff\xff\x0e\0\0\0\xff\xff", 10);
  write_bytes(dir.path("tga.png"), tga);
  expect_read_error(dir.path("tga.png"), "not a PNG file");
  write_bytes(dir.path("garbage.exr"), "this is not an EXR file at all");
  expect_read_error(dir.path("garbage.exr"), "corrupt or unsupported EXR file");
  write_bytes(dir.path("garbage.hdr"), "#?RADIANCE\nnothing else");
  expect_read_error(dir.path("garbage.hdr"), "corrupt or unsupported image (");
  write_bytes(dir.path("ldr.hdr"), "P6\n1 1\n255\nabc");  // an 8-bit file named .hdr
  expect_read_error(dir.path("ldr.hdr"), "not a Radiance HDR");
  write_bytes(dir.path("image.tga"), "whatever");
  expect_read_error(dir.path("image.tga"), "unknown image extension \".tga\" (expected .png, .jpg, .jpeg, .hdr, .exr or .pfm)");
  expect_read_error(dir.path("noext"), "unknown image extension");

  // Non-finite and negative values name the first offending pixel (row 0 = top).
  std::vector<float> v(2 * 3 * 3, 0.5f);
  v[(1 * 2 + 0) * 3 + 1] = std::nanf("");  // file row 1 of 3, from the bottom: y = 1
  write_bytes(dir.path("nan.pfm"), pfm_bytes("PF\n2 3\n-1.0\n", v));
  expect_read_error(dir.path("nan.pfm"), "pixel (0, 1) is not finite");
  v[(1 * 2 + 0) * 3 + 1] = 0.5f;
  v[(0 * 2 + 1) * 3 + 2] = -1.0f;  // file row 0, the bottom: y = 2
  write_bytes(dir.path("neg.pfm"), pfm_bytes("PF\n2 3\n-1.0\n", v));
  expect_read_error(dir.path("neg.pfm"), "pixel (1, 2) is negative");
  Image inf(3, 2);
  inf.set(2, 1, RGB(0.0f, std::numeric_limits<float>::infinity(), 0.0f));
  write_image(dir.path("inf.exr"), inf);  // writing does not judge the values
  expect_read_error(dir.path("inf.exr"), "pixel (2, 1) is not finite");

  // A truncated EXR and a truncated PNG (cut from good files).
  write_image(dir.path("good.exr"), test_image(16, 16));
  write_image(dir.path("good.png"), test_image(16, 16));
  for (const char* name : {"good.exr", "good.png"}) {
    std::ifstream in(dir.path(name), std::ios::binary);
    const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = std::string("cut_") + name;
    write_bytes(dir.path(cut), s.substr(0, s.size() / 2));
    expect_read_error(dir.path(cut), "corrupt");
  }
}

TEST(ImageIo, FailedWritesLeaveNothingBehind) {
  TempDir dir;
  const Image img = test_image(4, 4);
  for (const char* name : {"missing/a.png", "missing/a.exr", "missing/a.pfm"}) {
    try {
      write_image(dir.path(name), img);
      ADD_FAILURE() << "no error writing " << name;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("cannot write " + dir.path(name) + ": ", 0), 0u) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(dir.path("missing")));

  try {
    write_image(dir.path("a.jpg"), img);
    ADD_FAILURE() << "no error for .jpg";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir.path("a.jpg")), std::string::npos) << msg;
    EXPECT_NE(msg.find(".png, .exr or .pfm"), std::string::npos) << msg;
  }
  EXPECT_THROW(write_image(dir.path("empty.pfm"), Image()), std::runtime_error);
  EXPECT_THROW(write_png(dir.path("empty.png"), DisplayImage()), std::runtime_error);

  // The target is a directory: the rename fails, the temporary file is removed.
  fs::create_directory(dir.path("taken.pfm"));
  EXPECT_THROW(write_image(dir.path("taken.pfm"), img), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(dir.path("taken.pfm")));
  EXPECT_EQ(dir.files(), std::vector<std::string>{"taken.pfm"});
}

// ---------------------------------------------------------------------------------------------

int changed_pixels(const DisplayImage& a, const DisplayImage& b, int x0 = 0, int y0 = 0, int x1 = 1 << 30, int y1 = 1 << 30) {
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, a.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, a.width); ++x) {
      const size_t i = (size_t(y) * size_t(a.width) + size_t(x)) * 3;
      n += a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2];
    }
  return n;
}

TEST(ImageText, DrawsInsideItsBox) {
  DisplayImage img(200, 60, 255);
  const DisplayImage blank = img;
  const float px = 20.0f;
  const int w = draw_text(img, 10, 15, "Ward α = 0.12, 45°", px, {0, 0, 0});
  EXPECT_EQ(w, text_width("Ward α = 0.12, 45°", px));
  EXPECT_GT(w, 100);
  const int changed = changed_pixels(img, blank);
  EXPECT_GT(changed, 100);
  // Everything drawn lies in the text box (a pixel of slack for anti-aliasing).
  EXPECT_EQ(changed_pixels(img, blank, 9, 14, 10 + w + 1, 15 + int(px) + 1), changed);
  // Anti-aliased: some pixels are neither the background nor the ink.
  int grey = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3) grey += img.rgb[i] > 0 && img.rgb[i] < 255;
  EXPECT_GT(grey, 20);
  // The colour is the one asked for.
  DisplayImage red(40, 40, 0);
  draw_text(red, 5, 5, "H", 30.0f, {255, 0, 0});
  int full = 0;
  for (size_t i = 0; i < red.rgb.size(); i += 3) {
    EXPECT_EQ(red.rgb[i + 1], 0);
    full += red.rgb[i] == 255;
  }
  EXPECT_GT(full, 20);
}

TEST(ImageText, Width) {
  EXPECT_EQ(text_width("", 16.0f), 0);
  EXPECT_GT(text_width("α", 16.0f), 0);
  EXPECT_GT(text_width("°", 16.0f), 0);
  EXPECT_GT(text_width("ψ", 16.0f), 0);
  EXPECT_LT(text_width("Wa", 16.0f), text_width("Ward", 16.0f));
  EXPECT_LT(text_width("Ward", 16.0f), text_width("Ward", 32.0f));
  EXPECT_NEAR(text_width("Anisotropic", 32.0f), 2 * text_width("Anisotropic", 16.0f), 2);
  // Kerning: "AV" is tighter than "A" + "V".
  EXPECT_LT(text_width("AVAVAVAV", 40.0f), 4 * (text_width("A", 40.0f) + text_width("V", 40.0f)) - 4);
  EXPECT_EQ(text_width("abc", 0.0f), 0);
  EXPECT_EQ(text_width("abc", std::nanf("")), 0);
  // Malformed UTF-8 neither crashes nor disappears.
  EXPECT_GT(text_width("\xff\xce", 16.0f), 0);
}

TEST(ImageText, ClippedAtTheEdges) {
  DisplayImage img(50, 20, 255);
  const DisplayImage blank = img;
  for (auto [x, y] : {std::pair{-30, -10},
                      {-1000, 5},
                      {40, 15},
                      {1 << 30, 0},
                      {0, 1 << 30},
                      {std::numeric_limits<int>::max(), std::numeric_limits<int>::max()},
                      {std::numeric_limits<int>::min(), std::numeric_limits<int>::min()}})
    draw_text(img, x, y, "Clipped α ψ°", 24.0f, {0, 0, 0});
  EXPECT_GT(changed_pixels(img, blank), 0);  // the (-30, -10) and (40, 15) ones show partly
  DisplayImage empty;
  EXPECT_GT(draw_text(empty, 0, 0, "x", 12.0f, {0, 0, 0}), 0);
}

TEST(ImageCompose, FillRectAndBlitClip) {
  DisplayImage img(10, 8, 0);
  fill_rect(img, -5, -5, 8, 7, {1, 2, 3});  // covers x 0..2, y 0..1
  fill_rect(img, 8, 6, 100, 100, {4, 5, 6});
  fill_rect(img, std::numeric_limits<int>::max(), 0, std::numeric_limits<int>::max(), 3, {9, 9, 9});
  EXPECT_EQ(img.rgb[(1 * 10 + 2) * 3 + 2], 3);
  EXPECT_EQ(img.rgb[(2 * 10 + 2) * 3 + 2], 0);
  EXPECT_EQ(img.rgb[(1 * 10 + 3) * 3 + 2], 0);
  EXPECT_EQ(img.rgb[(7 * 10 + 9) * 3 + 0], 4);
  DisplayImage src(4, 3, 0);
  for (size_t i = 0; i < src.rgb.size(); ++i) src.rgb[i] = uint8_t(100 + i);
  DisplayImage dst(5, 5, 0);
  blit(dst, src, -2, 3);  // src columns 2..3, rows 0..1 land at x 0..1, y 3..4
  EXPECT_EQ(dst.rgb[(3 * 5 + 0) * 3], src.rgb[(0 * 4 + 2) * 3]);
  EXPECT_EQ(dst.rgb[(4 * 5 + 1) * 3 + 2], src.rgb[(1 * 4 + 3) * 3 + 2]);
  EXPECT_EQ(dst.rgb[(2 * 5 + 0) * 3], 0);
  EXPECT_EQ(dst.rgb[(3 * 5 + 2) * 3], 0);
  blit(dst, src, 100, 100);
  blit(dst, src, -100, -100);
}

}  // namespace
}  // namespace aniso::render
