// tests/test_glsl_exports.cpp: `aniso export-glsl` and `aniso export-brdf`, run as the CLI. The
// exported GLSL compiles as GLSL 3.30 core and ES 3.00, defines only aniso_ names, and its aniso_f,
// aniso_pdf and aniso_f_world match `aniso eval`; the .brdf file has BRDF Explorer's format, its
// shader compiles in BRDF Explorer's template and, with its parameters set as uniforms the way
// BRDF Explorer sets them, matches `aniso eval`. Bad materials are rejected as `aniso eval`
// rejects them, and no file is written.
#include <sys/wait.h>

#include <filesystem>
#include <sstream>

#include "aniso/core/frame.h"
#include "aniso/io/presets.h"
#include "glsl_util.h"
#include "test_util.h"

namespace aniso::test {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  std::string out, err;
  int code = -1;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CliRun run_cli(const std::string& args, const std::string& stdin_text = "") {
  const fs::path dir = fs::path(::testing::TempDir()) / fmt::format("aniso_glsl_cli_{}", getpid());
  fs::create_directories(dir);
  const fs::path in = dir / "in.txt", out = dir / "out.txt", err = dir / "err.txt";
  {
    std::ofstream f(in);
    f << stdin_text;
  }
  const std::string cmd = fmt::format("{} {} < {} > {} 2> {}", ANISO_CLI, args, in.string(), out.string(), err.string());
  const int st = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
  r.out = slurp(out);
  r.err = slurp(err);
  std::error_code ec;
  fs::remove_all(dir, ec);
  return r;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

// Materials given to the CLI: JSON files for the test materials, preset names for the presets.
struct CliMaterial {
  std::string name, arg;
};
void PrintTo(const CliMaterial& c, std::ostream* os) { *os << c.name; }

// The test materials go inline (`-m '{...}'`): no files, so nothing is left in the temporary
// directory by the many processes ctest starts (each one registers these parameters).
std::vector<CliMaterial> cli_materials() {
  std::vector<CliMaterial> v;
  for (const NamedMaterial& m : all_model_materials()) v.push_back({m.name, m.json.dump()});
  for (const char* p : {"matte-steel", "clay", "gold", "brushed-copper"}) v.push_back({std::string("preset_") + p, p});
  return v;
}

struct Pairs {
  std::vector<glm::vec3> wi, wo, u;
  std::string eval_input;
};

Pairs pairs() {
  Pairs p;
  Rng rng(66);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 wo = random_upper<float>(rng);
    glm::vec3 wi = i % 2 ? random_upper<float>(rng)
                         : glm::normalize(glm::vec3(-wo.x, -wo.y, wo.z) +
                                          0.1f * glm::vec3(float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), 0.f));
    if (!(wi.z > 0.01f)) wi = glm::normalize(glm::vec3(wi.x, wi.y, 0.01f));
    p.wi.push_back(wi);
    p.wo.push_back(wo);
    p.u.push_back(glm::vec3(float(rng.uniform()), float(rng.uniform()), float(rng.uniform())));
    // The float directions exactly, so that eval (double) sees the same pair.
    p.eval_input += fmt::format("{:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
  }
  return p;
}

std::vector<std::array<double, 4>> eval_lines(const std::string& out) {
  std::vector<std::array<double, 4>> v;
  std::istringstream in(out);
  std::array<double, 4> a;
  while (in >> a[0] >> a[1] >> a[2] >> a[3]) v.push_back(a);
  return v;
}

// A random world frame: L, V in world space, and the same pair in the local frame.
struct World {
  glm::vec3 N, X, Y;
};
World random_world(Rng& rng) {
  const glm::vec3 n =
      glm::normalize(glm::vec3(float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), float(rng.uniform() - 0.5)));
  const aniso::Frame f = aniso::Frame::from_normal_tangent(n, glm::vec3(0.3f, 1.f, -0.2f));
  return {f.n, f.t, f.b};
}

class GlslExport : public ::testing::TestWithParam<CliMaterial> {};

TEST_P(GlslExport, ExportGlslCompilesAndMatchesEval) {
  const CliMaterial& m = GetParam();
  const fs::path file = fs::path(::testing::TempDir()) / fmt::format("aniso_export_{}_{}.glsl", m.name, getpid());
  const CliRun r = run_cli("export-glsl -m " + quote(m.arg) + " -o " + quote(file.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string src = slurp(file);
  fs::remove(file);
  // No #version (nor any preprocessor line) and no main: the user's shader brings both.
  std::istringstream lines(src);
  for (std::string line; std::getline(lines, line);)
    EXPECT_NE(line.find_first_not_of(" \t") == std::string::npos ? ' ' : line[line.find_first_not_of(" \t")], '#') << line;
  EXPECT_EQ(gl::glsl_declared_names(src).count("main"), 0u);
  for (const std::string& name : gl::glsl_declared_names(src))
    EXPECT_EQ(name.rfind("aniso_", 0), 0u) << "export-glsl defines \"" << name << "\" without the aniso_ prefix";
  // A user's shader that defines the library's plain names as well: no clash.
  const std::string user =
      "float sqr(float x) { return x; }\nstruct Material { int kind; };\nconst float kPi = 3.0;\n"
      "out vec4 color;\nvoid main() {\n  vec3 w; float p;\n"
      "  vec3 wi = aniso_sample(vec3(0.0, 0.0, 1.0), vec3(0.5), w, p);\n"
      "  color = vec4(aniso_f(wi, vec3(0.0, 0.0, 1.0)) + aniso_f_world(vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), "
      "vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)) + w, aniso_pdf(wi, vec3(0.0, 0.0, 1.0)) + p);\n}\n";
  if (!std::string(ANISO_GLSLANG).empty()) {
    for (gl::GlslDialect d : {gl::GlslDialect::Core330, gl::GlslDialect::Es300})
      EXPECT_EQ(glslang_errors(gl::glsl_preamble(d) + src + user, "frag", "export"), "")
          << (d == gl::GlslDialect::Core330 ? "GLSL 3.30 core" : "GLSL ES 3.00");
  }

  ANISO_REQUIRE_GL();
  const Pairs p = pairs();
  const CliRun ev = run_cli("eval -m " + quote(m.arg), p.eval_input);
  ASSERT_EQ(ev.code, 0) << ev.err;
  const auto ref = eval_lines(ev.out);
  ASSERT_EQ(ref.size(), p.wi.size());
  const Material cpu = build_material<float>(load_material(m.arg));
  const MaterialD cpu_d = build_material<double>(load_material(m.arg));
  // aniso_f and aniso_pdf in the local frame; aniso_f_world with the pair in a random world frame.
  Rng rng(3);
  std::vector<glm::vec3> L(p.wi.size()), V(p.wi.size()), N(p.wi.size()), X(p.wi.size()), Y(p.wi.size());
  std::vector<glm::vec3> frame_in(3 * p.wi.size());
  for (size_t i = 0; i < p.wi.size(); ++i) {
    const World w = random_world(rng);
    frame_in[3 * i] = w.N;
    frame_in[3 * i + 1] = w.X;
    frame_in[3 * i + 2] = w.Y;
    L[i] = p.wi[i].x * w.X + p.wi[i].y * w.Y + p.wi[i].z * w.N;
    V[i] = p.wo[i].x * w.X + p.wo[i].y * w.Y + p.wo[i].z * w.N;
  }
  // Pass 1: local frame. Pass 2: world frame, the frame packed into u's slot... kept simple:
  // two runs of the same kernel shape.
  const auto local = run_pairs(src,
                               "  f = aniso_f(wi, wo);\n  pdf = aniso_pdf(wi, wo);\n"
                               "  vec3 weight; float spdf;\n  vec3 swi = aniso_sample(wo, u, weight, spdf);\n"
                               "  s = BSDFSample(swi, weight, spdf, spdf > 0.0);\n",
                               p.wi, p.wo, p.u);
  // World: wi <- L, wo <- V, and u carries the index into a frame table in a second buffer.
  std::vector<glm::vec3> idx(p.wi.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = glm::vec3(float(i), 0.f, 0.f);
  std::vector<glm::vec4> frames(frame_in.size());
  for (size_t i = 0; i < frames.size(); ++i) frames[i] = glm::vec4(frame_in[i], 0.f);
  gl::StorageBuffer fb(2, frames.size() * sizeof(glm::vec4), frames.data());
  const auto world = run_pairs(src + "layout(std430, binding = 2) readonly buffer Frames { vec4 frames[]; };\n",
                               "  int k = int(u.x);\n"
                               "  f = aniso_f_world(wi, wo, frames[3 * k].xyz, frames[3 * k + 1].xyz, frames[3 * k + 2].xyz);\n",
                               L, V, idx);
  const double tol = 1e-4;
  int bad = 0;
  for (size_t i = 0; i < ref.size() && bad < 10; ++i) {
    bool ok = true;
    for (int c = 0; c < 3; ++c) {
      if (!close(local[i].f[c], ref[i][c], tol)) {
        ADD_FAILURE() << m.name << ": aniso_f channel " << c << " = " << local[i].f[c] << ", aniso eval " << ref[i][c]
                      << " at pair " << i;
        ok = false;
      }
      // World space: the frame change costs a few float roundings on wi and wo, so 1e-3.
      if (!close(world[i].f[c], ref[i][c], 1e-3, 1e-5)) {
        ADD_FAILURE() << m.name << ": aniso_f_world channel " << c << " = " << world[i].f[c] << ", aniso eval " << ref[i][c]
                      << " at pair " << i;
        ok = false;
      }
    }
    // `aniso eval` normalises its input in double, so it evaluates a direction up to 6e-8 away from
    // the float pair the GPU sees. Where the pdf is that ill-conditioned (both directions grazing
    // and nearly opposite: |wi + wo| ~ 0.03, the half vector amplifies the difference; principled's
    // clearcoat at pair 190 moves by 1.8e-4), the reference is the double kernel at the float pair.
    const double pdf_at_pair = cpu_d.pdf(Vec3d(p.wi[i]), Vec3d(p.wo[i]));
    const double pdf_ref = close(pdf_at_pair, ref[i][3], tol) ? ref[i][3] : pdf_at_pair;
    if (!close(local[i].pdf, pdf_ref, tol)) {
      ADD_FAILURE() << m.name << ": aniso_pdf = " << local[i].pdf << ", aniso eval " << ref[i][3]
                    << ", double kernel at the float pair " << pdf_at_pair << " at pair " << i;
      ok = false;
    }
    // aniso_sample: the C++ float sampler fed the same u (u.x picks the lobe, u.yz the direction).
    const BSDFSampleT<float> cs = cpu.sample(p.wo[i], p.u[i].x, Vec2(p.u[i].y, p.u[i].z));
    if (local[i].sample_valid != cs.valid) {
      ADD_FAILURE() << m.name << ": aniso_sample gives " << (local[i].sample_valid ? "a sample" : "no sample")
                    << ", C++ the opposite, at pair " << i;
      ok = false;
    } else if (cs.valid) {
      // Within 1e-4 of the C++ float sampler, except where that sampler is itself more than 1e-5
      // from double: for u.z near 0 the pow-based samplers (AS_SampleHalf, sample_cosine_power) take
      // sin(theta) from 1 - cos^2 with cos within 1e-6 of 1, which keeps only a few bits in float
      // (Ashikhmin-Shirley, u.z = 7e-5,
      // grazing wo: C++ float is 2.6e-5 from double in wi.z, llvmpipe's pow puts GLSL at 1.05e-4).
      // There GLSL is held to 8 times the C++ float error, against double. A weakness of the
      // kernels (C++ and GLSL alike), not a drift between them.
      const BSDFSampleT<double> ds = cpu_d.sample(Vec3d(p.wo[i]), double(p.u[i].x), Vec2T<double>(p.u[i].y, p.u[i].z));
      const float own = ds.valid ? glm::length(Vec3(ds.wi) - cs.wi) : 0.f;
      const bool ill = own > 1e-5f && own < 1e-3f;  // beyond 1e-3 float and double chose different lobes
      for (int c = 0; c < 3; ++c) {
        const float ref_c = ill ? float(ds.wi[c]) : cs.wi[c];
        if (!(std::abs(local[i].sample_wi[c] - ref_c) <= (ill ? 8.f * own : 1e-4f))) {
          ADD_FAILURE() << m.name << ": aniso_sample wi[" << c << "] = " << local[i].sample_wi[c] << ", C++ " << cs.wi[c]
                        << " (double " << ds.wi[c] << ") at pair " << i;
          ok = false;
        }
      }
    }
    if (!ok) ++bad;
  }
}

// --- BRDF Explorer ---------------------------------------------------------------------------

struct BrdfFile {
  struct Param {
    std::string type, name;
    std::vector<float> values;  // float: min max default; bool: value; color: r g b
  };
  std::vector<Param> params;
  std::string shader;
};

// Reads a .brdf file the way BRDF Explorer's BRDFBase::loadBRDF does: the first line's first
// token is the type, lines starting with '#' and blank lines are skipped everywhere, "::begin X"
// / "::end X" delimit sections, parameter lines are "float name min max default", "bool name v",
// "color name r g b".
BrdfFile parse_brdf(const std::string& text) {
  BrdfFile f;
  std::istringstream in(text);
  std::string line, section;
  std::getline(in, line);
  EXPECT_EQ(line.substr(0, line.find(' ')), "analytic");
  while (std::getline(in, line)) {
    const size_t a = line.find_first_not_of(" \t\r"), b = line.find_last_not_of(" \t\r");
    const std::string trimmed = a == std::string::npos ? "" : line.substr(a, b - a + 1);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    std::istringstream os(trimmed);
    std::string tok;
    os >> tok;
    if (tok == "::begin") {
      EXPECT_EQ(section, "") << "nested section";
      os >> section;
    } else if (tok == "::end") {
      os >> tok;
      EXPECT_EQ(tok, section);
      section.clear();
    } else if (section == "parameters") {
      BrdfFile::Param p;
      p.type = tok;
      os >> p.name;
      const int n = tok == "float" ? 3 : (tok == "bool" ? 1 : 3);
      EXPECT_TRUE(tok == "float" || tok == "bool" || tok == "color") << "parameter line: " << trimmed;
      for (int i = 0; i < n; ++i) {
        float v;
        EXPECT_TRUE(bool(os >> v)) << "parameter line: " << trimmed;
        p.values.push_back(v);
      }
      if (tok == "float") {
        EXPECT_LE(p.values[0], p.values[2]) << trimmed;
        EXPECT_LE(p.values[2], p.values[1]) << trimmed;
      }
      f.params.push_back(p);
    } else if (section == "shader") {
      f.shader += line + "\n";
    }
  }
  EXPECT_EQ(section, "");
  return f;
}

// The uniforms BRDF Explorer declares in front of the shader (BRDFBase::loadShaderFromFile).
std::string brdf_uniforms(const BrdfFile& f) {
  std::string s;
  for (const auto& p : f.params)
    if (p.type == "float") s += "uniform float " + p.name + ";\n";
  for (const auto& p : f.params)
    if (p.type == "bool") s += "uniform bool " + p.name + ";\n";
  for (const auto& p : f.params)
    if (p.type == "color") s += "uniform vec3 " + p.name + ";\n";
  return s;
}

TEST_P(GlslExport, ExportBrdfLoadsInBrdfExplorerAndMatchesEval) {
  const CliMaterial& m = GetParam();
  const fs::path file = fs::path(::testing::TempDir()) / fmt::format("aniso_export_{}_{}.brdf", m.name, getpid());
  const CliRun r = run_cli("export-brdf -m " + quote(m.arg) + " -o " + quote(file.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const BrdfFile f = parse_brdf(slurp(file));
  fs::remove(file);
  ASSERT_FALSE(f.shader.empty());
  EXPECT_NE(f.shader.find("vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"), std::string::npos);
  // BRDF Explorer's lit-sphere fragment template (#version 410), reduced to what touches BRDF().
  if (!std::string(ANISO_GLSLANG).empty()) {
    const std::string frag = "#version 410\nuniform vec3 incidentVector;\nout vec4 fragColor;\n" + brdf_uniforms(f) + "\n" +
                             f.shader +
                             "\nvoid main(void) {\n  vec3 normal = vec3(0, 0, 1);\n  vec3 tangent = vec3(1, 0, 0);\n"
                             "  vec3 bitangent = vec3(0, 1, 0);\n"
                             "  vec3 b = max(BRDF(incidentVector, vec3(0, 0, 1), normal, tangent, bitangent), vec3(0.0));\n"
                             "  fragColor = vec4(b, 1.0);\n}\n";
    EXPECT_EQ(glslang_errors(frag, "frag", "brdf"), "");
  }

  ANISO_REQUIRE_GL();
  const Pairs p = pairs();
  const CliRun ev = run_cli("eval -m " + quote(m.arg), p.eval_input);
  ASSERT_EQ(ev.code, 0) << ev.err;
  const auto ref = eval_lines(ev.out);
  // Local frame passed as world: N = z, X = x, Y = y.
  const auto g = run_pairs(brdf_uniforms(f) + f.shader,
                           "  f = BRDF(wi, wo, vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0));\n", p.wi, p.wo,
                           p.u, [&](const gl::ComputeProgram& prog) {
                             // As BRDFBase::adjustShaderPreRender: setUniformFloat / setUniformInt / 3 floats.
                             for (const auto& q : f.params) {
                               if (q.type == "float") prog.set(q.name, q.values[2]);
                               if (q.type == "bool") prog.set(q.name, int(q.values[0]));
                               if (q.type == "color") prog.set(q.name, glm::vec3(q.values[0], q.values[1], q.values[2]));
                             }
                           });
  int bad = 0;
  for (size_t i = 0; i < ref.size() && bad < 10; ++i)
    for (int c = 0; c < 3; ++c)
      if (!close(g[i].f[c], ref[i][c], 1e-4)) {
        ADD_FAILURE() << m.name << ": .brdf BRDF() channel " << c << " = " << g[i].f[c] << ", aniso eval " << ref[i][c]
                      << " at pair " << i;
        ++bad;
      }
}

std::string cli_name(const ::testing::TestParamInfo<CliMaterial>& info) {
  std::string s = info.param.name;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(All, GlslExport, ::testing::ValuesIn(cli_materials()), cli_name);

TEST(GlslExportErrors, BadMaterialsAreRejectedLikeEvalAndWriteNoFile) {
  const fs::path dir = fs::path(::testing::TempDir()) / fmt::format("aniso_glsl_bad_{}", getpid());
  fs::create_directories(dir);
  const fs::path bad = dir / "bad.json";
  std::ofstream(bad) << R"({"model": "ward", "alpha_x": 0})";
  const fs::path nolobe = dir / "dd.json";
  std::ofstream(nolobe)
      << R"({"model": "metal", "metal": "gold", "lobe": {"model": "ggx"}, "directional_diffuse": {"cxy": 0, "cz": 0}})";
  for (const fs::path& m : {bad, nolobe, dir / "missing.json"}) {
    const CliRun ev = run_cli("eval -m " + quote(m.string()), "0 0 1 0 0 1\n");
    for (const char* cmd : {"export-glsl", "export-brdf"}) {
      const fs::path out = dir / "out.txt";
      fs::remove(out);
      const CliRun r = run_cli(std::string(cmd) + " -m " + quote(m.string()) + " -o " + quote(out.string()));
      EXPECT_EQ(r.code, ev.code) << cmd << " " << m;
      EXPECT_EQ(r.code, 2) << cmd << " " << m;
      EXPECT_EQ(r.err, ev.err) << cmd << " " << m;
      EXPECT_EQ(r.err.rfind("aniso: error: ", 0), 0u) << r.err;
      EXPECT_FALSE(fs::exists(out)) << cmd << " wrote a file for a bad material";
      for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << "left behind " << e.path();
    }
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace aniso::test

namespace aniso::test {
namespace {

// An inline JSON material written over several lines: its name in the header comments must not
// break the GLSL or the .brdf.
TEST(GlslExportInline, MultiLineInlineMaterial) {
  const std::string inline_json = "{\"model\": \"ward\",\n \"alpha_x\": 0.1,\n \"alpha_y\": 0.3}";
  const CliRun g = run_cli("export-glsl -m " + quote(inline_json));
  ASSERT_EQ(g.code, 0) << g.err;
  if (!std::string(ANISO_GLSLANG).empty()) {
    EXPECT_EQ(glslang_errors(gl::glsl_preamble(gl::GlslDialect::Core330) + g.out + "void main() {}\n", "frag", "inline"), "");
  }
  const CliRun b = run_cli("export-brdf -m " + quote(inline_json));
  ASSERT_EQ(b.code, 0) << b.err;
  const BrdfFile f = parse_brdf(b.out);
  EXPECT_EQ(f.params.size(), 7u);  // kd, ks, alpha_x, alpha_y, form, normalization, rotation_deg
}

}  // namespace
}  // namespace aniso::test
