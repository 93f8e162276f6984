// tests/test_cli.cpp: the `aniso` command-line tool, run as a separate process (ANISO_CLI is the
// path of the built executable). Checks the exact formats of eval, sample, albedo, fresnel,
// presets and models (docs/cli.md), that they agree with the library called directly, and that
// every bad input exits non-zero with a message on stderr naming the problem and nothing on stdout:
// NaN and out-of-range options, integer options, read errors on stdin, write errors on stdout
// (exit 1), and `-o` naming a FIFO or device written through rather than replaced.
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/io/presets.h"
#include "cli_fixture.h"

namespace aniso {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);) v.push_back(line);
  return v;
}

std::vector<double> numbers_of(const std::string& line) {
  std::vector<double> v;
  std::istringstream in(line);
  for (std::string tok; in >> tok;) v.push_back(std::stod(tok));
  return v;
}

std::vector<std::string> tokens_of(const std::string& line) {
  std::vector<std::string> v;
  std::istringstream in(line);
  for (std::string tok; in >> tok;) v.push_back(tok);
  return v;
}

// Significant digits of a printed number: the digits of the mantissa without leading zeros.
int significant_digits(const std::string& tok) {
  int n = 0;
  bool leading = true;
  for (char c : tok) {
    if (c == 'e' || c == 'E') break;
    if (!std::isdigit(static_cast<unsigned char>(c))) continue;
    if (leading && c == '0') continue;
    leading = false;
    ++n;
  }
  return n;
}

// |a - b| <= rel * max(|a|, |b|) + abs
::testing::AssertionResult close(double a, double b, double rel, double abs = 1e-300) {
  if (std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + abs) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << " (rel " << rel << ", abs " << abs << ")";
}

// Output of the library for the same material and directions (the tool normalises its input).
RGBT<double> library_f(const std::string& material, Vec3d wi, Vec3d wo, double* pdf = nullptr) {
  const MaterialD m = build_material<double>(load_material(material));
  wi = glm::normalize(wi);
  wo = glm::normalize(wo);
  if (pdf) *pdf = m.pdf(wi, wo);
  return m.f(wi, wo);
}

// ------------------------------------------------------------------------------------------------
// eval
// ------------------------------------------------------------------------------------------------

using CliEval = Cli;

TEST_F(CliEval, OneLineOfFourNumbersPerInputLine) {
  const Result r = run({"eval", "--material", "clay"}, "0 0 1 0 0 1\n0.3 0.1 0.9 -0.2 0.4 0.8\n0.5 -0.5 0.7 0.1 0.1 1\n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 3u);
  for (const std::string& line : lines) {
    const auto v = numbers_of(line);
    ASSERT_EQ(v.size(), 4u) << line;
    for (double x : v) {
      EXPECT_TRUE(std::isfinite(x));
      EXPECT_GE(x, 0.0);
    }
  }
}

TEST_F(CliEval, PrintsNineSignificantDigits) {
  // Lambert kd = 0.5 at normal incidence: f = 0.5 / pi, pdf = 1 / pi; neither is a short decimal.
  const std::string m = write("lambert.json", R"({"model": "lambert", "kd": 0.5})");
  const Result r = run({"eval", "--material", m}, "0 0 1 0 0 1\n");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto tok = tokens_of(r.out);
  ASSERT_EQ(tok.size(), 4u);
  for (const std::string& t : tok) {
    EXPECT_GE(significant_digits(t), 9) << t;
  }
  EXPECT_EQ(tok[0], "0.159154943");
  EXPECT_EQ(tok[3], "0.318309886");
  EXPECT_TRUE(close(std::stod(tok[0]), 0.5 / M_PI, 5e-9));
}

TEST_F(CliEval, InputIsNormalised) {
  const std::string dirs = "0.3 0.1 0.9 -0.2 0.4 0.8\n";
  const Result a = run({"eval", "--material", "brushed-gold"}, dirs);
  // A power-of-two scale gives bit-identical unit vectors, so identical text.
  const Result b = run({"eval", "--material", "brushed-gold"}, "1.2 0.4 3.6 -0.1 0.2 0.4\n");
  // Any other scale: equal to rounding.
  const Result c = run({"eval", "--material", "brushed-gold"}, "3.3 1.1 9.9 -0.02 0.04 0.08\n");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_EQ(a.out, b.out);
  const auto va = numbers_of(a.out), vc = numbers_of(c.out);
  ASSERT_EQ(va.size(), 4u);
  ASSERT_EQ(vc.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(close(va[i], vc[i], 1e-7)) << i;
  EXPECT_GT(va[0], 0.0);
}

TEST_F(CliEval, BelowTheHorizonGivesZeros) {
  const Result r = run({"eval", "--material", "gold"}, "0 0 -1 0 0 1\n0 0 1 0.3 0 -0.5\n0.5 0 0 0 0 1\n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0 0 0 0\n0 0 0 0\n0 0 0 0\n");
}

TEST_F(CliEval, BlankLinesAndCommentsAreSkipped) {
  const Result r = run({"eval", "--material", "clay"}, "# wi wo\n\n0 0 1 0 0 1\n   \n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 1u);
}

TEST_F(CliEval, AgreesWithTheLibrary) {
  struct Probe {
    std::string material;
    Vec3d wi, wo;
  };
  const std::vector<Probe> probes = {
      {"clay", {0.3, 0.1, 0.9}, {-0.2, 0.4, 0.8}},
      {"brushed-gold", {0.5, 0.1, 0.7}, {-0.45, -0.2, 0.75}},
      {"ngan/ward/nickel", {0.2, -0.3, 0.9}, {-0.25, 0.3, 0.85}},
      {"matte-steel", {0.6, 0.0, 0.8}, {-0.6, 0.05, 0.8}},
  };
  for (const Probe& p : probes) {
    SCOPED_TRACE(p.material);
    std::ostringstream in;
    in.precision(17);
    in << p.wi.x << " " << p.wi.y << " " << p.wi.z << " " << p.wo.x << " " << p.wo.y << " " << p.wo.z << "\n";
    const Result r = run({"eval", "--material", p.material}, in.str());
    ASSERT_EQ(r.code, 0) << r.err;
    const auto v = numbers_of(r.out);
    ASSERT_EQ(v.size(), 4u);
    double pdf = 0.0;
    const RGBT<double> f = library_f(p.material, p.wi, p.wo, &pdf);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(close(v[c], f[c], 1e-8)) << "channel " << c;
    EXPECT_TRUE(close(v[3], pdf, 1e-8)) << "pdf";
    EXPECT_GT(f.x, 0.0);
  }
}

// Nearly opposite grazing directions: h.wi is rounding alone, and Ashikhmin-Shirley printed -1.34e17.
TEST_F(CliEval, AshikhminShirleyNearlyOppositeGrazingPairIsNotNegative) {
  const Result r = run({"eval", "-m", "{\"model\":\"ashikhmin-shirley\"}"},
                       "0.9519527964440391 -0.30624479316777603 2.6982672065979276e-10 "
                       "-0.9519527964455237 0.3062447931631613 2.7586451918744186e-11\n");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto v = numbers_of(r.out);
  ASSERT_EQ(v.size(), 4u) << r.out;
  for (double x : v) EXPECT_TRUE(std::isfinite(x) && x >= 0.0) << r.out;
}

// A NUL byte is named with its line; the lines around it stay separate (a reader that stops at the
// NUL, as fgets does, joins what follows to the next line: one result for two bad lines, exit 0).
TEST_F(CliEval, NulByteIsAnErrorNamingItsLine) {
  expect_input_error(run({"eval", "--material", "clay"}, std::string("0 0 1 \0\n0 0 1\n", 14)),
                     {"stdin line 1: column 7: a NUL byte"});
  expect_input_error(run({"eval", "--material", "clay"}, std::string("0 0 1 0 0 1\n0 0 1 0 0 1\0\n", 25)),
                     {"stdin line 2: column 12: a NUL byte"});
  // A NUL inside a comment is part of the comment.
  const Result r = run({"eval", "--material", "clay"}, std::string("# a\0b\n0 0 1 0 0 1\n", 18));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(numbers_of(r.out).size(), 4u);
}

TEST_F(CliEval, WrongNumberOfFieldsNamesTheLineAndPrintsNothing) {
  // Line 1 is valid: it must not be printed either (all lines are checked before any output).
  const Result r = run({"eval", "--material", "clay"}, "0 0 1 0 0 1\n0 0 1 0 0\n");
  expect_input_error(r, {"line 2", "6 numbers"});
}

TEST_F(CliEval, TooManyFields) {
  expect_input_error(run({"eval", "--material", "clay"}, "0 0 1 0 0 1 7\n"), {"line 1", "6 numbers"});
}

TEST_F(CliEval, NonNumberNamesTheLineAndField) {
  const Result r = run({"eval", "--material", "clay"}, "0 0 1 0 0 1\n0 0 1 0 0 x\n");
  expect_input_error(r, {"line 2", "field 6", "\"x\""});
}

TEST_F(CliEval, NonFiniteNumbersAreRejected) {
  expect_input_error(run({"eval", "--material", "clay"}, "nan 0 1 0 0 1\n"), {"line 1", "finite"});
  expect_input_error(run({"eval", "--material", "clay"}, "0 0 1e999 0 0 1\n"), {"line 1", "finite"});
}

TEST_F(CliEval, ZeroVectorIsRejected) {
  expect_input_error(run({"eval", "--material", "clay"}, "0 0 1 0 0 1\n0 0 0 0 0 1\n"), {"line 2", "wi", "non-zero"});
  expect_input_error(run({"eval", "--material", "clay"}, "0 0 1 0 0 0\n"), {"line 1", "wo", "non-zero"});
}

TEST_F(CliEval, ReadErrorOnStdinIsAnError) {
  const Result r = run_redirected({"eval", "-m", "gold"}, "< " + shell_quote(dir_.string()));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "stdin: read error")) << r.err;
}

// Any finite phi in --angles: phi * pi / 180 overflows to inf above about 5.7e307 degrees, so phi is
// reduced modulo 360 first and a huge phi is the direction of its remainder, never NaN.
TEST_F(CliEval, AnglesHugePhiIsReducedNotNaN) {
  const Result huge = run({"eval", "-m", "gold", "--angles"}, "30 1e300 30 -1e308\n");
  EXPECT_EQ(huge.code, 0) << huge.err;
  EXPECT_EQ(huge.out.find("nan"), std::string::npos) << huge.out;
  const Result reduced = run({"eval", "-m", "gold", "--angles"},
                             fmt::format("30 {:.17g} 30 {:.17g}\n", std::fmod(1e300, 360.0), std::fmod(-1e308, 360.0)));
  EXPECT_EQ(huge.out, reduced.out);
}

TEST_F(CliEval, AnglesEqualVectors) {
  const Result a = run({"eval", "-m", "brushed-gold", "--angles"}, "30 0 45 180\n");
  const double t = M_PI / 6, o = M_PI / 4;
  const Result v =
      run({"eval", "-m", "brushed-gold"}, fmt::format("{:.17g} 0 {:.17g} {:.17g} {:.17g} {:.17g}\n", std::sin(t), std::cos(t),
                                                      -std::sin(o), std::sin(o) * std::sin(M_PI), std::cos(o)));
  EXPECT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, v.out);
}

TEST_F(CliEval, InlineMaterialJson) {
  const Result r = run({"eval", "-m", R"({"model": "lambert", "kd": -0.0})"}, "0 0 1 0 0 1\n");
  EXPECT_EQ(r.out, "0 0 0 0.318309886\n") << r.err;
  const Result bad = run({"eval", "-m", R"({"model": "ward", "alpha_x": 0.1})"}, "0 0 1 0 0 1\n");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(contains(bad.err, "inline material: key \"alpha_x\": given without its partner")) << bad.err;
}

// ------------------------------------------------------------------------------------------------
// sample
// ------------------------------------------------------------------------------------------------

using CliSample = Cli;

TEST_F(CliSample, CountLinesOfSevenNumbersWithUnitDirections) {
  const Result r = run({"sample", "--material", "brushed-gold", "--wo", "0.3", "0.1", "0.9", "--count", "200", "--seed", "5"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 200u);
  int valid = 0;
  for (const std::string& line : lines) {
    const auto v = numbers_of(line);
    ASSERT_EQ(v.size(), 7u) << line;
    if (line == "0 0 0 0 0 0 0") continue;
    ++valid;
    EXPECT_TRUE(close(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 1.0, 0.0, 5e-9)) << line;
    EXPECT_GT(v[2], 0.0) << line;
    for (int i = 3; i < 7; ++i) {
      EXPECT_TRUE(std::isfinite(v[i]));
      EXPECT_GE(v[i], 0.0);
    }
    EXPECT_GT(v[6], 0.0) << "a valid sample has a positive pdf";
  }
  EXPECT_GT(valid, 150);
}

TEST_F(CliSample, SameSeedSameOutputDifferentSeedDifferentOutput) {
  const std::vector<std::string> base = {"sample", "--material", "brushed-gold", "--wo", "0.2", "0.3", "0.9", "--count", "50"};
  auto with_seed = [&](const std::string& s) {
    auto a = base;
    a.insert(a.end(), {"--seed", s});
    return run(a);
  };
  const Result a = with_seed("11"), b = with_seed("11"), c = with_seed("12");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_NE(a.out, c.out);
  EXPECT_EQ(lines_of(a.out).size(), 50u);
  EXPECT_NE(a.out.find_first_of("123456789"), std::string::npos) << "only \"no sample\" lines";
}

TEST_F(CliSample, DefaultCountIsOne) {
  const Result r = run({"sample", "--material", "clay", "--wo", "0", "0", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 1u);
}

// weight == f cos(theta_i) / pdf, and pdf == pdf(wi, wo): feed each sampled wi back through eval.
TEST_F(CliSample, WeightIsFCosOverPdfAccordingToEval) {
  for (const std::string material :
       {"gold", "brushed-gold", "bluepaint", "ngan/ward/nickel", "ngan/ashikhminshirley/nickel", "matte-steel"}) {
    SCOPED_TRACE(material);
    const std::string wo = "-0.3 0.2 0.85";
    const Result s = run({"sample", "--material", material, "--wo", "-0.3", "0.2", "0.85", "--count", "64", "--seed", "3"});
    ASSERT_EQ(s.code, 0) << s.err;
    std::string eval_in;
    std::vector<std::vector<double>> samples;
    for (const std::string& line : lines_of(s.out)) {
      if (line == "0 0 0 0 0 0 0") continue;
      const auto v = numbers_of(line);
      ASSERT_EQ(v.size(), 7u);
      samples.push_back(v);
      const auto tok = tokens_of(line);
      eval_in += tok[0] + " " + tok[1] + " " + tok[2] + " " + wo + "\n";
    }
    ASSERT_GT(samples.size(), 32u);
    const Result e = run({"eval", "--material", material}, eval_in);
    ASSERT_EQ(e.code, 0) << e.err;
    const auto lines = lines_of(e.out);
    ASSERT_EQ(lines.size(), samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
      const auto& v = samples[i];
      const auto f = numbers_of(lines[i]);
      ASSERT_EQ(f.size(), 4u);
      const double cos_i = v[2] / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      EXPECT_TRUE(close(v[6], f[3], 1e-5)) << "pdf, sample " << i;
      for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(close(v[3 + c], f[c] * cos_i / f[3], 1e-5, 1e-12)) << "weight " << c << ", sample " << i;
    }
  }
}

TEST_F(CliSample, NoSampleBelowTheHorizon) {
  const Result r = run({"sample", "--material", "gold", "--wo", "0", "0", "-1", "--count", "3"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0 0 0 0 0 0 0\n0 0 0 0 0 0 0\n0 0 0 0 0 0 0\n");
}

TEST_F(CliSample, ZeroWoIsRejected) {
  expect_input_error(run({"sample", "--material", "gold", "--wo", "0", "0", "0", "--count", "3"}), {"--wo", "non-zero"});
}

TEST_F(CliSample, UnknownMaterialIsRejected) {
  expect_input_error(run({"sample", "--material", "no-such-preset", "--wo", "0", "0", "1"}), {"no-such-preset"});
}

TEST_F(CliSample, CountIsDecimal) {
  const Result r = run({"sample", "-m", "gold", "--wo", "0", "0", "1", "--count", "010"});
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 10);
}

// ------------------------------------------------------------------------------------------------
// albedo, fresnel
// ------------------------------------------------------------------------------------------------

using CliAlbedo = Cli;

TEST_F(CliAlbedo, LambertHalfIsHalf) {
  const std::string m = write("lambert.json", R"({"model": "lambert", "kd": 0.5})");
  const Result r = run({"albedo", "--material", m, "--theta-deg", "40", "--phi-deg", "30", "--samples", "20000"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto v = numbers_of(r.out);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(lines_of(r.out).size(), 1u);
  for (double x : v) EXPECT_NEAR(x, 0.5, 1e-3);
}

TEST_F(CliAlbedo, ThetaOutOfRangeIsRejected) {
  const Result r = run({"albedo", "--material", "clay", "--theta-deg", "100"});
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(contains(r.err, "--theta-deg")) << r.err;
}

TEST_F(CliAlbedo, ThetaNinetyIsTheHorizon) {
  const Result r = run({"albedo", "-m", "ngan/wardduer/nickel", "--theta-deg", "90", "--samples", "1000"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0 0 0\n");
}

using CliFresnel = Cli;

TEST_F(CliFresnel, NormalIncidenceMatchesTheTable) {
  for (const MetalData& md : metal_table()) {
    SCOPED_TRACE(std::string(md.name));
    const Result r = run({"fresnel", "--metal", std::string(md.name), "--theta-deg", "0"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto v = numbers_of(r.out);
    ASSERT_EQ(v.size(), 3u);
    const RGBT<double> F = F_Conductor(1.0, RGBT<double>(md.eta), RGBT<double>(md.k));
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(close(v[c], F[c], 1e-8)) << c;
      // and F(0) = ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2)
      const double e = md.eta[c], k = md.k[c];
      EXPECT_TRUE(close(v[c], ((e - 1) * (e - 1) + k * k) / ((e + 1) * (e + 1) + k * k), 1e-8)) << c;
    }
  }
}

TEST_F(CliFresnel, GrazingIsOne) {
  const Result r = run({"fresnel", "--metal", "gold", "--theta-deg", "90"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto v = numbers_of(r.out);
  ASSERT_EQ(v.size(), 3u);
  for (double x : v) EXPECT_NEAR(x, 1.0, 1e-9);
}

TEST_F(CliFresnel, UnknownMetalIsRejected) {
  expect_input_error(run({"fresnel", "--metal", "unobtainium", "--theta-deg", "0"}), {"unknown metal \"unobtainium\"", "gold"});
}

TEST_F(CliFresnel, EtaAndKOfAMetalEqualItsName) {
  // --eta/--k with gold's own values equals --metal gold.
  const MetalData* gold = find_metal("gold");
  const auto fmt3 = [](const glm::dvec3& c) {
    return std::vector<std::string>{fmt::format("{:.17g}", c.x), fmt::format("{:.17g}", c.y), fmt::format("{:.17g}", c.z)};
  };
  std::vector<std::string> args = {"fresnel", "--theta-deg", "60", "--eta"};
  for (const auto& s : fmt3(gold->eta)) args.push_back(s);
  args.push_back("--k");
  for (const auto& s : fmt3(gold->k)) args.push_back(s);
  const Result ek = run(args);
  const Result named = run({"fresnel", "--theta-deg", "60", "--metal", "gold"});
  EXPECT_EQ(ek.code, 0) << ek.err;
  EXPECT_EQ(ek.out, named.out);
  const Result wrong = run({"fresnel", "--metal", "gld"});
  EXPECT_TRUE(contains(wrong.err, "did you mean \"gold\"")) << wrong.err;
}

// ------------------------------------------------------------------------------------------------
// presets, models
// ------------------------------------------------------------------------------------------------

using CliPresets = Cli;

TEST_F(CliPresets, ListsThePresets) {
  const Result r = run({"presets"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = lines_of(r.out);
  EXPECT_EQ(lines.size(), presets().size());
  std::vector<std::string> names;
  for (const std::string& l : lines) names.push_back(tokens_of(l).at(0));
  for (const std::string n : {"matte-steel", "ngan/ward/nickel", "gold", "brushed-gold", "clay"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST_F(CliPresets, ShowPrintsTheJson) {
  const Result r = run({"presets", "--show", "ngan/ward/nickel"});
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
  // The preset with every default filled in (resolved_json): here the orientation, rotation_deg 0.
  nlohmann::json preset = *find_preset("ngan/ward/nickel");
  preset["rotation_deg"] = 0.0;
  EXPECT_EQ(j, preset);
  EXPECT_EQ(j.at("model"), "ward");
  // The printed JSON is itself a valid material file.
  const std::string path = write("nickel.json", r.out);
  const Result e = run({"eval", "--material", path}, "0.3 0.1 0.9 -0.2 0.4 0.8\n");
  const Result p = run({"eval", "--material", "ngan/ward/nickel"}, "0.3 0.1 0.9 -0.2 0.4 0.8\n");
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_EQ(e.out, p.out);
}

TEST_F(CliPresets, ShowUnknownIsRejected) {
  expect_input_error(run({"presets", "--show", "no-such-preset"}), {"no-such-preset"});
}

TEST_F(CliPresets, ModelsListsEveryModelAndParameter) {
  const Result r = run({"models"});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const ModelSpec* m : model_specs()) {
    EXPECT_TRUE(contains(r.out, std::string(m->name) + " (")) << m->name;
    for (const ParamSpec* p : m->params()) EXPECT_TRUE(contains(r.out, "  " + std::string(p->name) + " ")) << p->name;
  }
}

TEST_F(CliPresets, ShowPrintsTheResolvedMaterialWhichIsValidInput) {
  const Result r = run({"presets", "--show", "brushed-gold"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["lobe"].contains("alpha_x") && j["lobe"].contains("normalization")) << r.out;  // defaults filled in
  const std::string file = write("resolved.json", r.out);
  const Result e = run({"eval", "-m", file}, "0.3 0.1 0.9 -0.2 0.1 0.8\n");
  const Result e2 = run({"eval", "-m", "brushed-gold"}, "0.3 0.1 0.9 -0.2 0.1 0.8\n");
  EXPECT_EQ(e.code, 0) << e.err;
  EXPECT_EQ(e.out, e2.out);
}

TEST_F(CliPresets, VersionAndMetals) {
  const Result version = run({"--version"});
  EXPECT_EQ(version.code, 0);
  EXPECT_TRUE(contains(version.out, "aniso ")) << version.out;
  const Result metals = run({"metals"});
  EXPECT_EQ(metals.code, 0);
  EXPECT_TRUE(contains(metals.out, "gold") && contains(metals.out, "Au")) << metals.out;
}

// ------------------------------------------------------------------------------------------------
// bad material files and arguments
// ------------------------------------------------------------------------------------------------

using CliErrors = Cli;

TEST_F(CliErrors, BadMaterialFiles) {
  struct Case {
    std::string name, json;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"invalid", R"({"model": "lambert")", {"invalid.json", "invalid JSON"}},
      {"unknown_key", R"({"model": "lambert", "kd": 0.5, "foo": 1})", {"unknown key \"foo\""}},
      {"missing_lobes", R"({"model": "lafortune"})", {"\"lobes\"", "missing"}},
      {"missing_model", R"({"kd": 0.5})", {"\"model\"", "missing"}},
      {"wrong_type", R"({"model": "ward", "alpha_x": "big"})", {"\"alpha_x\"", "\"big\""}},
      {"negative_alpha", R"({"model": "ward", "alpha_x": -0.1})", {"\"alpha_x\"", "[0.001, 1]"}},
      {"zero_alpha", R"({"model": "ward", "alpha_x": 0})", {"\"alpha_x\"", "[0.001, 1]"}},
      {"kd_too_big", R"({"model": "lambert", "kd": 1.5})", {"\"kd\"", "[0, 1]"}},
      {"cxy_and_cx", R"({"model": "lafortune", "lobes": [{"cx": -1, "cxy": -1, "n": 10}]})", {"\"cxy\"", "\"cx\""}},
      {"unknown_metal",
       R"({"model": "metal", "metal": "unobtainium", "lobe": {"model": "ggx"}})",
       {"unknown metal \"unobtainium\""}},
      {"metal_and_eta",
       R"({"model": "metal", "metal": "gold", "eta": 1.0, "lobe": {"model": "ggx"}})",
       {"\"metal\"", "not both"}},
      {"not_an_object", R"([1, 2, 3])", {"expected a JSON object"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = write(c.name + ".json", c.json);
    expect_input_error(run({"eval", "--material", path}, "0 0 1 0 0 1\n"), c.expect);
  }
}

// A number that overflows a double (1e999) is bad input like any other: exit 2 with a message
// naming the file and the number, never an abort (nlohmann::json throws out_of_range, 406, for it,
// not parse_error).
TEST_F(CliErrors, OverflowingNumberInFile) {
  const std::string path = write("overflow.json", R"({"model": "lambert", "kd": 1e999})");
  expect_input_error(run({"eval", "--material", path}, "0 0 1 0 0 1\n"), {"overflow.json", "1e999"});
}

TEST_F(CliErrors, MissingFileAndUnknownPreset) {
  const std::string missing = (dir_ / "missing.json").string();
  expect_input_error(run({"eval", "--material", missing}, "0 0 1 0 0 1\n"), {"missing.json", "neither a preset"});
  expect_input_error(run({"eval", "--material", "no-such-preset"}, "0 0 1 0 0 1\n"), {"no-such-preset"});
  expect_input_error(run({"albedo", "--material", "no-such-preset", "--theta-deg", "0"}), {"no-such-preset"});
}

// A missing required option is bad input like any other: non-zero exit, stderr names the option,
// stdout empty.
TEST_F(CliErrors, MissingMaterial) {
  const Result r = run({"eval"}, "0 0 1 0 0 1\n");
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(contains(r.err, "--material")) << r.err;
}

// Command-line errors caught by CLI11 (missing or malformed options) exit 2 like every other input
// error (docs/cli.md: "2 for input errors"), not with CLI11's own codes (106 RequiredError, 105
// ValidationError, ...).
TEST_F(CliErrors, CommandLineErrorsExitTwo) {
  EXPECT_EQ(run({"eval"}, "").code, 2);
  EXPECT_EQ(run({"albedo", "--material", "clay", "--theta-deg", "100"}).code, 2);
  EXPECT_EQ(run({"sample", "--material", "clay", "--wo", "0", "1"}).code, 2);
}

TEST_F(CliErrors, UnknownCommandIsNamed) {
  const Result r = run({"bogus"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("unknown command \"bogus\""), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("eval"), std::string::npos) << r.err;
}

TEST_F(CliErrors, NoCommand) {
  const Result r = run({});
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(r.err.empty());
}

TEST_F(CliErrors, NanAndOutOfRangeOptionsExitTwo) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"albedo", "-m", "gold", "--theta-deg", "nan"},
           {"albedo", "-m", "gold", "--theta-deg", "10", "--phi-deg", "nan"},
           {"fresnel", "--metal", "gold", "--theta-deg", "nan"},
           {"albedo", "-m", "gold", "--theta-deg", "90.5"},
           {"render", "-m", "gold", "--exposure", "nan"},
           {"sample", "-m", "gold", "--wo", "0", "0", "1", "--count", "1.5"},
           {"sample", "-m", "gold", "--wo", "0", "0", "1", "--seed", "-1"},
           {"sample", "-m", "gold", "--wo", "0", "0", "1", "--seed", "99999999999999999999999"},
           {"presets", "--show", ""},
           {"models", "--model", ""},
       }) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args[0] << " " << args.back() << ": " << r.err;
    EXPECT_EQ(r.out, "");
  }
}

TEST_F(CliErrors, WriteErrorsExitNonZero) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  const std::string line = write("in.txt", "0 0 1 0 0 1\n");
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"eval", "-m", "gold"},
           {"sample", "-m", "gold", "--wo", "0", "0", "1", "--count", "10"},
           {"albedo", "-m", "gold", "--theta-deg", "10", "--samples", "100"},
           {"fresnel", "--metal", "gold"},
           {"presets"},
           {"models"},
           {"metals"},
           {"export-glsl", "-m", "gold"},
           {"export-brdf", "-m", "gold"},
       }) {
    const Result r = run_redirected(args, "< " + shell_quote(line) + " > /dev/full");
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "aniso: error: stdout: write error")) << args[0] << ": " << r.err;
  }
}

// `-o` naming a FIFO (or a device such as /dev/null or /dev/full) is written in place, never
// replaced: renaming the temporary file over it would replace the node itself (as root, /dev/full
// would become a regular file and a write error would go unseen).
TEST_F(CliErrors, OutputToAFifoWritesThroughIt) {
  const std::vector<std::vector<std::string>> commands = {
      {"export-glsl", "-m", "gold"},
      {"export-brdf", "-m", "gold"},
      {"render", "-m", "gold", "--width", "16", "--height", "16", "--spp", "1"},
  };
  for (size_t i = 0; i < commands.size(); ++i) {
    const fs::path fifo = dir_ / (i == 2 ? "fifo.pfm" : "fifo.out"), got = dir_ / "got";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string args;
    for (const std::string& a : commands[i]) args += fmt::format(" {}", shell_quote(a));
    // A reader on the FIFO in the background, the command writing into it, then the command's status.
    const std::string cmd =
        fmt::format("cat {0} > {1} & {2}{3} -o {0} > /dev/null 2> {4}; rc=$?; wait; exit $rc", shell_quote(fifo.string()),
                    shell_quote(got.string()), shell_quote(ANISO_CLI), args, shell_quote((dir_ / "err").string()));
    const int status = std::system(fmt::format("sh -c {}", shell_quote(cmd)).c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << commands[i][0] << ": " << read_file(dir_ / "err");
    struct stat st {};
    ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << commands[i][0] << " replaced the FIFO";
    const std::string text = read_file(got);
    EXPECT_GT(text.size(), 40u) << commands[i][0];
    if (i == 2) {
      EXPECT_EQ(text.substr(0, 3), "PF\n");
    }
    fs::remove(fifo);
    fs::remove(got);
  }
}

}  // namespace
}  // namespace aniso
