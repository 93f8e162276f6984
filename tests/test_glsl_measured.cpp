// tests/test_glsl_measured.cpp: the GLSL twins of the measured materials (include/aniso/brdf/rgl.glsl,
// measured.glsl) reading their tables from the tables texture (gl::glsl_tables, docs/glsl.md
// "Measured materials"), against the C++ float kernels: f, pdf and sampling fed the same u, and the
// chi-square of the GLSL sampler against the C++ pdf. Instantiated over tensor files that aniso
// writes (isotropic and anisotropic, small grids), the RGL database's own files when
// ../shared/data/rgl-real/ is present, and MERL tables (analytic models tabulated).
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "aniso/gl/glsl_export.h"
#include "aniso/measured/measured.h"
#include "aniso/measured/merl.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"
#include "chi2.h"
#include "glsl_util.h"
#include "test_util.h"

namespace aniso::test {
namespace {

namespace fs = std::filesystem;

struct MeasuredCase {
  std::string name;
  std::string kind;       // "rgl", "merl", "real"
  nlohmann::json source;  // the analytic material tabulated; or the real file's path
};
void PrintTo(const MeasuredCase& c, std::ostream* os) { *os << c.name; }

fs::path scratch() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(::testing::TempDir()) / fmt::format("aniso_glsl_measured_{}", getpid());
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// The material of a case, loaded from a file as a user's would be (load_material), once per process.
const MaterialDesc& case_material(const MeasuredCase& c) {
  static std::map<std::string, MaterialDesc> cache;
  auto it = cache.find(c.name);
  if (it != cache.end()) return it->second;
  std::string path;
  if (c.kind == "real") {
    path = c.source.get<std::string>();
  } else if (c.kind == "rgl") {
    rgl::BrdfSource src = rgl::brdf_source(build<double>(c.source));
    src.description = c.source.dump();
    const std::vector<uint8_t> bytes = rgl::serialize_tensor(rgl::export_rgl(src, small_rgl_options()));
    path = (scratch() / (c.name + ".bsdf")).string();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  } else {
    path = (scratch() / (c.name + ".binary")).string();
    write_merl(path, tabulate_merl(build<double>(c.source)));
  }
  return cache.emplace(c.name, load_material(path)).first->second;
}

fs::path real_dir() { return fs::path(ANISO_SOURCE_DIR) / ".." / "shared" / "data" / "rgl-real"; }

std::vector<MeasuredCase> measured_cases() {
  std::vector<MeasuredCase> v = {
      {"rgl_ggx_iso", "rgl", {{"model", "ggx"}, {"kd", {0.2, 0.1, 0.05}}, {"f0", 0.04}, {"alpha", 0.2}}},
      {"rgl_ggx_aniso", "rgl", {{"model", "ggx"}, {"kd", 0.0}, {"f0", {0.9, 0.6, 0.3}}, {"alpha_x", 0.05}, {"alpha_y", 0.3}}},
      {"rgl_ward_aniso",
       "rgl",
       {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.3}, {"alpha_x", 0.1}, {"alpha_y", 0.3}, {"rotation_deg", 30.0}}},
      {"merl_ward", "merl", {{"model", "ward"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", 0.2}, {"alpha", 0.25}}},
      {"merl_ashikhmin_shirley", "merl", {{"model", "ashikhmin-shirley"}, {"rd", {0.2, 0.3, 0.4}}, {"rs", 0.1}, {"n", 100.0}}},
  };
  std::vector<std::string> real;
  if (fs::is_directory(real_dir()))
    for (const auto& e : fs::directory_iterator(real_dir()))
      if (e.path().extension() == ".bsdf") real.push_back(e.path().string());
  std::sort(real.begin(), real.end());
  for (const std::string& p : real) v.push_back({"real_" + fs::path(p).stem().string(), "real", p});
  if (real.empty()) v.push_back({"real_absent", "real", ""});
  for (auto& c : v)
    for (char& ch : c.name)
      if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return v;
}

#define ANISO_REQUIRE_CASE(c)                                      \
  if ((c).kind == "real" && (c).source.get<std::string>().empty()) \
  GTEST_SKIP() << "../shared/data/rgl-real/ is absent (CI has it): no real RGL file for the GLSL twin"

// Random pairs, near-mirror pairs (the highlight), grazing pairs, h = n and normal view, a few
// below the horizon (f = pdf = 0, "no sample").
Grid make_grid() {
  Grid g;
  Rng rng(16);
  auto add = [&](glm::vec3 a, glm::vec3 b, const char* k) { g.add(a, b, k, rng); };
  for (int i = 0; i < 300; ++i) add(random_upper<float>(rng), random_upper<float>(rng), "random");
  for (int i = 0; i < 150; ++i) {
    const glm::vec3 wo = random_upper<float>(rng);
    glm::vec3 wi = glm::vec3(-wo.x, -wo.y, wo.z) + 0.1f * glm::vec3(float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), 0.f);
    if (wi.z <= 0.01f) wi.z = 0.01f;
    add(wi, wo, "near-mirror");
  }
  for (int i = 0; i < 60; ++i)
    add(unit(M_PI / 2 - 0.06 * rng.uniform() - 1e-3, 2 * M_PI * rng.uniform()),
        unit(std::acos(rng.uniform()), 6.3 * rng.uniform()), "grazing");
  for (int i = 0; i < 30; ++i) {
    const glm::vec3 wo = random_upper<float>(rng);
    add(glm::vec3(-wo.x, -wo.y, wo.z), wo, "h = n");
  }
  add(glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), "normal");
  add(random_upper<float>(rng), glm::vec3(0, 0, 1), "normal view");
  for (int i = 0; i < 10; ++i) add(unit(M_PI / 2 + 0.5 * rng.uniform(), 6 * rng.uniform()), random_upper<float>(rng), "below");
  return g;
}

// The bound of a GLSL value from float arithmetic. GLSL's atan, sqrt and normalize are allowed
// more error than glibc's correctly rounded ones (llvmpipe's atan: ~1e-6 rad, 8 ulp; its acos was
// 6e-5 rad off, so rgl.glsl takes theta from atan), so the GLSL kernel sees its angles a few ulp
// off the C++'s, and the tables' interpolation turns that into a change of f in proportion to its
// slope. The bound of a pair is what such a perturbation does to the C++ kernel itself: the
// largest change of f (or pdf) when wi and wo are each turned by kJitter = 4e-6 rad (4 x that atan
// error) in 8 directions, times 4 (several angles err at once: theta and phi of wo and of the half
// vector), and at least 2e-4 relative (the largest difference seen on smooth aniso-written files,
// 1.8e-4, with room) or 1e-6 absolute. Where f is steep (a sharp real highlight, the pole of the
// tensor's sqrt(theta) parameterisation) the slope term governs; at a MERL bin edge (nearest-bin
// lookup: f steps) it is the step, so either neighbouring bin is accepted there.
constexpr double kJitter = 4e-6;

glm::vec3 turned(const glm::vec3& w, int k, int which) {
  glm::vec3 t, b;
  const glm::vec3 a = std::abs(w.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
  t = glm::normalize(glm::cross(a, w));
  b = glm::cross(w, t);
  const double ang = 2 * M_PI * (k + 0.5 * which) / 8.0;
  return glm::normalize(w + float(kJitter) * (float(std::cos(ang)) * t + float(std::sin(ang)) * b));
}

struct Bound {
  glm::dvec3 f{0.0};
  double pdf = 0.0;
};

Bound jitter_bound(const Material& m, const glm::vec3& wi, const glm::vec3& wo) {
  const RGB f0 = m.f(wi, wo);
  const float p0 = m.pdf(wi, wo);
  Bound b;
  for (int k = 0; k < 8; ++k)
    for (int which = 0; which < 3; ++which) {
      const glm::vec3 a = which != 1 ? turned(wi, k, which) : wi, c = which != 0 ? turned(wo, k, which) : wo;
      const RGB f = m.f(a, c);
      for (int ch = 0; ch < 3; ++ch) b.f[ch] = std::max(b.f[ch], 4.0 * std::abs(double(f[ch]) - double(f0[ch])));
      b.pdf = std::max(b.pdf, 4.0 * std::abs(double(m.pdf(a, c)) - double(p0)));
    }
  return b;
}

bool within(double gpu, double cpu, double bound) {
  if (!std::isfinite(gpu) || !std::isfinite(cpu)) return false;
  return std::abs(gpu - cpu) <= std::max({bound, 2e-4 * std::abs(cpu), 1e-6});
}

class GlslMeasured : public ::testing::TestWithParam<MeasuredCase> {};

TEST_P(GlslMeasured, MaterialMatchesCppFloat) {
  ANISO_REQUIRE_CASE(GetParam());
  ANISO_REQUIRE_GL();
  const MaterialDesc& d = case_material(GetParam());
  const Material cpu = build_material<float>(d);
  const gl::GlslMaterial gm = gl::glsl_material(d, gl::GlslStorage::Uniform, "u_");
  ASSERT_TRUE(gm.needs_tables);
  const gl::TablesTexture tex(gl::glsl_tables(d));
  tex.bind(0);
  const Grid g = make_grid();
  const auto r = run_pairs(gm.declarations + gm.code,
                           "  Material m = aniso_material();\n"
                           "  f = Material_f(m, wi, wo);\n  pdf = Material_pdf(m, wi, wo);\n"
                           "  s = Material_sample(m, wo, u.x, u.yz);\n",
                           g.wi, g.wo, g.u, [&](const gl::ComputeProgram& p) { p.set(gl::kGlslTablesSampler, 0); });
  const std::string M = gm.model_struct;
  int failures = 0, widened = 0;
  double worst_rel = 0.0;
  for (size_t i = 0; i < g.wi.size() && failures < 10; ++i) {
    const RGB f = cpu.f(g.wi[i], g.wo[i]);
    const float pdf = cpu.pdf(g.wi[i], g.wo[i]);
    const Bound b = jitter_bound(cpu, g.wi[i], g.wo[i]);
    bool ok = true;
    for (int c = 0; c < 3; ++c) {
      if (f[c] > 1e-6f) worst_rel = std::max(worst_rel, std::abs(double(r[i].f[c]) - f[c]) / f[c]);
      widened += b.f[c] > 2e-4 * std::abs(f[c]) && b.f[c] > 1e-6;
      if (!within(r[i].f[c], f[c], b.f[c])) {
        ADD_FAILURE() << "GLSL " << M << "_f channel " << c << ": " << r[i].f[c] << " vs C++ " << f[c] << " (bound " << b.f[c]
                      << ") at " << describe(g, i);
        ok = false;
      }
    }
    if (!within(r[i].pdf, pdf, b.pdf)) {
      ADD_FAILURE() << "GLSL " << M << "_pdf: " << r[i].pdf << " vs C++ " << pdf << " (bound " << b.pdf << ") at "
                    << describe(g, i);
      ok = false;
    }
    const BSDFSampleT<float> s = cpu.sample(g.wo[i], g.u[i].x, Vec2(g.u[i].y, g.u[i].z));
    if (r[i].sample_valid != s.valid) {
      ADD_FAILURE() << "GLSL " << M << "_sample valid = " << r[i].sample_valid << ", C++ " << s.valid << " at " << describe(g, i);
      ok = false;
    } else if (s.valid) {
      // wi within 1e-3 (the sampled direction is as well conditioned as the tables' inverse cdfs,
      // whose square roots amplify a rounding of u by up to 1 / sqrt(cell mass)); the record's
      // weight and pdf are then compared with the C++ at the GLSL wi, under that wi's bound.
      const float dwi = glm::length(r[i].sample_wi - s.wi);
      if (!(dwi <= 1e-3f)) {
        ADD_FAILURE() << "GLSL " << M << "_sample wi (" << r[i].sample_wi.x << ", " << r[i].sample_wi.y << ", "
                      << r[i].sample_wi.z << "), C++ (" << s.wi.x << ", " << s.wi.y << ", " << s.wi.z << ") at "
                      << describe(g, i);
        ok = false;
      }
      const glm::vec3 gwi = r[i].sample_wi;
      const float p_at = cpu.pdf(gwi, g.wo[i]);
      const Bound ba = jitter_bound(cpu, gwi, g.wo[i]);
      if (!within(r[i].sample_pdf, p_at, ba.pdf)) {
        ADD_FAILURE() << "GLSL " << M << "_sample pdf " << r[i].sample_pdf << ", C++ at the GLSL wi " << p_at << " at "
                      << describe(g, i);
        ok = false;
      }
    }
    if (!ok) ++failures;
  }
  std::cout << "[ INFO     ] " << GetParam().name << ": largest relative f difference GLSL vs C++ " << worst_rel << "; "
            << widened << " of " << 3 * g.wi.size() << " channel bounds above 2e-4 (steep f, bin edges, the pole)\n";
}

// The GLSL sampler against the C++ pdf (double kernel), as GlslParity.SamplesPassChiSquare: two
// views, scaled(300k) samples each.
TEST_P(GlslMeasured, SamplesPassChiSquare) {
  ANISO_REQUIRE_CASE(GetParam());
  ANISO_REQUIRE_GL();
  const MaterialDesc& d = case_material(GetParam());
  const MaterialD md = build_material<double>(d);
  const gl::GlslMaterial gm = gl::glsl_material(d, gl::GlslStorage::Uniform, "u_");
  const gl::TablesTexture tex(gl::glsl_tables(d));
  tex.bind(0);
  const bool merl = GetParam().kind == "merl";
  const int64_t kSamples = scaled(GetParam().kind == "real" ? 100'000 : 200'000);
  constexpr uint64_t kSeed = 23;
  const double views[][2] = {{35.0, 30.0}, {70.0, 200.0}};
  for (const auto& view : views) {
    const Vec3d wod = spherical(view[0], view[1]);
    const glm::vec3 wo(wod);
    GlslDraws draws = glsl_draws(gm.declarations + gm.code, wo, kSamples, kSeed,
                                 [&](const gl::ComputeProgram& p) { p.set(gl::kGlslTablesSampler, 0); });
    const std::vector<glm::vec3>& us = draws.u;
    const std::vector<GpuResult>& r = draws.r;
    // Sample by sample: the same u through the C++ float sampler gives the same wi (1e-3, as the
    // parity test above) but for a few draws on a cell edge of the tables' cdfs, where float
    // rounding picks the neighbouring cell.
    const Material cpu = build_material<float>(d);
    int64_t apart = 0;
    for (int64_t i = 0; i < kSamples; ++i) {
      const BSDFSampleT<float> s = cpu.sample(wo, us[size_t(i)].x, Vec2(us[size_t(i)].y, us[size_t(i)].z));
      apart += s.valid != r[size_t(i)].sample_valid || (s.valid && !(glm::length(s.wi - r[size_t(i)].sample_wi) <= 1e-3f));
    }
    EXPECT_LE(double(apart), 1e-3 * double(kSamples)) << apart << " of " << kSamples << " GLSL samples differ from the C++ ones";
    // The MERL pdf is piecewise constant on MERL's bins: 24 sub-cells per bin as test_measured.cpp
    // (kChi2Sub, the reason there); the tensor's is continuous: 4 as test_rgl.cpp.
    const int tb = merl ? 20 : 30, pb = merl ? 40 : 60, sub = merl ? 24 : 4;
    const auto pdf = [&](const Vec3d& w) { return md.pdf(w, wod); };
    const Chi2Result c = chi2_test([&](float, Vec2) { return draws.sample(); }, pdf, kSamples, kSeed, tb, pb, sub);
    ASSERT_EQ(draws.next, r.size());
    std::cout << "[ INFO     ] " << GetParam().name << " view theta " << view[0] << ": chi2 " << c.chi2 << " dof " << c.dof
              << " p " << c.p_value << " pdf integral " << c.pdf_integral << " accepted " << c.accepted_fraction
              << (c.message.empty() ? "" : " (" + c.message + ")") << "\n";
    const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(2 * measured_cases().size()));
    if (c.message.empty() && c.p_value > alpha) continue;
    // A real file's sampler and pdf need not agree (pbrt-v4's Sample_f rejects the wi it reflects
    // below the horizon, which its PDF does not discount; chm_light_blue at 70 degrees loses 1 %
    // so): the GLSL is then held to what the C++ sampler gets from the same harness, which the
    // sample-by-sample check above already ties it to.
    const Chi2Result ref = chi2_test([&](float uc, Vec2 u) { return cpu.sample(wo, uc, u); }, pdf, kSamples, kSeed, tb, pb, sub);
    std::cout << "[ INFO     ] the C++ float sampler there: chi2 " << ref.chi2 << " p " << ref.p_value
              << (ref.message.empty() ? "" : " (" + ref.message + ")") << "\n";
    EXPECT_TRUE(GetParam().kind == "real" && (!ref.message.empty() || ref.p_value <= alpha))
        << "GLSL " << gm.model_struct << "_sample, wo theta " << view[0] << ": chi2 " << c.chi2 << " dof " << c.dof << " p "
        << c.p_value << " " << c.message;
  }
}

INSTANTIATE_TEST_SUITE_P(Files, GlslMeasured, ::testing::ValuesIn(measured_cases()),
                         [](const testing::TestParamInfo<MeasuredCase>& i) { return i.param.name; });

// The tables texture's header (measured.glsl, rgl.glsl): what the GLSL loaders read.
TEST(GlslMeasuredTables, HeadersDescribeTheTables) {
  const MaterialDesc& merl = case_material(measured_cases()[3]);
  const std::vector<float> t = gl::glsl_tables(merl);
  ASSERT_GE(t.size(), 16u);
  EXPECT_EQ(t[0], 2.f);
  EXPECT_EQ(t[1], float(merl.measured->theta_o_bins));
  EXPECT_EQ(t[2], float(merl.measured->phi_h_bins));
  EXPECT_EQ(t[4], 16.f);
  EXPECT_EQ(t[size_t(t[4]) + 12345], float(merl.measured->brdf.table[12345]));
  const size_t nb = size_t(merl.measured->theta_o_bins) * 90 * size_t(merl.measured->phi_h_bins);
  EXPECT_EQ(t.size(), size_t(t[8]) + nb);
  EXPECT_LT(t.size() / size_t(gl::kGlslTablesWidth) + 1, 2048u) << "the MERL texture fits WebGL2's minimum 2048 rows";
  const MaterialDesc& aniso = case_material(measured_cases()[1]);
  const std::vector<float> a = gl::glsl_tables(aniso);
  EXPECT_EQ(a[0], 1.f);
  EXPECT_EQ(a[1], 0.f) << "anisotropic";
  const rgl::PL2DTables& v = aniso.rgl->vndf;
  EXPECT_EQ(a[48], float(v.view.size_x));
  EXPECT_EQ(a[48 + 2], 2.f);
  EXPECT_EQ(a[size_t(a[48 + 12]) + 7], v.data[7]);
  EXPECT_TRUE(gl::glsl_tables(parse_material({{"model", "ggx"}}, "analytic")).empty());
}

// export-glsl of a measured material: the shader names its tables file, the file holds the
// texture's floats (little-endian, whole rows), and the shader compiles as GLSL 3.30 and ES 3.00.
TEST(GlslMeasuredExport, ShaderAndTablesFile) {
  for (size_t k : {size_t(0), size_t(3)}) {
    const MaterialDesc& d = case_material(measured_cases()[k]);
    const std::string glsl = gl::export_glsl(d, "m.bsdf", false, "m.glsl.tables");
    EXPECT_NE(glsl.find("m.glsl.tables"), std::string::npos);
    EXPECT_NE(glsl.find("uniform highp sampler2D aniso_MeasuredTables_texture;"), std::string::npos);
    const std::string bytes = gl::export_glsl_tables(d);
    const std::vector<float> t = gl::glsl_tables(d);
    ASSERT_EQ(bytes.size() % (4 * size_t(gl::kGlslTablesWidth)), 0u);
    ASSERT_GE(bytes.size(), 4 * t.size());
    for (size_t i : {size_t(0), size_t(5), t.size() - 1}) {
      float x;
      std::memcpy(&x, bytes.data() + 4 * i, 4);
      EXPECT_EQ(x, t[i]) << i;
    }
    if (std::string(ANISO_GLSLANG).empty()) continue;
    for (gl::GlslDialect dl : {gl::GlslDialect::Core330, gl::GlslDialect::Es300})
      EXPECT_EQ(glslang_errors(gl::glsl_preamble(dl) + glsl +
                                   "out vec4 c;\nvoid main() { c = vec4(aniso_f(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8)), "
                                   "aniso_pdf(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8))); }\n",
                               "frag", "measured_export"),
                "");
  }
  try {
    (void)gl::export_brdf(case_material(measured_cases()[0]), "m.bsdf");
    ADD_FAILURE() << "export-brdf of a tensor file accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot carry"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aniso::test
