// The model registry (aniso/brdf/registry.h): every row reaches every dispatch.
//
// Compile time: the dispatches are generated from ANISO_MODELS, so a row cannot be left out of
// the ModelKind enumeration, the union, visit, visit_kind, the batch dispatch or the GLSL
// Material; what a row must bring (its model file src/models/<member>.h with its table and its
// builders, bound rows or hand-written; its SimdTwin when it says Simd) is a compile error where it
// is used when missing (src/models/all.h, dispatch-inl.h). The
// static_asserts below hold the union side over the whole list.
// Run time: every row has a parameter table named like it, a docs page quoting the table, its GLSL
// twin in the library and in the Material dispatch (or none, declared), a batch path (a SIMD twin
// file, or the declared scalar fallback), an independent reference formula, and a place in the
// test list every suite is instantiated over (test_util.h, all_model_materials).
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include "aniso/batch/batch.h"
#include "aniso/brdf/material.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "test_util.h"

namespace aniso {
namespace {

// Each row's kernel converts to MaterialT (float and double) and the union holds it as the row's
// member.
#define ANISO_X(Tag, Type, member, name, batch, glsl)                                                                \
  static_assert(std::is_constructible_v<MaterialT<float>, const Type<float>&>, #Tag ": no MaterialT constructor");   \
  static_assert(std::is_constructible_v<MaterialT<double>, const Type<double>&>, #Tag ": no MaterialT constructor"); \
  static_assert(std::is_same_v<decltype(MaterialT<float>::member), Type<float>>, #Tag ": union member");
ANISO_MODELS(ANISO_X)
#undef ANISO_X

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::filesystem::path kRoot = ANISO_SOURCE_DIR;

TEST(Registry, VisitReachesEachRowsMember){
// visit hands the row's own kernel type to the function, for every row (no default case).
#define ANISO_X(Tag, Type, member, name, batch, glsl)                                                                   \
  {                                                                                                                     \
    const MaterialT<float> m{Type<float>{}};                                                                            \
    EXPECT_EQ(m.kind, ModelKind::Tag);                                                                                  \
    EXPECT_TRUE(m.visit([](const auto& x) { return std::is_same_v<std::decay_t<decltype(x)>, Type<float>>; })) << #Tag; \
    EXPECT_TRUE(visit_kind<double>(ModelKind::Tag, [](auto t) {                                                         \
      return std::is_same_v<typename decltype(t)::type, Type<double>>;                                                  \
    })) << #Tag;                                                                                                        \
  }
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
}

TEST(Registry, EveryRowHasItsParameterTableInRegistryOrder) {
  ASSERT_EQ(model_specs().size(), kModelCount);
  for (size_t i = 0; i < kModelCount; ++i) {
    EXPECT_EQ(model_specs()[i]->name, kModels[i].name);
    EXPECT_EQ(find_model_kind(kModels[i].name), kModels[i].kind);
    EXPECT_EQ(std::string(model_name(kModels[i].kind)), kModels[i].name);
  }
  EXPECT_FALSE(find_model_kind("wardd").has_value());
}

// (That each page quotes its generated table verbatim is Docs.ModelPagesQuoteTheGeneratedParameterTables.)
TEST(Registry, EveryRowHasADocsPage) {
  for (const ModelInfo& m : kModels)
    EXPECT_TRUE(std::filesystem::exists(kRoot / "docs" / "models" / (std::string(m.name) + ".md"))) << m.name;
}

TEST(Registry, EveryGlslRowHasItsTwinInTheLibraryAndTheDispatch) {
  std::set<std::string> paths;
  for (const gl::GlslFile& f : gl::glsl_library_files()) paths.insert(std::string(f.path));
  const std::string dispatch = gl::glsl_material_dispatch();
  for (const ModelInfo& m : kModels) {
    const std::string path = std::string("include/aniso/brdf/") + m.member + ".glsl";
    EXPECT_NE(dispatch.find(std::string("const int ModelKind_") + m.tag + " = " + std::to_string(int(m.kind)) + ";"),
              std::string::npos)
        << m.tag;
    if (!m.glsl) {
      // Declared without a twin: no file, no member, and the exports refuse it with a message.
      EXPECT_EQ(paths.count(path), 0u) << path;
      EXPECT_EQ(dispatch.find(std::string("self.") + m.member), std::string::npos) << m.tag;
      continue;
    }
    EXPECT_EQ(paths.count(path), 1u) << path << " is not in the GLSL library";
    EXPECT_TRUE(std::filesystem::exists(kRoot / path)) << path;
    EXPECT_NE(dispatch.find(std::string("  ") + m.tag + " " + m.member + ";"), std::string::npos) << m.tag;
    if (m.kind == ModelKind::Lambert) continue;  // Lambert is each function's last line
    for (const char* fn : {"f(self.", "pdf(self.", "sample(self."})
      EXPECT_NE(dispatch.find(std::string(m.tag) + "_" + fn + m.member), std::string::npos) << m.tag << " " << fn;
  }
}

TEST(Registry, EveryRowHasABatchPath) {
  for (const ModelInfo& m : kModels) {
    const std::filesystem::path twin = kRoot / "src" / "batch" / "twins" / (std::string(m.member) + "-inl.h");
    if (m.batch == BatchPath::Simd)
      EXPECT_TRUE(std::filesystem::exists(twin)) << twin;
    else
      EXPECT_FALSE(std::filesystem::exists(twin)) << twin << ": the registry says Scalar";
  }
}

TEST(Registry, EveryRowHasAReferenceFormula) {
  // An independent transcription (plain double, from the papers) per analytic model; the measured
  // table's reference is MERL's BRDFRead.cpp, transcribed in test_merl.cpp.
  const std::string reference = read_text(kRoot / "tests" / "reference" / "reference_brdfs.h");
  const std::string merl = read_text(kRoot / "tests" / "test_merl.cpp");
  for (const ModelInfo& m : kModels) {
    if (m.kind == ModelKind::Measured) {
      EXPECT_NE(merl.find("an independent transcription of MERL's BRDFRead.cpp"), std::string::npos);
      continue;
    }
    // The tensor file's kernel is pbrt-v4's MeasuredBxDF transcribed; its reference is the analytic
    // material a file was written from (test_rgl.cpp, RglRoundTrip).
    if (m.kind == ModelKind::Rgl) {
      EXPECT_NE(read_text(kRoot / "tests" / "test_rgl.cpp").find("RglRoundTrip, ReadBackMatchesTheSource"), std::string::npos);
      continue;
    }
    EXPECT_NE(reference.find(std::string("inline C3 ") + m.member + "("), std::string::npos)
        << "tests/reference/reference_brdfs.h has no C3 " << m.member << "(...)";
  }
}

TEST(Registry, EveryAnalyticRowIsInTheTestList) {
  // all_model_materials() is what the property, sampling, batch, albedo, GLSL, GL and plot suites
  // are instantiated over; the measured tables have their own suites (test_measured.cpp,
  // test_rgl.cpp).
  std::set<std::string> listed;
  for (const test::NamedMaterial& nm : test::all_model_materials()) listed.insert(nm.json.at("model").get<std::string>());
  for (const ModelInfo& m : kModels) {
    if (m.kind == ModelKind::Measured || m.kind == ModelKind::Rgl) continue;
    EXPECT_EQ(listed.count(m.name), 1u) << m.name << " is not in all_model_materials()";
  }
}

// Every row says how it roughens (core/kernel.h, ModelKernel, checked at compile time in
// registry.h): no model changes for alpha <= 0 or below its own roughness, the analytic glossy ones
// change at 0.5, and Lambert, Lafortune and the tables are left as they are (their reasons beside
// each regularize).
TEST(Registry, EveryRowRegularizesByItsOwnRule) {
  std::vector<std::pair<std::string, Material>> materials;
  for (const test::NamedMaterial& nm : test::all_model_materials()) materials.emplace_back(nm.name, test::build<float>(nm.json));
  materials.emplace_back("measured", Material(MeasuredT<float>{}));
  materials.emplace_back("rgl", Material(RglT<float>{}));
  std::set<ModelKind> seen;
  for (const auto& [name, m] : materials) {
    seen.insert(m.kind);
    for (const float alpha : {0.0f, -1.0f, 1e-4f}) {
      Material r = m;
      r.regularize(alpha);
      EXPECT_EQ(std::memcmp(&r, &m, sizeof m), 0) << name << " alpha " << alpha;
    }
    Material r = m;
    r.regularize(0.5f);
    const bool left = m.kind == ModelKind::Lambert || m.kind == ModelKind::Lafortune || m.kind == ModelKind::Measured ||
                      m.kind == ModelKind::Rgl;
    EXPECT_EQ(std::memcmp(&r, &m, sizeof m) == 0, left) << name;
  }
  EXPECT_EQ(seen.size(), kModelCount);
}

// The exporters' question (core/kernel.h, ggx_distribution): where a model says it is a GGX as a
// whole, the GGX it describes (D, G, F and a Lambertian term) is its f.
TEST(Registry, AWholeGgxIsTheModel) {
  const auto ggx_f = [](const GgxDistributionT<double>& d, const Vec3d& wi, const Vec3d& wo) {
    const Vec3d h = glm::normalize(wi + wo);
    const double D = D_GGX_Aniso(h.x, h.y, h.z, d.alpha_x, d.alpha_y);
    const double G =
        d.masking == GgxMasking::HeightCorrelated
            ? G2_SmithGGX_HeightCorrelated(Lambda_GGX_Aniso(wi, d.alpha_x, d.alpha_y),
                                           Lambda_GGX_Aniso(wo, d.alpha_x, d.alpha_y)) /
                  (4.0 * wi.z * wo.z)
            : Principled_SmithG_GGX_Aniso(wi, d.alpha_x, d.alpha_y) * Principled_SmithG_GGX_Aniso(wo, d.alpha_x, d.alpha_y);
    const double c = glm::dot(wi, h);
    const Vec3d F = d.fresnel == GgxFresnel::Conductor ? F_Conductor(c, d.eta, d.k) : F_Schlick(d.f0, d.f90, c);
    return F * D * G + d.kd / M_PI;
  };
  int whole = 0;
  for (const test::NamedMaterial& nm : test::all_model_materials()) {
    const MaterialD m = test::build<double>(nm.json);
    const GgxDistributionT<double> d = m.ggx_distribution();
    if (d.part != GgxPart::Whole) continue;
    ++whole;
    for (const auto& [ti, pi, to, po] : {std::array{20.0, 0.0, 35.0, 180.0}, std::array{60.0, 40.0, 10.0, 250.0}}) {
      const Vec3d wi = m.rotation.to_model(test::spherical(ti, pi)), wo = m.rotation.to_model(test::spherical(to, po));
      const Vec3d want = m.visit([&](const auto&k) { return Vec3d(k.f(wi, wo)); }), got = ggx_f(d, wi, wo);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * std::max(1.0, want[c])) << nm.name;
    }
  }
  EXPECT_GE(whole, 4);  // ggx_aniso, ggx_iso, metal_ggx, principled_metal_aniso, principled_rotated
  // A lobe beside other terms, and none.
  EXPECT_EQ(test::build<double>({{"model", "principled"}, {"clearcoat", 0.5}}).ggx_distribution().part, GgxPart::None);
  EXPECT_EQ(test::build<double>({{"model", "principled"}, {"metallic", 0.5}}).ggx_distribution().part, GgxPart::Lobe);
  EXPECT_EQ(test::build<double>({{"model", "metal"},
                                 {"metal", "gold"},
                                 {"lobe", {{"model", "ggx"}}},
                                 {"directional_diffuse", {{"albedo", 0.2}, {"n", 4.0}}}})
                .ggx_distribution()
                .part,
            GgxPart::Lobe);
  for (const char* model : {"lambert", "phong", "ward", "ashikhmin-shirley"})
    EXPECT_EQ(test::build<double>({{"model", model}}).ggx_distribution().part, GgxPart::None) << model;
}

}  // namespace
}  // namespace aniso
