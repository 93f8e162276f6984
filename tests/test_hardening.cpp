// tests/test_hardening.cpp: what issues 11 and 13 found a user (or a fuzzer) could do wrong, and
// what the tool now says. Reader rules (anisotropic pairs, duplicate keys, nesting depth, inline
// materials, names), the number rule of io/text_input.h, and the CLI's exits for NaN options,
// integer options, read and write errors. Each reproducer from the issues is here.
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "cli_fixture.h"
#include "io/json_read.h"
#include "io/text_input.h"
#include "stats/rng.h"

namespace aniso {
namespace {

using nlohmann::json;

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string parse_error(const json& j) {
  return error_of([&] { parse_material(j, "m.json"); });
}

// --- anisotropic pairs (docs/conventions.md, "Anisotropic pairs") -------------------------------

TEST(AnisotropicPairs, HalfAPairNamesThePartner) {
  // The issue's reproducer: n_u without n_v evaluated with n_v = 100.
  EXPECT_TRUE(contains(parse_error({{"model", "ashikhmin-shirley"}, {"rd", 0.1}, {"rs", 0.2}, {"n_u", 10}}),
                       "key \"n_u\": given without its partner \"n_v\""));
  EXPECT_TRUE(contains(parse_error({{"model", "ward"}, {"alpha_y", 0.2}}), "partner \"alpha_x\""));
  EXPECT_TRUE(contains(parse_error({{"model", "ggx"}, {"alpha_x", 0.2}}), "partner \"alpha_y\""));
  EXPECT_TRUE(
      contains(parse_error({{"model", "lafortune"}, {"lobes", json::array({{{"cx", -1}, {"n", 5}}})}}), "partner \"cy\""));
  EXPECT_TRUE(contains(parse_error({{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}, {"alpha_x", 0.1}}}}),
                       "partner \"alpha_y\""));
  EXPECT_TRUE(contains(
      parse_error({{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ward"}}}, {"directional_diffuse", {{"cy", -1}}}}),
      "partner \"cx\""));
  // The message offers the shorthand.
  EXPECT_TRUE(contains(parse_error({{"model", "ward"}, {"alpha_x", 0.2}}), "or \"alpha\" alone"));
}

TEST(AnisotropicPairs, ShorthandSetsBothAndExcludesThem) {
  const MaterialDesc w = parse_material({{"model", "ward"}, {"alpha", 0.3}}, "m");
  EXPECT_EQ(w.params.scalar("alpha_x"), 0.3);
  EXPECT_EQ(w.params.scalar("alpha_y"), 0.3);
  EXPECT_FALSE(w.params.has("alpha"));
  const MaterialDesc a = parse_material({{"model", "ashikhmin-shirley"}, {"n", 40}}, "m");
  EXPECT_EQ(a.params.scalar("n_u"), 40.0);
  EXPECT_EQ(a.params.scalar("n_v"), 40.0);
  EXPECT_TRUE(contains(parse_error({{"model", "ward"}, {"alpha", 0.3}, {"alpha_x", 0.2}}), "cannot be given together"));
  // Both halves, or neither (both defaults), stay accepted.
  EXPECT_NO_THROW(parse_material({{"model", "ward"}, {"alpha_x", 0.1}, {"alpha_y", 0.3}}, "m"));
  EXPECT_NO_THROW(parse_material({{"model", "ward"}}, "m"));
}

// --- JSON documents -------------------------------------------------------------------------------

TEST(JsonRead, DuplicateKeysAreErrorsNamingKeyAndPath) {
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"alpha_x": 0.1, "alpha_x": 0.5})", "f.json"); }),
                       "f.json: alpha_x: duplicate key \"alpha_x\""));
  // Both orders (issue 13: one order was accepted, the other rejected by range).
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"kd": 2, "kd": 0.5})", "f"); }), "duplicate key \"kd\""));
  EXPECT_TRUE(
      contains(error_of([] { parse_json_text(R"({"model": "ward", "model": "lambert"})", "f"); }), "duplicate key \"model\""));
  EXPECT_TRUE(contains(error_of([] { parse_json_text(R"({"lobes": [{"n": 1}, {"n": 2, "n": 3}]})", "f"); }),
                       "lobes[1].n: duplicate key"));
  // The same key in different objects is fine.
  EXPECT_NO_THROW(parse_json_text(R"({"a": {"n": 1}, "b": {"n": 2}, "c": [{"n": 1}, {"n": 2}]})", "f"));
}

TEST(JsonRead, DeepNestingIsRejectedNotACrash) {
  // Issue 13's reproducer: 200,000 levels of arrays crashed with SIGSEGV in a recursive copy.
  std::string deep = R"({"model": "lambert", "zz": )";
  deep += std::string(200000, '[') + std::string(200000, ']') + "}";
  const std::string msg = error_of([&] { load_material(deep); });
  EXPECT_TRUE(contains(msg, "inline material")) << msg;
  EXPECT_TRUE(contains(msg, "nested deeper than 64 levels")) << msg;
  // 60 levels are still read (and then rejected as an unknown key, by the material reader).
  std::string ok = R"({"model": "lambert", "zz": )" + std::string(60, '[') + std::string(60, ']') + "}";
  EXPECT_TRUE(contains(error_of([&] { load_material(ok); }), "unknown key \"zz\""));
}

TEST(JsonRead, ControlCharactersInKeysAreEscaped) {
  const std::string msg = parse_error(json::parse("{\"model\": \"lambert\", \"a\\u0000b\\u001b[31m\": 1}"));
  EXPECT_TRUE(contains(msg, "a\\u0000b\\u001b[31m")) << msg;  // the whole key, escaped
  EXPECT_EQ(msg.find('\x1b'), std::string::npos);
}

TEST(JsonRead, FileKindsHaveTheirOwnMessages) {
  const fs::path dir = fs::temp_directory_path() / ("aniso-hardening-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_TRUE(contains(error_of([&] { read_json_file((dir / "missing.json").string()); }), "no such file"));
  EXPECT_TRUE(contains(error_of([&] { read_json_file(dir.string()); }), "is a directory"));
  std::ofstream(dir / "bad.json") << "{\"model\": ";
  EXPECT_TRUE(contains(error_of([&] { read_json_file((dir / "bad.json").string()); }), "invalid JSON"));
  // A FIFO is read like a file (`-m <(...)` passes /dev/fd/N, a pipe).
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << R"({"model": "lambert", "kd": 0.25})"; });
  const MaterialDesc d = load_material(fifo.string());
  writer.join();
  EXPECT_EQ(d.params.color("kd"), glm::dvec3(0.25));
  fs::remove_all(dir);
}

// --- materials: inline, names, resolved form ---------------------------------------------------

TEST(MaterialSpec, InlineJsonAndNames) {
  const MaterialDesc d = load_material(R"({"model": "ward", "alpha_x": 0.1, "alpha_y": 0.3})");
  EXPECT_EQ(d.params.scalar("alpha_y"), 0.3);
  EXPECT_TRUE(contains(error_of([] { load_material(R"({"model": "ward", "alpha": 7})"); }), "inline material: key \"alpha\""));
  EXPECT_TRUE(contains(error_of([] { load_material("gld"); }), "did you mean \"gold\""));
  EXPECT_TRUE(contains(error_of([] { load_material(""); }), "empty name"));
  // The American spelling is an alias (docs/presets.md).
  EXPECT_NO_THROW(load_material("aluminum"));
  EXPECT_NO_THROW(load_material("brushed-aluminum"));
  EXPECT_NO_THROW(parse_material({{"model", "metal"}, {"metal", "aluminum"}, {"lobe", {{"model", "ggx"}}}}, "m"));
  EXPECT_TRUE(
      contains(parse_error({{"model", "metal"}, {"metal", "gld"}, {"lobe", {{"model", "ggx"}}}}), "did you mean \"gold\""));
}

TEST(MaterialSpec, ResolvedJsonIsValidInputGivingTheSameMaterial) {
  Rng rng(11);
  for (const PresetInfo& p : presets()) {
    const MaterialDesc d = load_material(p.name);
    const json r = resolved_json(d);
    const MaterialDesc again = parse_material(r, "resolved " + p.name);
    const MaterialD a = build_material<double>(d), b = build_material<double>(again);
    for (int i = 0; i < 8; ++i) {
      const Vec3d wi = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() + 0.05));
      const Vec3d wo = glm::normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() + 0.05));
      ASSERT_EQ(a.f(wi, wo), b.f(wi, wo)) << p.name;
    }
    ASSERT_EQ(resolved_json(again), r) << p.name;  // a fixed point
  }
}

TEST(MaterialSpec, NegativeZeroReadsAsZero) {
  const MaterialDesc d = parse_material({{"model", "lambert"}, {"kd", -0.0}}, "m");
  EXPECT_FALSE(std::signbit(d.params.color("kd").x));
}

// --- the number rule (io/text_input.h) -----------------------------------------------------------

TEST(NumberRule, DecimalOnlyUnderflowToZeroOverflowRejected) {
  EXPECT_EQ(parse_decimal("010").value(), 10.0);
  EXPECT_EQ(parse_decimal("1e-400").value(), 0.0);
  EXPECT_GT(parse_decimal("1e-310").value(), 0.0);  // subnormal: accepted (issue 13)
  EXPECT_FALSE(std::signbit(parse_decimal("-0").value()));
  for (const char* bad : {"inf", "nan", "-inf", "0x10", "1e999", "", ".", "e5", "1e", "1,5", " 1"})
    EXPECT_FALSE(parse_decimal(bad).has_value()) << bad;
  EXPECT_EQ(parse_decimal("1.").value(), 1.0);
  EXPECT_EQ(parse_decimal(".5").value(), 0.5);
}

TEST(NumberRule, IntegersAreDecimalWholeAndInRange) {
  EXPECT_EQ(parse_unsigned("010", 100, "--count"), 10u);
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("-1", UINT64_MAX, "--seed"); }), "--seed: expected a whole decimal"));
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("18446744073709551616", UINT64_MAX, "--seed"); }), "out of range"));
  EXPECT_TRUE(contains(error_of([] { parse_unsigned("1.5", 100, "--count"); }), "whole decimal number"));
  EXPECT_EQ(parse_unsigned("18446744073709551615", UINT64_MAX, "--seed"), UINT64_MAX);
  EXPECT_EQ(parse_integer("-3", -5, 5, "x"), -3);
}

TEST(NumberRule, DirectionLines) {
  // Issue 13: (1e200, 1e200, 1e200) is non-zero and finite: scaled before normalising.
  const DirectionPair d = parse_direction_line("1e200 1e200 1e200 0 0 1e-300", 1, false);
  EXPECT_NEAR(d.wi.z, 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(d.wo, Vec3d(0, 0, 1));
  EXPECT_TRUE(is_blank_or_comment("\f"));
  EXPECT_TRUE(is_blank_or_comment(" \v\t# x"));
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("0 0 0 0 0 1", 7, false); }), "stdin line 7: wi"));
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("0 0 1 0 0 nan", 2, false); }), "field 6"));
  const DirectionPair a = parse_direction_line("30 0 30 180", 1, true);
  EXPECT_NEAR(a.wi.x, 0.5, 1e-15);
  EXPECT_NEAR(a.wo.x, -0.5, 1e-15);
  EXPECT_TRUE(contains(error_of([] { parse_direction_line("91 0 0 0", 3, true); }), "theta must be in [0, 90]"));
}

// --- the CLI ------------------------------------------------------------------------------------------

class Hardening : public Cli {};

TEST_F(Hardening, NanAndOutOfRangeOptionsExitTwo) {
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

TEST_F(Hardening, ThetaNinetyIsTheHorizon) {
  const Result r = run({"albedo", "-m", "ngan/wardduer/nickel", "--theta-deg", "90", "--samples", "1000"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "0 0 0\n");
}

TEST_F(Hardening, CountIsDecimal) {
  const Result r = run({"sample", "-m", "gold", "--wo", "0", "0", "1", "--count", "010"});
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 10);
}

TEST_F(Hardening, ReadErrorOnStdinIsAnError) {
  const Result r = run_redirected({"eval", "-m", "gold"}, "< " + shell_quote(dir_.string()));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "stdin: read error")) << r.err;
}

TEST_F(Hardening, WriteErrorsExitNonZero) {
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

// `-o` naming a FIFO (or a device such as /dev/null) is written in place: renaming the temporary
// file over it replaced the FIFO or device node itself (found running `export-brdf -o /dev/full`
// as root: /dev/full became a regular file and the command exited 0).
TEST_F(Hardening, OutputToAFifoWritesThroughIt) {
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

TEST_F(Hardening, ShowPrintsTheResolvedMaterialWhichIsValidInput) {
  const Result r = run({"presets", "--show", "brushed-gold"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_TRUE(j["lobe"].contains("alpha_x") && j["lobe"].contains("normalization")) << r.out;  // defaults filled in
  const std::string file = write("resolved.json", r.out);
  const Result e = run({"eval", "-m", file}, "0.3 0.1 0.9 -0.2 0.1 0.8\n");
  const Result e2 = run({"eval", "-m", "brushed-gold"}, "0.3 0.1 0.9 -0.2 0.1 0.8\n");
  EXPECT_EQ(e.code, 0) << e.err;
  EXPECT_EQ(e.out, e2.out);
}

TEST_F(Hardening, InlineMaterialVersionFresnelEtaKAndMetals) {
  const Result r = run({"eval", "-m", R"({"model": "lambert", "kd": -0.0})"}, "0 0 1 0 0 1\n");
  EXPECT_EQ(r.out, "0 0 0 0.318309886\n") << r.err;
  const Result bad = run({"eval", "-m", R"({"model": "ward", "alpha_x": 0.1})"}, "0 0 1 0 0 1\n");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(contains(bad.err, "inline material: key \"alpha_x\": given without its partner")) << bad.err;
  const Result version = run({"--version"});
  EXPECT_EQ(version.code, 0);
  EXPECT_TRUE(contains(version.out, "aniso ")) << version.out;
  const Result metals = run({"metals"});
  EXPECT_EQ(metals.code, 0);
  EXPECT_TRUE(contains(metals.out, "gold") && contains(metals.out, "Au")) << metals.out;
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

// fuzz_eval_line: phi * pi / 180 overflowed to inf for |phi| above 5.7e307 degrees (NaN, exit 0);
// phi is reduced modulo 360 first, so a huge phi is the direction of its remainder.
TEST_F(Hardening, EvalAnglesHugePhiIsReducedNotNaN) {
  const Result huge = run({"eval", "-m", "gold", "--angles"}, "30 1e300 30 -1e308\n");
  EXPECT_EQ(huge.code, 0) << huge.err;
  EXPECT_EQ(huge.out.find("nan"), std::string::npos) << huge.out;
  const Result reduced = run({"eval", "-m", "gold", "--angles"},
                             fmt::format("30 {:.17g} 30 {:.17g}\n", std::fmod(1e300, 360.0), std::fmod(-1e308, 360.0)));
  EXPECT_EQ(huge.out, reduced.out);
}

TEST_F(Hardening, EvalAnglesEqualsVectors) {
  const Result a = run({"eval", "-m", "brushed-gold", "--angles"}, "30 0 45 180\n");
  const double t = M_PI / 6, o = M_PI / 4;
  const Result v =
      run({"eval", "-m", "brushed-gold"}, fmt::format("{:.17g} 0 {:.17g} {:.17g} {:.17g} {:.17g}\n", std::sin(t), std::cos(t),
                                                      -std::sin(o), std::sin(o) * std::sin(M_PI), std::cos(o)));
  EXPECT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, v.out);
}

}  // namespace
}  // namespace aniso
