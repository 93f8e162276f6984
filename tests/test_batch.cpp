// tests/test_batch.cpp: the batch path (include/aniso/batch/batch.h) against the scalar kernels,
// which are its reference: f and pdf for every model, form and normalisation and several presets,
// on random, grazing, h = n and below-horizon direction pairs, float and double; determinism over
// thread counts; the batch sampler against the scalar sampler, and a chi-square test of it.
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <unistd.h>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/batch/batch.h"
#include "aniso/io/presets.h"
#include "chi2.h"
#include "test_util.h"

namespace aniso::test {
namespace {

// The test materials of test_util.h plus presets that exercise the fitted tables and the metals.
std::vector<NamedMaterial> batch_materials() {
  std::vector<NamedMaterial> v = all_model_materials();
  for (const char* name : {"matte-steel", "gold", "brushed-gold", "copper"}) {
    const auto j = find_preset(name);
    if (j) v.push_back({std::string("preset_") + name, *j});
  }
  // A pbrt-v1 Lafortune fit and an Ngan fit, if the tables have them (first of each kind).
  for (const PresetInfo& p : presets()) {
    if (p.name.rfind("pbrt", 0) == 0 || p.name.rfind("ngan/ashikhmin", 0) == 0 || p.name.rfind("ngan/ward", 0) == 0) {
      std::string key = p.name;
      std::replace(key.begin(), key.end(), '/', '_');
      std::replace(key.begin(), key.end(), '-', '_');
      v.push_back({"preset_" + key, p.json});
      if (v.size() > all_model_materials().size() + 12) break;
    }
  }
  for (auto& m : v) std::replace(m.name.begin(), m.name.end(), '-', '_');
  return v;
}

// The direction pairs: random pairs on the upper hemisphere, grazing ones (either cosine in
// [1e-4, 1e-2]), h = n (wi the mirror of wo), and pairs with a direction on or below the horizon.
// An odd count, so that the last SIMD vector is partial.
template <typename T> void make_pairs(batch::DirectionArray<T>& wi, batch::DirectionArray<T>& wo) {
  Rng rng(424242);
  std::vector<Vec3T<T>> vi, vo;
  const auto grazing = [&](double cos_lo, double cos_hi) {
    const double z = cos_lo + (cos_hi - cos_lo) * rng.uniform();
    const double r = std::sqrt(1.0 - z * z), phi = 2.0 * M_PI * rng.uniform();
    return Vec3T<T>(T(r * std::cos(phi)), T(r * std::sin(phi)), T(z));
  };
  for (int i = 0; i < 1500; ++i) vi.push_back(random_upper<T>(rng)), vo.push_back(random_upper<T>(rng));
  for (int i = 0; i < 300; ++i) vi.push_back(grazing(1e-4, 1e-2)), vo.push_back(random_upper<T>(rng));
  for (int i = 0; i < 300; ++i) vi.push_back(random_upper<T>(rng)), vo.push_back(grazing(1e-4, 1e-2));
  for (int i = 0; i < 100; ++i) vi.push_back(grazing(1e-4, 1e-2)), vo.push_back(grazing(1e-4, 1e-2));
  for (int i = 0; i < 300; ++i) {
    const Vec3T<T> o = random_upper<T>(rng);
    vi.push_back(reflect_about_normal(o)), vo.push_back(o);  // h = wi + wo along n
  }
  // Around the horizon cosine (math.h: 1e-6 in float, 1e-12 in double), on both sides.
  const double horizon = HorizonCos<T>::value;
  for (int i = 0; i < 60; ++i) vi.push_back(grazing(0.1 * horizon, 10.0 * horizon)), vo.push_back(random_upper<T>(rng));
  for (int i = 0; i < 60; ++i) vi.push_back(random_upper<T>(rng)), vo.push_back(grazing(0.1 * horizon, 10.0 * horizon));
  vi.push_back(Vec3T<T>(0, 0, 1)), vo.push_back(Vec3T<T>(0, 0, 1));  // both along n
  for (int i = 0; i < 100; ++i) {
    Vec3T<T> i_dir = random_upper<T>(rng), o_dir = random_upper<T>(rng);
    if (i % 2)
      i_dir.z = -i_dir.z;
    else
      o_dir.z = -o_dir.z;
    vi.push_back(i_dir), vo.push_back(o_dir);
  }
  vi.push_back(Vec3T<T>(1, 0, 0)), vo.push_back(Vec3T<T>(0, 0, 1));  // on the horizon
  wi.resize(vi.size());
  wo.resize(vo.size());
  for (size_t i = 0; i < vi.size(); ++i) wi.set(i, vi[i]), wo.set(i, vo[i]);
}

// The batch path may differ from the scalar path by 1e-5 relative, plus twice the scalar float
// path's own rounding error (measured at the same inputs against the scalar double path): where
// float itself cannot hold 1e-5 (the angle form's tan near theta_h = 90 degrees, a Gaussian exponent
// of -50 whose 1-ulp error becomes 50 ulp of the result) two correct float evaluations may differ by
// that much. Values below 1e-12 of the channel's largest value over the pairs are compared
// absolutely (a renderer or a fit cannot see them). In double the float slack is 0.
template <typename T> bool close_to_scalar(T batch, T scalar, double scalar_double, T peak, double& worst) {
  const double b = batch, s = scalar;
  if (b == s) return true;
  const double own_error = sizeof(T) == sizeof(float) ? std::abs(s - scalar_double) : 0.0;
  const double scale = std::max(std::abs(s), 1e-12 * double(peak));
  const double excess = (std::abs(b - s) - 2.0 * own_error) / scale;
  worst = std::max(worst, excess);
  return excess <= 1e-5;
}

class BatchTest : public testing::TestWithParam<NamedMaterial> {};

template <typename T> void check_against_scalar(const NamedMaterial& nm) {
  const MaterialT<T> m = build<T>(nm.json);
  const MaterialD md = build<double>(nm.json);
  batch::DirectionArray<T> wi, wo;
  make_pairs(wi, wo);
  const size_t n = wi.size();
  batch::ColorArray<T> f(n);
  std::vector<T> p(n);
  batch::evaluate(m, wi.view(), wo.view(), n, f.view());
  batch::pdf(m, wi.view(), wo.view(), n, p.data());
  std::vector<RGBT<T>> fs(n);
  std::vector<T> ps(n);
  std::vector<glm::dvec3> fd(n);
  std::vector<double> pd(n);
  T peak_f[3] = {0, 0, 0}, peak_p = 0;
  for (size_t i = 0; i < n; ++i) {
    fs[i] = m.f(wi.get(i), wo.get(i));
    ps[i] = m.pdf(wi.get(i), wo.get(i));
    fd[i] = md.f(Vec3d(wi.get(i)), Vec3d(wo.get(i)));
    pd[i] = md.pdf(Vec3d(wi.get(i)), Vec3d(wo.get(i)));
    for (int c = 0; c < 3; ++c) peak_f[c] = std::max(peak_f[c], fs[i][c]);
    peak_p = std::max(peak_p, ps[i]);
  }
  double worst_f = 0, worst_p = 0;
  const auto show = [&](size_t i) {
    return "pair " + std::to_string(i) + " wi (" + std::to_string(wi.x[i]) + ", " + std::to_string(wi.y[i]) + ", " +
           std::to_string(wi.z[i]) + ") wo (" + std::to_string(wo.x[i]) + ", " + std::to_string(wo.y[i]) + ", " +
           std::to_string(wo.z[i]) + ")";
  };
  const char* type = sizeof(T) == 4 ? " float" : " double";
  int reported = 0;
  for (size_t i = 0; i < n; ++i) {
    const RGBT<T> b = f.get(i);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(b[c]) && b[c] >= T(0)) << nm.name << " pair " << i << " f[" << c << "] = " << b[c];
      if (!close_to_scalar(b[c], fs[i][c], fd[i][c], peak_f[c], worst_f) && reported++ < 3)
        ADD_FAILURE() << nm.name << type << " f[" << c << "]: " << show(i) << " batch " << b[c] << " scalar " << fs[i][c]
                      << " double " << fd[i][c];
    }
    ASSERT_TRUE(std::isfinite(p[i]) && p[i] >= T(0)) << nm.name << " pair " << i << " pdf = " << p[i];
    if (!close_to_scalar(p[i], ps[i], pd[i], peak_p, worst_p) && reported++ < 3)
      ADD_FAILURE() << nm.name << type << " pdf: " << show(i) << " batch " << p[i] << " scalar " << ps[i] << " double " << pd[i];
  }
  testing::Test::RecordProperty("worst_f_excess", fmt::format("{:.3g}", worst_f));
  testing::Test::RecordProperty("worst_pdf_excess", fmt::format("{:.3g}", worst_p));
}

TEST_P(BatchTest, EvaluateAndPdfMatchScalarFloat) { check_against_scalar<float>(GetParam()); }
TEST_P(BatchTest, EvaluateAndPdfMatchScalarDouble) { check_against_scalar<double>(GetParam()); }

// evaluate_interleaved / pdf_interleaved (rows (x, y, z) in, RGB rows out) are evaluate / pdf on the
// same elements bit for bit: the same kernels, loaded and stored by LoadInterleaved3 /
// StoreInterleaved3; with a broadcast direction (stride 0) as with that direction repeated; with
// NonFinite::NaN, NaN in every output of a row with a NaN or infinite input value and the other
// rows unchanged (and so do evaluate / pdf with NonFinite::NaN). SIMD and scalar kernels, one and
// all threads; the pair count is odd (a partial last vector), and the interleaved arrays start one
// element into their buffer.
template <typename T> void check_interleaved(const NamedMaterial& nm) {
  const MaterialT<T> m = build<T>(nm.json);
  batch::DirectionArray<T> wi, wo;
  make_pairs(wi, wo);
  const size_t n = wi.size();
  // Rows 7, 100, 101, ... get a NaN or an infinity in one coordinate of wi or wo.
  const T bad_values[3] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity(),
                           -std::numeric_limits<T>::infinity()};
  std::vector<bool> bad(n, false);
  std::vector<T> wi_rows(3 * n + 1), wo_rows(3 * n + 1);
  T* pi = wi_rows.data() + 1;
  T* po = wo_rows.data() + 1;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) pi[3 * i + c] = wi.get(i)[c], po[3 * i + c] = wo.get(i)[c];
  const Vec3T<T> fixed = wi.get(3);
  for (batch::Kernels kernels : {batch::Kernels::Simd, batch::Kernels::Scalar}) {
    const char* kname = kernels == batch::Kernels::Simd ? "simd" : "scalar";
    batch::ColorArray<T> f(n), f_fixed(n);
    std::vector<T> p(n), p_fixed(n);
    batch::DirectionArray<T> wi_fixed(n);
    for (size_t i = 0; i < n; ++i) wi_fixed.set(i, fixed);
    batch::evaluate(m, wi.view(), wo.view(), n, f.view(), batch::Threads::One, kernels);
    batch::pdf(m, wi.view(), wo.view(), n, p.data(), batch::Threads::One, kernels);
    batch::evaluate(m, wi_fixed.view(), wo.view(), n, f_fixed.view(), batch::Threads::One, kernels);
    batch::pdf(m, wi_fixed.view(), wo.view(), n, p_fixed.data(), batch::Threads::One, kernels);
    for (batch::Threads threads : {batch::Threads::One, batch::Threads::All}) {
      std::vector<T> g(3 * n), q(n), g_fixed(3 * n), q_fixed(n);
      batch::evaluate_interleaved(m, {pi, 3}, {po, 3}, n, g.data(), threads, kernels);
      batch::pdf_interleaved(m, {pi, 3}, {po, 3}, n, q.data(), threads, kernels);
      const T fixed_row[3] = {fixed.x, fixed.y, fixed.z};
      batch::evaluate_interleaved(m, {fixed_row, 0}, {po, 3}, n, g_fixed.data(), threads, kernels);
      batch::pdf_interleaved(m, {fixed_row, 0}, {po, 3}, n, q_fixed.data(), threads, kernels);
      for (size_t i = 0; i < n; ++i) {
        const RGBT<T> ref = f.get(i), ref_fixed = f_fixed.get(i);
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(std::memcmp(&ref[c], &g[3 * i + c], sizeof(T)), 0)
              << nm.name << " " << kname << " f row " << i << " channel " << c;
          ASSERT_EQ(std::memcmp(&ref_fixed[c], &g_fixed[3 * i + c], sizeof(T)), 0)
              << nm.name << " " << kname << " broadcast f row " << i;
        }
        ASSERT_EQ(std::memcmp(&p[i], &q[i], sizeof(T)), 0) << nm.name << " " << kname << " pdf row " << i;
        ASSERT_EQ(std::memcmp(&p_fixed[i], &q_fixed[i], sizeof(T)), 0) << nm.name << " " << kname << " broadcast pdf row " << i;
      }
    }
    // NaN rows: the NaN / Inf rows give NaN, every other row the value it had.
    std::vector<T> bi(wi_rows), bo(wo_rows);
    for (size_t i = 7, k = 0; i < n; i += 93 + k % 5, ++k) {
      (k % 2 ? bo : bi)[1 + 3 * i + k % 3] = bad_values[k % 3];
      bad[i] = true;
    }
    std::vector<T> g(3 * n), q(n);
    batch::evaluate_interleaved(m, {bi.data() + 1, 3}, {bo.data() + 1, 3}, n, g.data(), batch::Threads::All, kernels,
                                batch::NonFinite::NaN);
    batch::pdf_interleaved(m, {bi.data() + 1, 3}, {bo.data() + 1, 3}, n, q.data(), batch::Threads::All, kernels,
                           batch::NonFinite::NaN);
    // The structure-of-arrays entry points with NonFinite::NaN, on the same rows.
    batch::DirectionArray<T> si(n), so(n);
    for (size_t i = 0; i < n; ++i)
      si.set(i, Vec3T<T>(bi[1 + 3 * i], bi[2 + 3 * i], bi[3 + 3 * i])),
          so.set(i, Vec3T<T>(bo[1 + 3 * i], bo[2 + 3 * i], bo[3 + 3 * i]));
    batch::ColorArray<T> sf(n);
    std::vector<T> sp(n);
    batch::evaluate(m, si.view(), so.view(), n, sf.view(), batch::Threads::All, kernels, batch::NonFinite::NaN);
    batch::pdf(m, si.view(), so.view(), n, sp.data(), batch::Threads::All, kernels, batch::NonFinite::NaN);
    for (size_t i = 0; i < n; ++i) {
      const RGBT<T> ref = f.get(i), soa = sf.get(i);
      for (int c = 0; c < 3; ++c) {
        if (bad[i]) {
          ASSERT_TRUE(std::isnan(g[3 * i + c])) << nm.name << " " << kname << " row " << i;
          ASSERT_TRUE(std::isnan(soa[c])) << nm.name << " " << kname << " SoA row " << i;
        } else {
          ASSERT_EQ(std::memcmp(&ref[c], &g[3 * i + c], sizeof(T)), 0) << nm.name << " " << kname << " row " << i;
          ASSERT_EQ(std::memcmp(&ref[c], &soa[c], sizeof(T)), 0) << nm.name << " " << kname << " SoA row " << i;
        }
      }
      if (bad[i]) {
        ASSERT_TRUE(std::isnan(q[i]) && std::isnan(sp[i])) << nm.name << " " << kname << " pdf row " << i;
      } else {
        ASSERT_EQ(std::memcmp(&p[i], &q[i], sizeof(T)), 0) << nm.name << " " << kname << " pdf row " << i;
        ASSERT_EQ(std::memcmp(&p[i], &sp[i], sizeof(T)), 0) << nm.name << " " << kname << " SoA pdf row " << i;
      }
    }
  }
}

TEST_P(BatchTest, InterleavedRowsEqualStructureOfArraysFloat) { check_interleaved<float>(GetParam()); }
TEST_P(BatchTest, InterleavedRowsEqualStructureOfArraysDouble) { check_interleaved<double>(GetParam()); }

// The batch sampler fed the same uniforms gives the scalar sampler's records. The SIMD samplers
// compute the same directions with other sin / cos / atan / log implementations: the same validity, wi within 1e-4, and a record
// whose pdf and weight are the scalar pdf and f cos / pdf at the batch's own wi (the comparison of the main test). Where a
// uniform sits on a branch boundary (the lobe choice uc = p_spec, the concentric map's diagonals)
// an ulp can change the branch: at most 1 in 1000 elements may differ in validity or wi.
TEST_P(BatchTest, SampleMatchesScalar) {
  const MaterialT<float> m = build<float>(GetParam().json);
  const MaterialD md = build<double>(GetParam().json);
  Rng rng(99);
  const size_t n = 3001;
  batch::DirectionArray<float> wo(n);
  std::vector<float> uc(n), u0(n), u1(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3 o = random_upper<float>(rng);
    if (i % 97 == 0) o.z = -o.z;  // a few below the horizon: "no sample"
    wo.set(i, o);
    uc[i] = rng.uniform_as<float>(), u0[i] = rng.uniform_as<float>(), u1[i] = rng.uniform_as<float>();
  }
  batch::SampleArray<float> s(n);
  batch::sample(m, wo.view(), uc.data(), u0.data(), u1.data(), n, s.view());
  size_t branch_differs = 0, valid = 0;
  double worst_wi = 0.0, worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const BSDFSampleT<float> ref = m.sample(wo.get(i), uc[i], Vec2(u0[i], u1[i]));
    const BSDFSampleT<float> got = s.get(i);
    if (!got.valid) {
      ASSERT_EQ(got.pdf, 0.0f);
      ASSERT_EQ(got.weight, RGB(0.0f));
    }
    const double dwi = glm::length(glm::dvec3(got.wi) - glm::dvec3(ref.wi));
    if (got.valid != ref.valid || dwi > 1e-4) {
      ++branch_differs;
      continue;
    }
    worst_wi = std::max(worst_wi, dwi);
    if (!got.valid) continue;
    ++valid;
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(std::isfinite(got.weight[c]) && got.weight[c] >= 0.0f) << i << ": weight " << got.weight[c];
    // The record at its own wi: pdf and weight from the scalar kernels.
    const float p = m.pdf(got.wi, wo.get(i));
    const double pd = md.pdf(Vec3d(got.wi), Vec3d(wo.get(i)));
    // A turned material (rotation_deg) computes its record in its own frame and turns wi back in
    // float: the wi it returns is the record's direction rounded (a few 1e-8), and turned forward
    // again for the scalar check; near the horizon a sharp lobe (Ashikhmin-Shirley n_u = 180, pdf
    // ~700) moves by up to 2.3e-3 relative over that (measured, AVX2). The kernels are checked to
    // 1e-5 by the unturned materials; for the turned ones this checks the turning (an error there
    // is of order 1), so 1e-2.
    const double turned = m.rotation.identity() ? 0.0 : 1e-2;
    const auto near = [&](double got_v, float scalar, double scalar_d) {
      return close_to_scalar(float(got_v), scalar, scalar_d, scalar, worst) ||
             std::abs(got_v - scalar_d) <= turned * std::abs(scalar_d);
    };
    EXPECT_TRUE(near(got.pdf, p, pd)) << i << ": pdf " << got.pdf << " scalar " << p;
    const RGB f = m.f(got.wi, wo.get(i));
    const glm::dvec3 fd = md.f(Vec3d(got.wi), Vec3d(wo.get(i)));
    for (int c = 0; c < 3; ++c) {
      const float w = f[c] * (got.wi.z / p);
      const double wd = fd[c] * (double(got.wi.z) / pd);
      EXPECT_TRUE(near(got.weight[c], w, wd)) << i << ": weight " << got.weight[c] << " scalar " << w;
    }
  }
  EXPECT_LE(branch_differs, n / 1000) << GetParam().name;
  EXPECT_GT(valid, n / 2) << GetParam().name;
  testing::Test::RecordProperty("worst_wi_distance", std::to_string(worst_wi));
}

INSTANTIATE_TEST_SUITE_P(Models, BatchTest, testing::ValuesIn(batch_materials()), material_name);

// Nearly opposite grazing pairs (wo within 1e-3 rad of -wi in azimuth, cosines log-uniform in
// [1e-11, 1e-2]), where h.wi is rounding alone (Ashikhmin-Shirley's f went negative there), and
// samples from grazing views: the batch path's f, pdf and weights are finite and >= 0 for every
// model and every Ngan preset, float and double. Agreement with the scalar path is not asserted
// here: 1 / h.wi magnifies a one-ulp difference without bound.
template <typename T> void check_near_opposite_batch(const NamedMaterial& nm) {
  const MaterialT<T> m = build<T>(nm.json);
  Rng rng(2301);
  const auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, rng.uniform()); };
  const auto at = [](double z, double phi) {
    const double r = std::sqrt(1.0 - z * z);
    return Vec3T<T>(T(r * std::cos(phi)), T(r * std::sin(phi)), T(z));
  };
  const size_t n = 501;
  batch::DirectionArray<T> wi(n), wo(n);
  std::vector<T> uc(n), u0(n), u1(n);
  for (size_t i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * rng.uniform();
    wi.set(i, at(log_uniform(1e-11, 1e-2), phi));
    wo.set(i, at(log_uniform(1e-11, 1e-2), phi + M_PI + (rng.uniform() - 0.5) * log_uniform(1e-12, 2e-3)));
    uc[i] = T(rng.uniform()), u0[i] = T(rng.uniform()), u1[i] = T(rng.uniform());
  }
  batch::ColorArray<T> f(n);
  std::vector<T> p(n);
  batch::evaluate(m, wi.view(), wo.view(), n, f.view());
  batch::pdf(m, wi.view(), wo.view(), n, p.data());
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(f.get(i)[c]) && f.get(i)[c] >= T(0)) << nm.name << " pair " << i;
    ASSERT_TRUE(std::isfinite(p[i]) && p[i] >= T(0)) << nm.name << " pair " << i;
  }
  for (size_t i = 0; i < n; ++i) wo.set(i, at(log_uniform(1e-5, 1e-1), 2.0 * M_PI * rng.uniform()));
  batch::SampleArray<T> s(n);
  batch::sample(m, wo.view(), uc.data(), u0.data(), u1.data(), n, s.view());
  for (size_t i = 0; i < n; ++i) {
    const BSDFSampleT<T> got = s.get(i);
    if (!got.valid) continue;
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(std::isfinite(got.weight[c]) && got.weight[c] >= T(0))
          << nm.name << " sample " << i << " weight " << got.weight[c];
  }
}

TEST(Batch, NearlyOppositeGrazingPairsAreNonNegativeForEveryModelAndNganPreset) {
  std::vector<NamedMaterial> v = all_model_materials();
  for (const PresetInfo& p : presets())
    if (p.name.rfind("ngan/", 0) == 0) v.push_back({p.name, p.json});
  ASSERT_GT(v.size(), all_model_materials().size() + 80);
  for (const NamedMaterial& nm : v) {
    check_near_opposite_batch<float>(nm);
    check_near_opposite_batch<double>(nm);
  }
}

// One thread or all: the same bits (fixed blocks, each element computed alone).
TEST(Batch, ThreadCountDoesNotChangeResults) {
  const MaterialT<float> m =
      build<float>({{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.1}, {"alpha_y", 0.25}, {"form", "vector"}});
  Rng rng(5);
  const size_t n = 100003;
  batch::DirectionArray<float> wi(n), wo(n);
  for (size_t i = 0; i < n; ++i) wi.set(i, random_upper<float>(rng)), wo.set(i, random_upper<float>(rng));
  batch::ColorArray<float> a(n), b(n);
  std::vector<float> pa(n), pb(n);
  batch::evaluate(m, wi.view(), wo.view(), n, a.view(), batch::Threads::One);
  batch::evaluate(m, wi.view(), wo.view(), n, b.view(), batch::Threads::All);
  batch::pdf(m, wi.view(), wo.view(), n, pa.data(), batch::Threads::One);
  batch::pdf(m, wi.view(), wo.view(), n, pb.data(), batch::Threads::All);
  EXPECT_EQ(std::memcmp(a.r.data(), b.r.data(), n * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.b.data(), b.b.data(), n * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(pa.data(), pb.data(), n * sizeof(float)), 0);
  // A sub-range evaluated alone gives the same values as inside the whole (alignment-independent).
  batch::ColorArray<float> c(n);
  const size_t off = 7;
  batch::evaluate(m, {wi.x.data() + off, wi.y.data() + off, wi.z.data() + off},
                  {wo.x.data() + off, wo.y.data() + off, wo.z.data() + off}, 1000, {c.r.data(), c.g.data(), c.b.data()});
  EXPECT_EQ(std::memcmp(a.r.data() + off, c.r.data(), 1000 * sizeof(float)), 0);
}

TEST(Batch, ReportsItsTarget) {
  EXPECT_NE(std::string(batch::simd_target()), "");
  EXPECT_GE(batch::simd_lanes_float(), 1u);
  // Two floats per double lane on every SIMD target; the scalar fallback has one of each.
  if (batch::simd_lanes_float() > 1) {
    EXPECT_EQ(batch::simd_lanes_float(), 2 * batch::simd_lanes_double());
  }
}

// Chi-square test of the batch sampler (the samples drawn in one batch call with the uniforms the
// harness draws, in its order) against the batch pdf.
TEST(Batch, SamplerPassesChiSquare) {
  const int64_t kSamples = scaled(400'000);
  const char* const names[] = {"lambert", "phong", "ward_vector_ward", "as_aniso", "lafortune_aniso", "ggx_aniso", "metal_ward"};
  const double significance = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(std::size(names)));
  for (const NamedMaterial& nm : all_model_materials()) {
    if (std::find_if(std::begin(names), std::end(names), [&](const char* s) { return nm.name == s; }) == std::end(names))
      continue;
    const MaterialT<float> m = build<float>(nm.json);
    const MaterialT<double> md = build<double>(nm.json);
    const Vec3d wod = spherical(50.0, 20.0);
    const Vec3 wo = Vec3(wod);
    // The harness's uniforms, in its order (uc, u.x, u.y per sample, one Rng with its seed).
    const uint64_t seed = 17;
    Rng rng(seed);
    batch::DirectionArray<float> wos(kSamples);
    std::vector<float> uc(kSamples), u0(kSamples), u1(kSamples);
    for (int64_t i = 0; i < kSamples; ++i) {
      wos.set(size_t(i), wo);
      uc[i] = rng.uniform_as<float>(), u0[i] = rng.uniform_as<float>(), u1[i] = rng.uniform_as<float>();
    }
    batch::SampleArray<float> s(kSamples);
    batch::sample(m, wos.view(), uc.data(), u0.data(), u1.data(), kSamples, s.view());
    int64_t next = 0;
    const Chi2Result r = chi2_test([&](float, Vec2) { return s.get(size_t(next++)); },
                                   [&](const Vec3d& wi) {
                                     double p = 0.0;
                                     batch::pdf(md, {&wi.x, &wi.y, &wi.z}, {&wod.x, &wod.y, &wod.z}, 1, &p, batch::Threads::One);
                                     return p;
                                   },
                                   kSamples, seed, 20, 40, 6);
    ASSERT_TRUE(r.message.empty()) << nm.name << ": " << r.message;
    EXPECT_GT(r.p_value, significance) << nm.name << ": chi2 " << r.chi2 << " dof " << r.dof;
    EXPECT_NEAR(r.pdf_integral, r.accepted_fraction, 5e-3) << nm.name;
  }
}

}  // namespace
}  // namespace aniso::test

namespace aniso::test {
namespace {

// `aniso eval` on a large input takes the batch path; its output is the scalar path's, byte for byte
// (9 significant digits of double results that agree to ~1e-15).
TEST(Batch, CliEvalLargeInputMatchesScalarOutput) {
  for (const char* material : {"brushed-gold", "matte-steel"}) {
    const MaterialD m = build_material<double>(load_material(material));
    Rng rng(31);
    std::string input, expected;
    for (int i = 0; i < 3000; ++i) {
      Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
      if (i % 50 == 0) wi.z = -wi.z;
      input += fmt::format("{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
      // The CLI normalises what it reads: do the same to the parsed numbers.
      const Vec3d pi = glm::normalize(Vec3d(std::stod(fmt::format("{:.17g}", wi.x)), std::stod(fmt::format("{:.17g}", wi.y)),
                                            std::stod(fmt::format("{:.17g}", wi.z))));
      const Vec3d po = glm::normalize(Vec3d(std::stod(fmt::format("{:.17g}", wo.x)), std::stod(fmt::format("{:.17g}", wo.y)),
                                            std::stod(fmt::format("{:.17g}", wo.z))));
      const RGBT<double> f = m.f(pi, po);
      expected += fmt::format("{:.9g} {:.9g} {:.9g} {:.9g}\n", f.x, f.y, f.z, m.pdf(pi, po));
    }
    const std::string dir = testing::TempDir();
    // Per-process names: ctest runs this test in several processes at once (batch_tests_*).
    const std::string tag = std::to_string(::getpid()) + "_" + material;
    const std::string in_path = dir + "/batch_eval_in_" + tag + ".txt", out_path = dir + "/batch_eval_out_" + tag + ".txt";
    {
      FILE* fp = std::fopen(in_path.c_str(), "w");
      ASSERT_NE(fp, nullptr);
      std::fwrite(input.data(), 1, input.size(), fp);
      std::fclose(fp);
    }
    const std::string cmd = std::string(ANISO_CLI) + " eval --material " + material + " < " + in_path + " > " + out_path;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::string got;
    {
      FILE* fp = std::fopen(out_path.c_str(), "r");
      ASSERT_NE(fp, nullptr);
      char buf[1 << 16];
      size_t k;
      while ((k = std::fread(buf, 1, sizeof buf, fp)) > 0) got.append(buf, k);
      std::fclose(fp);
    }
    size_t first_diff = 0;
    while (first_diff < got.size() && first_diff < expected.size() && got[first_diff] == expected[first_diff]) ++first_diff;
    std::remove(in_path.c_str());
    std::remove(out_path.c_str());
    EXPECT_EQ(got, expected) << material << ": first difference at byte " << first_diff << ": \""
                             << got.substr(first_diff > 40 ? first_diff - 40 : 0, 80) << "\"";
  }
}

}  // namespace
}  // namespace aniso::test

namespace aniso::test {
namespace {

// Kernels::Scalar is MaterialT::f / pdf bit for bit, on any number of threads.
TEST(Batch, ScalarKernelsAreTheScalarPathBitForBit) {
  const MaterialD m = build_material<double>(load_material("brushed-gold"));
  batch::DirectionArray<double> wi, wo;
  make_pairs(wi, wo);
  const size_t n = wi.size();
  batch::ColorArray<double> f(n);
  std::vector<double> p(n);
  batch::evaluate(m, wi.view(), wo.view(), n, f.view(), batch::Threads::All, batch::Kernels::Scalar);
  batch::pdf(m, wi.view(), wo.view(), n, p.data(), batch::Threads::All, batch::Kernels::Scalar);
  for (size_t i = 0; i < n; ++i) {
    const RGBT<double> ref = m.f(wi.get(i), wo.get(i));
    const RGBT<double> got = f.get(i);
    ASSERT_EQ(std::memcmp(&ref, &got, sizeof ref), 0) << i;
    const double pref = m.pdf(wi.get(i), wo.get(i));
    ASSERT_EQ(std::memcmp(&pref, &p[i], sizeof pref), 0) << i;
  }
}

}  // namespace
}  // namespace aniso::test

namespace aniso::test {
namespace {

// The chi-square suite of test_sampling.cpp (every test material, normal, moderate, oblique and
// near-grazing views), run on the batch sampler: one batch::sample call draws all the samples with
// the harness's uniforms, in its order; expected frequencies from the scalar double pdf.
struct BatchSamplingCase {
  std::string material;
  nlohmann::json json;
  double theta_deg, phi_deg;
};

std::vector<BatchSamplingCase> batch_sampling_cases() {
  std::vector<BatchSamplingCase> cases;
  const double views[][2] = {{0.0, 0.0}, {35.0, 30.0}, {65.0, 120.0}, {85.0, 200.0}};
  for (const auto& m : all_model_materials())
    for (const auto& v : views) cases.push_back({m.name, m.json, v[0], v[1]});
  return cases;
}

void PrintTo(const BatchSamplingCase& c, std::ostream* os) {
  *os << c.material << " wo(theta " << c.theta_deg << ", phi " << c.phi_deg << ")";
}

class BatchSamplingTest : public testing::TestWithParam<BatchSamplingCase> {};

TEST_P(BatchSamplingTest, ChiSquareMatchesPdf) {
  const int64_t kSamples = scaled(1'000'000);
  const BatchSamplingCase& c = GetParam();
  const MaterialT<float> m = build<float>(c.json);
  const MaterialD md = build<double>(c.json);
  const Vec3d wod = spherical(c.theta_deg, c.phi_deg);
  const Vec3 wo = Vec3(wod);
  const uint64_t seed = 7;
  Rng rng(seed);
  batch::DirectionArray<float> wos(kSamples);
  std::vector<float> uc(kSamples), u0(kSamples), u1(kSamples);
  for (int64_t i = 0; i < kSamples; ++i) {
    wos.set(size_t(i), wo);
    uc[i] = rng.uniform_as<float>(), u0[i] = rng.uniform_as<float>(), u1[i] = rng.uniform_as<float>();
  }
  batch::SampleArray<float> s(kSamples);
  batch::sample(m, wos.view(), uc.data(), u0.data(), u1.data(), kSamples, s.view());
  int64_t next = 0;
  const Chi2Result r = chi2_test([&](float, Vec2) { return s.get(size_t(next++)); },
                                 [&](const Vec3d& wi) { return md.pdf(wi, wod); }, kSamples, seed);
  ASSERT_TRUE(r.message.empty()) << r.message;
  const double significance = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(batch_sampling_cases().size()));
  EXPECT_GT(r.p_value, significance) << c.material << " wo theta " << c.theta_deg << ": chi2 " << r.chi2 << " dof " << r.dof
                                     << " pdf integral " << r.pdf_integral << " accepted " << r.accepted_fraction;
  EXPECT_NEAR(r.pdf_integral, r.accepted_fraction, 5e-3);
}

std::string batch_sampling_case_name(const testing::TestParamInfo<BatchSamplingCase>& param_info) {
  return param_info.param.material + "_theta" + std::to_string(int(param_info.param.theta_deg));
}

INSTANTIATE_TEST_SUITE_P(Models, BatchSamplingTest, testing::ValuesIn(batch_sampling_cases()), batch_sampling_case_name);

}  // namespace
}  // namespace aniso::test
