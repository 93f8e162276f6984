// Sampling tests of every model: chi-square goodness of fit of sample() against pdf(), the
// consistency of the sample record (weight == f cos / pdf, pdf == pdf(wi, wo)), and the pdf's
// integral (<= 1, and equal to the fraction of accepted samples).
#include <gtest/gtest.h>

#include <cstring>
#include <type_traits>

#include "chi2.h"
#include "test_util.h"

namespace aniso::test {
namespace {

struct SamplingCase {
  std::string material;
  nlohmann::json json;
  double theta_deg, phi_deg;
};

std::vector<SamplingCase> sampling_cases() {
  std::vector<SamplingCase> cases;
  // Normal, moderate, oblique and near-grazing views; azimuths away from the axes so that
  // anisotropy matters.
  const double views[][2] = {{0.0, 0.0}, {35.0, 30.0}, {65.0, 120.0}, {85.0, 200.0}};
  for (const auto& m : all_model_materials())
    for (const auto& v : views) cases.push_back({m.name, m.json, v[0], v[1]});
  return cases;
}

// Readable test names and failure messages instead of gtest's byte dump.
void PrintTo(const SamplingCase& c, std::ostream* os) {
  *os << c.material << " wo(theta " << c.theta_deg << ", phi " << c.phi_deg << ")";
}

std::string case_name(const testing::TestParamInfo<SamplingCase>& info) {
  return info.param.material + "_theta" + std::to_string(int(info.param.theta_deg));
}

class SamplingTest : public testing::TestWithParam<SamplingCase> {};

const int64_t kChi2Samples = scaled(2'000'000);  // ANISO_TEST_SCALE (test_util.h)
// Significance 1% for the whole family, Sidak-corrected for the number of tests in it.
double per_test_significance() {
  const double n = double(sampling_cases().size());
  return 1.0 - std::pow(1.0 - 0.01, 1.0 / n);
}

TEST_P(SamplingTest, ChiSquareMatchesPdf) {
  const SamplingCase& c = GetParam();
  const MaterialT<float> m = build<float>(c.json);
  const MaterialT<double> md = build<double>(c.json);
  const Vec3 wo = Vec3(spherical(c.theta_deg, c.phi_deg));
  const Vec3d wod = spherical(c.theta_deg, c.phi_deg);
  const Chi2Result r = chi2_test([&](float uc, Vec2 u) { return m.sample(wo, uc, u); },
                                 [&](const Vec3d& wi) { return md.pdf(wi, wod); }, kChi2Samples, 7);
  ASSERT_TRUE(r.message.empty()) << r.message;
  EXPECT_GT(r.p_value, per_test_significance())
      << c.material << " wo theta " << c.theta_deg << ": chi2 " << r.chi2 << " dof " << r.dof << " pdf integral "
      << r.pdf_integral << " accepted " << r.accepted_fraction;
  // The pdf integrates to at most 1 (numerical quadrature: 1e-3 slack), and to the acceptance rate.
  EXPECT_LE(r.pdf_integral, 1.0 + 1e-3);
  EXPECT_NEAR(r.pdf_integral, r.accepted_fraction, 5e-3);
}

TEST_P(SamplingTest, WeightIsFCosOverPdf) {
  const SamplingCase& c = GetParam();
  const MaterialT<double> m = build<double>(c.json);
  const Vec3d wo = spherical(c.theta_deg, c.phi_deg);
  Rng rng(11);
  int valid = 0;
  for (int i = 0; i < 20000; ++i) {
    const BSDFSampleT<double> s = m.sample(wo, rng.uniform(), Vec2T<double>(rng.uniform(), rng.uniform()));
    if (!s.valid) {
      EXPECT_EQ(s.pdf, 0.0);
      EXPECT_EQ(s.weight, Vec3d(0.0));
      continue;
    }
    ++valid;
    ASSERT_NEAR(glm::length(s.wi), 1.0, 1e-9);
    ASSERT_GT(s.wi.z, 0.0);
    const double pdf = m.pdf(s.wi, wo);
    ASSERT_NEAR(s.pdf, pdf, 1e-9 * pdf) << c.material;
    const Vec3d expected = m.f(s.wi, wo) * s.wi.z / pdf;
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(s.weight[ch], expected[ch], 1e-9 * (1.0 + expected[ch])) << c.material;
  }
  EXPECT_GT(valid, 1000) << c.material << ": the sampler rejects almost everything";
}

// The models whose lobe choice has wo-dependent weights (sampling_weights(wo): MetalT, LafortuneT)
// give the same pdf and sample, bit for bit, from weights computed once as from their own per-call
// ones: the renderer computes them once per vertex (src/render/integrator.cpp, MaterialAtWo).
template <typename M>
concept HasSamplingWeights = requires(const M& m, const Vec3& w) {
  m.sampling_weights(w);
};
static_assert(HasSamplingWeights<MetalT<float>> && HasSamplingWeights<LafortuneT<float>>);

// One ctest entry for all the cases (each takes microseconds).
TEST(SamplingWeights, ComputedOnceGiveTheSamePdfAndSample) {
  for (const SamplingCase& c : sampling_cases()) {
    const MaterialT<float> m = build<float>(c.json);
    const Vec3 o = m.rotation.to_model(Vec3(spherical(c.theta_deg, c.phi_deg)));
    m.visit([&](const auto& model) {
      using M = std::decay_t<decltype(model)>;
      if constexpr (HasSamplingWeights<M>) {
        const typename M::SamplingWeights w = model.sampling_weights(o);
        Rng rng(5);
        for (int i = 0; i < 500; ++i) {
          const float uc = rng.uniform_as<float>();
          const Vec2 u(rng.uniform_as<float>(), rng.uniform_as<float>());
          const BSDFSampleT<float> a = model.sample(o, uc, u), b = model.sample(w, o, uc, u);
          ASSERT_EQ(a.valid, b.valid) << c.material;
          ASSERT_EQ(std::memcmp(&a.wi, &b.wi, sizeof(a.wi)), 0) << c.material;
          ASSERT_EQ(std::memcmp(&a.weight, &b.weight, sizeof(a.weight)), 0) << c.material;
          ASSERT_EQ(std::memcmp(&a.pdf, &b.pdf, sizeof(a.pdf)), 0) << c.material;
          const Vec3 wi = Vec3(spherical(90.0 * rng.uniform(), 360.0 * rng.uniform()));
          const float p = model.pdf(wi, o), q = model.pdf(w, wi, o);
          ASSERT_EQ(std::memcmp(&p, &q, sizeof(p)), 0) << c.material << ": " << p << " vs " << q;
        }
      }
    });
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, SamplingTest, testing::ValuesIn(sampling_cases()), case_name);

}  // namespace
}  // namespace aniso::test
