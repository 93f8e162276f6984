// A measured BRDF as a material (aniso/brdf/measured.h, include/aniso/measured/measured.h): the tabulated
// sampler against its pdf (chi-square, tests/chi2.h), the sample record, albedo by sampling
// against uniform integration, the batch API, load_material and the CLI (eval, sample, albedo,
// presets --show, render, export-glsl, bad files).
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/batch/batch.h"
#include "aniso/measured/measured.h"
#include "aniso/stats/albedo.h"
#include "chi2.h"
#include "cli_fixture.h"
#include "test_util.h"

namespace aniso::test {
namespace {

// The analytic models tabulated: a broad isotropic Ward with a coloured diffuse term, and an
// Ashikhmin-Shirley with a sharper lobe (n = 100) and a Fresnel rise towards grazing.
const nlohmann::json kWard = {{"model", "ward"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", 0.2}, {"alpha", 0.25}};
const nlohmann::json kAS = {{"model", "ashikhmin-shirley"}, {"rd", {0.2, 0.3, 0.4}}, {"rs", 0.1}, {"n", 100.0}};

std::shared_ptr<const MeasuredData> measured_from(const nlohmann::json& j, const std::string& label) {
  return make_measured(tabulate_merl(build<double>(j)), label);
}
const std::shared_ptr<const MeasuredData>& ward_data() {
  static const auto d = measured_from(kWard, "tabulated ward");
  return d;
}
const std::shared_ptr<const MeasuredData>& as_data() {
  static const auto d = measured_from(kAS, "tabulated ashikhmin-shirley");
  return d;
}

TEST(MeasuredTables, SizeAndBuildTime) {
  const MeasuredData& d = *ward_data();
  EXPECT_EQ(d.theta_o_bins, kMeasuredThetaOBins);
  EXPECT_EQ(d.phi_h_bins, kMeasuredPhiHBins);
  // marginal 64 x 91, conditional 64 x 90 x 97, plus 181 edge values: 4.5 MB.
  EXPECT_EQ(d.sampling_bytes(), sizeof(double) * (64 * 91 + 64 * 90 * 97 + 91 + 90));
  std::printf("sampling tables: %.2f MB, built in %.3f s\n", double(d.sampling_bytes()) / 1e6, d.table_build_seconds);
  for (int o = 0; o < d.theta_o_bins; ++o) {
    const double* m = d.marginal_cdf.data() + size_t(o) * 91;
    EXPECT_EQ(m[0], 0.0);
    EXPECT_EQ(m[90], 1.0);
    for (int i = 0; i < 90; ++i) ASSERT_LE(m[i], m[i + 1]);
  }
}

struct View {
  double theta, phi;
};
const View kViews[] = {{0.0, 0.0}, {30.0, 40.0}, {60.0, 200.0}, {80.0, 310.0}};

class MeasuredSampling : public testing::TestWithParam<std::tuple<int, int>> {};

// Quadrature sub-cells per chi-square bin and axis (tests/chi2.h; 6 for the analytic models). The
// tabulated pdf is piecewise constant: where the nearest-bin f steps at a MERL theta_h bin edge
// (by ~10% across the lobe of a tabulated n = 100 lobe), so does the pdf. At normal view those
// steps are circles of constant cos(theta), parallel to the harness's bins, so the 3-point
// Gauss-Legendre error at each step has the same sign in every phi bin and does not average out:
// with 16 sub-cells the pdf integral came out 3e-4 low (n = 100) or 6e-4 (n = 200) and chi2
// failed, although the sampler agrees with a fine midpoint integration of the same pdf. With 24
// the integral matches the acceptance to 1e-5 at every view tested.
constexpr int kChi2Sub = 24;

// Chi-square goodness of fit of sample() against pdf() (float sampler, double pdf, as the other
// models' tests), 2M samples at four views, two materials. 8 tests at 1% family-wise significance.
TEST_P(MeasuredSampling, ChiSquareMatchesPdf) {
  const auto [which, view] = GetParam();
  const auto data = which == 0 ? ward_data() : as_data();
  const MaterialT<float> m = measured_kernel<float>(*data);
  const MaterialT<double> md = measured_kernel<double>(*data);
  const View v = kViews[view];
  const Vec3 wo = Vec3(spherical(v.theta, v.phi));
  const Vec3d wod = spherical(v.theta, v.phi);
  const Chi2Result r = chi2_test([&](float uc, Vec2 u) { return m.sample(wo, uc, u); },
                                 [&](const Vec3d& wi) { return md.pdf(wi, wod); }, 2'000'000, 17, 40, 80, kChi2Sub);
  ASSERT_TRUE(r.message.empty()) << r.message;
  const double alpha = 1.0 - std::pow(0.99, 1.0 / 8.0);
  std::printf("%s view theta %g: chi2 %.1f dof %d p %.3f pdf integral %.5f accepted %.5f\n", data->source.c_str(), v.theta,
              r.chi2, r.dof, r.p_value, r.pdf_integral, r.accepted_fraction);
  EXPECT_GT(r.p_value, alpha) << "chi2 " << r.chi2 << " dof " << r.dof;
  EXPECT_LE(r.pdf_integral, 1.0 + 1e-3);
  EXPECT_NEAR(r.pdf_integral, r.accepted_fraction, 5e-3);
}

// The sample record at every view of both materials (one test: the tables are built once).
TEST(MeasuredSamplingRecord, WeightIsFCosOverPdf) {
  for (int which = 0; which < 2; ++which)
    for (const View& v : kViews) {
      SCOPED_TRACE(fmt::format("{} theta {}", which == 0 ? "ward" : "as", v.theta));
      const auto data = which == 0 ? ward_data() : as_data();
      const MaterialT<double> m = measured_kernel<double>(*data);
      const Vec3d wo = spherical(v.theta, v.phi);
      Rng rng(11);
      int valid = 0;
      for (int i = 0; i < 20000; ++i) {
        const BSDFSampleT<double> s = m.sample(wo, rng.uniform(), Vec2T<double>(rng.uniform(), rng.uniform()));
        if (!s.valid) {
          EXPECT_EQ(s.pdf, 0.0);
          continue;
        }
        ++valid;
        ASSERT_NEAR(glm::length(s.wi), 1.0, 1e-9);
        const double pdf = m.pdf(s.wi, wo);
        ASSERT_NEAR(s.pdf, pdf, 1e-9 * pdf);
        const Vec3d expected = m.f(s.wi, wo) * s.wi.z / pdf;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.weight[c], expected[c], 1e-9 * (1.0 + expected[c]));
      }
      EXPECT_GT(valid, 15000);
    }
}

// The albedo by the sampler (E[weight]) equals the albedo by uniform hemisphere integration of
// the same table, within 4 standard errors of the difference; and the sampler's variance is lower.
TEST(MeasuredSamplingRecord, AlbedoBySamplingEqualsUniformIntegration) {
  for (int which = 0; which < 2; ++which)
    for (const View& v : kViews) {
      SCOPED_TRACE(fmt::format("{} theta {}", which == 0 ? "ward" : "as", v.theta));
      const MaterialT<double> m = measured_kernel<double>(*(which == 0 ? ward_data() : as_data()));
      const Vec3d wo = spherical(v.theta, v.phi);
      const AlbedoEstimate is = albedo_importance(m, wo, 200000, 3), un = albedo_uniform(m, wo, 400000, 5);
      for (int c = 0; c < 3; ++c) {
        const double se = std::hypot(is.std_error[c], un.std_error[c]);
        EXPECT_NEAR(is.mean[c], un.mean[c], 4.0 * se + 1e-6) << "channel " << c;
      }
      EXPECT_LT(is.std_error.y * std::sqrt(2.0), un.std_error.y) << "importance sampling no better than uniform";
    }
}

std::string sampling_name(const testing::TestParamInfo<std::tuple<int, int>>& info) {
  return std::string(std::get<0>(info.param) == 0 ? "ward" : "as") + "_theta" +
         std::to_string(int(kViews[std::get<1>(info.param)].theta));
}
INSTANTIATE_TEST_SUITE_P(Tabulated, MeasuredSampling, testing::Combine(testing::Values(0, 1), testing::Values(0, 1, 2, 3)),
                         sampling_name);

// The discrete part of the sampler without quadrature: with uc in the table branch, the half
// vector of each sample falls in cell (theta_h row, phi_h column) with exactly the probability the
// tables give (marginal x conditional), whatever wo is within its bin. Pearson's chi-square over
// the cells (tests/chi2.h: sparse cells pooled), 1M samples, two views.
TEST(MeasuredSamplingCells, HalfVectorCellsHaveTheirTableProbabilities) {
  const MeasuredData& d = *as_data();
  const MaterialT<double> m = measured_kernel<double>(d);
  const int H = MerlLayout::kThetaH, P = d.phi_h_bins;
  for (const View v : {View{37.0, 50.0}, View{72.0, 290.0}}) {
    const Vec3d wo = spherical(v.theta, v.phi);
    double c, sn;
    int o;
    m.measured.view_frame(wo, c, sn, o);
    std::vector<double> observed(size_t(H) * P, 0.0), expected(size_t(H) * P, 0.0);
    const double* mcdf = d.marginal_cdf.data() + size_t(o) * (H + 1);
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < P; ++j) {
        const double* ccdf = d.conditional_cdf.data() + (size_t(o) * H + i) * (P + 1);
        expected[size_t(i) * P + j] = (mcdf[i + 1] - mcdf[i]) * (ccdf[j + 1] - ccdf[j]);
      }
    Rng rng(23);
    const int n = 1'000'000;
    int rejected = 0;
    for (int k = 0; k < n; ++k) {
      const double uc = m.measured.uniform_fraction + (1.0 - m.measured.uniform_fraction) * rng.uniform();
      const BSDFSampleT<double> s = m.sample(wo, uc, Vec2T<double>(rng.uniform(), rng.uniform()));
      if (!s.valid) {
        ++rejected;
        continue;
      }
      const Vec3d h = glm::normalize(s.wi + wo);
      const double hx = h.x * c + h.y * sn, hy = -h.x * sn + h.y * c;
      const int i = merl_theta_half_index(std::atan2(std::sqrt(hx * hx + hy * hy), h.z));
      double phi = std::atan2(hy, hx);
      if (phi < 0) phi += 2 * M_PI;
      const int j = std::min(P - 1, int(phi / (2 * M_PI) * P));
      observed[size_t(i) * P + j] += 1.0;
    }
    for (double& e : expected) e *= n;
    // The rejected draws (h whose reflection of wo is below the horizon) belong to the pooled rest.
    PearsonOptions po;
    po.pooled_extra_observed = rejected;
    const PearsonResult r = pearson_chi2(observed, expected, po);
    ASSERT_TRUE(r.message.empty()) << r.message;
    std::printf("cells, view theta %g: chi2 %.1f dof %d p %.3f rejected %d\n", v.theta, r.chi2, r.dof, r.p_value, rejected);
    EXPECT_GT(r.p_value, 0.005) << "chi2 " << r.chi2 << " dof " << r.dof;
    EXPECT_LT(rejected, n / 1000);
  }
}

// The tabulated material evaluates as the MERL lookup, in float as in double, and through the
// batch API (its scalar fallback) bit for bit as the scalar kernel.
TEST(MeasuredMaterial, KernelBatchAndLookupAgree) {
  const MeasuredData& d = *ward_data();
  const MaterialT<double> md = measured_kernel<double>(d);
  const MaterialT<float> mf = measured_kernel<float>(d);
  ASSERT_EQ(md.kind, ModelKind::Measured);
  Rng rng(21);
  const size_t n = 5000;
  batch::DirectionArray<double> wi(n), wo(n);
  batch::DirectionArray<float> wif(n), wof(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3d a = random_upper<double>(rng), b = random_upper<double>(rng);
    wi.set(i, a), wo.set(i, b), wif.set(i, Vec3(a)), wof.set(i, Vec3(b));
  }
  batch::ColorArray<double> f(n);
  std::vector<double> pdf(n);
  batch::evaluate(md, wi.view(), wo.view(), n, f.view());
  batch::pdf(md, wi.view(), wo.view(), n, pdf.data());
  int float_bin_differs = 0;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(f.get(i), md.f(wi.get(i), wo.get(i)));
    ASSERT_EQ(f.get(i), d.brdf.lookup(wi.get(i), wo.get(i)));
    ASSERT_EQ(pdf[i], md.pdf(wi.get(i), wo.get(i)));
    const Vec3 ff = mf.f(wif.get(i), wof.get(i));
    if (glm::distance(Vec3d(ff), f.get(i)) > 1e-6 * glm::length(f.get(i))) ++float_bin_differs;
  }
  // float rounds a query within ~1e-7 rad of a bin edge into the neighbour bin: rare.
  EXPECT_LT(float_bin_differs, 10);
  // sample through the batch API: the scalar kernel's records.
  std::vector<double> uc(n), u0(n), u1(n);
  for (size_t i = 0; i < n; ++i) uc[i] = rng.uniform(), u0[i] = rng.uniform(), u1[i] = rng.uniform();
  batch::SampleArray<double> s(n);
  batch::sample(md, wo.view(), uc.data(), u0.data(), u1.data(), n, s.view());
  for (size_t i = 0; i < n; ++i) {
    const BSDFSampleT<double> r = md.sample(wo.get(i), uc[i], Vec2T<double>(u0[i], u1[i]));
    ASSERT_EQ(s.get(i).valid, r.valid);
    ASSERT_EQ(s.get(i).wi, r.wi);
    ASSERT_EQ(s.get(i).pdf, r.pdf);
  }
}

// Reciprocity of the lookup (MERL folds phi_d by it) and no NaN anywhere, down to the horizon.
TEST(MeasuredMaterial, ReciprocalAndFinite) {
  const MaterialT<double> m = measured_kernel<double>(*as_data());
  Rng rng(4);
  for (int i = 0; i < 20000; ++i) {
    Vec3d a = random_upper<double>(rng), b = random_upper<double>(rng);
    if (i % 4 == 0) a = glm::normalize(Vec3d(a.x, a.y, 1e-9));
    const Vec3d f = m.f(a, b), g = m.f(b, a);
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(f[c]));
    if (glm::distance(f, g) > 1e-12 * glm::length(f)) ADD_FAILURE() << "not reciprocal at sample " << i;
    ASSERT_TRUE(std::isfinite(m.pdf(a, b)));
    const BSDFSampleT<double> s = m.sample(b, rng.uniform(), Vec2T<double>(rng.uniform(), rng.uniform()));
    ASSERT_TRUE(std::isfinite(s.pdf) && std::isfinite(s.weight.x));
  }
}

// --- files, load_material and the CLI -------------------------------------------------------

// One MERL file per test process (35 MB), written on first use into a directory removed at exit.
struct SharedFile {
  fs::path dir;
  std::string path;
  SharedFile() {
    std::string tmpl = (fs::temp_directory_path() / "aniso-measured-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    dir = tmpl;
    path = (dir / "ward.binary").string();
    write_merl(path, ward_data()->brdf);
  }
  ~SharedFile() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};
const std::string& ward_file() {
  static const SharedFile f;
  return f.path;
}

TEST(MeasuredMaterial, LoadMaterialReadsABinaryFile) {
  const MaterialDesc d = load_material(ward_file());
  EXPECT_EQ(d.model, "measured");
  ASSERT_TRUE(d.measured);
  EXPECT_TRUE(d.measured->merl_name.empty());  // not one of MERL's files
  EXPECT_EQ(d.measured->sha256.size(), 64u);
  EXPECT_EQ(resolved_json(d), (nlohmann::json{{"model", "measured"}, {"file", ward_file()}}));
  // The same file again: the registry's copy (read once per process).
  EXPECT_EQ(load_material(ward_file()).measured.get(), d.measured.get());
  // The JSON form, and a JSON file naming it relative to its own folder.
  const MaterialDesc j = parse_material(nlohmann::json{{"model", "measured"}, {"file", "ward.binary"}}, "x.json",
                                        fs::path(ward_file()).parent_path().string());
  EXPECT_EQ(j.measured.get(), d.measured.get());
  // The kernel's values are the table's.
  const MaterialD m = build_material<double>(d);
  const Vec3d wi = spherical(30, 10), wo = spherical(40, 200);
  EXPECT_EQ(m.f(wi, wo), ward_data()->brdf.lookup(wi, wo));
}

TEST(MeasuredMaterial, RecognisesMerlFilesBySha256) {
  EXPECT_EQ(merl_known_count(), 100u);
  EXPECT_EQ(merl_material_name("d6506c69e44430bfe8ea676f3950599ca3a6bfb1f46b9906da336d13991bd37d"), "alum-bronze");
  EXPECT_EQ(merl_material_name("cc036db74087f380747a0746d39dd1e4be359c409fa729214a894bd883a4757e"), "yellow-plastic");
  EXPECT_EQ(merl_material_name("0000000000000000000000000000000000000000000000000000000000000000"), "");
  // sha256 itself: FIPS 180-2's "abc" example.
  const fs::path p = fs::temp_directory_path() / ("aniso-sha256-" + std::to_string(::getpid()) + ".txt");
  std::ofstream(p) << "abc";
  EXPECT_EQ(sha256_file(p.string()), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  fs::remove(p);
}

class MeasuredCli : public Cli {};

TEST_F(MeasuredCli, EvalSampleAlbedoWithABinaryMaterial) {
  const std::string& file = ward_file();
  const Result e = run({"eval", "--material", file}, "0 0 1 0 0 1\n0.5 0 0.8660254 -0.5 0 0.8660254\n");
  ASSERT_EQ(e.code, 0) << e.err;
  const MaterialD m = build_material<double>(load_material(file));
  const Vec3d f = m.f(Vec3d(0, 0, 1), Vec3d(0, 0, 1));
  EXPECT_TRUE(contains(e.out, fmt::format("{:.9g} {:.9g} {:.9g}", f.x, f.y, f.z))) << e.out;
  EXPECT_EQ(std::count(e.out.begin(), e.out.end(), '\n'), 2);
  const Result s = run({"sample", "--material", file, "--wo", "0.3", "0", "0.9", "--count", "100"});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(std::count(s.out.begin(), s.out.end(), '\n'), 100);
  // albedo of the tabulated Ward at 30 degrees against the analytic model's.
  const Result a = run({"albedo", "--material", file, "--theta-deg", "30", "--samples", "200000"});
  ASSERT_EQ(a.code, 0) << a.err;
  std::istringstream in(a.out);
  Vec3d rho;
  in >> rho.x >> rho.y >> rho.z;
  const AlbedoEstimate ref = albedo_importance(build<double>(kWard), spherical(30, 0), 400000, 9);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(rho[c], ref.mean[c], 0.01) << c;
}

TEST_F(MeasuredCli, PresetsShowNamesTheFileAndModelsListsMeasured) {
  const Result r = run({"presets", "--show", ward_file()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out), (nlohmann::json{{"model", "measured"}, {"file", ward_file()}}));
  EXPECT_TRUE(contains(r.err, "not one of the 100 MERL database files (sha256 ")) << r.err;
  const Result m = run({"models", "--model", "measured"});
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(contains(m.out, "measured (Measured (MERL table))")) << m.out;
  EXPECT_TRUE(contains(m.out, "no other parameters")) << m.out;
}

TEST_F(MeasuredCli, RenderPreviewOfABinaryMaterial) {
  const std::string png = (dir_ / "m.png").string();
  const Result r = run({"render", "--material", ward_file(), "--width", "64", "--height", "36", "--spp", "4", "-o", png});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 100u);
  EXPECT_FALSE(contains(r.err, "NaN")) << r.err;
}

// In a scene: a measured material by path and in JSON form, both relative to the scene's folder.
TEST_F(MeasuredCli, SceneWithMeasuredMaterialsRelativeToItsFolder) {
  const Result p = run({"render", "--material", "clay", "--print-scene"});
  ASSERT_EQ(p.code, 0) << p.err;
  nlohmann::json scene = nlohmann::json::parse(p.out);
  ASSERT_EQ(scene["objects"].size(), 2u);
  scene["objects"][0]["material"] = "ward.binary";
  scene["objects"][1]["material"] = {{"model", "measured"}, {"file", "ward.binary"}};
  const fs::path scene_path = fs::path(ward_file()).parent_path() / "scene.json";
  std::ofstream(scene_path) << scene.dump();
  const std::string png = (dir_ / "scene.png").string();
  const Result r = run({"render", scene_path.string(), "--width", "48", "--height", "32", "--spp", "2", "-o", png});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
  fs::remove(scene_path);
}

// export-glsl writes the shader and its tables file (docs/glsl.md "Measured materials"; the GLSL
// twin's parity: tests/test_glsl_measured.cpp); to stdout it needs a path for the tables.
TEST_F(MeasuredCli, ExportGlslOfAMeasuredMaterialWritesItsTables) {
  expect_input_error(run({"export-glsl", "--material", ward_file()}), {ward_file(), "needs its tables file", "--tables"});
  const std::string out = (dir_ / "m.glsl").string();
  const Result r = run({"export-glsl", "--material", ward_file(), "-o", out});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_EQ(fs::file_size(out + ".tables") % (4 * 4096), 0u);
}

// Every kind of bad file exits 2 through each command, naming the file and the byte offset.
TEST_F(MeasuredCli, BadFilesExit2NamingFileAndOffset) {
  std::string header(12, '\0');
  const int32_t dims[3] = {90, 90, 180};
  std::memcpy(header.data(), dims, 12);
  std::string nan_file = header + std::string(8 * 10, '\0');
  const double nan = std::nan("");
  std::memcpy(nan_file.data() + 12 + 8 * 3, &nan, 8);
  const std::string empty = write("empty.binary", "");
  const std::string wrong = write("wrong.binary", std::string("\x5a\0\0\0\x5a\0\0\0\xb3\0\0\0", 12) + std::string(64, '\0'));
  const std::string truncated = write("truncated.binary", header + std::string(8 * 1000, '\0'));
  const std::string text = write("text.binary", "# not a MERL file\n");
  fs::create_directory(dir_ / "dir.binary");
  const std::string directory = (dir_ / "dir.binary").string();
  // A NaN: a full-size file (35 MB) with one NaN value.
  std::string big = header + std::string(MerlBrdf::kFileBytes - 12, '\0');
  std::memcpy(big.data() + 12 + 8 * 5000, &nan, 8);
  const std::string nan_path = write("nan.binary", big);
  const std::string long_path = write("long.binary", big + "x");  // one byte too many
  big.clear();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {empty, "byte offset 0: empty file"},
      {wrong, "byte offset 8: header: phi_d resolution 179, expected 180"},
      {truncated, "byte offset 8012: truncated"},
      {text, "byte offset 0: header: theta_h resolution"},
      {directory, "is a directory"},
      {nan_path, fmt::format("byte offset {}: NaN", 12 + 8 * 5000)},
      {long_path, "byte offset 34992012: trailing data: the file is 34992013 bytes"},
      {(dir_ / "absent.binary").string(), "no such file"},
  };
  for (const auto& [path, expect] : cases) {
    SCOPED_TRACE(path);
    expect_input_error(run({"eval", "--material", path}, "0 0 1 0 0 1\n"), {path, expect});
    expect_input_error(run({"albedo", "--material", path, "--theta-deg", "10"}), {path, expect});
    if (path == wrong) {
      expect_input_error(run({"sample", "--material", path, "--wo", "0", "0", "1"}), {path, expect});
      expect_input_error(run({"presets", "--show", path}), {path, expect});
      const Result r = run({"render", "--material", path, "-o", (dir_ / "x.png").string()});
      EXPECT_EQ(r.code, 2) << r.err;
      EXPECT_TRUE(contains(r.err, expect)) << r.err;
      EXPECT_FALSE(fs::exists(dir_ / "x.png"));
    }
  }
  fs::remove(nan_path);
  fs::remove(long_path);
}

}  // namespace
}  // namespace aniso::test
