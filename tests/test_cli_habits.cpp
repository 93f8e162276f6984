// The CLI's habits as a new user meets them (docs/cli.md): mistyped options and commands are named
// with the nearest spelling, options that would be ignored are refused, help shows real defaults,
// streams and exit statuses hold when stdout fails, and `fit` refuses data it cannot fit.
#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "cli_fixture.h"
#include "test_util.h"
#include "view/explorer.h"

namespace aniso {
namespace {

class CliHabits : public Cli {
 protected:
  // A file in the test's directory (the CLI runs in the test's working directory).
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  // The CSV of samples `fit` reads: a Ward-like lobe over a grid of directions.
  std::string ward_csv(const std::string& name, double scale = 1.0) {
    std::string csv = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n";
    const MaterialD m = build_material<double>(parse_material(
        nlohmann::json::parse(R"({"model": "ward", "kd": 0.1, "ks": 0.3, "alpha_x": 0.1, "alpha_y": 0.25})"), "test"));
    for (int ti = 5; ti < 90; ti += 10)
      for (int to = 5; to < 90; to += 10)
        for (int po = 0; po < 360; po += 30) {
          const auto dir = [](double t, double p) {
            t *= M_PI / 180.0, p *= M_PI / 180.0;
            return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
          };
          const RGBT<double> f = m.f(dir(ti, 0), dir(to, po));
          csv += fmt::format("{},0,{},{},{:.9g},{:.9g},{:.9g}\n", ti, to, po, scale * f.x, scale * f.y, scale * f.z);
        }
    return write(name, csv);
  }
};

TEST_F(CliHabits, AMistypedOptionIsNamedWithTheNearest) {
  Result r = run({"eval", "--materail", "gold"});
  expect_input_error(r, {"unknown option --materail for aniso eval; did you mean --material?"});
  EXPECT_FALSE(contains(r.err, "is required")) << r.err;
  expect_input_error(run({"albedo", "-m", "gold", "--theta", "30"}), {"unknown option --theta", "--theta-deg"});
  expect_input_error(run({"fit", "x.csv", "--modle", "ward", "-o", at("f.json")}),
                     {"unknown option --modle", "did you mean --model"});
  expect_input_error(run({"render", "-m", "gold", "--widht=200"}), {"unknown option --widht", "--width"});
  expect_input_error(run({"--verison"}), {"unknown option --verison", "--version"});
  // Negative numbers are values, not options.
  EXPECT_EQ(run({"sample", "-m", "gold", "--wo", "-0.5", "-0.1", "1"}).code, 0);
}

TEST_F(CliHabits, AMistypedCommandIsNamedWithTheNearestAndNoCommandListsThem) {
  Result r = run({"rendr"});
  expect_input_error(r, {"unknown command \"rendr\"; did you mean render?", "  eval ", "  export-glsl "});
  r = run({});
  expect_input_error(r, {"no command given", "  eval ", "  render ", "  fit ", "  view "});
}

TEST_F(CliHabits, OptionsThatDoNotApplyAreRefused) {
  const std::string data = ward_csv("data.csv");
  expect_input_error(run({"fit", data, "--model", "ward", "--lobes", "3", "-o", at("f.json")}),
                     {"--lobes applies to --model lafortune only, not to --model ward"});
  expect_input_error(run({"fit", data, "--model", "ashikhmin-shirley", "--normalization", "duer", "-o", at("f.json")}),
                     {"--normalization applies to --model ward only"});
  expect_input_error(run({"fit", data, "--compare", "--model", "ward"}), {"--model does not apply with --compare"});
  expect_input_error(run({"fit", data, "--model", "ggx", "--metal", "gold", "-o", at("f.json")}),
                     {"--metal applies to --model metal only"});
  expect_input_error(run({"render", "-m", "gold", "--exposure", "1", "-o", at("x.exr")}),
                     {"--exposure and --tonemap apply to PNG output only"});
  expect_input_error(run({"render", "-m", "gold", "--tonemap", "clamp", "-o", at("x.pfm")}), {"PNG output only"});
  EXPECT_FALSE(fs::exists(dir_ / "f.json"));
  EXPECT_FALSE(fs::exists(dir_ / "x.exr"));
}

TEST_F(CliHabits, NumberOptionsAreDecimalAndNanHasItsOwnMessage) {
  expect_input_error(run({"sample", "-m", "gold", "--wo", "0x1", "0", "1"}),
                     {"--wo", "expected a finite decimal number, got \"0x1\""});
  Result r = run({"sample", "-m", "gold", "--wo", "nan", "0", "1"});
  expect_input_error(r, {"--wo", "expected a finite decimal number, got \"nan\""});
  EXPECT_FALSE(contains(r.err, "non-zero")) << r.err;
  expect_input_error(run({"sample", "-m", "gold", "--wo", "0", "0", "0"}), {"--wo: expected a non-zero direction"});
  expect_input_error(run({"fresnel", "--eta", "0x1p-1", "1", "1", "--k", "1", "1", "1"}), {"--eta", "got \"0x1p-1\""});
  expect_input_error(run({"fresnel", "--eta", "1", "1", "1", "--k", "inf", "1", "1"}), {"--k", "got \"inf\""});
  r = run({"fresnel", "--eta", "0.5", "1", "1", "--k", "1e0", "1", "1"});
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(CliHabits, HelpShowsRealDefaultsAndTypes) {
  const Result albedo = run({"albedo", "--help"});
  EXPECT_EQ(albedo.code, 0);
  EXPECT_FALSE(contains(albedo.out, "=0 REQUIRED")) << albedo.out;
  EXPECT_TRUE(contains(albedo.out, "--samples INT=1048576")) << albedo.out;
  const Result render = run({"render", "--help"});
  EXPECT_FALSE(contains(render.out, "1048576]=0")) << render.out;  // --spp: the scene's, not 0
  EXPECT_FALSE(contains(render.out, "16384]=0")) << render.out;    // --width, --height
  EXPECT_TRUE(contains(render.out, "the scene's")) << render.out;
  const Result fit = run({"fit", "--help"});
  EXPECT_TRUE(contains(fit.out, "--lobes INT=1")) << fit.out;
  EXPECT_TRUE(contains(fit.out, "--loss-scale FLOAT=0")) << fit.out;
  EXPECT_FALSE(contains(fit.out, "--starts TEXT")) << fit.out;
}

// A closed pipe is a write error with the documented message and exit 1, not death by SIGPIPE.
TEST_F(CliHabits, AClosedPipeIsAWriteError) {
  const fs::path code = dir_ / "code.txt", err = dir_ / "err.txt";
  const std::string cmd =
      fmt::format("{{ {} sample -m gold --wo 0 0 1 --count 1000000 2> {}; echo $? > {}; }} | head -c 10 > /dev/null",
                  shell_quote(ANISO_CLI), shell_quote(err.string()), shell_quote(code.string()));
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(read_file(code), "1\n");
  EXPECT_TRUE(contains(read_file(err), "aniso: error: stdout: write error: Broken pipe")) << read_file(err);
}

TEST_F(CliHabits, HelpVersionAndPrintSceneToAFailingStdoutExitOne) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  for (const auto& args : std::vector<std::vector<std::string>>{{"--help"},
                                                                {"--version"},
                                                                {"eval", "--help"},
                                                                {"render", "-m", "gold", "--print-scene"},
                                                                {"render", "--print-scene"}}) {
    for (const std::string redirect : {"> /dev/full", ">&-"}) {
      const Result r = run_redirected(args, "< /dev/null " + redirect);
      EXPECT_EQ(r.code, 1) << args[0] << " " << redirect << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "aniso: error: stdout: write error")) << args[0] << " " << redirect << ": " << r.err;
    }
  }
}

// The commands that write a file and say so on stdout ("wrote ...", what was fitted or exported),
// and the exports to stdout: a stdout that fails (a full disk, a closed descriptor) is exit 1 with
// the documented message, one line (docs/cli.md, "Exit status"), never exit 0 with the line lost,
// and never the error twice (a command's own stdout write error is not reported again by main's
// final check).
TEST_F(CliHabits, FileWritingCommandsWithAFailingStdoutExitOneWithOneMessage) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  const std::string data = ward_csv("data.csv");
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"render", "-m", "gold", "--spp", "1", "--width", "32", "-o", at("r.png")},
                                             {"export", "--to", "pbrt-v4", "-m", "gold", "-o", at("g.pbrt")},
                                             {"fit", data, "--model", "ward", "-q", "--starts", "1", "-o", at("f.json")},
                                             {"export-glsl", "-m", "gold"},
                                             {"export-brdf", "-m", "gold"}}) {
    for (const std::string redirect : {"> /dev/full", ">&-"}) {
      const Result r = run_redirected(args, "< /dev/null " + redirect);
      EXPECT_EQ(r.code, 1) << args[0] << " " << redirect << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "aniso: error: stdout: write error: ")) << args[0] << " " << redirect << ": " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args[0] << " " << redirect << ": " << r.err;
    }
  }
}

TEST_F(CliHabits, PrintSceneWritesAbsoluteAssetPaths) {
  for (const std::string scene : {"studio-map.json", "tangent-map.json", "brushed-vase.json"}) {
    const Result r = run({"render", std::string(ANISO_SOURCE_DIR) + "/examples/" + scene, "--print-scene"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(r.out);
    int files = 0;
    const auto check = [&](const nlohmann::json& v) {
      ASSERT_TRUE(v.is_string());
      EXPECT_TRUE(fs::path(v.get<std::string>()).is_absolute()) << v;
      EXPECT_TRUE(fs::exists(v.get<std::string>())) << v;
      ++files;
    };
    if (doc.contains("environment") && doc["environment"].contains("file")) check(doc["environment"]["file"]);
    for (const auto& o : doc["objects"]) {
      if (o.contains("file")) check(o["file"]);
      if (o.contains("tangent") && o["tangent"].contains("map")) check(o["tangent"]["map"]);
    }
    EXPECT_GT(files, 0) << scene;
    // Saved elsewhere, the printed scene renders (its assets found).
    write("elsewhere.json", r.out);
    const Result again = run({"render", (dir_ / "elsewhere.json").string(), "--print-scene"});
    EXPECT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(again.out, r.out);
  }
}

TEST_F(CliHabits, WidthAloneKeepsTheAspectRatioAndUnlitScenesWarn) {
  // gl-direct.json is 640 x 360.
  Result r = run(
      {"render", std::string(ANISO_SOURCE_DIR) + "/examples/gl-direct.json", "--width", "64", "--spp", "1", "-o", at("a.pfm")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "(64x36, 1 spp)")) << r.out;
  r = run(
      {"render", std::string(ANISO_SOURCE_DIR) + "/examples/gl-direct.json", "--height", "18", "--spp", "1", "-o", at("b.pfm")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "(32x18, 1 spp)")) << r.out;
  EXPECT_FALSE(contains(r.err, "warning")) << r.err;
  const std::string dark = write("dark.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
    "film": {"width": 16, "height": 16, "spp": 1},
    "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "gold"}]})");
  r = run({"render", dark, "-o", at("dark.pfm")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "aniso render: warning: " + dark + ": no light with power and no environment")) << r.err;
}

TEST_F(CliHabits, AnUnwritableOutputSaysWhy) {
  expect_input_error(run({"export-brdf", "-m", "gold", "-o", "/no/such/dir/x.brdf"}),
                     {"-o /no/such/dir/x.brdf: cannot open for writing: ", "(No such file or directory)"});
  expect_input_error(run({"export-glsl", "-m", "gold", "-o", "/no/such/dir/x.glsl"}), {"No such file or directory"});
}

TEST_F(CliHabits, FitRefusesDataItCannotFitAndPlotsOnlyPng) {
  const std::string data = ward_csv("data.csv");
  std::string text = read_file(data);
  const std::string huge =
      write("huge.csv", text.substr(0, text.find('\n') + 1) + "10,0,20,0,1e300,0.1,0.1\n" + text.substr(text.find('\n') + 1));
  expect_input_error(run({"fit", huge, "--model", "ward", "-o", at("f.json")}),
                     {"huge.csv: line 2: column r = 1e+300: expected a BRDF value of at most 1e+30 (1/sr)"});
  const std::string zero = ward_csv("zero.csv", 0.0);
  expect_input_error(run({"fit", zero, "--model", "ward", "-o", at("f.json")}),
                     {"zero.csv: every sample is 0: there is nothing to fit"});
  expect_input_error(run({"fit", data, "--model", "ward", "--plot", at("p.bmp"), "-o", at("f.json")}),
                     {"--plot ", "p.bmp: expected a .png file name"});
  EXPECT_FALSE(fs::exists(dir_ / "p.bmp"));
  EXPECT_FALSE(fs::exists(dir_ / "f.json"));
}

// Ceres sums per thread in an order that depends on the thread count; the fit sums its blocks in
// order (fit.cpp, BlockCache): the same file whatever --threads.
// Scale (ANISO_TEST_SCALE, test_util.h): the release suite (scale 1) fits from `fit`'s default 6
// starts; the sanitizer suite (0.25) from 2, whose residual blocks are split over 1, 2 and 3 threads
// the same way (fit.cpp, BlockCache): 55 CPU s under ASan instead of 68.
TEST_F(CliHabits, FitIsBitIdenticalWhateverTheThreadCount) {
  const std::string data = ward_csv("data.csv");
  const std::string starts = std::to_string(test::scaled(6));
  for (const std::vector<std::string>& model : {std::vector<std::string>{"--model", "ward", "--anisotropic"},
                                                std::vector<std::string>{"--model", "lafortune", "--lobes", "2"},
                                                std::vector<std::string>{"--model", "ggx", "--loss", "huber"}}) {
    std::vector<std::string> outputs;
    for (const char* threads : {"1", "2", "3"}) {
      std::vector<std::string> args = {
          "fit", data, "-q", "--threads", threads, "--starts", starts, "-o", at(fmt::format("t{}.json", threads))};
      args.insert(args.end(), model.begin(), model.end());
      const Result r = run(args);
      ASSERT_EQ(r.code, 0) << r.err;
      nlohmann::json j = nlohmann::json::parse(read_file(dir_ / fmt::format("t{}.json", threads)));
      j["fit"].erase("seconds");
      outputs.push_back(j.dump());
    }
    EXPECT_EQ(outputs[0], outputs[1]) << model[1];
    EXPECT_EQ(outputs[0], outputs[2]) << model[1];
  }
}

// Piped eval output beyond the in-memory limit (16 MiB) goes through the temporary file: the same
// bytes, and a bad last line still leaves stdout empty.
TEST_F(CliHabits, LongPipedEvalIsTheSameAndABadLastLineLeavesStdoutEmpty) {
  constexpr size_t kLines = 420000;  // ~20 MB of output
  std::string in;
  in.reserve(kLines * 26);
  for (size_t i = 0; i < kLines; ++i) in += i % 2 ? "0 0 1 0 0 1\n" : "0.3 0.1 0.9 -0.2 0.4 0.8\n";
  const std::string file = write("in.txt", in);
  const Result few = run({"eval", "-m", "brushed-gold"}, "0.3 0.1 0.9 -0.2 0.4 0.8\n0 0 1 0 0 1\n");
  ASSERT_EQ(few.code, 0) << few.err;
  const Result r = run_redirected({"eval", "-m", "brushed-gold"}, "< " + shell_quote(file));
  ASSERT_EQ(r.code, 0) << r.err;
  std::string expected;
  expected.reserve(few.out.size() * kLines / 2);
  for (size_t i = 0; i < kLines / 2; ++i) expected += few.out;
  EXPECT_GT(expected.size(), size_t(16) << 20);
  EXPECT_TRUE(r.out == expected) << r.out.size() << " bytes, expected " << expected.size();
  write("in.txt", in + "0 0 1 0 0\n");
  const Result bad = run_redirected({"eval", "-m", "brushed-gold"}, "< " + shell_quote(file));
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.out, "");
  EXPECT_TRUE(contains(bad.err, fmt::format("stdin line {}", kLines + 1))) << bad.err;
}

// export-glsl writes the library functions the material uses; --full the whole library. Both
// compile (glslangValidator) with a user's shader calling every entry point.
TEST_F(CliHabits, ExportGlslWritesWhatTheMaterialNeeds) {
  const std::string lafortune =
      R"({"model": "lafortune", "rho_d": 0.1, "lobes": [{"cxy": -1, "cz": 1, "n": 20}, {"cxy": -0.5, "cz": 0.8, "n": 5}]})";
  const auto lines = [](const std::string& s) { return std::count(s.begin(), s.end(), '\n'); };
  for (const std::string& m :
       {lafortune, std::string("brushed-gold"), std::string("clay"), std::string("ngan/ashikhminshirley/nickel")}) {
    const Result minimal = run({"export-glsl", "-m", m}), full = run({"export-glsl", "-m", m, "--full"});
    ASSERT_EQ(minimal.code, 0) << minimal.err;
    ASSERT_EQ(full.code, 0) << full.err;
    // A metal keeps about half (its kernel struct holds every specular lobe kind), the others less.
    EXPECT_LT(lines(minimal.out), lines(full.out) * 6 / 10) << m;
    EXPECT_FALSE(contains(minimal.out, "aniso_material()")) << m;
    EXPECT_TRUE(contains(full.out, "Material aniso_material()")) << m;
    if (std::string(ANISO_GLSLANG).empty()) continue;
    const std::string user =
        "out vec4 color;\nvoid main() {\n  vec3 w; float p;\n"
        "  vec3 wi = aniso_sample(vec3(0.0, 0.0, 1.0), vec3(0.5), w, p);\n"
        "  color = vec4(aniso_f(wi, vec3(0.0, 0.0, 1.0)) + aniso_f_world(vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), "
        "vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)) + w, aniso_pdf(wi, vec3(0.0, 0.0, 1.0)) + p);\n}\n";
    for (const Result* r : {&minimal, &full}) {
      const std::string file = write("shader.frag", "#version 330 core\n" + r->out + user);
      const std::string cmd = fmt::format("{} {} > {} 2>&1", shell_quote(ANISO_GLSLANG), shell_quote(file),
                                          shell_quote((dir_ / "glslang.txt").string()));
      EXPECT_EQ(std::system(cmd.c_str()), 0) << m << (r == &full ? " --full" : "") << ": " << read_file(dir_ / "glslang.txt");
    }
  }
  // The lecture's two-lobe Lafortune: 1224 lines with the whole library, 299 without.
  const Result r = run({"export-glsl", "-m", lafortune});
  EXPECT_LT(lines(r.out), 350) << r.out;
}

// BRDF Explorer's sliders are linear: open-ended ranges (exponents, Lafortune's scale) end near the
// material's value, not at the table's 1e6.
TEST_F(CliHabits, ExportBrdfSlidersHaveUsefulRanges) {
  const Result r = run({"export-brdf", "-m", R"({"model": "lafortune", "lobes": [{"cxy": -1, "cz": 1, "n": 20}]})"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  int sliders = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("float ", 0) != 0) continue;
    std::istringstream f(line.substr(6));
    std::string name;
    double lo = 0, hi = 0, value = 0;
    f >> name >> lo >> hi >> value;
    EXPECT_LE(hi, 1000.0) << line;
    EXPECT_GE(hi, value) << line;
    EXPECT_LE(lo, value) << line;
    ++sliders;
  }
  EXPECT_GT(sliders, 5);
  EXPECT_TRUE(contains(r.out, "float lobes0_n_r 0 1000 20\n")) << r.out;
}

// `--set alpha_x=0.3` on a metal, whose alpha_x belongs to its lobe (the help's own example).
TEST(ViewSet, ATopLevelKeyOfANestedObjectSuggestsItsPath) {
  view::MaterialSlot slot = view::load_slot("brushed-gold");
  try {
    view::apply_assignment(slot, "alpha_x=0.3");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "unknown key \"alpha_x\"")) << e.what();
    EXPECT_TRUE(contains(e.what(), "did you mean lobe.alpha_x?")) << e.what();
  }
  view::apply_assignment(slot, "lobe.alpha_x=0.3");
  EXPECT_EQ(slot.edit["lobe"]["alpha_x"], 0.3);
}

}  // namespace
}  // namespace aniso
