// tests/test_tonemap_parity.cpp: the one tone map, three runners. The CPU's render::tonemap
// (src/image/tonemap.cpp) gives exactly the bytes of tests/reference/tonemap_cpu.json, and the GL
// backend's display pass (gl/tonemap_pass.h, the GLSL twin aniso/image/tonemap.glsl) gives them to
// within rounding, on probe values written into a float texture: 0, tiny, around sRGB's and ACES's
// knees, 1, huge, +inf, -inf, NaN, negative, at several exposures, both curves. The web explorer's
// display pass is held to the same file by tests/web/explorer.test.mjs (check "tonemap").
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/image/tonemap.h"
#include "gl/gl_objects.h"
#include "gl/tonemap_pass.h"
#include "glsl_util.h"

namespace aniso::test {
namespace {

using nlohmann::json;

// A float display value d in [0, 1] agrees with the CPU's byte b when |255 d - b| <= 0.5 + kSlack:
// the CPU rounds 255 d to the nearest byte, and GLSL's pow may differ from the C library's in the
// last bits, which moves a value near a rounding boundary by far less than kSlack of a step.
constexpr double kSlack = 0.05;

struct Probe {
  std::vector<float> radiance;
  json cases;
};

Probe load_probe() {
  const std::string path = ANISO_SOURCE_DIR "/tests/reference/tonemap_cpu.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  const json j = json::parse(in);
  Probe p;
  // Strings, so that Infinity, -Infinity and NaN travel too (strtof and JavaScript's Number read them).
  for (const json& v : j.at("radiance")) p.radiance.push_back(std::strtof(v.get<std::string>().c_str(), nullptr));
  p.cases = j.at("cases");
  return p;
}

render::ToneMapOptions options(const json& c) {
  return {c.at("exposure").get<float>(),
          c.at("curve").get<std::string>() == "clamp" ? render::ToneMap::Clamp : render::ToneMap::Aces};
}

TEST(ToneMapParity, ProbeCoversTheCasesThatNeedCare) {
  const Probe p = load_probe();
  bool zero = false, inf = false, ninf = false, nan = false, negative = false, huge = false, knee = false;
  for (float v : p.radiance) {
    zero = zero || v == 0.0f;
    inf = inf || v == INFINITY;
    ninf = ninf || v == -INFINITY;
    nan = nan || std::isnan(v);
    negative = negative || (v < 0.0f && std::isfinite(v));
    huge = huge || (std::isfinite(v) && v > 1e30f);
    knee = knee || (v > 5.0f && v < 10.0f);
  }
  EXPECT_TRUE(zero && inf && ninf && nan && negative && huge && knee);
  bool aces = false, clamp = false;
  for (const json& c : p.cases) (options(c).curve == render::ToneMap::Aces ? aces : clamp) = true;
  EXPECT_TRUE(aces && clamp);
  EXPECT_GE(p.cases.size(), 6u);
}

// The reference file is the CPU's output: a change of render::tonemap shows here first, with the
// row to write into the file.
TEST(ToneMapParity, CpuGivesTheReferenceBytes) {
  const Probe p = load_probe();
  const int n = int(p.radiance.size());
  render::Image img(n, 1);
  for (int i = 0; i < n; ++i) img.set(i, 0, RGB(p.radiance[size_t(i)]));
  for (const json& c : p.cases) {
    const render::DisplayImage d = render::tonemap(img, options(c));
    std::vector<int> got;
    for (int i = 0; i < n; ++i) got.push_back(d.rgb[size_t(i) * 3]);
    EXPECT_EQ(got, c.at("bytes").get<std::vector<int>>())
        << "exposure " << c.at("exposure") << ", " << c.at("curve") << ": the CPU now gives " << json(got).dump();
  }
}

TEST(ToneMapParity, GlBackendDisplayPassGivesTheCpuBytes) {
  ANISO_REQUIRE_GL();
  const Probe p = load_probe();
  const int n = int(p.radiance.size());
  // The probe in R; G and B hold it shifted by one and two, so that every channel sees every value.
  std::vector<float> texels(size_t(n) * 4);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) texels[size_t(i) * 4 + size_t(k)] = p.radiance[size_t((i + k) % n)];
  GLuint src = 0, dst = 0, fbo = 0;
  glGenTextures(1, &src);
  glBindTexture(GL_TEXTURE_2D, src);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, 1, 0, GL_RGBA, GL_FLOAT, texels.data());
  glGenTextures(1, &dst);
  glBindTexture(GL_TEXTURE_2D, dst);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, 1, 0, GL_RGBA, GL_FLOAT, nullptr);
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, dst, 0);
  ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
  glViewport(0, 0, n, 1);
  const gl::TonemapPass pass;
  double worst = 0.0;
  for (const json& c : p.cases) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    pass.draw(src, glm::ivec2(n, 1), options(c));
    const std::vector<float> out = gl::read_rgba(fbo, n, 1);
    const std::vector<int> bytes = c.at("bytes").get<std::vector<int>>();
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        const float d = out[size_t(i) * 4 + size_t(k)];
        const int want = bytes[size_t((i + k) % n)];
        const double diff = std::isfinite(d) ? std::abs(255.0 * double(d) - double(want)) : 1e9;
        worst = std::max(worst, diff);
        EXPECT_LE(diff, 0.5 + kSlack) << "radiance " << p.radiance[size_t((i + k) % n)] << ", exposure " << c.at("exposure")
                                      << ", " << c.at("curve") << ": GL " << d << " (x 255 = " << 255.0 * double(d)
                                      << "), CPU byte " << want;
      }
  }
  RecordProperty("worst_steps", fmt::format("{:.4f}", worst));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteFramebuffers(1, &fbo);
  const GLuint textures[] = {src, dst};
  glDeleteTextures(2, textures);
}

}  // namespace
}  // namespace aniso::test
