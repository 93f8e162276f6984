// The model registry (aniso/brdf/registry.h): every row reaches every dispatch.
//
// Compile time: the dispatches are generated from ANISO_MODELS, so a row cannot be left out of
// the ModelKind enumeration, the union, visit, visit_kind, the batch dispatch or the GLSL
// Material; what a row must bring (its parameter table k<Tag>Spec, its builder build(ModelType<..>),
// its GLSL builder body(ModelType<..>), its SimdTwin when it says Simd) is a compile error where it
// is used when missing (params.cpp, materials.cpp, glsl_material.cpp, dispatch-inl.h). The
// static_asserts below hold the union side over the whole list.
// Run time: every row has a parameter table named like it, a docs page quoting the table, its GLSL
// twin in the library and in the Material dispatch (or none, declared), a batch path (a SIMD twin
// file, or the declared scalar fallback), an independent reference formula, and a place in the
// test list every suite is instantiated over (test_util.h, all_model_materials).
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

}  // namespace
}  // namespace aniso
