// tests/test_samples.cpp: the measured-data readers (include/aniso/measured/samples.h) and the spectral
// reduction (include/aniso/measured/spectral.h): reference values, every bad-input case, and the CLI's exit 2.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "aniso/io/params.h"
#include "aniso/measured/samples.h"
#include "aniso/measured/spectral.h"
#include "cli_fixture.h"

namespace aniso {
namespace {

const std::string kCornell = std::string(ANISO_SOURCE_DIR) + "/data/measured/cornell/";

// scripts/reduce_ior.py's rgb_weights() on 400..700 nm every 10 nm, applied to four spectra, run
// with /usr/bin/python3 (numpy) when these tests were written:
//   W, _ = reduce_ior.rgb_weights(np.arange(400.0, 700.5, 10.0)); W @ spectrum
TEST(Spectral, AgreesWithTheMetalsPythonReduction) {
  std::vector<double> lambda;
  for (int l = 400; l <= 700; l += 10) lambda.push_back(l);
  const SpectralToRgb to_rgb(lambda);
  std::vector<double> flat(31, 0.5), ramp(31), gauss(31);
  for (int j = 0; j < 31; ++j) ramp[j] = j / 30.0, gauss[j] = std::exp(-0.5 * std::pow((lambda[j] - 550.0) / 30.0, 2));
  const std::vector<double> krylon = {0.017415, 0.036844, 0.044973, 0.054382, 0.069262, 0.086848, 0.092864, 0.088583,
                                      0.076870, 0.062686, 0.048442, 0.035325, 0.024838, 0.017140, 0.012132, 0.008862,
                                      0.006773, 0.005678, 0.005299, 0.005074, 0.004735, 0.005091, 0.005267, 0.005727,
                                      0.006374, 0.007006, 0.007266, 0.006798, 0.006084, 0.005271, 0.005187};
  const struct {
    const std::vector<double>* spectrum;
    glm::dvec3 python;
  } cases[] = {
      {&flat, {0.5, 0.5000000000000002, 0.5000000000000001}},
      {&ramp, {0.7796066881178868, 0.4813571662463829, 0.12562173362075846}},
      {&krylon, {-0.00205197912591689, 0.01506189353186859, 0.08218845461955109}},
      {&gauss, {0.14250153542399685, 0.7996491630802329, -0.06222415486067596}},
  };
  for (const auto& c : cases) {
    const glm::dvec3 rgb = to_rgb(*c.spectrum);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(rgb[k], c.python[k], 1e-12) << k;
  }
}

TEST(Spectral, GreyStaysGreyOnAnyGrid) {
  const std::vector<double> lambda = {380, 415, 500, 512, 640, 780};
  const SpectralToRgb to_rgb(lambda);
  const glm::dvec3 rgb = to_rgb(std::vector<double>(lambda.size(), 0.25));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rgb[k], 0.25, 1e-14);
}

TEST(Cornell, ReadsThePbrtV2Files) {
  for (const char* name : {"acryl_blue", "cayman", "garnet_red", "krylon_blue"}) {
    const SampleSet s = read_cornell(kCornell + name + ".brdf");
    EXPECT_EQ(s.samples.size(), 1439u) << name;
    EXPECT_EQ(s.format, "cornell");
    for (const MeasuredSample& m : s.samples) {
      ASSERT_GT(m.wi.z, 0.0);
      ASSERT_GT(m.wo.z, 0.0);
      ASSERT_NEAR(glm::length(m.wi), 1.0, 1e-12);
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(m.value[c]));
    }
  }
  // krylon_blue's first row: theta_i 0.872665 (50 deg), phi_i 0, theta_s 0.573513, phi_s 0, and the
  // spectrum of Spectral.AgreesWithTheMetalsPythonReduction.
  const SampleSet k = read_cornell(kCornell + "krylon_blue.brdf");
  EXPECT_NEAR(k.samples[0].wi.z, std::cos(0.872665), 1e-12);
  EXPECT_NEAR(k.samples[0].wo.x, std::sin(0.573513), 1e-12);
  EXPECT_NEAR(k.samples[0].value.z, 0.08218845461955109, 1e-12);
  // The specular peak of the glossy paint lies at the mirror direction (phi_s = phi_i + pi).
  const SampleSet c = read_cornell(kCornell + "cayman.brdf");
  const MeasuredSample* peak = &c.samples[0];
  for (const MeasuredSample& m : c.samples)
    if (m.value.y > peak->value.y) peak = &m;
  EXPECT_GT(glm::dot(peak->wi, Vec3d(-peak->wo.x, -peak->wo.y, peak->wo.z)), 0.99);
}

class MeasuredInput : public Cli {
 protected:
  // Returns the InputError's message of reading `text` as `name` (empty if it was accepted).
  std::string error_of(const std::string& name, const std::string& text) {
    const std::string p = write(name, text);
    try {
      (void)read_measured(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(MeasuredInput, CsvColumnsInAnyOrderDegreesAndWeights) {
  const std::string p = write("a.csv",
                              "# my gonioreflectometer\n"
                              "b,g,r,phi_o_deg,theta_o_deg,phi_i,theta_i,weight\n"
                              "0.3,0.2,0.1,180,30,0,0.5235987755982988,2\n");
  const SampleSet s = read_samples_csv(p);
  ASSERT_EQ(s.samples.size(), 1u);
  EXPECT_TRUE(s.warnings.empty());
  const MeasuredSample& m = s.samples[0];
  EXPECT_NEAR(m.wi.x, 0.5, 1e-12);
  EXPECT_NEAR(m.wo.x, -0.5, 1e-12);
  EXPECT_NEAR(m.wo.y, 0.0, 1e-12);
  EXPECT_EQ(m.value, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_EQ(m.weight, 2.0);
}

TEST_F(MeasuredInput, CsvExtraColumnsAreIgnoredWithAWarning) {
  const std::string p = write("a.csv", "theta_i,phi_i,theta_o,phi_o,r,g,b,operator,temperature\n0.1,0,0.2,3,1,1,1,ann,20\n");
  const SampleSet s = read_samples_csv(p);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_TRUE(contains(s.warnings[0], "line 1: column \"operator\" is not used and is ignored")) << s.warnings[0];
}

TEST_F(MeasuredInput, EveryBadCsvIsAnErrorNamingFileLineAndProblem) {
  const std::string h = "theta_i,phi_i,theta_o,phi_o,r,g,b\n";
  const struct {
    std::string text, expect;
  } cases[] = {
      {"", "empty file"},
      {"# only a comment\n\n", "empty file"},
      {h, "no samples after the header (line 1)"},
      {"theta_i,phi_i,theta_o,r,g,b\n0,0,0,1,1,1\n", "line 1: missing column \"phi_o\" (or \"phi_o_deg\")"},
      {"theta_i,phi_i,theta_o,phi_o,r,g\n", "missing column \"b\""},
      {"theta_i,theta_i_deg,phi_i,theta_o,phi_o,r,g,b\n", "both \"theta_i\" and \"theta_i_deg\" given"},
      {"theta_i,phi_i,theta_o,phi_o,r,r,g,b\n", "column \"r\" appears twice"},
      {"theta_i,,phi_i,theta_o,phi_o,r,g,b\n", "column 2: empty name"},
      {h + "0.1,0,0.2,0,1,1\n", "line 2: 6 columns, but the header (line 1) names 7"},
      {h + "0.1,0,0.2,0,1,1,1,1\n", "line 2: 8 columns"},
      {h + "0.1,0,0.2,0,nan,1,1\n", "line 2: column r: expected a finite decimal number, got \"nan\""},
      {h + "0.1,0,0.2,0,1,,1\n", "line 2: column g: expected a finite decimal number, got \"\""},
      {h + "0.1,0,0.2,0,1,1,-0.5\n", "line 2: column b = -0.5: a BRDF value cannot be negative"},
      {h + "1.6,0,0.2,0,1,1,1\n", "line 2: theta_i = 1.6: out of range, expected [0, 1.5708)"},
      {h + "0.1,0,-0.2,0,1,1,1\n", "theta_o = -0.2: out of range"},
      {h + "0.1,7,0.2,0,1,1,1\n", "phi_i = 7: out of range"},
      {"theta_i_deg,phi_i,theta_o,phi_o,r,g,b\n90,0,0.2,0,1,1,1\n", "theta_i_deg = 90: out of range, expected [0, 90)"},
      {"theta_i,phi_i,theta_o,phi_o,r,g,b,weight\n0.1,0,0.2,0,1,1,1,0\n", "column weight = 0: expected a number > 0"},
      {h + "0.1,0,0.2,0,1,1,1\n0.1,0,0.2", "line 3: 3 columns"},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of("bad.csv", c.text);
    EXPECT_TRUE(contains(msg, c.expect)) << "input:\n" << c.text << "\nmessage: " << msg;
    EXPECT_TRUE(contains(msg, "bad.csv")) << msg;
  }
}

TEST_F(MeasuredInput, EveryBadCornellFileIsAnErrorNamingFileLineAndProblem) {
  std::string wls = "# wls\n";
  for (int l = 400; l <= 700; l += 10) wls += std::to_string(l) + (l == 580 ? "\n" : " ");
  wls += "\n";
  std::string row = "0.5 0 0.5 3.14159";
  for (int j = 0; j < 31; ++j) row += " 0.1";
  const std::string good = "# num wls\n31\n" + wls + row + "\n";
  ASSERT_EQ(error_of("ok.brdf", good), "");
  const struct {
    std::string text, expect;
  } cases[] = {
      {"", "empty file"},
      {"# nothing\n", "empty file"},
      {"31 400\n", "line 1: expected the number of wavelengths alone on the line, got 2 values"},
      {"3.5\n", "number of wavelengths = 3.5: expected a whole number"},
      {"31\n400 410\n", "the file is truncated: 2 of 31 wavelengths"},
      {"31\n" + wls, "no samples after the wavelengths"},
      {"3\n400 410 405\n", "wavelength 405 nm after 410 nm: wavelengths must increase"},
      {"2\n400 410 420\n", "3 more wavelengths, but only 2 of 2 were missing"},
      {"# num wls\n31\n" + wls + row.substr(0, 40) + "\n",
       "values, expected 35 (theta_i phi_i theta_s phi_s and 31 spectral values): the file is truncated"},
      {"# num wls\n31\n" + wls + row + " 0.1\n" + row + "\n", "36 values, expected 35"},
      {"# num wls\n31\n" + wls + "1.7" + row.substr(3) + "\n", "theta_i = 1.7: out of range"},
      {"# num wls\n31\n" + wls + "0.5 0 0.5 3.14159 -0.1" + row.substr(21) + "\n",
       "spectral value 1 (400 nm) = -0.1: a BRDF value cannot be negative"},
      {"# num wls\n31\n" + wls + "0.5 0 0.5 3.14159 inf" + row.substr(21) + "\n",
       "spectral value 1: expected a finite decimal number, got \"inf\""},
      // The CSV reader's bound (samples.cpp, kMaxSampleValue): a value the fit's squares would overflow.
      {"# num wls\n31\n" + wls + "0.5 0 0.5 3.14159 1e300" + row.substr(21) + "\n",
       "line 6: spectral value 1 (400 nm) = 1e+300: expected a BRDF value of at most 1e+30 (1/sr)"},
      {"# num wls\n31\n" + wls + row.substr(0, 17) + " 0.1 1.01e30" + row.substr(25) + "\n",
       "spectral value 2 (410 nm) = 1.01e+30: expected a BRDF value of at most 1e+30"},
  };
  // The bound itself is accepted.
  EXPECT_EQ(error_of("edge.brdf", "# num wls\n31\n" + wls + "0.5 0 0.5 3.14159 1e30" + row.substr(21) + "\n"), "");
  for (const auto& c : cases) {
    const std::string msg = error_of("bad.brdf", c.text);
    EXPECT_TRUE(contains(msg, c.expect)) << "input:\n" << c.text << "\nmessage: " << msg;
    EXPECT_TRUE(contains(msg, "bad.brdf")) << msg;
  }
  EXPECT_TRUE(contains(error_of("data.txt", "x"), "unknown data format \".txt\""));
  EXPECT_TRUE(contains(error_of("m.binary", "short"), "m.binary")) << error_of("m.binary", "short");
}

// The CLI: exit 2, the message on stderr, nothing on stdout, no fitted file.
TEST_F(MeasuredInput, FitOfBadDataExitsTwoAndWritesNothing) {
  const std::string out = (dir_ / "fitted.json").string();
  const struct {
    std::string name, text, expect;
  } cases[] = {
      {"e.csv", "", "e.csv: empty file"},
      {"h.csv", "theta_i,phi_i,theta_o,r,g,b\n0,0,0,1,1,1\n", "h.csv: line 1: missing column"},
      {"t.csv", "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.1,0,0.2,0,1,1,1\n0.1,0", "t.csv: line 3: 2 columns"},
      {"n.csv", "theta_i,phi_i,theta_o,phi_o,r,g,b\n0.1,0,0.2,0,1,NaN,1\n", "n.csv: line 2: column g"},
      {"a.csv", "theta_i_deg,phi_i,theta_o,phi_o,r,g,b\n95,0,0.2,0,1,1,1\n", "a.csv: line 2: theta_i_deg = 95"},
      {"c.brdf", "31\n400 410\n", "c.brdf: line 2: the file is truncated"},
      {"big.brdf", "2\n400 700\n0.5 0 0.5 3.14159 0.1 1e300\n",
       "big.brdf: line 3: spectral value 2 (700 nm) = 1e+300: expected a BRDF value of at most 1e+30 (1/sr)"},
      {"m.binary", std::string("\x5a\0\0\0\x5a\0\0\0", 8), "m.binary"},
  };
  for (const auto& c : cases) {
    const Result r = run({"fit", write(c.name, c.text), "--model", "ward", "-o", out});
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.expect)) << r.err;
    EXPECT_EQ(r.out, "") << c.name;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
  const Result missing = run({"fit", (dir_ / "absent.csv").string(), "--model", "ward", "-o", out});
  EXPECT_EQ(missing.code, 2);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace aniso
