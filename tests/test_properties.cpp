// Properties every model must have: Helmholtz reciprocity, invariance under rotation about n for
// isotropic parameters, finite non-negative values everywhere (grazing angles, h = n, below the
// horizon), float agreeing with double, and the tangent frame's algebra.
#include <gtest/gtest.h>

#include <cmath>

#include "aniso/core/frame.h"
#include "test_util.h"

namespace aniso::test {
namespace {

class PropertyTest : public testing::TestWithParam<NamedMaterial> {};

// Helmholtz reciprocity: f(wi, wo) = f(wo, wi), in double to 1e-12 relative, for random pairs.
TEST_P(PropertyTest, Reciprocity) {
  const MaterialT<double> m = build<double>(GetParam().json);
  Rng rng(3);
  for (int i = 0; i < 20000; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const Vec3d a = m.f(wi, wo), b = m.f(wo, wi);
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(a[c], b[c], 1e-12 * std::max(1.0, std::abs(a[c]))) << GetParam().name << " channel " << c;
  }
}

// No NaN or Inf, never negative: a million random pairs in float, half of them within a degree of
// the horizon, plus the special configurations h = n (wi = mirror of wo), wi = wo, normal
// incidence, exactly grazing, and below the horizon (f = 0, pdf = 0, no sample).
TEST_P(PropertyTest, FiniteAndNonNegativeEverywhere) {
  const MaterialT<float> m = build<float>(GetParam().json);
  Rng rng(5);
  const auto check = [&](const Vec3& wi, const Vec3& wo) {
    const Vec3 f = m.f(wi, wo);
    const float pdf = m.pdf(wi, wo);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(f[c]) && f[c] >= 0.0f) << GetParam().name << " f = " << f[c] << " at wi " << wi.x << " " << wi.y
                                                       << " " << wi.z << " wo " << wo.x << " " << wo.y << " " << wo.z;
    }
    ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f) << GetParam().name << " pdf = " << pdf;
  };
  const auto grazing = [&]() {
    // z in (0, sin 1 deg]: within a degree of the horizon.
    const float z = float(0.0174524 * (1.0 - rng.uniform()));
    const float phi = float(2.0 * M_PI * rng.uniform());
    const float r = std::sqrt(1.0f - z * z);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  for (int i = 0; i < 1'000'000; ++i) {
    const Vec3 wo = (i % 2) ? grazing() : random_upper<float>(rng);
    const Vec3 wi = (i % 4 < 2) ? grazing() : random_upper<float>(rng);
    check(wi, wo);
    if (i % 8 == 0) {
      check(reflect_about_normal(wo), wo);  // h = n exactly
      check(wo, wo);
      const BSDFSampleT<float> s = m.sample(wo, rng.uniform_as<float>(), Vec2(rng.uniform_as<float>(), rng.uniform_as<float>()));
      if (s.valid) {
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0.0f) << GetParam().name;
        ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.0f);
      }
    }
  }
  const Vec3 n(0, 0, 1), horizon(1, 0, 0), below(0.3f, 0.1f, -0.5f);
  check(n, n);
  for (const Vec3& w : {horizon, below, Vec3(0, 0, -1)}) {
    EXPECT_EQ(m.f(w, n), Vec3(0.0f)) << GetParam().name;
    EXPECT_EQ(m.f(n, w), Vec3(0.0f)) << GetParam().name;
    EXPECT_EQ(m.pdf(w, n), 0.0f);
    EXPECT_EQ(m.pdf(n, w), 0.0f);
    EXPECT_FALSE(m.sample(w, 0.5f, Vec2(0.3f, 0.7f)).valid) << GetParam().name;
  }
  // wi + wo = 0 cannot have both above the horizon; the nearest legal case is grazing-opposite.
  check(Vec3(0.9999f, 0.0f, 0.0141f), Vec3(-0.9999f, 0.0f, 0.0141f));
  // Extreme uniforms: 0 and the largest float below 1.
  const float u1 = 0x1.fffffep-1f;
  for (float uc : {0.0f, 0.5f, u1})
    for (float a : {0.0f, u1})
      for (float b : {0.0f, u1}) {
        const BSDFSampleT<float> s = m.sample(Vec3(0.3f, 0.2f, 0.932738f), uc, Vec2(a, b));
        if (s.valid) {
          for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0.0f) << GetParam().name;
        }
      }
}

// float evaluation agrees with double (the renderer runs float, references run double).
TEST_P(PropertyTest, FloatAgreesWithDouble) {
  const MaterialT<float> mf = build<float>(GetParam().json);
  const MaterialT<double> md = build<double>(GetParam().json);
  Rng rng(9);
  for (int i = 0; i < 20000; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    if (wi.z < 0.05 || wo.z < 0.05) continue;  // float's cosines lose relative precision at grazing
    const Vec3d fd = md.f(wi, wo);
    const Vec3 ff = mf.f(Vec3(wi), Vec3(wo));
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(ff[c], fd[c], 2e-3 * fd[c] + 1e-6) << GetParam().name;  // exponents up to ~500 amplify rounding
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, PropertyTest, testing::ValuesIn(all_model_materials()), material_name);

// Isotropic parameters give values invariant under rotation of both directions about n.
TEST(Isotropy, RotationAboutNormalLeavesIsotropicModelsUnchanged) {
  using nlohmann::json;
  const std::vector<json> isotropic = {
      {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.5}, {"alpha_x", 0.2}, {"alpha_y", 0.2}, {"form", "vector"}},
      {{"model", "ward"}, {"ks", 0.5}, {"alpha_x", 0.2}, {"alpha_y", 0.2}, {"form", "angle"}, {"normalization", "duer"}},
      {{"model", "ward"}, {"ks", 0.5}, {"alpha_x", 0.2}, {"alpha_y", 0.2}, {"form", "approx"}, {"normalization", "balanced"}},
      {{"model", "ashikhmin-shirley"}, {"rd", 0.3}, {"rs", 0.1}, {"n_u", 50.0}, {"n_v", 50.0}},
      {{"model", "lafortune"}, {"rho_d", 0.1}, {"lobes", json::array({{{"cxy", -1.0}, {"cz", 0.9}, {"n", 12.0}}})}},
      {{"model", "ggx"}, {"kd", 0.1}, {"f0", 0.5}, {"alpha_x", 0.25}, {"alpha_y", 0.25}},
      {{"model", "phong"}, {"kd", 0.1}, {"ks", 0.5}, {"exponent", 40.0}},
      {{"model", "metal"},
       {"metal", "silver"},
       {"lobe", {{"model", "ward"}, {"alpha_x", 0.1}, {"alpha_y", 0.1}}},
       {"directional_diffuse", {{"albedo", 0.3}}}},
  };
  Rng rng(17);
  for (const json& j : isotropic) {
    const MaterialT<double> m = build<double>(j);
    for (int i = 0; i < 2000; ++i) {
      const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
      const double psi = 2.0 * M_PI * rng.uniform();
      const double c = std::cos(psi), s = std::sin(psi);
      const auto rot = [&](const Vec3d& w) { return Vec3d(c * w.x - s * w.y, s * w.x + c * w.y, w.z); };
      const Vec3d a = m.f(wi, wo), b = m.f(rot(wi), rot(wo));
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(a[ch], b[ch], 1e-10 * std::max(1.0, a[ch])) << j.dump();
      ASSERT_NEAR(m.pdf(wi, wo), m.pdf(rot(wi), rot(wo)), 1e-10 * std::max(1.0, m.pdf(wi, wo))) << j.dump();
    }
  }
}

// Anisotropic parameters do change under rotation (so the isotropy test above can fail).
TEST(Isotropy, AnisotropicModelsDependOnAzimuth) {
  for (const auto& nm : all_model_materials()) {
    if (nm.name.find("aniso") == std::string::npos) continue;
    const MaterialT<double> m = build<double>(nm.json);
    // The same geometry rotated by 90 degrees about n: off-specular along t versus along b.
    const Vec3d a = m.f(spherical(55, 170), spherical(40, 0));
    const Vec3d b = m.f(spherical(55, 260), spherical(40, 90));
    EXPECT_GT(std::abs(a.x - b.x), 1e-3 * std::max(a.x, b.x)) << nm.name;
  }
}

// --- Tangent frame --------------------------------------------------------------------------

TEST(Frame, GramSchmidtGivesRightHandedOrthonormalFrame) {
  Rng rng(21);
  for (int i = 0; i < 10000; ++i) {
    Vec3d n = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
    const Vec3d t_approx(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    const FrameT<double> f = FrameT<double>::from_normal_tangent(n, t_approx);
    EXPECT_NEAR(glm::length(f.t), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(f.b), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.t, f.n), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.b, f.n), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.t, f.b), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::cross(f.t, f.b) - f.n), 0.0, 1e-12);  // b = n x t: right-handed
    // t keeps the direction of the tangent's projection.
    EXPECT_GT(glm::dot(f.t, t_approx - glm::dot(t_approx, n) * n), 0.0);
    const Vec3d w = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
    EXPECT_NEAR(glm::length(f.to_world(f.to_local(w)) - w), 0.0, 1e-12);
  }
  // A tangent parallel to n falls back to an arbitrary orthonormal frame, never NaN.
  const FrameT<double> f = FrameT<double>::from_normal_tangent(Vec3d(0, 0, 1), Vec3d(0, 0, 2));
  EXPECT_NEAR(glm::length(f.t), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.t, f.n), 0.0, 1e-12);
}

TEST(Frame, RotationByPsiRotatesTheHighlight) {
  // Rotating the frame by psi equals rotating the anisotropic material by -psi about n.
  const FrameT<double> base;
  const FrameT<double> rotated = base.rotated(M_PI / 2);
  EXPECT_NEAR(glm::length(rotated.t - Vec3d(0, 1, 0)), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(rotated.b - Vec3d(-1, 0, 0)), 0.0, 1e-12);
  const MaterialT<double> m = build<double>({{"model", "ward"}, {"ks", 0.5}, {"alpha_x", 0.05}, {"alpha_y", 0.4}});
  Rng rng(23);
  const FrameT<double> r30 = base.rotated(M_PI / 6);
  for (int i = 0; i < 1000; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    // World directions seen in the rotated frame are the directions rotated by -psi.
    const double c = std::cos(-M_PI / 6), s = std::sin(-M_PI / 6);
    const auto rot = [&](const Vec3d& w) { return Vec3d(c * w.x - s * w.y, s * w.x + c * w.y, w.z); };
    const Vec3d a = m.f(r30.to_local(wi), r30.to_local(wo)), b = m.f(rot(wi), rot(wo));
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(a[ch], b[ch], 1e-9 * std::max(1.0, a[ch]));
  }
}

}  // namespace
}  // namespace aniso::test
