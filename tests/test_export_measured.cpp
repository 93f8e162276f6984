// tests/test_export_measured.cpp: exports that look like the source (docs/export.md, "Measured
// sources" and "The check in image space"): a measured source as Mitsuba 3's and pbrt-v4's own
// measured BSDF with its tensor file beside the scene; the fitted targets' rules (an isotropic
// source stays isotropic, a negligible diffuse never flips the metal / dielectric branch, factors
// within their meaning); the image check in every report.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/export/export.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"
#include "cli_fixture.h"
#include "input_error_text.h"

namespace aniso {
namespace {

using namespace exporter;
using json = nlohmann::json;

// An RGL tensor file written by aniso's export-rgl code (src/rgl) from an analytic material, on
// small grids (the tests' files, not the database's).
void write_rgl(const std::filesystem::path& path, const std::string& material, bool anisotropic) {
  const MaterialD m = build_material<double>(load_material(material));
  rgl::BrdfSource src = rgl::brdf_source(m);
  src.description = "test file: " + material;
  rgl::ExportOptions o;
  o.spectral = false;
  o.colour = 16, o.theta_i = 6, o.phi_i = 9, o.ndf = 32, o.vndf = 16;
  o.isotropy = anisotropic ? rgl::ExportOptions::Isotropy::Anisotropic : rgl::ExportOptions::Isotropy::Isotropic;
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(rgl::export_rgl(src, o));
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

ExportOptions quick(const std::string& target) {
  ExportOptions o;
  o.target = target;
  o.grid = 2, o.starts = 1, o.check_size = 16, o.measured_grid = 16;
  return o;
}

// A diffuse of 1e-4 or 2.5e-4 in one channel on a GGX metal: every target writes the same model and
// branch as for kd 0 (negligible_diffuse's margin), and no colour from it (Mitsuba 3's blend of a
// pure-green diffuse was the symptom).
TEST(ExportRules, NegligibleDiffuseNeverFlipsTheBranch) {
  const std::string base = R"({"model": "ggx", "alpha_x": 0.2, "alpha_y": 0.2, "f0": [0.95, 0.64, 0.54], "kd": )";
  for (const TargetInfo& t : targets()) {
    const ExportResult r0 = export_material(load_material(base + "0}"), "metal", quick(std::string(t.name)));
    for (const char* kd : {"[0.00025, 0, 0]", "[0, 0.0001, 0]", "[0.00025, 0.0001, 0.00025]"}) {
      const ExportResult r = export_material(load_material(base + kd + "}"), "metal", quick(std::string(t.name)));
      EXPECT_EQ(r.report.target_model, r0.report.target_model) << t.name << " kd " << kd;
      EXPECT_EQ(r.report.parameters.dump(), r0.report.parameters.dump()) << t.name << " kd " << kd;
      EXPECT_NEAR(r.report.errors.relative_l2cos, r0.report.errors.relative_l2cos, 0.01) << t.name << " kd " << kd;
    }
  }
  // A diffuse that is not negligible keeps its branch (a dielectric).
  const ExportResult d = export_material(load_material(base + "0.2}"), "plastic", quick("blender"));
  EXPECT_EQ(d.report.parameters["Metallic"].get<double>(), 0.0) << d.report.parameters.dump();
}

// glTF: a dielectric F0 of 0.46 (with a diffuse part) is written through KHR_materials_ior, every
// factor within [0, 1] (specularColorFactor 11.6 before).
TEST(ExportRules, GltfFactorsStayWithinTheirMeaning) {
  const ExportResult r = export_material(
      load_material(R"({"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.1, "f0": [0.1, 0.3, 0.46], "kd": [0.1, 0.1, 0.05]})"),
      "film", quick("gltf"));
  const json& p = r.report.parameters;
  ASSERT_TRUE(p.contains("specularColorFactor")) << p.dump();
  for (int c = 0; c < 3; ++c) {
    EXPECT_GE(p["specularColorFactor"][c].get<double>(), 0.0) << p.dump();
    EXPECT_LE(p["specularColorFactor"][c].get<double>(), 1.0) << p.dump();
    EXPECT_LE(p["baseColorFactor"][c].get<double>(), 1.0) << p.dump();
  }
  EXPECT_GT(p["ior"].get<double>(), 1.5) << p.dump();
  // Schlick's F0 carried exactly; what remains is glTF's diffuse weighted by 1 - max(F) (noted).
  EXPECT_LT(r.report.errors.relative_l2cos, 0.05) << r.report.text();
}

using ExportMeasuredCli = Cli;

// An isotropic RGL file (one phi_i) is isotropic by construction: the fit is isotropic and no target
// writes an anisotropy; an anisotropic file (a GGX 0.08 x 0.3 on 9 azimuths) is written anisotropic.
TEST_F(ExportMeasuredCli, IsotropicRglFileStaysIsotropicAnAnisotropicOneDoesNot) {
  const auto iso = dir_ / "iso.bsdf", aniso_file = dir_ / "aniso.bsdf";
  write_rgl(iso, R"({"model": "ggx", "alpha_x": 0.15, "alpha_y": 0.15, "f0": 0.05, "kd": [0.3, 0.2, 0.1]})", false);
  write_rgl(aniso_file, R"({"model": "ggx", "alpha_x": 0.08, "alpha_y": 0.3, "f0": [0.9, 0.6, 0.4], "kd": 0})", true);
  const ExportResult r = export_material(load_material(iso.string()), iso.string(), quick("gltf"));
  EXPECT_TRUE(r.ggx.isotropic) << r.report.text();
  EXPECT_EQ(r.ggx.alpha_x, r.ggx.alpha_y) << r.report.text();
  EXPECT_EQ(r.report.parameters["anisotropyStrength"].get<double>(), 0.0) << r.report.parameters.dump();
  for (const char* t : {"blender", "materialx", "openpbr"}) {
    json p;
    (void)target_model(find_target(t)->target, r.ggx, &p);
    const char* key = std::string(t) == "blender"     ? "Anisotropic"
                      : std::string(t) == "materialx" ? "specular_anisotropy"
                                                      : "specular_roughness_anisotropy";
    EXPECT_EQ(p[key].get<double>(), 0.0) << t << ": " << p.dump();
  }
  const ExportResult a = export_material(load_material(aniso_file.string()), aniso_file.string(), quick("gltf"));
  EXPECT_FALSE(a.ggx.isotropic) << a.report.text();
  EXPECT_GT(a.report.parameters["anisotropyStrength"].get<double>(), 0.3) << a.report.parameters.dump();
}

// Mitsuba 3 and pbrt-v4: a tensor file is written as the renderer's own measured BSDF, the tensor
// beside the scene (Mitsuba 3: rgb; pbrt-v4: spectral, with wavelengths), its name from -o made safe;
// --analytic writes the fitted material and no tensor file.
TEST_F(ExportMeasuredCli, TensorFileWrittenAsTheRenderersMeasuredBsdf) {
  const auto iso = dir_ / "film.bsdf";
  write_rgl(iso, R"({"model": "ggx", "alpha_x": 0.15, "alpha_y": 0.15, "f0": 0.05, "kd": [0.3, 0.2, 0.1]})", false);
  const std::string xml = (dir_ / "my film.xml").string();
  Result r = run({"export", "--to", "mitsuba3", "--material", iso.string(), "-o", xml, "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string x = read_file(xml);
  EXPECT_TRUE(contains(x, "<bsdf type=\"measured\"")) << x;
  EXPECT_TRUE(contains(x, "<string name=\"filename\" value=\"my_film_rgb.bsdf\"/>")) << x;
  const rgl::TensorFile rgb = rgl::read_tensor_file((dir_ / "my_film_rgb.bsdf").string());
  EXPECT_TRUE(rgb.find("rgb") != nullptr);
  EXPECT_FALSE(rgb.find("wavelengths") != nullptr);
  EXPECT_TRUE(contains(r.out, "image check")) << r.out;
  EXPECT_TRUE(contains(r.out, "relative 0)") || contains(r.out, "relative 1e-") || contains(r.out, "relative 2e-")) << r.out;

  const std::string pbrt = (dir_ / "film.pbrt").string();
  r = run({"export", "--to", "pbrt-v4", "--material", iso.string(), "-o", pbrt, "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string s = read_file(pbrt);
  EXPECT_TRUE(contains(s, "\"string type\" \"measured\"")) << s;
  EXPECT_TRUE(contains(s, "\"string filename\" \"film_spec.bsdf\"")) << s;
  const rgl::TensorFile spec = rgl::read_tensor_file((dir_ / "film_spec.bsdf").string());
  EXPECT_TRUE(spec.find("wavelengths") != nullptr);
  EXPECT_TRUE(spec.find("spectra") != nullptr);

  const std::string analytic = (dir_ / "fit.pbrt").string();
  r = run(
      {"export", "--to", "pbrt-v4", "--material", iso.string(), "-o", analytic, "--grid", "2", "--starts", "1", "--analytic"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(contains(read_file(analytic), "measured")) << read_file(analytic);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "fit_spec.bsdf"));
  // stdout cannot hold two files.
  r = run({"export", "--to", "mitsuba3", "--material", iso.string()});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(contains(r.err, "--analytic")) << r.err;
}

// The material's name is the source file's stem whatever the target and path (export.cpp,
// material_name): a tensor file's as a JSON file's, not its full path; the tensor file beside the
// scene is named from -o (measured_file_name_for_path).
TEST_F(ExportMeasuredCli, MaterialNameIsTheSourceFilesStem) {
  std::filesystem::create_directories(dir_ / "films");
  const auto film = dir_ / "films" / "Film.BSDF";
  write_rgl(film, R"({"model": "ggx", "alpha_x": 0.15, "alpha_y": 0.15, "f0": 0.05, "kd": [0.3, 0.2, 0.1]})", false);
  const std::string xml = (dir_ / "scene.xml").string();
  Result r = run({"export", "--to", "mitsuba3", "--material", film.string(), "-o", xml, "--grid", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(read_file(xml), "<bsdf type=\"measured\" id=\"Film\">")) << read_file(xml);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "scene_rgb.bsdf"));
  const std::string pbrt = (dir_ / "fit.pbrt").string();
  r = run({"export", "--to", "pbrt-v4", "--material", film.string(), "-o", pbrt, "--grid", "2", "--starts", "1", "--analytic"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(read_file(pbrt), "MakeNamedMaterial \"Film\"")) << read_file(pbrt);
  const std::string json_file = (dir_ / "films" / "paint.json").string();
  std::ofstream(json_file) << R"({"model": "ggx", "alpha_x": 0.15, "alpha_y": 0.15, "f0": 0.05, "kd": 0.3})";
  for (const std::string& m : {film.string(), json_file}) {
    r = run({"export", "--to", "blender", "--material", m, "--grid", "2", "--starts", "1"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, m == json_file ? "NAME = \"paint\"\n" : "NAME = \"Film\"\n")) << r.out;
  }
}

// The image check: an exact export renders as its source (within the check's own quadrature), in
// the report's text, its JSON and the glTF's asset.extras.
TEST(ExportRules, ImageCheckInEveryReport) {
  const ExportResult r =
      export_material(load_material(R"({"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.3, "f0": 0.04, "kd": [0.4, 0.2, 0.1]})"),
                      "plastic", quick("openpbr"));
  EXPECT_EQ(r.report.image.size, 16);
  EXPECT_GT(r.report.image.mean_source, 0.0);
  EXPECT_LT(r.report.image.mean_difference, 0.25);
  const json j = r.report.to_json();
  ASSERT_TRUE(j.contains("image_check")) << j.dump();
  EXPECT_TRUE(j["image_check"]["mean"].contains("relative_difference"));
  EXPECT_TRUE(contains(r.report.text(), "image check")) << r.report.text();
  const ExportResult exact =
      export_material(load_material(R"({"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.3, "f0": 0.04, "kd": [0.4, 0.2, 0.1]})"),
                      "plastic", quick("gltf"));
  EXPECT_LT(exact.report.image.mean_difference, 0.05) << exact.report.text();
}

}  // namespace
}  // namespace aniso
