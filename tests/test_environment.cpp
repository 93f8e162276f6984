// tests/test_environment.cpp: the piecewise-constant distributions (histograms against the
// function, chi-square; pdf consistency and normalisation) and the environments (uniform, map,
// sky): sample() against pdf() and eval(), pdf integrating to 1 over the sphere, importance-sampled
// integrals against exact texel sums, the documented lat-long mapping and rotation, and the sun's
// power surviving tabulation.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "aniso/render/environment.h"
#include "chi2.h"
#include "stats/rng.h"

namespace aniso::render {
namespace {

constexpr double kPi = std::numbers::pi;

// Pearson's chi-square of observed counts against expected ones (tests/chi2.h) passes at
// significance 1e-3; a cell of expected count 0 must be empty.
void expect_chi2_fits(const std::vector<double>& observed, const std::vector<double>& expected) {
  const test::PearsonResult r = test::pearson_chi2(observed, expected);
  EXPECT_TRUE(r.message.empty()) << r.message;
  EXPECT_GT(r.p_value, 1e-3) << "chi2 " << r.chi2 << " dof " << r.dof;
}

// The documented lat-long mapping (environment.h), written out independently of environment.cpp:
// the world direction of map coordinates (u, v) for a map rotated by rotation_deg.
Vec3 direction_of_uv(double u, double v, double rotation_deg = 0.0) {
  const double phi = (u - rotation_deg / 360.0 - 0.5) * 2.0 * kPi;
  const double theta = v * kPi;
  return Vec3(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)), float(-std::sin(theta) * std::cos(phi)));
}

// Integral of eval() over the sphere for a piecewise-constant map of w x h texels: eval at each
// texel centre times the texel's solid angle dphi (cos theta0 - cos theta1), exact for nearest
// lookup. Rows [y0, y1) only, when given.
glm::dvec3 texel_sum(const Environment& env, int w, int h, double rotation_deg = 0.0, int y0 = 0, int y1 = -1) {
  glm::dvec3 sum(0.0);
  for (int y = y0; y < (y1 < 0 ? h : y1); ++y) {
    const double omega = 2.0 * kPi / w * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
    glm::dvec3 row(0.0);
    for (int x = 0; x < w; ++x) row += glm::dvec3(env.eval(direction_of_uv((x + 0.5) / w, (y + 0.5) / h, rotation_deg)));
    sum += row * omega;
  }
  return sum;
}

Vec3 uniform_sphere(Rng& rng) {
  const double y = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
  return Vec3(float(r * std::cos(phi)), float(y), float(r * std::sin(phi)));
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// ---- Distribution1D -------------------------------------------------------------------------

TEST(Distribution1D, HistogramMatchesFunctionChiSquare) {
  const std::vector<float> f = {1.0f, 0.0f, 3.0f, 0.5f, 2.0f, 0.0f, 0.1f, 5.0f};
  const Distribution1D d(f);
  const int n = int(f.size()), sub = 4;  // 4 cells per bin: also checks uniformity inside a bin
  double total = 0.0;
  for (float v : f) total += v;
  EXPECT_NEAR(d.integral(), total / n, 1e-6);
  const int64_t samples = 200000;
  std::vector<double> observed(size_t(n * sub), 0.0), expected(size_t(n * sub), 0.0);
  for (int i = 0; i < n * sub; ++i) expected[size_t(i)] = samples * f[size_t(i / sub)] / total / sub;
  Rng rng(7);
  for (int64_t k = 0; k < samples; ++k) {
    float pdf = -1.0f;
    int offset = -1;
    const float x = d.sample(rng.uniform_as<float>(), &pdf, &offset);
    ASSERT_GE(x, 0.0f);
    ASSERT_LT(x, 1.0f);
    ASSERT_EQ(offset, std::min(n - 1, int(x * n)));
    ASSERT_GT(f[size_t(offset)], 0.0f) << "zero bin sampled";
    ASSERT_FLOAT_EQ(pdf, f[size_t(offset)] / d.integral());
    observed[size_t(std::min(n * sub - 1, int(x * n * sub)))] += 1.0;
  }
  expect_chi2_fits(observed, expected);
}

TEST(Distribution1D, PdfIntegratesToOne) {
  const Distribution1D d({0.2f, 7.0f, 0.0f, 1e-4f, 3.0f});
  double integral = 0.0;
  for (int i = 0; i < d.size(); ++i) integral += d.func(i) / d.integral() / d.size();
  EXPECT_NEAR(integral, 1.0, 1e-6);
}

TEST(Distribution1D, ZeroFunctionIsUniform) {
  const Distribution1D d(std::vector<float>(5, 0.0f));
  for (float u : {0.0f, 0.13f, 0.5f, 0.77f, 0.999f}) {
    float pdf = 0.0f;
    int offset = -1;
    EXPECT_NEAR(d.sample(u, &pdf, &offset), u, 1e-6f);
    EXPECT_EQ(pdf, 1.0f);
    EXPECT_EQ(offset, int(u * 5));
  }
}

TEST(Distribution1D, StaysBelowOneAndSkipsTrailingZeroBin) {
  const Distribution1D d({1.0f, 0.0f});
  const float u = 0x1.fffffep-1f;  // the largest float below 1
  int offset = -1;
  const float x = d.sample(u, nullptr, &offset);
  EXPECT_EQ(offset, 0);
  EXPECT_LT(x, 0.5f);
  const Distribution1D one({2.0f});
  EXPECT_LT(one.sample(u, nullptr, nullptr), 1.0f);
}

// The guide table only narrows the search: every u finds the bin the binary search of the whole
// CDF finds (the first entry above u, minus one), on functions with zero runs, a spike that holds
// almost all the weight (its neighbours' bins narrower than a guide cell) and a size that is not
// a power of two. The CDF is rebuilt here as the constructor documents it (double sums, divided
// once, the last entry exactly 1); u runs over a grid, over random values, and over every CDF entry
// and guide-cell edge with the floats on either side.
TEST(Distribution1D, GuideTableFindsTheBinOfTheFullSearch) {
  std::vector<float> f(300, 0.0f);
  Rng rng(5);
  for (size_t i = 0; i < f.size(); ++i) f[i] = (i / 7) % 3 == 0 ? 0.0f : float(rng.uniform()) * 2.0f;
  f[123] = 1e6f;
  f[0] = f[299] = 0.0f;
  const Distribution1D d(f);
  const size_t n = f.size();
  std::vector<double> acc(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) acc[i + 1] = acc[i] + double(f[i]);
  std::vector<float> cdf(n + 1);
  for (size_t i = 0; i <= n; ++i) cdf[i] = float(acc[i] / acc[n]);
  cdf[n] = 1.0f;
  std::vector<float> us;
  for (int k = 0; k <= 4096; ++k) us.push_back(float(k) / 4096.0f);
  for (int k = 0; k < 20000; ++k) us.push_back(float(rng.uniform()));
  for (size_t i = 0; i <= n; ++i) us.insert(us.end(), {cdf[i], std::nextafter(cdf[i], 0.0f), std::nextafter(cdf[i], 1.0f)});
  for (int k = 0; k <= 512; ++k) {
    const float t = float(k) / 512.0f;  // the guide cells' edges (512: the power of two above 300)
    us.insert(us.end(), {t, std::nextafter(t, 0.0f), std::nextafter(t, 1.0f)});
  }
  for (float u : us) {
    const float uc = std::clamp(u, 0.0f, 0x1.fffffep-1f);
    const int want = std::clamp(int(std::upper_bound(cdf.begin(), cdf.end(), uc) - cdf.begin()) - 1, 0, int(n) - 1);
    int offset = -1;
    d.sample(u, nullptr, &offset);
    ASSERT_EQ(offset, want) << "u = " << u;
    ASSERT_GT(f[size_t(offset)], 0.0f) << "zero bin sampled at u = " << u;
  }
}

// Equal weights over a power-of-two number of bins (a sky's rows) take a shortcut (u itself, bin
// int(u n)): it must give what the CDF search gives, bit for bit: the sample, the pdf and the bin,
// the search written out here as sample() documents it (CDF in double, divided once; the bin's
// offset rescaled by its width), for u on a grid, at random, and on every bin edge and the floats
// on either side.
TEST(Distribution1D, EqualWeightsOfPowerOfTwoSizeSampleAsTheSearch) {
  Rng rng(9);
  for (const size_t n : {size_t(1), size_t(2), size_t(256), size_t(2048)})
    for (const float w : {1.0f, 0.37f, 0.1234567f, 3e4f}) {
      const Distribution1D d(std::vector<float>(n, w));
      std::vector<double> acc(n + 1, 0.0);
      for (size_t i = 0; i < n; ++i) acc[i + 1] = acc[i] + double(w);
      std::vector<float> cdf(n + 1);
      for (size_t i = 0; i <= n; ++i) cdf[i] = float(acc[i] / acc[n]);
      cdf[n] = 1.0f;
      const float integral = float(acc[n] / double(n));
      std::vector<float> us;
      for (int k = 0; k <= 1000; ++k) us.push_back(float(k) / 1000.0f);
      for (int k = 0; k < 2000; ++k) us.push_back(float(rng.uniform()));
      for (size_t i = 0; i <= n; ++i) us.insert(us.end(), {cdf[i], std::nextafter(cdf[i], 0.0f), std::nextafter(cdf[i], 1.0f)});
      for (float u : us) {
        const float uc = std::clamp(u, 0.0f, 0x1.fffffep-1f);
        const int o = std::clamp(int(std::upper_bound(cdf.begin(), cdf.end(), uc) - cdf.begin()) - 1, 0, int(n) - 1);
        float du = uc - cdf[size_t(o)];
        const float width = cdf[size_t(o) + 1] - cdf[size_t(o)];
        if (width > 0.0f) du /= width;
        const float want = std::min((float(o) + du) / float(n), 0x1.fffffep-1f);
        float pdf = -1.0f;
        int offset = -1;
        const float x = d.sample(u, &pdf, &offset);
        ASSERT_EQ(offset, o) << "n " << n << " w " << w << " u " << u;
        ASSERT_EQ(x, want) << "n " << n << " w " << w << " u " << u;
        ASSERT_EQ(pdf, w / integral) << "n " << n << " w " << w << " u " << u;
      }
    }
}

// ---- Distribution2D -------------------------------------------------------------------------

TEST(Distribution2D, HistogramPdfConsistencyAndNormalisation) {
  const int nu = 8, nv = 6;
  std::vector<float> f(size_t(nu * nv));
  Rng rng(11);
  for (float& v : f) v = rng.uniform() < 0.2 ? 0.0f : float(rng.uniform() * 4.0);
  for (int u = 0; u < nu; ++u) f[size_t(2 * nu + u)] = 0.0f;  // a whole zero row
  f[size_t(4 * nu + 3)] = 40.0f;                              // a peak
  const Distribution2D d(f, nu, nv);

  double total = 0.0;
  for (float v : f) total += v;
  // The pdf integrates to 1 over [0, 1)^2 and equals f / mean(f).
  double integral = 0.0;
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) {
      const float p = d.pdf(Vec2((u + 0.5f) / nu, (v + 0.5f) / nv));
      EXPECT_NEAR(p, f[size_t(v * nu + u)] / (total / (nu * nv)), 1e-5 * (1.0 + p));
      integral += p / (nu * nv);
    }
  EXPECT_NEAR(integral, 1.0, 1e-5);

  const int64_t samples = 300000;
  std::vector<double> observed(f.size(), 0.0), expected(f.size(), 0.0);
  for (size_t i = 0; i < f.size(); ++i) expected[i] = samples * f[i] / total;
  for (int64_t k = 0; k < samples; ++k) {
    float pdf = 0.0f;
    const Vec2 uv = d.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()), &pdf);
    ASSERT_TRUE(uv.x >= 0.0f && uv.x < 1.0f && uv.y >= 0.0f && uv.y < 1.0f);
    ASSERT_NEAR(d.pdf(uv), pdf, 1e-5f * pdf);
    observed[size_t(int(uv.y * nv) * nu + int(uv.x * nu))] += 1.0;
  }
  expect_chi2_fits(observed, expected);
}

TEST(Distribution2D, DefaultConstructedGivesNoSample) {
  float pdf = -1.0f;
  EXPECT_EQ(Distribution2D().pdf(Vec2(0.5f)), 0.0f);
  Distribution2D().sample(Vec2(0.5f), &pdf);
  EXPECT_EQ(pdf, 0.0f);
  pdf = -1.0f;
  Distribution1D().sample(0.5f, &pdf, nullptr);
  EXPECT_EQ(pdf, 0.0f);
}

TEST(Distribution2D, ZeroFunctionIsUniform) {
  const Distribution2D d(std::vector<float>(12, 0.0f), 4, 3);
  float pdf = 0.0f;
  const Vec2 uv = d.sample(Vec2(0.3f, 0.8f), &pdf);
  EXPECT_NEAR(uv.x, 0.3f, 1e-6f);
  EXPECT_NEAR(uv.y, 0.8f, 1e-6f);
  EXPECT_EQ(pdf, 1.0f);
  EXPECT_EQ(d.pdf(Vec2(0.9f, 0.1f)), 1.0f);
}

// ---- Environment: black and uniform ---------------------------------------------------------

TEST(EnvironmentBlack, DefaultZeroUniformAndBlackMapAreBlack) {
  for (const Environment& e : {Environment(), Environment::uniform(RGB(0.0f)), Environment::from_image(Image(8, 4), 1.0f, 0.0f),
                               Environment::from_image(Image(), 1.0f, 0.0f)}) {
    EXPECT_TRUE(e.is_black());
    EXPECT_EQ(e.eval(Vec3(0, 1, 0)), RGB(0.0f));
    EXPECT_EQ(e.pdf(Vec3(0, 1, 0)), 0.0f);
    EXPECT_EQ(e.sample(Vec2(0.5f)).pdf, 0.0f);
  }
}

TEST(EnvironmentUniform, ConstantRadianceUniformSphere) {
  const RGB L(0.5f, 1.0f, 2.0f);
  const Environment e = Environment::uniform(L);
  EXPECT_FALSE(e.is_black());
  Rng rng(3);
  glm::dvec3 mean_w(0.0);
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const EnvSample s = e.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    ASSERT_NEAR(glm::length(s.w), 1.0f, 1e-5f);
    ASSERT_FLOAT_EQ(s.pdf, float(1.0 / (4.0 * kPi)));
    ASSERT_EQ(s.radiance, L);
    ASSERT_EQ(e.eval(s.w), L);
    ASSERT_EQ(e.pdf(s.w), s.pdf);
    mean_w += glm::dvec3(s.w);
  }
  // Uniform on the sphere: each coordinate has mean 0 and variance 1/3.
  mean_w /= double(n);
  EXPECT_LT(glm::length(mean_w), 5.0 * std::sqrt(1.0 / 3.0 / n) * std::sqrt(3.0));
}

// ---- Environment: maps ----------------------------------------------------------------------

// 32 x 16 random colours with black texels, a few bright ones and saturated, dim ones (tiny
// luminance: they get the pdf floor).
Image random_map() {
  Image img(32, 16);
  Rng rng(5);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double r = rng.uniform();
      RGB c(float(rng.uniform()), float(rng.uniform()), float(rng.uniform()));
      if (r < 0.1)
        c = RGB(0.0f);
      else if (r < 0.15)
        c = RGB(0.0f, 0.0f, 1e-5f);
      else if (r < 0.18)
        c *= 20.0f;
      img.set(x, y, c);
    }
  return img;
}

constexpr float kScale = 1.5f, kRotation = 37.0f;

// The documented density of a texel: f = max(lum, 1e-3 mean lum) sin(theta_c) (0 for black
// texels, mean lum the solid-angle mean), normalised over [0, 1)^2, then divided by the Jacobian
// 2 pi^2 sin(theta) of the lat-long mapping.
class ExpectedPdf {
 public:
  ExpectedPdf(const Image& img, double rotation_deg) : img_(img), rotation_deg_(rotation_deg) {
    auto lum = [](const RGB& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    double lum_sum = 0.0, sin_sum = 0.0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const double s = std::sin((y + 0.5) * kPi / img.height);
        lum_sum += lum(img.at(x, y)) * s;
        sin_sum += s;
      }
    const double floor = 1e-3 * lum_sum / sin_sum;
    double mean = 0.0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const RGB c = img.at(x, y);
        f_.push_back(max_component(c) > 0.0f ? std::max(lum(c), floor) * std::sin((y + 0.5) * kPi / img.height) : 0.0);
        mean += f_.back();
      }
    mean_ = mean / f_.size();
  }
  double operator()(const Vec3& w) const {
    double u = 0.5 + std::atan2(double(w.x), -double(w.z)) / (2.0 * kPi) + rotation_deg_ / 360.0;
    u -= std::floor(u);
    const double v = std::acos(std::clamp(double(w.y), -1.0, 1.0)) / kPi;
    const int x = std::min(img_.width - 1, int(u * img_.width)), y = std::min(img_.height - 1, int(v * img_.height));
    return f_[size_t(y * img_.width + x)] / mean_ / (2.0 * kPi * kPi * std::sqrt(double(w.x) * w.x + double(w.z) * w.z));
  }

 private:
  const Image& img_;
  double rotation_deg_, mean_ = 0.0;
  std::vector<double> f_;
};

TEST(EnvironmentMap, SampleAgreesWithPdfAndEval) {
  Image img = random_map();
  Image scaled = img;
  for (float& c : scaled.rgb) c *= kScale;
  const Environment env = Environment::from_image(img, kScale, kRotation);
  ASSERT_FALSE(env.is_black());
  const ExpectedPdf expected_pdf(scaled, kRotation);
  Rng rng(17);
  int rejected = 0;
  for (int i = 0; i < 20000; ++i) {
    const EnvSample s = env.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    if (s.pdf == 0.0f) {
      ++rejected;
      continue;
    }
    ASSERT_NEAR(glm::length(s.w), 1.0f, 1e-5f);
    ASSERT_NEAR(env.pdf(s.w), s.pdf, 1e-4f * s.pdf);  // (a)
    ASSERT_EQ(env.eval(s.w), s.radiance);             // (b)
    ASSERT_GT(max_component(s.radiance), 0.0f) << "black texel sampled";
    ASSERT_NEAR(s.pdf, expected_pdf(s.w), 1e-4 * s.pdf);  // the documented density
  }
  EXPECT_LE(rejected, 2);  // only by rounding onto a texel edge next to a black texel
}

// sample_above(u, n) is sample(u) wherever its direction is above the plane of n, bit for bit, and
// no sample below it: maps (sky with and without a sun, a rotated random map) and a constant one.
TEST(EnvironmentMap, SampleAboveIsTheSampleAboveThePlane) {
  SkyParams sun;
  sun.sun_radiance = RGB(2000.0f);
  sun.resolution = 64;
  SkyParams plain;
  plain.resolution = 64;
  const Environment envs[] = {Environment::from_image(random_map(), kScale, kRotation), Environment::sky(sun),
                              Environment::sky(plain), Environment::uniform(RGB(0.5f, 1.0f, 2.0f))};
  Rng rng(29);
  for (const Environment& env : envs) {
    int above = 0, below = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec2 u(rng.uniform_as<float>(), rng.uniform_as<float>());
      const Vec3 n =
          glm::normalize(Vec3(rng.uniform_as<float>() - 0.5f, rng.uniform_as<float>() - 0.5f, rng.uniform_as<float>() - 0.5f));
      const EnvSample all = env.sample(u), kept = env.sample_above(u, n);
      if (all.pdf > 0.0f && glm::dot(all.w, n) > 0.0f) {
        ++above;
        ASSERT_EQ(kept.w, all.w);
        ASSERT_EQ(kept.radiance, all.radiance);
        ASSERT_EQ(kept.pdf, all.pdf);
      } else {
        ++below;
        ASSERT_EQ(kept.pdf, 0.0f);
      }
    }
    EXPECT_GT(above, 1000);
    EXPECT_GT(below, 1000);
  }
}

TEST(EnvironmentMap, PdfPositiveWhereverRadianceIs) {
  const Environment env = Environment::from_image(random_map(), kScale, kRotation);
  Rng rng(19);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 w = uniform_sphere(rng);
    const bool lit = max_component(env.eval(w)) > 0.0f;
    ASSERT_EQ(env.pdf(w) > 0.0f, lit) << w.x << " " << w.y << " " << w.z;
  }
}

TEST(EnvironmentMap, ImportanceSampledIntegralMatchesTexelSum) {
  const Environment env = Environment::from_image(random_map(), kScale, kRotation);
  const glm::dvec3 exact = texel_sum(env, 32, 16, kRotation);

  // (c) importance sampling: mean of radiance / pdf.
  Rng rng(23);
  const int n = 100000;
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int i = 0; i < n; ++i) {
    const EnvSample s = env.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    const glm::dvec3 x = s.pdf > 0.0f ? glm::dvec3(s.radiance) / double(s.pdf) : glm::dvec3(0.0);
    sum += x;
    sum2 += x * x;
  }
  const glm::dvec3 mean = sum / double(n), err = glm::sqrt((sum2 / double(n) - mean * mean) / double(n));
  // Brute force: uniform sphere, eval * 4 pi.
  glm::dvec3 usum(0.0), usum2(0.0);
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 x = glm::dvec3(env.eval(uniform_sphere(rng))) * (4.0 * kPi);
    usum += x;
    usum2 += x * x;
  }
  const glm::dvec3 umean = usum / double(n), uerr = glm::sqrt((usum2 / double(n) - umean * umean) / double(n));
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(err[c], 0.01 * exact[c]) << "importance sampling should be tight, channel " << c;
    EXPECT_NEAR(mean[c], exact[c], 5.0 * err[c]) << "channel " << c;
    EXPECT_NEAR(umean[c], exact[c], 5.0 * uerr[c]) << "channel " << c;
  }
}

TEST(EnvironmentMap, PdfIntegratesToOneOverSphere) {
  const Environment env = Environment::from_image(random_map(), kScale, kRotation);
  // (d) uniform-sphere Monte Carlo of pdf / (1 / 4 pi).
  Rng rng(29);
  const int n = 1000000;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = env.pdf(uniform_sphere(rng)) * 4.0 * kPi;
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n, err = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_LT(err, 0.005);
  EXPECT_NEAR(mean, 1.0, std::max(5.0 * err, 0.01));
  // And by quadrature in (u, v), where pdf(w) * 2 pi^2 sin(theta) is constant per texel (4 x 4
  // midpoints per texel, away from the poles where pdf is 0).
  double quad = 0.0;
  const int su = 32 * 4, sv = 16 * 4;
  for (int j = 0; j < sv; ++j)
    for (int i = 0; i < su; ++i) {
      const Vec3 w = direction_of_uv((i + 0.5) / su, (j + 0.5) / sv, kRotation);
      quad += env.pdf(w) * 2.0 * kPi * kPi * std::sqrt(double(w.x) * w.x + double(w.z) * w.z) / (su * sv);
    }
  EXPECT_NEAR(quad, 1.0, 1e-4);
}

TEST(EnvironmentMap, DocumentedLookupAndRotation) {
  Image img(32, 16);
  const RGB bright(7.0f, 8.0f, 9.0f);
  img.set(5, 3, bright);
  img.set(16, 8, bright * 2.0f);  // u = 0.5, v = 0.5: straight along -z
  const Environment env = Environment::from_image(img, 1.0f, 0.0f);
  EXPECT_EQ(env.eval(direction_of_uv(5.5 / 32, 3.5 / 16)), bright);
  EXPECT_EQ(env.eval(direction_of_uv(6.5 / 32, 3.5 / 16)), RGB(0.0f));
  EXPECT_EQ(env.eval(direction_of_uv(5.5 / 32, 4.5 / 16)), RGB(0.0f));
  EXPECT_EQ(env.eval(Vec3(0.0f, 0.0f, -1.0f)), bright * 2.0f);
  EXPECT_EQ(env.eval(Vec3(-1.0f, 0.0f, 0.0f)), RGB(0.0f));

  // Rotated by +90 degrees about +y (counter-clockwise seen from above): u -> u - 0.25, so what
  // looked along -z now looks along -x, and texel (5, 3) moves to u = 5.5 / 32 - 0.25 (mod 1).
  const Environment rot = Environment::from_image(img, 1.0f, 90.0f);
  EXPECT_EQ(rot.eval(Vec3(-1.0f, 0.0f, 0.0f)), bright * 2.0f);
  EXPECT_EQ(rot.eval(Vec3(0.0f, 0.0f, -1.0f)), RGB(0.0f));
  EXPECT_EQ(rot.eval(direction_of_uv(5.5 / 32 - 0.25 + 1.0, 3.5 / 16)), bright);
  EXPECT_EQ(rot.eval(direction_of_uv(5.5 / 32, 3.5 / 16)), RGB(0.0f));
  // The helper's own rotation argument says the same.
  EXPECT_EQ(rot.eval(direction_of_uv(5.5 / 32, 3.5 / 16, 90.0)), bright);

  // Only the two lit texels are ever sampled, and in proportion to luminance x solid angle.
  Rng rng(31);
  int first = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const EnvSample s = rot.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    ASSERT_GT(s.pdf, 0.0f);
    ASSERT_TRUE(s.radiance == bright || s.radiance == bright * 2.0f);
    first += s.radiance == bright;
  }
  auto lum = [](const RGB& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
  const double w1 = lum(bright) * std::sin(3.5 / 16 * kPi), w2 = lum(bright * 2.0f) * std::sin(8.5 / 16 * kPi);
  const double p1 = w1 / (w1 + w2);
  EXPECT_NEAR(double(first) / n, p1, 5.0 * std::sqrt(p1 * (1 - p1) / n));
}

// ---- Environment: sky -----------------------------------------------------------------------

TEST(EnvironmentSky, SunPowerSurvivesTabulation) {
  const double r_deg = 0.5;
  const RGB sun(2.0e4f, 1.8e4f, 1.5e4f);
  const glm::dvec3 analytic = glm::dvec3(sun) * (2.0 * kPi * (1.0 - std::cos(r_deg * kPi / 180.0)));
  struct Case {
    int resolution;
    Vec3 sun_to;
  };
  for (const Case& c :
       {Case{1024, glm::normalize(Vec3(0.3f, 0.8f, 0.5f))}, Case{1024, glm::normalize(Vec3(0.01f, 1.0f, 0.02f))},
        Case{1024, glm::normalize(Vec3(-0.7f, 0.05f, 0.2f))}, Case{2048, glm::normalize(Vec3(0.3f, 0.8f, 0.5f))}}) {
    SkyParams p;
    p.resolution = c.resolution;
    p.sun_to = c.sun_to;
    p.sun_radius_deg = float(r_deg);
    const Environment no_sun = Environment::sky(p);
    p.sun_radiance = sun;
    const Environment with_sun = Environment::sky(p);
    // The two tables differ only in the rows within a few degrees of the sun.
    const int w = c.resolution, h = c.resolution / 2;
    const double theta_s = std::acos(double(c.sun_to.y)) * 180.0 / kPi;
    const int y0 = std::max(0, int((theta_s - 3.0) / 180.0 * h)), y1 = std::min(h, int((theta_s + 3.0) / 180.0 * h) + 1);
    const glm::dvec3 power = texel_sum(with_sun, w, h, 0.0, y0, y1) - texel_sum(no_sun, w, h, 0.0, y0, y1);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(power[k] / analytic[k], 1.0, 0.005)
          << "resolution " << c.resolution << " sun " << c.sun_to.x << " " << c.sun_to.y << " " << c.sun_to.z << " channel " << k;
    // The disc itself is lit (at least one texel holds the full sun) and found by sampling.
    EXPECT_GT(with_sun.eval(c.sun_to).x, sun.x * 0.5f);
  }
}

TEST(EnvironmentSky, SunOnlyIsImportanceSampledExactly) {
  SkyParams p;
  p.zenith = p.horizon = p.ground = RGB(0.0f);
  p.sun_radiance = RGB(1.0e5f);
  p.sun_radius_deg = 0.5f;
  p.resolution = 1024;
  const Environment env = Environment::sky(p);
  ASSERT_FALSE(env.is_black());
  const double analytic = 1.0e5 * 2.0 * kPi * (1.0 - std::cos(0.5 * kPi / 180.0));
  const Vec3 s = glm::normalize(p.sun_to);
  Rng rng(37);
  double sum = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const EnvSample e = env.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    ASSERT_GT(e.pdf, 0.0f);
    ASSERT_GT(glm::dot(e.w, s), std::cos(1.5 * kPi / 180.0)) << "sample far from the sun";
    sum += e.radiance.x / e.pdf;
  }
  EXPECT_NEAR(sum / n / analytic, 1.0, 0.01);
}

TEST(EnvironmentSky, GradientGroundAndNoNaN) {
  SkyParams p;
  p.resolution = 256;
  p.sun_radiance = RGB(1.0e4f);
  const Environment env = Environment::sky(p);
  EXPECT_EQ(env.eval(Vec3(0.0f, -1.0f, 0.0f)), p.ground);
  EXPECT_EQ(env.eval(glm::normalize(Vec3(0.3f, -0.5f, 0.2f))), p.ground);
  // L = horizon + (zenith - horizon) sqrt(sin e), up to the texel's band average.
  const Vec3 w = glm::normalize(Vec3(0.0f, 0.5f, -0.8f));
  const RGB expected = p.horizon + (p.zenith - p.horizon) * std::sqrt(w.y);
  const RGB got = env.eval(w);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expected[k], 0.01f);
  for (const Vec3& d : {Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(-1, 0, 0)}) {
    EXPECT_TRUE(finite(env.eval(d)));
    EXPECT_TRUE(std::isfinite(env.pdf(d)));
    EXPECT_GE(env.pdf(d), 0.0f);
  }
  Rng rng(41);
  for (int i = 0; i < 2000; ++i) {
    const EnvSample s = env.sample(Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
    ASSERT_TRUE(finite(s.w) && finite(s.radiance) && std::isfinite(s.pdf));
  }
  // Degenerate inputs the reader would reject still give no NaN.
  SkyParams bad;
  bad.sun_to = Vec3(0.0f);
  bad.sun_radiance = RGB(1.0f);
  bad.resolution = 0;
  const Environment e2 = Environment::sky(bad);
  EXPECT_TRUE(finite(e2.eval(Vec3(0, 1, 0))));
  EXPECT_TRUE(std::isfinite(e2.pdf(Vec3(0, 0, -1))));
  const EnvSample s2 = e2.sample(Vec2(0.3f, 0.6f));
  EXPECT_TRUE(finite(s2.w) && finite(s2.radiance) && std::isfinite(s2.pdf));
}

// The row of a direction comes from w.y by comparisons with the rows' boundaries cos(k pi / h)
// (Environment::row_of), not acos: the same row as theta = acos(y) in double everywhere except
// within rounding of a boundary, the poles in the first and last row, |y| > 1 (rounding of a unit
// vector) in the pole's row, NaN in a row (no crash), for maps of one column (the sky without a
// sun) and of many, of 1 to 1024 rows.
TEST(EnvironmentMap, RowOfADirectionIsTheRowOfItsPolarAngle) {
  for (const int h : {1, 2, 3, 16, 127, 1024})
    for (const int w : {1, 4}) {
      Image img(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set(x, y, RGB(float(y + 1), 1.0f, float(x + 1)));
      const Environment env = Environment::from_image(img, 1.0f, 0.0f);
      const auto row_seen = [&](const Vec3& d) { return int(env.eval(d).x) - 1; };
      Rng rng(uint64_t(77 + h));
      for (int i = 0; i < 4000; ++i) {
        const float y = float(2.0 * rng.uniform() - 1.0);
        const double phi = 2.0 * kPi * rng.uniform();
        const float s = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const Vec3 d(s * float(std::sin(phi)), y, -s * float(std::cos(phi)));
        const double v = std::acos(std::clamp(double(y), -1.0, 1.0)) / kPi * h;
        if (std::fabs(v - std::round(v)) < 1e-4 * h) continue;  // within rounding of a boundary
        ASSERT_EQ(row_seen(d), std::min(h - 1, int(v))) << "h " << h << " w " << w << " y " << y;
      }
      EXPECT_EQ(row_seen(Vec3(0, 1, 0)), 0);
      EXPECT_EQ(row_seen(Vec3(0, -1, 0)), h - 1);
      EXPECT_EQ(row_seen(Vec3(0, 1.0000002f, 0)), 0);
      EXPECT_EQ(row_seen(Vec3(0, -1.0000002f, 0)), h - 1);
      const int nan_row = row_seen(Vec3(0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f));
      EXPECT_TRUE(nan_row >= 0 && nan_row < h);
    }
}

}  // namespace
}  // namespace aniso::render
