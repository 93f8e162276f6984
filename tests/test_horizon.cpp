// The horizon rule (include/aniso/core/math.h, HorizonCos; docs/conventions.md): for every model
// and every preset, in float and in double, no direction pair gives a non-finite or negative f or
// pdf, down to the smallest normal (and subnormal) cosines; at or below kHorizonCos everything is 0.
// Grazing pairs that once gave NaN (`1 0 1e-170 -1 0 1e-170`, mirror pairs with z <= 1e-120, the
// float pdf at z = 1e-15) and Lafortune lobes whose base^n overflowed are held here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#include "aniso/io/presets.h"
#include "test_util.h"

namespace aniso::test {
namespace {

// Cosines from the smallest subnormal up to 0.1, a few per decade, plus the threshold itself and
// its neighbours.
template <typename T> std::vector<T> tiny_cosines() {
  std::vector<T> z;
  for (T v = std::numeric_limits<T>::denorm_min(); v < T(0.1); v *= T(1000)) z.push_back(v);
  z.push_back(std::numeric_limits<T>::min());
  const T h = horizon_cos<T>();
  z.push_back(h);
  z.push_back(std::nextafter(h, T(1)));
  z.push_back(std::nextafter(h, T(0)));
  z.push_back(T(2) * h);
  return z;
}

template <typename T> Vec3T<T> at(T z, double phi) {
  const T r = std::sqrt(T(1) - z * z);
  return Vec3T<T>(T(r * std::cos(phi)), T(r * std::sin(phi)), z);
}

template <typename T> void check_material(const std::string& name, const MaterialT<T>& m) {
  const auto ok = [&](const Vec3T<T>& wi, const Vec3T<T>& wo) {
    const RGBT<T> f = m.f(wi, wo);
    const T pdf = m.pdf(wi, wo);
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(std::isfinite(f[c]) && f[c] >= T(0))
          << name << " f[" << c << "] = " << f[c] << " at wi.z " << wi.z << " wo.z " << wo.z;
    ASSERT_TRUE(std::isfinite(pdf) && pdf >= T(0)) << name << " pdf = " << pdf << " at wi.z " << wi.z << " wo.z " << wo.z;
    if (!above_horizon(wi) || !above_horizon(wo)) {
      ASSERT_EQ(f, RGBT<T>(T(0))) << name << ": below kHorizonCos f must be 0";
      ASSERT_EQ(pdf, T(0)) << name;
    }
  };
  const std::vector<T> zs = tiny_cosines<T>();
  const T u1 = std::nextafter(T(1), T(0));
  for (T zi : zs) {
    for (T zo : {zi, T(0.5), T(1)}) {
      ok(at(zi, 0.0), at(zo, M_PI));  // mirror azimuth (h = n when zi == zo)
      ok(at(zi, 0.0), at(zo, 0.0));   // wi = wo when zi == zo
      ok(at(zi, 0.3), at(zo, 2.0));
      ok(at(zo, 1.0), at(zi, 1.0 + M_PI));
    }
    const Vec3T<T> wo = at(zi, 0.7);
    for (T uc : {T(0), T(0.5), u1})
      for (T a : {T(0), T(0.5), u1}) {
        const BSDFSampleT<T> s = m.sample(wo, uc, Vec2T<T>(a, T(0.25)));
        if (!s.valid) continue;
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= T(0)) << name;
        ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > T(0)) << name;
        ASSERT_TRUE(above_horizon(s.wi)) << name;
      }
  }
}

TEST(Horizon, EveryModelFiniteDownToTheSmallestCosines) {
  for (const NamedMaterial& nm : all_model_materials()) {
    check_material(nm.name + " (float)", build<float>(nm.json));
    check_material(nm.name + " (double)", build<double>(nm.json));
  }
}

TEST(Horizon, EveryPresetFiniteDownToTheSmallestCosines) {
  for (const PresetInfo& p : presets()) {
    check_material(p.name + " (float)", build<float>(p.json));
    check_material(p.name + " (double)", build<double>(p.json));
  }
}

// Nearly opposite grazing pairs: wo within 1e-3 rad of -wi in azimuth, both cosines in [1e-11, 1e-2]
// (log-uniform; below the float horizon cosine they test the double path alone). There h.wi is
// rounding alone: Ashikhmin-Shirley's f was negative for about 2 % of such pairs in double (the
// worst Ngan preset -5e22) and its float sample weights reached -1.4e6. f, pdf and the sample
// weights from grazing views must all be finite and >= 0.
template <typename T> void check_near_opposite(const std::string& name, const MaterialT<T>& m) {
  Rng rng(2300);
  const auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, rng.uniform()); };
  for (int i = 0; i < 400; ++i) {
    const double phi = 2.0 * M_PI * rng.uniform();
    const Vec3T<T> wi = at(T(log_uniform(1e-11, 1e-2)), phi);
    const Vec3T<T> wo = at(T(log_uniform(1e-11, 1e-2)), phi + M_PI + (rng.uniform() - 0.5) * log_uniform(1e-12, 2e-3));
    const RGBT<T> f = m.f(wi, wo);
    const T pdf = m.pdf(wi, wo);
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(std::isfinite(f[c]) && f[c] >= T(0))
          << name << " f[" << c << "] = " << f[c] << " at wi (" << wi.x << ", " << wi.y << ", " << wi.z << ") wo (" << wo.x
          << ", " << wo.y << ", " << wo.z << ")";
    ASSERT_TRUE(std::isfinite(pdf) && pdf >= T(0)) << name << " pdf = " << pdf;
  }
  for (int i = 0; i < 400; ++i) {
    const Vec3T<T> wo = at(T(log_uniform(1e-5, 1e-1)), 2.0 * M_PI * rng.uniform());
    const BSDFSampleT<T> s = m.sample(wo, T(rng.uniform()), Vec2T<T>(T(rng.uniform()), T(rng.uniform())));
    if (!s.valid) continue;
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= T(0))
          << name << " sample weight[" << c << "] = " << s.weight[c] << " at wo.z " << wo.z;
    ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > T(0)) << name;
  }
}

TEST(Horizon, NearlyOppositeGrazingPairsAreNonNegativeForEveryModelAndPreset) {
  for (const NamedMaterial& nm : all_model_materials()) {
    check_near_opposite(nm.name + " (float)", build<float>(nm.json));
    check_near_opposite(nm.name + " (double)", build<double>(nm.json));
  }
  for (const PresetInfo& p : presets()) {
    check_near_opposite(p.name + " (float)", build<float>(p.json));
    check_near_opposite(p.name + " (double)", build<double>(p.json));
  }
}

// A nearly opposite grazing pair where h . wi < 0 by rounding alone: Ashikhmin-Shirley (default
// parameters), alone and as a metal's lobe, stays finite and >= 0 there (its 1 / (h . wi) term,
// unguarded, gives f = -1.34e17 in double).
TEST(Horizon, AshikhminShirleyOppositeGrazingPairIsNotNegative) {
  const Vec3d wi(0.9519527964440391, -0.30624479316777603, 2.6982672065979276e-10);
  const Vec3d wo(-0.9519527964455237, 0.3062447931631613, 2.7586451918744186e-11);
  const Vec3d h = glm::normalize(wi + wo);
  ASSERT_LT(glm::dot(h, wi), 0.0);  // the rounding this test is about
  const MaterialT<double> m = build<double>({{"model", "ashikhmin-shirley"}});
  const Vec3d f = m.f(wi, wo);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(f[c]) && f[c] >= 0.0) << f[c];
  const MaterialT<double> metal = build<double>(
      {{"model", "metal"}, {"eta", {0.2, 0.9, 1.1}}, {"k", {3.9, 2.4, 2.2}}, {"lobe", {{"model", "ashikhmin-shirley"}}}});
  const Vec3d fm = metal.f(wi, wo);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(fm[c]) && fm[c] >= 0.0) << fm[c];
}

// The grazing opposite pair `1 0 1e-170 -1 0 1e-170` is exactly 0 for every preset, in double
// (where 1e-170 is representable and products of such cosines underflow).
TEST(Horizon, ReproducerGrazingOppositePairIsZero) {
  const Vec3d wi(1, 0, 1e-170), wo(-1, 0, 1e-170);
  for (const PresetInfo& p : presets()) {
    const MaterialT<double> m = build<double>(p.json);
    EXPECT_EQ(m.f(wi, wo), Vec3d(0.0)) << p.name;
    EXPECT_EQ(m.pdf(wi, wo), 0.0) << p.name;
  }
}

TEST(Horizon, ThresholdIsExactlyTheDocumentedValue) {
  const MaterialT<double> d = build<double>({{"model", "lambert"}, {"kd", 1.0}});
  const Vec3d n(0, 0, 1);
  EXPECT_EQ(d.f(Vec3d(1, 0, 1e-12), n), Vec3d(0.0));
  EXPECT_GT(d.f(Vec3d(1, 0, 1.0000001e-12), n).x, 0.0);
  const MaterialT<float> f = build<float>({{"model", "lambert"}, {"kd", 1.0}});
  EXPECT_EQ(f.f(Vec3(1, 0, 1e-6f), Vec3(0, 0, 1)), Vec3(0.0f));
  EXPECT_GT(f.f(Vec3(1, 0, 1.001e-6f), Vec3(0, 0, 1)).x, 0.0f);
}

// Every Lafortune material the reader accepts is finite: base^n would overflow before the scale
// brings it down, so the lobe is evaluated in log space (lafortune.h, Lafortune_Lobe).
TEST(LafortuneOverflow, AcceptedMaterialsAreFinite) {
  using nlohmann::json;
  const json cases[] = {
      {{"model", "lafortune"}, {"lobes", json::array({{{"cz", 100}, {"n", 160}, {"scale", 1e-300}}})}},
      {{"model", "lafortune"}, {"lobes", json::array({{{"cz", 100}, {"n", 160}, {"scale", 0}}})}},
      {{"model", "lafortune"}, {"lobes", json::array({{{"cz", 100}, {"n", 37}, {"scale", 1e-300}}})}},
      {{"model", "lafortune"}, {"lobes", json::array({{{"cxy", -100}, {"cz", 100}, {"n", 14}, {"scale", 1e-10}}})}},
  };
  Rng rng(17);
  for (const json& j : cases) {
    const MaterialT<double> md = build<double>(j);
    const MaterialT<float> mf = build<float>(j);
    for (int i = 0; i < 2000; ++i) {
      const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
      const Vec3d fd = md.f(wi, wo);
      const Vec3 ff = mf.f(Vec3(wi), Vec3(wo));
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(fd[c]) && fd[c] >= 0.0) << j.dump();
        ASSERT_TRUE(std::isfinite(ff[c]) && ff[c] >= 0.0f) << j.dump();
      }
      ASSERT_TRUE(std::isfinite(md.pdf(wi, wo)) && std::isfinite(mf.pdf(Vec3(wi), Vec3(wo)))) << j.dump();
      const BSDFSampleT<double> s = md.sample(wo, rng.uniform(), Vec2T<double>(rng.uniform(), rng.uniform()));
      if (s.valid) {
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(s.weight[c])) << j.dump();
      }
    }
  }
  // The value itself: 1e-300 * (100 * 1 * 1)^37 = 1e-226 at wi = wo = n, in double.
  const MaterialT<double> m = build<double>(cases[2]);
  EXPECT_NEAR(m.f(Vec3d(0, 0, 1), Vec3d(0, 0, 1)).x / 1e-226, 1.0, 1e-12);
}

// pow_small_int (math.h): an integer n in [1, 16] gives x^n within about n ulps of pow where the
// power is a normal, finite number; anything else gives -1 (the callers' pow or exp-log path).
template <typename T> void check_small_int_powers() {
  Rng rng(23);
  const T eps = std::numeric_limits<T>::epsilon();
  for (int n = 1; n <= 16; ++n)
    for (int i = 0; i < 200; ++i) {
      const T x = T(2.0 * rng.uniform() + 1e-3);
      const T r = pow_small_int(x, T(n)), want = std::pow(x, T(n));
      if (want >= std::numeric_limits<T>::min()) {
        ASSERT_GE(r, T(0)) << x << "^" << n;
        ASSERT_NEAR(double(r) / double(want), 1.0, double(n) * 2.0 * double(eps)) << x << "^" << n;
      } else {
        ASSERT_EQ(r, T(-1)) << x << "^" << n;
      }
    }
  for (const T n : {T(0), T(0.5), T(2.5), T(17), T(-2), T(1e9)}) EXPECT_EQ(pow_small_int(T(0.7), n), T(-1)) << n;
  EXPECT_EQ(pow_small_int(std::numeric_limits<T>::max() / T(4), T(2)), T(-1));             // overflows
  EXPECT_EQ(pow_small_int(std::sqrt(std::numeric_limits<T>::min()) / T(4), T(2)), T(-1));  // below the normal range
}
TEST(SmallIntegerPowers, CloseToPowAndFallBackOutsideTheirRange) {
  check_small_int_powers<float>();
  check_small_int_powers<double>();
}

// A lobe whose channels share their shape (a metal's directional diffuse lobe) takes one power for
// the three: each channel the same bit for bit as Lafortune_Lobe of its own, and within rounding of
// the exp-log form, for an integer n (by multiplication) and another (exp-log).
TEST(SmallIntegerPowers, SharedLafortuneChannelsAsEachAlone) {
  Rng rng(29);
  for (const float n : {4.0f, 3.0f, 4.5f}) {
    LafortuneLobeT<float> lobe;
    lobe.cx = lobe.cy = RGB(-0.8f);
    lobe.cz = RGB(1.0f);
    lobe.n = RGB(n);
    lobe.scale = RGB(0.3f, 0.2f, 0.0f);  // a channel switched off as well
    ASSERT_TRUE(lobe.channels_share_shape());
    for (int i = 0; i < 500; ++i) {
      const Vec3 wi(random_upper<double>(rng)), wo(random_upper<double>(rng));
      const RGB f = lobe.eval(wi, wo);
      float w[3];
      lobe.channel_weights(wo, w);
      const Vec3 p = wi * wo;
      const float base = -0.8f * p.x + -0.8f * p.y + p.z;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(f[c], Lafortune_Lobe(base, n, lobe.scale[c])) << n;
        ASSERT_EQ(w[c], lobe.channel_weight(wo, c)) << n;
        const double exact =
            base > 0.0f && lobe.scale[c] > 0.0f ? double(lobe.scale[c]) * std::pow(double(base), double(n)) : 0.0;
        ASSERT_NEAR(f[c], exact, 1e-5 * exact + 1e-30) << n;
      }
    }
  }
}

// eta = 1, k = 0 (index matched to air): F is exactly 0, never a negative rounding residue.
TEST(FresnelConductor, IndexMatchedToAirIsZeroNotNegative) {
  for (double c = 0.0; c <= 1.0; c += 1.0 / 64) {
    EXPECT_GE(F_Conductor(c, 1.0, 0.0), 0.0) << c;
    EXPECT_GE(F_Conductor(float(c), 1.0f, 0.0f), 0.0f) << c;
  }
}

// f and pdf together (model_f_pdf, lobe_mixture.h: Ward's Gaussian, GGX's D and Lambda(wo) and a
// metal's specular lobe computed once for both) equal f() and pdf() alone bit for bit, for every
// model and preset, every Ward form and normalisation, in float and double, at random pairs on
// and below the horizon; a metal's f_pdf with its sampling weights as pdf(weights, .).
template <typename T> void check_f_pdf_together(const std::string& name, const MaterialT<T>& m) {
  Rng rng(4100);
  const auto bits_equal = [](T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; };
  for (int i = 0; i < 300; ++i) {
    Vec3T<T> wi = random_upper<T>(rng), wo = random_upper<T>(rng);
    if (i % 10 == 0) wi.z = -wi.z;                                  // below the horizon
    if (i % 10 == 1) wi = at(T(1e-6), 2.0 * M_PI * rng.uniform());  // grazing
    m.visit([&](const auto& model) {
      T pdf = T(-1);
      const RGBT<T> f = model_f_pdf(model, wi, wo, &pdf);
      const RGBT<T> f_alone = model.f(wi, wo);
      const T pdf_alone = model.pdf(wi, wo);
      for (int c = 0; c < 3; ++c)
        ASSERT_TRUE(bits_equal(f[c], f_alone[c])) << name << " f[" << c << "] " << f[c] << " vs " << f_alone[c];
      ASSERT_TRUE(bits_equal(pdf, pdf_alone)) << name << " pdf " << pdf << " vs " << pdf_alone;
      using M = std::decay_t<decltype(model)>;
      if constexpr (requires { model.f_pdf(model.sampling_weights(wo), wi, wo, &pdf); }) {
        const auto ws = model.sampling_weights(wo);
        const RGBT<T> fw = model.f_pdf(ws, wi, wo, &pdf);
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(bits_equal(fw[c], f_alone[c])) << name;
        ASSERT_TRUE(bits_equal(pdf, model.pdf(ws, wi, wo))) << name;
        static_assert(std::is_same_v<M, MetalT<T>>);
      }
    });
  }
}

TEST(SharedTerms, FAndPdfTogetherAreEachAloneForEveryModelAndPreset) {
  std::vector<NamedMaterial> materials = all_model_materials();
  for (const char* form : {"vector", "angle", "approx"})
    for (const char* normalization : {"ward", "duer", "balanced"})
      materials.push_back(
          {fmt::format("ward {} {}", form, normalization),
           {{"model", "ward"}, {"alpha_x", 0.08}, {"alpha_y", 0.3}, {"form", form}, {"normalization", normalization}}});
  for (const char* lobe : {"ward", "ashikhmin-shirley", "ggx"})
    materials.push_back({fmt::format("metal {} lobe", lobe),
                         {{"model", "metal"},
                          {"metal", "gold"},
                          {"lobe", {{"model", lobe}}},
                          {"directional_diffuse", {{"albedo", 0.3}, {"n", 3}}}}});
  for (const PresetInfo& p : presets()) materials.push_back({p.name, p.json});
  for (const NamedMaterial& nm : materials) {
    check_f_pdf_together(nm.name + " (float)", build<float>(nm.json));
    check_f_pdf_together(nm.name + " (double)", build<double>(nm.json));
  }
}

}  // namespace
}  // namespace aniso::test
