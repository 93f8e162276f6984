// Text from inputs that reaches a written file or the terminal (src/io/text_escape.h): file names,
// --name, a scene object's name, a tensor file's description and field names, holding line breaks,
// quotes, comment ends, control bytes, C1 controls, line separators and bytes that are not UTF-8.
// Every exported file must parse in its own grammar with no input text turned into code (issue 40's
// reproducers: a file name that put live Python on line 2 of a Blender script, a pbrt-v4 directive
// through the same comment), and no control byte or invalid UTF-8 may reach the terminal.
#include <algorithm>
#include <cstdlib>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"
#include "cli_fixture.h"
#include "io/text_escape.h"
#include "test_util.h"

namespace aniso {
namespace {

// ---- the escape functions ---------------------------------------------------------------------------

TEST(TextEscape, ControlBytesLineBreaksAndC1AreEscaped) {
  EXPECT_EQ(text_escape("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(text_escape(std::string("x\0y", 3)), "x\\u0000y");
  EXPECT_EQ(text_escape("\x1b[31m\x07\x7f"), "\\u001b[31m\\u0007\\u007f");
  EXPECT_EQ(text_escape("\xc2\x9b"
                        "2J"),
            "\\u009b2J");                                                    // C1 CSI
  EXPECT_EQ(text_escape("x\xef\xbf\xbey\xef\xbf\xbf"), "x\\ufffey\\uffff");  // XML 1.0 refuses them
  EXPECT_EQ(text_escape("a\xe2\x80\xa8"
                        "b\xe2\x80\xa9"),
            "a\\u2028b\\u2029");  // line, paragraph separators
  EXPECT_EQ(terminal_text("one\ntwo\tthree\r\x1b"), "one\ntwo\tthree\\r\\u001b");
}

TEST(TextEscape, InvalidUtf8BecomesHexAndValidTextStays) {
  EXPECT_EQ(text_escape("caf\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x98\x80"), "caf\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x98\x80");
  EXPECT_EQ(text_escape("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(text_escape("\xc0\x80"), "\\xc0\\x80");                    // overlong NUL
  EXPECT_EQ(text_escape("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a UTF-16 surrogate
  EXPECT_EQ(text_escape("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
  EXPECT_EQ(text_escape("\xe6\x97"), "\\xe6\\x97");                    // cut short
  EXPECT_EQ(first_invalid_utf8("ok \xc3\xa9"), std::nullopt);
  EXPECT_EQ(first_invalid_utf8("ok \xc3"), std::optional<size_t>(3));
  // Whatever the bytes, the result is UTF-8 without a control character.
  std::string all;
  for (int i = 0; i < 256; ++i) all += char(i);
  const std::string e = text_escape(all + all.substr(128) + "\xe2\x80");
  EXPECT_EQ(first_invalid_utf8(e), std::nullopt);
  for (char c : e) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || c == 0x7f) << e;
}

bool has_raw_control(const std::string& s) {
  for (char c : s)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') || c == 0x7f) return true;
  return first_invalid_utf8(s).has_value();
}

// ---- exports with hostile text ---------------------------------------------------------------------

using HostileText = Cli;

const std::string kInjection = "m\nimport os; os.system(\"touch PWNED\")\n#";
// Quotes, backslash, XML's comment and tag ends, CR / LF with a pbrt-v4 directive, control bytes
// (ESC, BEL), a C1 control (CSI), a line separator and the noncharacter U+FFFE, in one text: one
// export per target tries all.
const std::string kHostile =
    "q\"uo'te \\ back </scene><!-- -- --> ]]> cr\rlf\r\nAttributeBegin\n ctl\x01\x02\x1b[31m\x07 c1\xc2\x9b"
    "2J \xe2\x80\xa8 \xef\xbf\xbe end";
const std::string kNotUtf8 = "not utf8 \xff\xfe\xc0";

bool have_python() { return std::system("command -v python3 > /dev/null 2>&1") == 0; }

// Python: the script parses and holds no call the export did not write (the injected os.system).
void expect_clean_python(const std::string& script, const std::string& why) {
  if (!have_python()) return;
  const std::string check =
      "import ast, sys\n"
      "t = ast.parse(open(sys.argv[1], 'rb').read())\n"
      "names = {n.id for n in ast.walk(t) if isinstance(n, ast.Name)} | {n.attr for n in ast.walk(t) if isinstance(n, "
      "ast.Attribute)}\n"
      "sys.exit(3 if 'os' in names or 'system' in names else 0)\n";
  EXPECT_EQ(std::system(("python3 -c " + shell_quote(check) + " " + shell_quote(script)).c_str()), 0) << why;
}

// XML: a real parser (Python's expat), which refuses what is not well formed or not UTF-8.
void expect_well_formed_xml(const std::string& file, const std::string& why) {
  if (!have_python()) return;
  EXPECT_EQ(std::system(("python3 -c 'import sys, xml.etree.ElementTree as E; E.parse(sys.argv[1])' " + shell_quote(file) +
                         " 2>/dev/null")
                            .c_str()),
            0)
      << why << "\n"
      << read_file(file);
}

// pbrt-v4: every line outside a comment is one of the statements the writer makes
// (MakeNamedMaterial and its parameter lines), so no input text became a directive.
void expect_pbrt_statements_only(const std::string& text, const std::string& why) {
  std::istringstream in(text);
  static const std::regex statement(R"re(^(MakeNamedMaterial "[A-Za-z0-9_-]+"|    "[a-z]+ [A-Za-z_]+" .*)?$)re");
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("#")) {
      EXPECT_EQ(line.find('\r'), std::string::npos) << why;
      continue;
    }
    EXPECT_TRUE(std::regex_match(line, statement)) << why << ": " << line;
  }
}

void expect_file_in_grammar(const std::string& target, const std::string& file, const std::string& why) {
  const std::string text = read_file(file);
  EXPECT_EQ(first_invalid_utf8(text), std::nullopt) << why;
  EXPECT_EQ(text.find("PWNED\")\n"), std::string::npos) << why;
  if (target == "blender") expect_clean_python(file, why);
  if (target == "pbrt-v4") expect_pbrt_statements_only(text, why);
  if (target == "mitsuba3" || target == "materialx" || target == "openpbr") expect_well_formed_xml(file, why);
  if (target == "gltf") {
    EXPECT_NO_THROW({
      const nlohmann::json j = nlohmann::json::parse(text);
      EXPECT_TRUE(j.is_object()) << why;
    }) << why;
  }
}

const char* const kTargets[] = {"blender", "mitsuba3", "pbrt-v4", "materialx", "openpbr", "gltf"};
const char* const kGgx = R"({"model": "ggx", "kd": 0.2, "f0": 0.04, "alpha_x": 0.1, "alpha_y": 0.3})";

// The source's file name (the comment's "from ..."): issue 40's reproducer and the other hostile texts.
TEST_F(HostileText, MaterialFileNamesStayInTheComment) {
  std::string hostile_file = kHostile;
  std::replace(hostile_file.begin(), hostile_file.end(), '/', '_');
  const std::vector<std::string> names = {kInjection, hostile_file, kNotUtf8};
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string material = write(names[i] + ".json", kGgx);
    for (const char* target : kTargets) {
      const std::string out = (dir_ / (std::string("f") + std::to_string(i) + "-" + target + ".gltf")).string();
      const Result r = run({"export", "--to", target, "--material", material, "-o", out, "--grid", "2", "--starts", "1"});
      const std::string why = std::string(target) + ", file name #" + std::to_string(i);
      ASSERT_EQ(r.code, 0) << why << ": " << r.err;
      expect_file_in_grammar(target, out, why);
    }
  }
  EXPECT_FALSE(fs::exists(dir_ / "PWNED"));
}

// --name: written as the target's name (an identifier, a Python or JSON string), never as code;
// text that is not UTF-8 is refused naming the option (exit 2, nothing written).
TEST_F(HostileText, NamesAreEscapedOrRefused) {
  for (const std::string& name : {kInjection, kHostile})
    for (const char* target : kTargets) {
      const std::string out = (dir_ / (std::string("n-") + target + ".gltf")).string();
      const Result r = run({"export", "--to", target, "--material", kGgx, "--name", name, "-o", out, "--grid", "2"});
      ASSERT_EQ(r.code, 0) << target << ": " << r.err;
      expect_file_in_grammar(target, out, target);
    }
  const std::string out = (dir_ / "bad.gltf").string();
  const Result r = run({"export", "--to", "gltf", "--material", kGgx, "--name", kNotUtf8, "-o", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(r.err.find("--name: expected UTF-8 text") != std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir_ / "bad.bin"));
  // The Blender script's NAME holds the name exactly (a carriage return included: issue 40, item 2).
  if (!have_python()) return;
  const std::string script = (dir_ / "cr.py").string();
  ASSERT_EQ(run({"export", "--to", "blender", "--material", kGgx, "--name", "a\rb\"c", "-o", script, "--grid", "2"}).code, 0);
  const std::string check =
      "import ast, sys\nt = ast.parse(open(sys.argv[1]).read())\n"
      "v = [n.value.value for n in t.body if isinstance(n, ast.Assign) and getattr(n.targets[0], 'id', '') == 'NAME']\n"
      "sys.exit(0 if v == ['a\\rb\"c'] else 3)\n";
  EXPECT_EQ(std::system(("python3 -c " + shell_quote(check) + " " + shell_quote(script)).c_str()), 0) << read_file(script);
}

// Through a scene: the object's name and its material's file name reach the comment and the name.
TEST_F(HostileText, SceneObjectNamesStayInTheComment) {
  const std::string material = write("mat\nAttributeBegin\nimport os; os.system(\"touch PWNED\")\n#.json", kGgx);
  nlohmann::json scene = {
      {"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}}},
      {"objects", {{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"name", kInjection}, {"material", material}}}}};
  const std::string path = write("s.json", scene.dump());
  for (const char* target : kTargets) {
    const std::string out = (dir_ / (std::string("s-") + target + ".gltf")).string();
    const Result r = run({"export", "--to", target, "--scene", path, "--object", "0", "-o", out, "--grid", "2", "--starts", "1"});
    ASSERT_EQ(r.code, 0) << target << ": " << r.err;
    expect_file_in_grammar(target, out, target);
  }
  EXPECT_FALSE(fs::exists(dir_ / "PWNED"));
}

// The data's file name goes into the fitted material's provenance (JSON: UTF-8 only) and a tensor
// file's description: a name that is not UTF-8 is written escaped, not a JSON type error after the
// fit's work (issue 40, item 2).
TEST_F(HostileText, FitAndExportRglOfAFileWhoseNameIsNotUtf8) {
  std::string csv = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n";
  for (int ti = 5; ti < 90; ti += 20)
    for (int to = 5; to < 90; to += 20)
      for (int po = 0; po < 360; po += 45) csv += fmt::format("{},0,{},{},0.3,0.2,0.1\n", ti, to, po);
  const std::string data = write("d\xff\x1b.csv", csv);
  const std::string fitted = (dir_ / "f.json").string();
  const Result r = run({"fit", data, "--model", "lambert", "--starts", "1", "-o", fitted});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(has_raw_control(r.out)) << r.out;
  EXPECT_EQ(nlohmann::json::parse(read_file(fitted))["fit"]["data"], text_escape(data));

  const std::string bsdf = (dir_ / "g\xff.bsdf").string();
  ASSERT_EQ(run({"export-rgl", "-m", "gold", "-o", bsdf, "--resolution", "8", "--theta-i", "4", "--ndf", "16"}).code, 0);
  const Result e = run({"export-rgl", "-m", bsdf, "-o", (dir_ / "h.bsdf").string()});
  EXPECT_EQ(e.code, 0) << e.err;
}

// ---- every output checked before any is written ------------------------------------------------------

TEST_F(HostileText, GltfBufferCannotOverwriteTheDocument) {
  const std::string out = (dir_ / "x.bin").string();
  const Result r = run({"export", "--to", "gltf", "--material", "gold", "-o", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(r.err.find("give -o FILE.gltf") != std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(HostileText, AnUnwritablePreviewWritesNothing) {
  const std::string out = (dir_ / "p.pbrt").string();
  const Result r = run({"export", "--to", "pbrt-v4", "--material", "gold", "--preview", (dir_ / "nope" / "p.png").string(), "-o",
                        out, "--grid", "2"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(r.err.find("--preview") != std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  const Result g = run({"export", "--to", "gltf", "--material", "gold", "--preview", (dir_ / "nope" / "p.png").string(), "-o",
                        (dir_ / "g.gltf").string(), "--grid", "2"});
  EXPECT_EQ(g.code, 2) << g.err;
  EXPECT_FALSE(fs::exists(dir_ / "g.gltf"));
  EXPECT_FALSE(fs::exists(dir_ / "g.bin"));
}

// ---- the terminal ---------------------------------------------------------------------------------

TEST_F(HostileText, ATensorFilesDescriptionAndFieldNamesReachTheTerminalEscaped) {
  // A valid tensor file's fields, its description holding ESC, BEL and NUL; then a field named with
  // control bytes in a file that is otherwise broken, whose message must be whole.
  const std::string description("film \x1b]0;owned\x07 \0 \xff end", sizeof "film \x1b]0;owned\x07 \0 \xff end" - 1);
  rgl::BrdfSource src = rgl::brdf_source(build_material<double>(load_material(kGgx)));
  src.description = description;
  const rgl::ExportOptions small = test::small_rgl_options(true);
  const auto bytes = [](const std::vector<uint8_t>& b) { return std::string(b.begin(), b.end()); };
  const std::string desc_file = write("d.bsdf", bytes(rgl::serialize_tensor(rgl::export_rgl(src, small))));
  const Result d = run({"presets", "--show", desc_file});
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_TRUE(d.out.find("film \\u001b]0;owned\\u0007 \\u0000 \\xff end") != std::string::npos) << d.out;
  EXPECT_FALSE(has_raw_control(d.out + d.err)) << d.out << d.err;

  // Byte 28: the dtype of the first field (header 18 bytes, name length 2, the 6-byte name, ndim 2);
  // code 0 is none, and the message names the field.
  const std::vector<float> v{1.f, 2.f};
  std::string broken =
      bytes(rgl::serialize_tensor({rgl::make_field(std::string("ndf\x02\0x", 6), {2}, std::span<const float>(v))}));
  broken[28] = 0;
  const Result b = run({"presets", "--show", write("b.bsdf", broken)});
  EXPECT_EQ(b.code, 2) << b.err;
  EXPECT_FALSE(has_raw_control(b.out + b.err)) << b.err;
  EXPECT_TRUE(b.err.find("field \"ndf\\u0002\\u0000x\": unknown dtype code 0") != std::string::npos) << b.err;
}

}  // namespace
}  // namespace aniso
