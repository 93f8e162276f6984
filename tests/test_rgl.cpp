// RGL tensor files (.bsdf; rgl/, aniso/brdf/rgl.h, docs/rgl.md): the container round trip, every
// bad file refused with its file, field and problem named, the readers' rules (pbrt-v4
// MeasuredBxDFData::Create and Mitsuba 3's measured plugin, written again here from their
// sources), pbrt-v4's PiecewiseLinear2D (sample and invert are inverses, pdf = evaluate), the
// round trip of every model (write, read back, compare f, albedo), chi-square of the read file's
// sampling, and the CLI.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/measured/measured.h"
#include "aniso/measured/spectral.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/rgl/tensor.h"
#include "chi2.h"
#include "cli_fixture.h"
#include "test_util.h"

namespace aniso::test {
namespace {

using rgl::TensorField;
using rgl::TensorFile;

std::vector<TensorField> export_json(const nlohmann::json& j, const rgl::ExportOptions& o) {
  rgl::BrdfSource src = rgl::brdf_source(build<double>(j));
  src.description = j.dump();
  return rgl::export_rgl(src, o);
}

std::shared_ptr<rgl::RglData> read_back(const std::vector<TensorField>& fields, const std::string& name = "test.bsdf") {
  return rgl::rgl_from_tensor(rgl::parse_tensor(rgl::serialize_tensor(fields), name));
}

const nlohmann::json kGGXIso = {{"model", "ggx"}, {"kd", {0.2, 0.1, 0.05}}, {"f0", 0.04}, {"alpha", 0.2}};
const nlohmann::json kGGXAniso = {{"model", "ggx"}, {"kd", 0.0}, {"f0", {0.9, 0.6, 0.3}}, {"alpha_x", 0.05}, {"alpha_y", 0.3}};

TEST(RglTensor, RoundTripsFieldsAndAlignsData) {
  const std::vector<float> a{1.f, 2.f, 3.f, 4.f, 5.f, 6.f};
  const std::string text = "hello";
  std::vector<TensorField> f{rgl::make_field("description", {5}, std::span(reinterpret_cast<const uint8_t*>(text.data()), 5)),
                             rgl::make_field("x", {2, 3}, a)};
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(f);
  ASSERT_EQ(std::memcmp(bytes.data(), "tensor_file\0\x01\x00", 14), 0);
  const TensorFile t = rgl::parse_tensor(bytes, "mem");
  ASSERT_EQ(t.fields.size(), 2u);
  EXPECT_EQ(t.fields[0].name, "description");
  EXPECT_EQ(std::string(t.fields[0].bytes.begin(), t.fields[0].bytes.end()), "hello");
  EXPECT_EQ(t.fields[1].dtype, rgl::Dtype::Float32);
  EXPECT_EQ(t.fields[1].shape, (std::vector<uint64_t>{2, 3}));
  EXPECT_EQ(t.fields[1].floats(), a);
  for (const TensorField& x : t.fields) EXPECT_EQ(x.offset % 8, 0u) << x.name;  // Mitsuba's tensor_io.py aligns to 8
}

// Each bad file: the message names the file, the field (where there is one) and the problem.
struct BadCase {
  std::string name;
  std::function<void(std::vector<uint8_t>&, std::vector<TensorField>&)> corrupt;  // bytes-level or field-level
  std::vector<std::string> expect;
};

TEST(RglTensor, BadFilesAreInputErrorsNamingFileFieldAndProblem) {
  const std::vector<TensorField> good = export_json(kGGXAniso, small_rgl_options());
  auto field = [](std::vector<TensorField>& fs, const std::string& n) -> TensorField& {
    for (TensorField& f : fs)
      if (f.name == n) return f;
    throw std::logic_error(n);
  };
  auto set_float = [](TensorField& f, size_t i, float v) { std::memcpy(f.bytes.data() + 4 * i, &v, 4); };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<BadCase> cases = {
      {"truncated", [](auto& b, auto&) { b.resize(b.size() / 2); }, {"past the end"}},
      {"tiny", [](auto& b, auto&) { b.resize(10); }, {"not a tensor file", "truncated"}},
      {"magic", [](auto& b, auto&) { b[0] = 'x'; }, {"not a tensor file", "tensor_file"}},
      {"version", [](auto& b, auto&) { b[12] = 2; }, {"version 2.0"}},
      {"huge field count", [](auto& b, auto&) { b[14] = b[15] = b[16] = b[17] = 0xff; }, {"4294967295 fields"}},
      {"huge shape",
       [](auto& b, auto&) {
         // the first field ("description", ndim 1): its shape follows name length 2 + 11 + ndim 2 +
         // dtype 1 + offset 8 after the 18-byte header
         const size_t at = 18 + 2 + 11 + 2 + 1 + 8;
         std::memset(b.data() + at, 0xff, 8);
       },
       {"field \"description\"", "more bytes than the file has"}},
      {"unknown dtype", [](auto& b, auto&) { b[18 + 2 + 11 + 2] = 12; }, {"field \"description\"", "unknown dtype code 12"}},
      {"wrong dtype",
       [&](auto&, auto& fs) {
         field(fs, "theta_i").dtype = rgl::Dtype::Float16;
         field(fs, "theta_i").bytes.resize(16);
       },
       {"field \"theta_i\"", "dtype float16, expected float32"}},
      {"wrong vndf shape",
       [&](auto&, auto& fs) {
         TensorField& v = field(fs, "vndf");
         v.shape[1] -= 1;
         v.bytes.resize(v.count() * 4);
       },
       {"field \"vndf\"", "expected [phi_i, theta_i, *, *]"}},
      {"non-square colour grid",
       [&](auto&, auto& fs) {
         TensorField& v = field(fs, "rgb");
         v.shape[4] -= 1;
         v.bytes.resize(v.count() * 4);
       },
       {"field \"rgb\"", "last two sizes must be equal"}},
      {"missing jacobian", [&](auto&, auto& fs) { fs.pop_back(); }, {"field \"jacobian\" is missing"}},
      {"jacobian 0", [&](auto&, auto& fs) { field(fs, "jacobian").bytes[0] = 0; }, {"field \"jacobian\"", "value 0"}},
      {"missing rgb", [&](auto&, auto& fs) { field(fs, "rgb").name = "colour"; }, {"field \"rgb\" is missing"}},
      {"NaN vndf", [&](auto&, auto& fs) { set_float(field(fs, "vndf"), 100, nan); }, {"field \"vndf\"", "nan", "finite"}},
      {"NaN colour",
       [&](auto&, auto& fs) { set_float(field(fs, "rgb"), 7, nan); },
       {"field \"rgb\"", "finite, magnitude <= 1e+15 expected"}},
      {"negative sigma",
       [&](auto&, auto& fs) { set_float(field(fs, "sigma"), 3, -0.01f); },
       {"field \"sigma\"", "value -0.01 at flat index 3", "read as 0"}},
      {"infinite luminance",
       [&](auto&, auto& fs) { set_float(field(fs, "luminance"), 5, std::numeric_limits<float>::infinity()); },
       {"field \"luminance\"", "value inf at flat index 5"}},
      {"half-circle phi",
       [&](auto&, auto& fs) {
         TensorField& p = field(fs, "phi_i");
         for (size_t i = 0; i < p.count(); ++i) set_float(p, i, float(-M_PI + M_PI * double(i) / double(p.count() - 1)));
       },
       {"field \"phi_i\"", "reduction 2", "full circle"}},
      {"unsorted theta",
       [&](auto&, auto& fs) { set_float(field(fs, "theta_i"), 2, 0.f); },
       {"field \"theta_i\"", "not strictly increasing"}},
      {"all-zero vndf slice",
       [&](auto&, auto& fs) {
         TensorField& v = field(fs, "vndf");
         std::fill(v.bytes.begin(), v.bytes.begin() + ptrdiff_t(v.shape[2] * v.shape[3] * 4), 0);
       },
       {"field \"vndf\"", "all zero"}},
      {"duplicate field", [&](auto&, auto& fs) { fs.push_back(fs.front()); }, {"appears twice"}},
  };
  for (const BadCase& c : cases) {
    std::vector<TensorField> fs = good;
    std::vector<uint8_t> empty;
    const bool byte_level = c.name == "truncated" || c.name == "tiny" || c.name == "magic" || c.name == "version" ||
                            c.name == "huge field count" || c.name == "huge shape" || c.name == "unknown dtype";
    std::vector<uint8_t> bytes;
    if (byte_level) {
      bytes = rgl::serialize_tensor(fs);
      std::vector<TensorField> none;
      c.corrupt(bytes, none);
    } else {
      c.corrupt(empty, fs);
      bytes = rgl::serialize_tensor(fs);
    }
    const std::string path = (std::filesystem::temp_directory_path() / fmt::format("aniso-rgl-bad-{}.bsdf", ::getpid())).string();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    try {
      (void)rgl::rgl_from_tensor(rgl::read_tensor_file(path));
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << c.name << ": " << msg;
      for (const std::string& s : c.expect)
        EXPECT_NE(msg.find(s), std::string::npos) << c.name << ": \"" << s << "\" not in: " << msg;
    }
    std::filesystem::remove(path);
  }
}

// pbrt-v4 src/pbrt/bxdfs.cpp:885-948 (MeasuredBxDFData::Create) and Mitsuba 3
// src/bsdfs/measured.cpp:98-180, restated from their sources: what must hold for each reader to
// load a file without error. Returns the first rule broken, or "".
std::string readers_rules(const TensorFile& t, bool for_pbrt) {
  auto has = [&](const char* n) { return t.find(n) != nullptr; };
  for (const char* n : {"theta_i", "phi_i", "ndf", "sigma", "vndf", "luminance", "description", "jacobian"})
    if (!has(n)) return fmt::format("missing {}", n);
  const bool spectral = has("wavelengths");
  if (for_pbrt && !(has("spectra") && spectral)) return "pbrt-v4 needs spectra and wavelengths";
  if (!spectral && !has("rgb")) return "Mitsuba RGB needs rgb";
  const TensorField &theta_i = *t.find("theta_i"), &phi_i = *t.find("phi_i"), &ndf = *t.find("ndf"), &sigma = *t.find("sigma"),
                    &vndf = *t.find("vndf"), &lum = *t.find("luminance"), &desc = *t.find("description"),
                    &jac = *t.find("jacobian");
  const TensorField& spectra = *t.find(spectral ? "spectra" : "rgb");
  const uint64_t n_lambda = spectral ? t.find("wavelengths")->shape.at(0) : 3;
  using D = rgl::Dtype;
  const bool ok = desc.shape.size() == 1 && desc.dtype == D::UInt8 && theta_i.shape.size() == 1 && theta_i.dtype == D::Float32 &&
                  phi_i.shape.size() == 1 && phi_i.dtype == D::Float32 &&
                  (!spectral || (t.find("wavelengths")->shape.size() == 1 && t.find("wavelengths")->dtype == D::Float32)) &&
                  ndf.shape.size() == 2 && ndf.dtype == D::Float32 && sigma.shape.size() == 2 && sigma.dtype == D::Float32 &&
                  vndf.shape.size() == 4 && vndf.dtype == D::Float32 && vndf.shape[0] == phi_i.shape[0] &&
                  vndf.shape[1] == theta_i.shape[0] && lum.shape.size() == 4 && lum.dtype == D::Float32 &&
                  lum.shape[0] == phi_i.shape[0] && lum.shape[1] == theta_i.shape[0] && lum.shape[2] == lum.shape[3] &&
                  spectra.dtype == D::Float32 && spectra.shape.size() == 5 && spectra.shape[0] == phi_i.shape[0] &&
                  spectra.shape[1] == theta_i.shape[0] && spectra.shape[2] == n_lambda && spectra.shape[3] == spectra.shape[4] &&
                  lum.shape[2] == spectra.shape[3] && lum.shape[3] == spectra.shape[4] && jac.shape.size() == 1 &&
                  jac.shape[0] == 1 && jac.dtype == D::UInt8;
  if (!ok) return "invalid BRDF file structure";
  const std::vector<float> phi = phi_i.floats();
  if (phi.size() > 2 && int(std::rint(2 * M_PI / (phi.back() - phi.front()))) != 1) return "reduction != 1";
  // PiecewiseLinear2D needs >= 2 points per axis (sampling.h:1330) and Mitsuba's m_jacobian
  // must be 1 for the two renderers to agree (measured.cpp:364).
  if (ndf.shape[0] < 2 || ndf.shape[1] < 2 || sigma.shape[0] < 2 || sigma.shape[1] < 2 || vndf.shape[2] < 2 ||
      vndf.shape[3] < 2 || lum.shape[2] < 2)
    return "grid smaller than 2 x 2";
  if (jac.bytes.at(0) != 1) return "jacobian != 1";
  return "";
}

TEST(RglExport, EveryWrittenFilePassesPbrtAndMitsubaRules) {
  for (const bool spectral : {true, false})
    for (const nlohmann::json& j : {kGGXIso, kGGXAniso}) {
      const TensorFile t = rgl::parse_tensor(rgl::serialize_tensor(export_json(j, small_rgl_options(spectral))), "x.bsdf");
      EXPECT_EQ(readers_rules(t, false), "") << j.dump();
      if (spectral)
        EXPECT_EQ(readers_rules(t, true), "") << j.dump();
      else
        EXPECT_EQ(readers_rules(t, true), "pbrt-v4 needs spectra and wavelengths");
      const bool iso = j == kGGXIso;
      EXPECT_EQ(t.find("phi_i")->shape[0] <= 2, iso) << j.dump();
      const std::string desc(t.find("description")->bytes.begin(), t.find("description")->bytes.end());
      EXPECT_EQ(desc, j.dump());
    }
}

// Extreme materials (issue 40, item 11): lobes far sharper than any grid, or scaled to the table's
// limit, are written as finite files that the reader takes back (their luminance slices, whose
// values were a few 1e-36, no longer underflow the readers' normalisation).
TEST(RglExport, ExtremeMaterialsGiveFilesTheReaderTakes) {
  for (const nlohmann::json& j :
       {nlohmann::json{{"model", "phong"}, {"exponent", 1e6}, {"ks", 1e6}},
        nlohmann::json{{"model", "lafortune"}, {"lobes", {{{"cx", 1}, {"cy", 1}, {"cz", 1}, {"n", 1e6}}}}},
        nlohmann::json{{"model", "lafortune"}, {"lobes", {{{"cx", -1}, {"cy", -1}, {"cz", 1}, {"n", 1e6}}}}}}) {
    const std::shared_ptr<rgl::RglData> d = read_back(export_json(j, small_rgl_options()));
    ASSERT_TRUE(d) << j.dump();
    const auto k = rgl::rgl_kernel<double>(*d);
    const Vec3d wi = glm::normalize(Vec3d(-0.3, 0.1, 0.9));
    for (const Vec3d& wo : {Vec3d(0, 0, 1), glm::normalize(Vec3d(0.5, 0.2, 0.8))}) {
      const RGBT<double> f = k.f(wi, wo);
      EXPECT_TRUE(std::isfinite(f.x) && f.x >= 0.0) << j.dump();
      EXPECT_TRUE(std::isfinite(k.pdf(wi, wo))) << j.dump();
    }
  }
}

// phi_i of an anisotropic file (docs/rgl.md, step 3): count values, increasing, from -pi to pi
// (both readers' rules), symmetric about the material's mirror axes with a slice on each (the
// tangent and bitangent, turned with rotation_deg; -pi added when it is not on one), denser where
// the readers' blend errs; the vndf grid is 32 x 32 for anisotropic files and the ndf's for
// isotropic ones.
TEST(RglExport, AzimuthsFollowTheMirrorAxes) {
  rgl::ExportOptions o = small_rgl_options();
  o.ndf = 16;
  o.phi_i = 13;
  for (const double turn : {0.0, 30.0}) {
    nlohmann::json j = kGGXAniso;
    j["rotation_deg"] = turn;
    const TensorFile t = rgl::parse_tensor(rgl::serialize_tensor(export_json(j, o)), "x.bsdf");
    EXPECT_EQ(readers_rules(t, false), "") << turn;
    EXPECT_EQ(t.find("vndf")->shape[2], 32u);
    const std::vector<float> phi = t.find("phi_i")->floats();
    ASSERT_EQ(phi.size(), turn == 0.0 ? 13u : 14u) << turn;  // turned: -pi is not on an axis, one more
    EXPECT_EQ(phi.front(), -float(M_PI));
    EXPECT_EQ(phi.back(), float(M_PI));
    for (size_t k = 1; k < phi.size(); ++k) EXPECT_LT(phi[k - 1], phi[k]) << turn << " at " << k;
    auto on_grid = [&](double a) {  // a slice at azimuth a (mod 2 pi)
      for (const float p : phi)
        if (std::abs(std::remainder(double(p) - a, 2.0 * M_PI)) < 1e-4) return true;
      return false;
    };
    const double b = turn * M_PI / 180.0;
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(on_grid(b + k * M_PI / 2)) << "axis " << k << " of the material turned " << turn;
    for (const float p : phi) {
      if (turn != 0.0 && std::abs(p) > 3.14159f) continue;  // the added end of the circle
      EXPECT_TRUE(on_grid(2.0 * b - p)) << "the mirror of " << p << " about " << b;
      EXPECT_TRUE(on_grid(2.0 * b + M_PI - p)) << "the mirror of " << p << " about " << b + M_PI / 2;
    }
    // Unequal spacing: the blend error is not the same at every azimuth.
    double lo = 10.0, hi = 0.0;
    for (size_t k = 1; k < phi.size(); ++k)
      lo = std::min(lo, double(phi[k] - phi[k - 1])), hi = std::max(hi, double(phi[k] - phi[k - 1]));
    EXPECT_GT(hi, 1.3 * lo) << turn;
  }
  const TensorFile iso = rgl::parse_tensor(rgl::serialize_tensor(export_json(kGGXIso, o)), "x.bsdf");
  EXPECT_EQ(iso.find("vndf")->shape[2], 16u);
  // Two lobes turned by different angles: no mirror axis, count values from -pi.
  nlohmann::json a = kGGXAniso, b = {{"model", "ggx"}, {"kd", 0.0}, {"f0", 0.5}, {"alpha_x", 0.1}, {"alpha_y", 0.2}};
  a["rotation_deg"] = 30.0;
  b["rotation_deg"] = 75.0;
  const MaterialD ma = build<double>(a), mb = build<double>(b);
  rgl::BrdfSource two;
  two.f = [&](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(ma.f(wi, wo)) + glm::dvec3(mb.f(wi, wo)); };
  two.description = "two turned lobes";
  const TensorFile t = rgl::parse_tensor(rgl::serialize_tensor(rgl::export_rgl(two, o)), "x.bsdf");
  EXPECT_EQ(readers_rules(t, false), "");
  const std::vector<float> phi = t.find("phi_i")->floats();
  ASSERT_EQ(phi.size(), 13u);
  EXPECT_EQ(phi.front(), -float(M_PI));
  EXPECT_EQ(phi.back(), float(M_PI));
  for (size_t k = 1; k < phi.size(); ++k) EXPECT_LT(phi[k - 1], phi[k]) << k;
}

// D of a model without a closed form (docs/rgl.md, step 2): Auto writes the file of the estimate that
// reproduces f best, byte for byte, and says which. matte-steel's lobes turn and grow towards the
// horizon (Lafortune, cxy = -1.1 against cz = 0.66 to 1): the envelope of the slices' own
// distributions with warps that follow f wins there (measured at the default grids: 3.2 % L1 at
// 80 degrees against 18 % for the lobe's mean shape and 30 % for the retro-reflection).
TEST(RglExport, AutoKeepsTheBetterEstimateOfD) {
  rgl::BrdfSource src = rgl::brdf_source(build_material<double>(load_material("matte-steel")));
  src.description = "matte-steel";
  rgl::ExportOptions o = small_rgl_options();
  rgl::ExportReport rep;
  const std::vector<uint8_t> chosen = rgl::serialize_tensor(rgl::export_rgl(src, o, &rep));
  EXPECT_NE(rep.d_method.find("envelope"), std::string::npos) << rep.d_method;
  EXPECT_NE(rep.d_method.find("chosen by the round trip"), std::string::npos) << rep.d_method;
  EXPECT_EQ(readers_rules(rgl::parse_tensor(chosen, "c.bsdf"), false), "");
  o.d_estimate = rgl::ExportOptions::DEstimate::LobeEnvelope;
  EXPECT_EQ(chosen, rgl::serialize_tensor(rgl::export_rgl(src, o)));
  o.d_estimate = rgl::ExportOptions::DEstimate::LobeAverage;
  EXPECT_NE(chosen, rgl::serialize_tensor(rgl::export_rgl(src, o)));
  // A fixed tilt is a different warp: the vndf differs, the ndf (D alone) does not.
  o.warp_tilt = 0.15;
  const TensorFile tilted = rgl::parse_tensor(rgl::serialize_tensor(rgl::export_rgl(src, o)), "t.bsdf");
  o.warp_tilt = 0.0;
  const TensorFile plain = rgl::parse_tensor(rgl::serialize_tensor(rgl::export_rgl(src, o)), "p.bsdf");
  EXPECT_EQ(readers_rules(tilted, false), "");
  EXPECT_EQ(tilted.find("ndf")->floats(), plain.find("ndf")->floats());
  EXPECT_NE(tilted.find("vndf")->floats(), plain.find("vndf")->floats());
}

// pbrt-v4's PiecewiseLinear2D: invert(sample(u)) = u and the sample's pdf equals evaluate() at the
// sampled point, for a conditional (2-parameter) table between its slices.
TEST(RglPL2D, SampleInvertAndEvaluateAgree) {
  const int nx = 7, ny = 5;
  const std::vector<float> pa{-1.f, 0.f, 2.f}, pb{0.f, 1.f};
  std::vector<float> data(pa.size() * pb.size() * nx * ny);
  for (size_t i = 0; i < data.size(); ++i) data[i] = 0.1f + float((i * 37) % 11);
  rgl::PL2DTables t;
  t.build(data.data(), nx, ny, {pa, pb}, true, true);
  Rng rng(5);
  for (int k = 0; k < 2000; ++k) {
    const float p[2] = {float(-1 + 3 * rng.uniform()), float(rng.uniform())};
    const float ux = rng.uniform_as<float>(), uy = rng.uniform_as<float>();
    const PL2DSample s = t.view.sample(ux, uy, p);
    const PL2DSample inv = t.view.invert(s.x, s.y, p);
    EXPECT_NEAR(inv.x, ux, 2e-4) << k;
    EXPECT_NEAR(inv.y, uy, 2e-4) << k;
    EXPECT_NEAR(t.view.evaluate(s.x, s.y, p), s.pdf, 1e-4 * s.pdf + 1e-6) << k;
    EXPECT_NEAR(inv.pdf, s.pdf, 1e-4 * s.pdf + 1e-6) << k;
  }
  // normalize = false, build_cdf = false: evaluate() returns the interpolated input.
  rgl::PL2DTables raw;
  raw.build(data.data(), nx, ny, {}, false, false);
  EXPECT_NEAR(raw.view.evaluate(0.f, 0.f, nullptr), data[0], 1e-5);
  EXPECT_NEAR(raw.view.evaluate(1.f, 1.f, nullptr), data[size_t(nx * ny - 1)], 1e-5);
}

// A material rotated about the normal by `angle` (the "rotated tangent" case).
rgl::SourceModel rotated(const MaterialD& m, double angle) {
  auto rot = [](const Vec3d& v, double a) {
    return Vec3d(std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z);
  };
  return {[=](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(rot(wi, -angle), rot(wo, -angle))); },
          [=](const Vec3d& wi, const Vec3d& wo) { return m.pdf(rot(wi, -angle), rot(wo, -angle)); },
          [=](const Vec3d& wo, double uc, const Vec2T<double>& u) {
            BSDFSampleT<double> s = m.sample(rot(wo, -angle), uc, u);
            s.wi = rot(s.wi, angle);
            return s;
          }};
}

struct RoundTripCase {
  std::string name;
  nlohmann::json material;  // a JSON material, or a string: a preset name
  bool merl = false;        // a MERL-layout table tabulated from the material
  double rotation = 0.0;
  // Bounds: the accuracy targets (L1 5 %, albedo 2 %) where they are met, else what is reached
  // with a margin of about 30 % (docs/rgl.md, "Accuracy", lists both).
  double l1_bound_60, l1_bound_80, albedo_bound;
};

void PrintTo(const RoundTripCase& c, std::ostream* os) { *os << c.name; }

class RglRoundTrip : public ::testing::TestWithParam<RoundTripCase> {};

TEST_P(RglRoundTrip, ReadBackMatchesTheSource) {
  const RoundTripCase& c = GetParam();
  std::shared_ptr<const MeasuredData> keep;
  MaterialD m =
      c.material.is_string() ? build_material<double>(load_material(c.material.get<std::string>())) : build<double>(c.material);
  if (c.merl) {
    keep = make_measured(tabulate_merl(m), c.name);
    m = MaterialD(measured_kernel<double>(*keep));
  }
  const rgl::SourceModel src = rotated(m, c.rotation);
  rgl::BrdfSource b = rgl::brdf_source(m);
  if (c.rotation != 0.0) {
    b.f = src.f;
    b.ggx_alpha.reset();  // the exact D is given in the unrotated frame: use the power iteration
  }
  b.description = c.name;
  rgl::ExportOptions o;  // the defaults: the accuracy users get
  o.spectral = false;
  rgl::ExportReport rep;
  const auto d = read_back(rgl::export_rgl(b, o, &rep));
  const rgl::RoundTripStats s = rgl::compare_rgl(src, rgl::rgl_kernel<double>(*d), 6000);
  std::printf("%-28s %s %-60s L1 by theta %.4f %.4f %.4f %.4f %.4f mean %.4f albedo %.4f export %.2f s CPU\n", c.name.c_str(),
              rep.isotropic ? "iso  " : "aniso", rep.d_method.c_str(), s.l1_by_theta[0], s.l1_by_theta[1], s.l1_by_theta[2],
              s.l1_by_theta[3], s.l1_by_theta[4], s.l1_mean, s.albedo_max, rep.seconds);
  const double l1_60 = std::max({s.l1_by_theta[0], s.l1_by_theta[1], s.l1_by_theta[2], s.l1_by_theta[3]});
  EXPECT_LE(l1_60, c.l1_bound_60) << "up to 60 degrees";
  EXPECT_LE(s.l1_by_theta[4], c.l1_bound_80) << "at 80 degrees";
  EXPECT_LE(s.albedo_max, c.albedo_bound);
}

INSTANTIATE_TEST_SUITE_P(
    Models, RglRoundTrip,
    ::testing::Values(
        RoundTripCase{
            "ward_vector_ward", {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.3}, {"alpha", 0.15}}, false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{
            "ward_angle_duer",
            {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.3}, {"alpha", 0.15}, {"form", "angle"}, {"normalization", "duer"}},
            false,
            0,
            0.05,
            0.05,
            0.02},
        RoundTripCase{"ward_approx_balanced_aniso",
                      {{"model", "ward"},
                       {"kd", 0.1},
                       {"ks", 0.3},
                       {"alpha_x", 0.05},
                       {"alpha_y", 0.3},
                       {"form", "approx"},
                       {"normalization", "balanced"}},
                      false,
                      0,
                      0.05,
                      0.07,
                      0.02},
        RoundTripCase{"ashikhmin_shirley",
                      {{"model", "ashikhmin-shirley"}, {"rd", {0.2, 0.3, 0.4}}, {"rs", 0.1}, {"n", 100.0}},
                      false,
                      0,
                      0.05,
                      0.05,
                      0.02},
        RoundTripCase{"ggx_iso", kGGXIso, false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{"ggx_aniso_0.05x0.3", kGGXAniso, false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{"ggx_aniso_rotated_30deg", kGGXAniso, false, M_PI / 6, 0.05, 0.05, 0.02},
        RoundTripCase{"matte_steel_lafortune3",
                      {{"model", "lafortune"},
                       {"rho_d", 0.0},
                       {"lobes",
                        {{{"cxy", -1.1}, {"cz", 1.0}, {"n", 15.0}},
                         {{"cxy", -1.06}, {"cz", 0.66}, {"n", 88.0}},
                         {{"cxy", -1.0}, {"cz", 1.0}, {"n", 180.0}}}}},
                      false,
                      0,
                      0.05,
                      0.05,
                      0.02},
        RoundTripCase{"matte_steel_preset", "matte-steel", false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{"gold_ggx_metal", "gold", false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{"brushed_gold", "brushed-gold", false, 0, 0.05, 0.05, 0.02},
        RoundTripCase{"merl_table_of_ward",
                      {{"model", "ward"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", 0.2}, {"alpha", 0.25}},
                      true,
                      0,
                      0.05,
                      0.05,
                      0.02}),
    [](const testing::TestParamInfo<RoundTripCase>& i) {
      std::string n = i.param.name;
      for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return n;
    });

// Sampling a read file (pbrt-v4's Sample_f) against its own PDF: the chi-square suite. The files of
// exact GGX D (VNDF warps), of matte-steel (the envelope D, warps 80 % the slice's own f) and of the
// anisotropic Ward form with its warps tilted towards the normal (docs/rgl.md, step 4).
TEST(RglSampling, ChiSquareOfTheReadFile) {
  const nlohmann::json ward_tilted = {{"model", "ward"},
                                      {"kd", 0.1},
                                      {"ks", 0.3},
                                      {"alpha_x", 0.05},
                                      {"alpha_y", 0.3},
                                      {"form", "approx"},
                                      {"normalization", "balanced"}};
  for (const nlohmann::json& j : {kGGXIso, kGGXAniso, nlohmann::json("matte-steel"), ward_tilted}) {
    rgl::ExportOptions o = small_rgl_options();
    if (j == ward_tilted) o.d_estimate = rgl::ExportOptions::DEstimate::LobeAverage, o.warp_tilt = 0.15;
    if (j.is_string()) o.d_estimate = rgl::ExportOptions::DEstimate::LobeEnvelope;
    rgl::BrdfSource b =
        rgl::brdf_source(j.is_string() ? build_material<double>(load_material(j.get<std::string>())) : build<double>(j));
    b.description = j.dump();
    const auto d = read_back(rgl::export_rgl(b, o));
    const RglT<float> k = rgl::rgl_kernel<float>(*d);
    const RglT<double> kd = rgl::rgl_kernel<double>(*d);
    for (const double theta : {30.0, 70.0}) {
      const Vec3d wod = spherical(theta, 40.0);
      const Vec3 wo(wod);
      const Chi2Result r = chi2_test([&](float uc, Vec2 u) { return k.sample(wo, uc, u); },
                                     [&](const Vec3d& wi) { return kd.pdf(wi, wod); }, scaled(400'000), 29, 30, 60, 4);
      ASSERT_TRUE(r.message.empty()) << r.message;
      const double alpha = 1.0 - std::pow(0.99, 1.0 / 4.0);
      std::printf("%s view theta %g: chi2 %.1f dof %d p %.3f pdf integral %.5f accepted %.5f\n", j.dump().c_str(), theta, r.chi2,
                  r.dof, r.p_value, r.pdf_integral, r.accepted_fraction);
      EXPECT_GT(r.p_value, alpha) << j.dump() << " theta " << theta;
      EXPECT_NEAR(r.pdf_integral, r.accepted_fraction, 0.01) << j.dump() << " theta " << theta;
    }
  }
}

// A spectral file, reduced back by aniso's reader, gives the colour of the material it was made
// from (docs/rgl.md "Spectral files"): the same accuracy as the RGB file.
TEST(RglExport, SpectralFileReducesBackToTheRgb) {
  const MaterialD m = build_material<double>(load_material("gold"));
  rgl::BrdfSource b = rgl::brdf_source(m);
  rgl::ExportOptions o = small_rgl_options(true);
  const auto spectral = read_back(rgl::export_rgl(b, o));
  o.spectral = false;
  const auto rgb = read_back(rgl::export_rgl(b, o));
  ASSERT_TRUE(spectral->spectral);
  Rng rng(11);
  for (int i = 0; i < 200; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const glm::dvec3 fs = rgl::rgl_kernel<double>(*spectral).f(wi, wo), fr = rgl::rgl_kernel<double>(*rgb).f(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fs[c], fr[c], 2e-3 * std::max(1.0, fr[c])) << i << " channel " << c;
  }
}

// A named metal's spectral file carries the conductor Fresnel of its measured n(lambda), k(lambda)
// (docs/rgl.md "Spectral files"), and aniso's reduction of it agrees with the RGB metal to the
// bound measured in docs/rgl.md: the RGB eta, k are a fit to the reduction over 81 wavelengths
// (docs/metals.md, step 9), the file has 21.
TEST(RglExport, MetalSpectraAreTheMeasuredFresnel) {
  const std::vector<float> lf = rgl::export_wavelengths();
  const std::vector<double> lambda(lf.begin(), lf.end());
  const SpectralToRgb reduce(lambda);
  double worst = 0.0;
  for (const MetalData& md : metal_table()) {
    EXPECT_EQ(metal_nk(md, 380.0), metal_nk(md, 300.0)) << md.name << ": the end value outside the data range";
    for (int deg = 0; deg <= 88; deg += 4) {
      const double c = std::cos(deg * kPi<double> / 180.0);
      std::vector<double> r(lambda.size());
      for (size_t j = 0; j < lambda.size(); ++j) {
        const glm::dvec2 nk = metal_nk(md, lambda[j]);
        r[j] = F_Conductor(c, nk.x, nk.y);
      }
      const glm::dvec3 reduced = reduce(r), rgb = glm::dvec3(F_Conductor(c, RGBT<double>(md.eta), RGBT<double>(md.k)));
      for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::abs(reduced[ch] - rgb[ch]));
      // The spectral F0 of the table (81 wavelengths) against 21: the reduction's own step.
      if (deg == 0) {
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(reduced[ch], md.f0[ch], 6e-3) << md.name << " channel " << ch;
      }
    }
  }
  fmt::print("metals: |reduction of the measured Fresnel over 21 wavelengths - RGB Fresnel| <= {:.4f}\n", worst);
  EXPECT_LT(worst, 0.02);

  // The source's spectra are the Fresnel equation at the measured n, k, term for term.
  const MaterialD gold = build_material<double>(load_material("gold"));
  const rgl::BrdfSource b = rgl::brdf_source(gold, find_metal("gold"));
  ASSERT_TRUE(bool(b.f_spectral));
  Rng rng(5);
  std::vector<double> out(lambda.size());
  for (int i = 0; i < 50; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    b.f_spectral(wi, wo, out.data());
    const double c = glm::dot(wi, glm::normalize(wi + wo)), spec = gold.metal.specular(wi, wo);
    for (size_t j = 0; j < lambda.size(); ++j) {
      const glm::dvec2 nk = metal_nk(*find_metal("gold"), lambda[j]);
      EXPECT_NEAR(out[j], F_Conductor(c, nk.x, nk.y) * spec, 1e-12 * std::max(1.0, out[j])) << i << " " << lambda[j];
    }
    const glm::dvec3 reduced = reduce(out), f = b.f(wi, wo);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(reduced[ch], f[ch], 0.02 * std::max(spec, 1e-3)) << i << " channel " << ch;
  }

  // The file: spectra that vary inside a box (gold falls from 500 to 580 nm), and a reduction
  // within the same bound of the RGB file's f.
  rgl::ExportOptions o = small_rgl_options(true);
  rgl::ExportReport rep;
  const std::vector<TensorField> fields = rgl::export_rgl(b, o, &rep);
  EXPECT_NE(rep.spectra.find("gold's measured n, k"), std::string::npos) << rep.spectra;
  const TensorField* spectra = nullptr;
  for (const TensorField& f : fields)
    if (f.name == "spectra") spectra = &f;
  ASSERT_NE(spectra, nullptr);
  const size_t plane = size_t(o.colour) * size_t(o.colour), j500 = 6, j580 = 10;  // 380 + 20 j nm
  ASSERT_EQ(lambda[j500], 500.0);
  ASSERT_EQ(lambda[j580], 580.0);
  const std::vector<float> v = spectra->floats();
  const size_t node = plane / 2 + size_t(o.colour) / 2;  // slice 0 (theta_i 0), the square's centre
  EXPECT_GT(v[j580 * plane + node], 1.1f * v[j500 * plane + node]);
  const auto spectral = read_back(fields);
  o.spectral = false;
  const auto rgb = read_back(rgl::export_rgl(b, o));
  double file_worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const glm::dvec3 fs = rgl::rgl_kernel<double>(*spectral).f(wi, wo), fr = rgl::rgl_kernel<double>(*rgb).f(wi, wo);
    const double spec = gold.metal.specular(wi, wo);
    for (int ch = 0; ch < 3; ++ch) {
      file_worst = std::max(file_worst, std::abs(fs[ch] - fr[ch]) / std::max(spec, 1e-3));
      EXPECT_NEAR(fs[ch], fr[ch], 0.02 * std::max(spec, 1e-3) + 2e-3 * fr[ch]) << i << " channel " << ch;
    }
  }
  fmt::print("gold: |spectral file (reduced) - rgb file| / specular lobe <= {:.4f}\n", file_worst);
}

// Real measurements carry float rounding: values a little below 0 where the true value is 0 (the
// RGL database's chm files: 16 luminance values down to -4e-10). Read as 0 with one note per field
// (rgl_material.h, kRoundingNoiseUlps); a clearly negative value stays an error naming the file,
// the field and the flat index. The readers' own rule is none (pbrt-v4 and Mitsuba 3 check no
// value), so aniso may note, never refuse, what is rounding.
TEST(RglNoise, RoundingNoiseIsReadAsZeroWithANoteAndClearNegativesAreRefused) {
  std::vector<TensorField> fields = export_json(kGGXIso, small_rgl_options());
  TensorField* lum = nullptr;
  for (TensorField& f : fields)
    if (f.name == "luminance") lum = &f;
  ASSERT_NE(lum, nullptr);
  std::vector<float> v = lum->floats();
  const float largest = *std::max_element(v.begin(), v.end());
  // Tiny negatives as in the real file: about 1e-10 of the largest value, at zeros and elsewhere.
  const std::vector<size_t> at{3, 17, 443, v.size() - 2};
  for (size_t k = 0; k < at.size(); ++k) v[at[k]] = -float(k + 1) * 1e-10f * largest;
  auto with = [&](const std::vector<float>& values) {
    std::vector<TensorField> fs = fields;
    for (TensorField& f : fs)
      if (f.name == "luminance") f = rgl::make_field("luminance", f.shape, values);
    return fs;
  };
  const auto d = read_back(with(v), "noisy.bsdf");
  ASSERT_EQ(d->notes.size(), 1u);
  const std::string& note = d->notes[0];
  for (const std::string& s : std::vector<std::string>{"noisy.bsdf", "field \"luminance\"", "4 negative values read as 0",
                                                       fmt::format("at flat index {})", at.back())})
    EXPECT_NE(note.find(s), std::string::npos) << "\"" << s << "\" not in: " << note;
  EXPECT_NE(note.find(fmt::format("{:.6g}", -4e-10f * largest)), std::string::npos) << note;  // the most negative
  ASSERT_EQ(d->read_as.size(), 1u);
  for (const size_t i : at) EXPECT_EQ(d->read_as[0].floats()[i], 0.f) << i;
  // The same file without the noise evaluates the same.
  std::vector<float> clean = v;
  for (const size_t i : at) clean[i] = 0.f;
  const auto c = read_back(with(clean), "clean.bsdf");
  EXPECT_TRUE(c->notes.empty());
  Rng rng(3);
  for (int i = 0; i < 50; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const glm::dvec3 a = rgl::rgl_kernel<double>(*d).f(wi, wo), b = rgl::rgl_kernel<double>(*c).f(wi, wo);
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(a[ch], b[ch]);
  }
  // The bound: 64 FLT_EPSILON x the largest value; one ulp beyond 1.5 x the bound is refused.
  const double bound = rgl::rounding_noise_bound(v);
  EXPECT_NEAR(bound, 64.0 * 1.1920929e-7 * largest, 1e-6 * bound);
  std::vector<float> bad = v;
  bad[100] = -float(1.5 * bound);
  try {
    (void)read_back(with(bad), "negative.bsdf");
    ADD_FAILURE() << "a clearly negative luminance accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string s : {"negative.bsdf", "field \"luminance\"", "at flat index 100", "read as 0"})
      EXPECT_NE(msg.find(s), std::string::npos) << "\"" << s << "\" not in: " << msg;
  }
  // NaN stays an error too, naming the index.
  bad = v;
  bad[7] = std::numeric_limits<float>::quiet_NaN();
  try {
    (void)read_back(with(bad), "nan.bsdf");
    ADD_FAILURE() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nan at flat index 7"), std::string::npos) << e.what();
  }
  // A zero sigma (a mirror's horizon): f divides by it; raised to the floor with a note.
  std::vector<TensorField> fs = fields;
  for (TensorField& f : fs)
    if (f.name == "sigma") {
      std::vector<float> sv = f.floats();
      sv[5] = 0.f;
      f = rgl::make_field("sigma", f.shape, sv);
    }
  const auto z = read_back(fs, "sigma0.bsdf");
  ASSERT_EQ(z->notes.size(), 1u);
  EXPECT_NE(z->notes[0].find("field \"sigma\": 1 value below 1e-06"), std::string::npos) << z->notes[0];
}

// The RGL database's own files (../shared/data/rgl-real/, README there; never copied into the
// repository): each reads, f is finite and >= 0 at a set of directions, and the note of rounding
// noise appears exactly for the files whose density tables hold values a little below 0.
std::vector<std::string> real_rgl_files() {
  const std::filesystem::path dir = std::filesystem::path(ANISO_SOURCE_DIR) / ".." / "shared" / "data" / "rgl-real";
  std::vector<std::string> out;
  if (std::filesystem::is_directory(dir))
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".bsdf") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RglReal, EveryFileReadsAndFIsFiniteAndNonNegative) {
  const std::vector<std::string> files = real_rgl_files();
  if (files.empty()) GTEST_SKIP() << "../shared/data/rgl-real/ is absent (CI has it): no real RGL file to read";
  for (const std::string& path : files) {
    const TensorFile t = rgl::read_tensor_file(path);
    // Whether a density table holds negatives (what the note must then report).
    bool noisy = false;
    for (const char* n : {"ndf", "sigma", "vndf", "luminance"})
      for (const float x : t.find(n)->floats()) noisy = noisy || x < 0.f;
    std::shared_ptr<rgl::RglData> d;
    ASSERT_NO_THROW(d = rgl::rgl_from_tensor(t)) << path;
    EXPECT_EQ(!d->notes.empty(), noisy) << path;
    for (const std::string& n : d->notes) EXPECT_NE(n.find("read as 0"), std::string::npos) << n;
    const RglT<double> k = rgl::rgl_kernel<double>(*d);
    Rng rng(11);
    for (int i = 0; i < 200; ++i) {
      const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
      const glm::dvec3 f = k.f(wi, wo);
      for (int ch = 0; ch < 3; ++ch) ASSERT_TRUE(std::isfinite(f[ch]) && f[ch] >= 0.0) << path << " f " << f[ch];
    }
    // The mirror direction of a few viewing angles too (the peak).
    for (const double th : {0.0, 0.3, 0.8, 1.3}) {
      const Vec3d wo(std::sin(th), 0.0, std::cos(th)), wi(-wo.x, -wo.y, wo.z);
      const glm::dvec3 f = k.f(wi, wo);
      for (int ch = 0; ch < 3; ++ch) ASSERT_TRUE(std::isfinite(f[ch]) && f[ch] >= 0.0) << path << " theta " << th;
    }
  }
}

// export-rgl's isotropy (rgl_export.h, decide_isotropy): the rotation test of a measured source
// allows for noise (kMeasuredIsotropyTolerance), an analytic one's does not; the flags force it.
TEST(RglExport, IsotropyDecision) {
  rgl::ExportOptions o;
  // A measured isotropic GGX with 1 % of noise that depends on the absolute azimuths (a
  // measurement's): isotropic within the tolerance, anisotropic without it.
  const MaterialD iso = build<double>(kGGXIso);
  rgl::BrdfSource noisy;
  noisy.f = [iso](const Vec3d& wi, const Vec3d& wo) {
    const double n = 1.0 + 0.01 * std::sin(7.0 * std::atan2(wi.y, wi.x) + 3.0 * std::atan2(wo.y, wo.x));
    return glm::dvec3(iso.f(wi, wo)) * n;
  };
  noisy.measured = true;
  const double rms = rgl::rotation_difference(noisy);
  EXPECT_GT(rms, 0.002);
  EXPECT_LT(rms, rgl::kMeasuredIsotropyTolerance);
  rgl::IsotropyDecision dec = rgl::decide_isotropy(noisy, o);
  EXPECT_TRUE(dec.isotropic) << dec.why;
  EXPECT_NE(dec.why.find("within"), std::string::npos) << dec.why;
  noisy.measured = false;
  EXPECT_FALSE(rgl::decide_isotropy(noisy, o).isotropic);
  // A measured anisotropic GGX (alpha 0.05 / 0.3) is anisotropic; the flags decide either way.
  rgl::BrdfSource aniso = rgl::brdf_source(build<double>(kGGXAniso));
  aniso.measured = true;
  EXPECT_GT(rgl::rotation_difference(aniso), 3.0 * rgl::kMeasuredIsotropyTolerance);
  EXPECT_FALSE(rgl::decide_isotropy(aniso, o).isotropic);
  o.isotropy = rgl::ExportOptions::Isotropy::Isotropic;
  dec = rgl::decide_isotropy(aniso, o);
  EXPECT_TRUE(dec.isotropic);
  EXPECT_NE(dec.why.find("--isotropic"), std::string::npos);
  o.isotropy = rgl::ExportOptions::Isotropy::Anisotropic;
  EXPECT_FALSE(rgl::decide_isotropy(rgl::brdf_source(iso), o).isotropic);
  // Written: one phi_i slice when isotropic, the full circle when forced anisotropic.
  rgl::ExportOptions s = small_rgl_options();
  s.isotropy = rgl::ExportOptions::Isotropy::Anisotropic;
  rgl::ExportReport rep;
  const auto forced = read_back(rgl::export_rgl(rgl::brdf_source(iso), s, &rep));
  EXPECT_GE(forced->phi_i.size(), size_t(s.phi_i));
  EXPECT_NE(rep.isotropy.find("--anisotropic"), std::string::npos) << rep.isotropy;
  s.isotropy = rgl::ExportOptions::Isotropy::Auto;
  const auto plain = read_back(rgl::export_rgl(rgl::brdf_source(iso), s, &rep));
  EXPECT_EQ(plain->phi_i.size(), 1u);
  EXPECT_NE(rep.isotropy.find("isotropic: f is unchanged"), std::string::npos) << rep.isotropy;
}

// A tensor file written from its own tables (transcode_tensor): RGB to spectral and back, one
// phi_i kept, f as the source's, at most twice the source's size; an anisotropic-grid file of an
// isotropic material is resampled to one phi_i slice.
class RglFromTensor : public Cli {};

TEST_F(RglFromTensor, IsotropicSourceStaysIsotropicAndSmall) {
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(export_json(kGGXIso, small_rgl_options()));
  const std::string path = write("iso.bsdf", std::string(bytes.begin(), bytes.end()));
  const MaterialDesc desc = load_material(path);
  const MaterialD m = build_material<double>(desc);
  rgl::BrdfSource src = rgl::brdf_source(m);
  src.tensor = desc.rgl;
  src.description = "test";
  for (const bool spectral : {true, false}) {
    rgl::ExportOptions o;
    o.spectral = spectral;
    rgl::ExportReport rep;
    const std::vector<uint8_t> out = rgl::serialize_tensor(rgl::export_rgl(src, o, &rep));
    EXPECT_TRUE(rep.transcoded);
    EXPECT_TRUE(rep.isotropic);
    EXPECT_NE(rep.isotropy.find("one phi_i"), std::string::npos) << rep.isotropy;
    // The same size written RGB; spectral, the rgb table (3 planes) becomes 21 (export_wavelengths):
    // the real files, whose vndf is most of the file, come to 1.9 x (RealFilesStay...).
    const uint64_t rgb_bytes = rgl::parse_tensor(bytes, "iso.bsdf").find("rgb")->bytes.size();
    EXPECT_LE(out.size(), bytes.size() + (spectral ? 6 * rgb_bytes : 0) + 512) << spectral;
    const auto d = rgl::rgl_from_tensor(rgl::parse_tensor(out, "out.bsdf"));
    EXPECT_EQ(d->phi_i.size(), 1u);
    EXPECT_EQ(d->spectral, spectral);
    EXPECT_NE(d->description.find("test"), std::string::npos);
    // f: the source's within the box spectra's round trip (rgb_to_box_coefficients, 1e-5).
    Rng rng(5);
    for (int i = 0; i < 100; ++i) {
      const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
      const glm::dvec3 a = rgl::rgl_kernel<double>(*d).f(wi, wo), b = glm::dvec3(m.f(wi, wo));
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(a[ch], b[ch], 1e-4 * b[ch] + 1e-6) << i << " " << ch;
    }
  }
  // The CLI says what it decided and the size against the source's.
  const std::string out = (dir_ / "out.bsdf").string();
  const Result r = run({"export-rgl", "-m", path, "-o", out});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "isotropic: the tensor file has one phi_i")) << r.err;
  EXPECT_TRUE(contains(r.err, "x the source's")) << r.err;
  const Result forced = run({"export-rgl", "-m", path, "-o", out, "--isotropic"});
  ASSERT_EQ(forced.code, 0) << forced.err;
  EXPECT_TRUE(contains(forced.err, "isotropic: --isotropic")) << forced.err;
  // An isotropic material on an anisotropic grid (33 phi_i, as export-rgl --anisotropic writes):
  // a measured source within the rotation noise, isotropic (written with one phi_i by the
  // resampling path, which IsotropyDecision covers).
  rgl::ExportOptions grid = small_rgl_options();
  grid.phi_i = 33;
  grid.isotropy = rgl::ExportOptions::Isotropy::Anisotropic;
  const std::vector<uint8_t> aniso_bytes = rgl::serialize_tensor(export_json(kGGXIso, grid));
  const std::string aniso_path = write("grid.bsdf", std::string(aniso_bytes.begin(), aniso_bytes.end()));
  const MaterialDesc grid_desc = load_material(aniso_path);
  EXPECT_FALSE(grid_desc.rgl->isotropic);
  rgl::BrdfSource grid_src = rgl::brdf_source(build_material<double>(grid_desc));
  grid_src.tensor = grid_desc.rgl;
  const rgl::IsotropyDecision dec = rgl::decide_isotropy(grid_src, rgl::ExportOptions{});
  EXPECT_TRUE(dec.isotropic) << dec.why;
  fmt::print("GGX alpha 0.2 on 33 phi_i: rotation difference {:.2f} %\n", 100.0 * dec.rotation_difference);
  EXPECT_EQ(run({"export-rgl", "-m", path, "-o", out, "--isotropic", "--anisotropic"}).code, 2);
}

// The real files through export-rgl: isotropic, one phi_i, at most twice the source's size.
TEST_F(RglFromTensor, RealFilesStayIsotropicWithinTwiceTheirSize) {
  const std::vector<std::string> files = real_rgl_files();
  if (files.empty()) GTEST_SKIP() << "../shared/data/rgl-real/ is absent (CI has it): no real RGL file to export";
  const std::string out = (dir_ / "real.bsdf").string();
  const Result r = run({"export-rgl", "-m", files.front(), "-o", out});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "isotropic: the tensor file has one phi_i")) << r.err;
  EXPECT_LE(std::filesystem::file_size(out), 2 * std::filesystem::file_size(files.front()));
  EXPECT_EQ(rgl::read_tensor_file(out).find("phi_i")->shape[0], 1u);
}

class RglCli : public Cli {};

TEST_F(RglCli, ExportShowAndBadFile) {
  const std::string out = (dir_ / "gold.bsdf").string();
  const Result r = run({"export-rgl", "--material", "brushed-gold", "--rgb", "--resolution", "8", "--theta-i", "4", "--phi-i",
                        "5", "--ndf", "16", "-o", out, "--check"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "anisotropic")) << r.err;
  EXPECT_TRUE(contains(r.out, "cosine-weighted relative L1")) << r.out;
  const Result show = run({"presets", "--show", out});
  ASSERT_EQ(show.code, 0) << show.err;
  EXPECT_TRUE(contains(show.out, "RGL tensor file")) << show.out;
  EXPECT_TRUE(contains(show.out, "anisotropic")) << show.out;
  EXPECT_TRUE(contains(show.out, "theta_i 4")) << show.out;
  EXPECT_TRUE(contains(show.out, "phi_i 5")) << show.out;
  EXPECT_TRUE(contains(show.out, "\"brushed-gold\"") || contains(show.out, "gold")) << show.out;
  const std::string bad = write("bad.bsdf", "tensor_file");
  const Result b = run({"presets", "--show", bad});
  EXPECT_EQ(b.code, 2);
  EXPECT_TRUE(contains(b.err, "aniso: error: " + bad)) << b.err;
  // --rgb and --spectral exclude each other; the resolution is range-checked.
  EXPECT_NE(run({"export-rgl", "-m", "gold", "-o", out, "--rgb", "--spectral"}).code, 0);
  const Result res = run({"export-rgl", "-m", "gold", "-o", out, "--resolution", "2"});
  EXPECT_EQ(res.code, 2);
  EXPECT_TRUE(contains(res.err, "--resolution")) << res.err;
  const Result vndf = run({"export-rgl", "-m", "gold", "-o", out, "--vndf", "4"});
  EXPECT_EQ(vndf.code, 2);
  EXPECT_TRUE(contains(vndf.err, "--vndf")) << vndf.err;
}

// A tensor file as a material (the registry row `rgl`, docs/models/rgl.md): a path ending in .bsdf
// and {"model": "rgl", "file": ...} (relative to the naming file's folder) evaluate the file's
// kernel; the CLI evaluates and renders it; GLSL and rotation_deg are refused with the way out.
class RglMaterial : public Cli {};

TEST_F(RglMaterial, ABsdfFileIsAMaterial) {
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(export_json(kGGXAniso, small_rgl_options()));
  const std::string path = write("ggx.bsdf", std::string(bytes.begin(), bytes.end()));
  const MaterialDesc d = load_material(path);
  EXPECT_EQ(d.model, "rgl");
  const MaterialD m = build_material<double>(d);
  EXPECT_EQ(m.kind, ModelKind::Rgl);
  const auto tables = rgl::rgl_from_tensor(rgl::parse_tensor(bytes, "ggx.bsdf"));
  const RglT<double> kernel = rgl::rgl_kernel<double>(*tables);
  const MaterialD relative =
      build_material<double>(parse_material({{"model", "rgl"}, {"file", "ggx.bsdf"}}, "scene.json", dir_.string()));
  Rng rng(8);
  int nonzero = 0;
  for (int i = 0; i < 500; ++i) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const RGBT<double> a = m.f(wi, wo), b = kernel.f(wi, wo), c = relative.f(wi, wo);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a[k], b[k]);
      EXPECT_EQ(c[k], b[k]);
    }
    EXPECT_EQ(m.pdf(wi, wo), kernel.pdf(wi, wo));
    nonzero += a[0] > 0.0;
  }
  EXPECT_GT(nonzero, 400);

  const Result e = run({"eval", "-m", path}, "0.3 0.1 0.9 -0.3 -0.1 0.9\n");
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_NEAR(std::stod(e.out), m.f(glm::normalize(Vec3d(0.3, 0.1, 0.9)), glm::normalize(Vec3d(-0.3, -0.1, 0.9)))[0], 1e-6);
  const Result r =
      run({"render", "--material", path, "--spp", "1", "--width", "16", "--height", "16", "-o", (dir_ / "r.png").string()});
  EXPECT_EQ(r.code, 0) << r.err;
  const Result g = run({"export-glsl", "-m", path});
  EXPECT_EQ(g.code, 2);
  EXPECT_TRUE(contains(g.err, "needs its tables file")) << g.err;
  try {
    (void)parse_material({{"model", "rgl"}, {"file", path}, {"rotation_deg", 10.0}}, "m.json");
    ADD_FAILURE() << "rotation_deg accepted";
  } catch (const InputError& err) {
    EXPECT_TRUE(contains(err.what(), "tangent.angle_deg")) << err.what();
  }
}

}  // namespace
}  // namespace aniso::test
