// gl/glsl_library.cpp: the embedded GLSL library and the name handling the exports use.
#include "aniso/gl/glsl_library.h"

#include <cctype>
#include <deque>
#include <regex>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "aniso/brdf/registry.h"

namespace aniso::embedded {
extern const std::string_view glsl_core_platform, glsl_core_math, glsl_core_frame, glsl_core_sampling, glsl_core_lobe_mixture,
    glsl_brdf_fresnel, glsl_tangent_fields, glsl_image_tonemap;
// The twin of each registry row that says Glsl: include/aniso/brdf/<member>.glsl (CMakeLists.txt
// embeds every brdf/*.glsl; a row whose file is missing does not link).
#define ANISO_GLSL_EXTERN_Glsl(member) extern const std::string_view glsl_brdf_##member;
#define ANISO_GLSL_EXTERN_NoGlsl(member)
#define ANISO_X(Tag, Type, member, name, batch, glsl) ANISO_GLSL_EXTERN_##glsl(member)
ANISO_MODELS(ANISO_X)
#undef ANISO_X
}  // namespace aniso::embedded

namespace aniso::gl {

std::string glsl_material_dispatch() {
  std::string kinds, members, f, pdf, sample;
  for (const ModelInfo& m : kModels) {
    kinds += fmt::format("const int ModelKind_{} = {};\n", m.tag, int(m.kind));
    if (!m.glsl) continue;
    members += fmt::format("  {} {};\n", m.tag, m.member);
    if (m.kind == ModelKind::Lambert) continue;  // the last line of each function
    const std::string test = fmt::format("  if (self.kind == ModelKind_{}) return {}_", m.tag, m.tag);
    f += fmt::format("{}f(self.{}, wi, wo);\n", test, m.member);
    pdf += fmt::format("{}pdf(self.{}, wi, wo);\n", test, m.member);
    sample += fmt::format("{}sample(self.{}, wo, uc, u);\n", test, m.member);
  }
  return fmt::format(
      "// aniso/brdf/material.glsl: GLSL twin of material.h, generated from the registry\n"
      "// (aniso/brdf/registry.h) by src/gl/glsl_library.cpp: every model behind one value type,\n"
      "// dispatched by a tag. GLSL has no unions: Material holds one member per model and `kind` says\n"
      "// which one is live (the others are never read). A model without a GLSL twin would have a\n"
      "// ModelKind constant and no member. The measured models (Measured, Rgl) read their tables from\n"
      "// the tables texture (measured.glsl); their members hold the tables' indices.\n"
      "//\n"
      "// Interface of every model (docs/conventions.md): directions in the local shading frame\n"
      "// (z = normal, x = tangent), wi towards the light, wo towards the viewer, both unit.\n"
      "//   Material_f(m, wi, wo)           the BRDF without the cosine; 0 unless both are above the horizon\n"
      "//   Material_pdf(m, wi, wo)         the solid-angle density of Material_sample producing wi for this wo\n"
      "//   Material_sample(m, wo, uc, u)   {{wi, weight = f cos / pdf, pdf}} or \"no sample\"; uc picks the lobe,\n"
      "//                                   u (2D) the direction; all uniform in [0, 1)\n"
      "\n"
      "// enum class ModelKind (enumerator values as in registry.h).\n"
      "{}\n"
      "// The orientation (material.h, FrameRotationT): r = (cos a, sin a) of the material's rotation_deg,\n"
      "// the tangent turned about the normal, t' = cos a t + sin a b. Directions into the turned frame\n"
      "// the model lives in, and sampled ones back.\n"
      "vec3 FrameRotation_to_model(vec2 r, vec3 w) {{ return vec3(r.x * w.x + r.y * w.y, r.x * w.y - r.y * w.x, w.z); }}\n"
      "vec3 FrameRotation_from_model(vec2 r, vec3 w) {{ return vec3(r.x * w.x - r.y * w.y, r.y * w.x + r.x * w.y, w.z); }}\n"
      "\n"
      "struct Material {{\n  int kind;  // ModelKind_*\n  vec2 rotation;  // FrameRotation: (1, 0) unless rotation_deg\n{}}};\n\n"
      "// The model of `kind` in its own (turned) frame.\n"
      "vec3 Material_model_f(Material self, vec3 wi, vec3 wo) {{\n{}  return Lambert_f(self.lambert, wi, wo);\n}}\n"
      "float Material_model_pdf(Material self, vec3 wi, vec3 wo) {{\n{}  return Lambert_pdf(self.lambert, wi, wo);\n}}\n"
      "BSDFSample Material_model_sample(Material self, vec3 wo, float uc, vec2 u) {{\n{}"
      "  return Lambert_sample(self.lambert, wo, uc, u);\n}}\n"
      "\n"
      "vec3 Material_f(Material self, vec3 wi, vec3 wo) {{\n"
      "  return Material_model_f(self, FrameRotation_to_model(self.rotation, wi), FrameRotation_to_model(self.rotation, "
      "wo));\n}}\n"
      "float Material_pdf(Material self, vec3 wi, vec3 wo) {{\n"
      "  return Material_model_pdf(self, FrameRotation_to_model(self.rotation, wi), FrameRotation_to_model(self.rotation, "
      "wo));\n}}\n"
      "BSDFSample Material_sample(Material self, vec3 wo, float uc, vec2 u) {{\n"
      "  BSDFSample s = Material_model_sample(self, FrameRotation_to_model(self.rotation, wo), uc, u);\n"
      "  s.wi = FrameRotation_from_model(self.rotation, s.wi);\n"
      "  return s;\n}}\n",
      kinds, members, f, pdf, sample);
}

namespace {

// The GLSL twin of lobe_mixture.h's templates, one text per template with $Model and $Lobe for the
// GLSL names of the model and of its lobe (docs/glsl.md, "Naming"): GLSL has no templates, so each
// model gets overloads with the C++ names and argument order. Every diffuse + specular model:
// pdf_diffuse_specular, sample_diffuse_specular and the model's pdf and sample through them.
constexpr std::string_view kDiffuseSpecularGlsl = R"(float pdf_diffuse_specular(float p_spec, $Lobe lobe, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return 0.0;
  return pdf_diffuse_specular_mix(p_spec, $Lobe_pdf(lobe, wi, wo), wi, wo);
}
float $Model_pdf($Model self, vec3 wi, vec3 wo) {
  return pdf_diffuse_specular($Model_specular_probability(self, wo), self.lobe, wi, wo);
}
BSDFSample sample_diffuse_specular($Model model, $Lobe lobe, float p_spec, vec3 wo, float uc, vec2 u) {
  if (!above_horizon(wo)) return BSDFSample_none();
  vec3 wi = uc < p_spec ? $Lobe_sample(lobe, wo, u) : sample_cosine_hemisphere(u);
  if (!above_horizon(wi)) return BSDFSample_none();
  return make_sample(wi, $Model_f(model, wi, wo), $Model_pdf(model, wi, wo));
}
BSDFSample $Model_sample($Model self, vec3 wo, float uc, vec2 u) {
  return sample_diffuse_specular(self, self.lobe, $Model_specular_probability(self, wo), wo, uc, u);
}
)";

// LambertPlusLobeT<T, Lobe>: the model's struct, f and lobe choice, before kDiffuseSpecularGlsl.
constexpr std::string_view kLambertPlusLobeGlsl =
    R"(// $Model = LambertPlusLobeT<T, $LobeT<T>> (lobe_mixture.h): f = kd / pi + ks lobe(wi, wo).
struct $Model {
  vec3 kd;
  vec3 ks;
  $Lobe lobe;
};

vec3 $Model_f($Model self, vec3 wi, vec3 wo) {
  if (!same_upper_hemisphere(wi, wo)) return vec3(0.0);
  return self.kd * kInvPi + self.ks * $Lobe_eval(self.lobe, wi, wo);
}
// Lobe choice by average colour (Walter 2005, Sec. 4).
float $Model_specular_probability($Model self, vec3 wo) { return specular_share(average_rgb(self.kd), average_rgb(self.ks)); }
)";

// A model made of lobe_mixture.h's mixture: one specular `lobe`, chosen with probability
// specular_probability(wo), its pdf and sample pdf_diffuse_specular and sample_diffuse_specular of
// those (Phong, Ward, Ashikhmin-Shirley, GGX). The GLSL parity tests hold each generated model to
// its C++ kernel.
template <typename M>
concept DiffuseSpecularModel = requires(const M& m, const Vec3T<float>& wo) {
  m.lobe;
  m.specular_probability(wo);
};
template <typename M> constexpr bool kIsLambertPlusLobe = false;
template <typename T, typename Lobe> constexpr bool kIsLambertPlusLobe<LambertPlusLobeT<T, Lobe>> = true;

template <typename M> constexpr LobeMixture lobe_mixture_of() {
  if constexpr (kIsLambertPlusLobe<M>)
    return LobeMixture::LambertPlusLobe;
  else if constexpr (DiffuseSpecularModel<M>)
    return LobeMixture::DiffuseSpecular;
  else
    return LobeMixture::None;
}

void replace_all(std::string& s, std::string_view from, std::string_view to) {
  for (size_t i = s.find(from); i != std::string::npos; i = s.find(from, i + to.size())) s.replace(i, from.size(), to);
}

}  // namespace

std::string glsl_lobe_mixture(std::string_view model, LobeMixture mixture) {
  if (mixture == LobeMixture::None) return {};
  std::string out = fmt::format(
      "// {0} with its lobe {0}Lobe: the diffuse + specular mixture of lobe_mixture.h, generated from\n"
      "// its template by gl::glsl_lobe_mixture (src/gl/glsl_library.cpp).\n",
      model);
  if (mixture == LobeMixture::LambertPlusLobe) out += kLambertPlusLobeGlsl;
  out += kDiffuseSpecularGlsl;
  replace_all(out, "$Model", model);
  replace_all(out, "$Lobe", std::string(model) + "Lobe");
  return out;
}

std::span<const GlslFile> glsl_library_files() {
  using namespace aniso::embedded;
  static const std::string dispatch = glsl_material_dispatch();
  // The models' generated mixtures (a deque keeps each text in place as it grows).
  static std::deque<std::string> mixtures;
  // Paths as written in the repository; the models' twins in registry order (metal after the
  // lobes it holds), each followed by its generated mixture if its C++ type is built on one, then
  // the generated Material dispatch.
  static const std::vector<GlslFile> files = [] {
    std::vector<GlslFile> v = {
        {"include/aniso/core/platform.glsl", glsl_core_platform},
        {"include/aniso/core/math.glsl", glsl_core_math},
        {"include/aniso/core/frame.glsl", glsl_core_frame},
        {"include/aniso/core/sampling.glsl", glsl_core_sampling},
        {"include/aniso/core/lobe_mixture.glsl", glsl_core_lobe_mixture},
        {"include/aniso/brdf/fresnel.glsl", glsl_brdf_fresnel},
    };
#define ANISO_GLSL_FILE_Glsl(Tag, Type, member)                                                                              \
  v.push_back({"include/aniso/brdf/" #member ".glsl", glsl_brdf_##member});                                                  \
  if (const std::string& mix = mixtures.emplace_back(glsl_lobe_mixture(#Tag, lobe_mixture_of<Type<float>>())); !mix.empty()) \
    v.push_back({"include/aniso/brdf/" #member "_mixture.glsl (generated: lobe_mixture.h's template)", mix});
#define ANISO_GLSL_FILE_NoGlsl(Tag, Type, member)
#define ANISO_X(Tag, Type, member, name, batch, glsl) ANISO_GLSL_FILE_##glsl(Tag, Type, member)
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
    v.push_back({"include/aniso/brdf/material.glsl (generated from the registry)", dispatch});
    v.push_back({"include/aniso/tangent/fields.glsl", glsl_tangent_fields});
    return v;
  }();
  return files;
}

std::string glsl_library_source() {
  std::string out;
  for (const GlslFile& f : glsl_library_files()) {
    out += "// ---- ";
    out += f.path;
    out += "\n";
    out += f.source;
    if (!out.empty() && out.back() != '\n') out += '\n';
  }
  return out;
}

std::string_view glsl_tonemap_source() { return embedded::glsl_image_tonemap; }

namespace {

// The identifiers of a line of GLSL outside its // comment (the library has no /* */ comments).
void identifiers(std::string_view code, std::set<std::string>& out) {
  size_t i = 0;
  while (i < code.size()) {
    const unsigned char c = static_cast<unsigned char>(code[i]);
    if (std::isalpha(c) || c == '_') {
      size_t j = i;
      while (j < code.size() && (std::isalnum(static_cast<unsigned char>(code[j])) || code[j] == '_')) ++j;
      out.emplace(code.substr(i, j - i));
      i = j;
    } else if (std::isdigit(c)) {  // a number and its suffix (1e-6, 0x80000000u): no identifier
      while (i < code.size() && (std::isalnum(static_cast<unsigned char>(code[i])) || code[i] == '.')) ++i;
    } else {
      ++i;
    }
  }
}

std::string_view code_part(std::string_view line) {
  const size_t c = line.find("//");
  return c == std::string_view::npos ? line : line.substr(0, c);
}

}  // namespace

std::string glsl_library_subset(std::string_view used) {
  // The library as file-scope items, each with the comment lines before it: a declaration starts
  // in column 0 (as glsl_declared_names reads them) and ends where its braces and parentheses
  // close on a line ending in '}' or ';'.
  struct Item {
    std::string text;
    std::set<std::string> names, uses;
  };
  std::vector<Item> items;
  std::string pending;  // comment and blank lines before the next item
  const std::string lib = glsl_library_source();
  std::istringstream in(lib);
  std::string line;
  Item* open = nullptr;
  int depth = 0;
  while (std::getline(in, line)) {
    const std::string_view code = code_part(line);
    if (!open) {
      if (code.find_first_not_of(" \t\r") == std::string_view::npos) {
        pending += line + "\n";
        continue;
      }
      items.push_back(Item{std::move(pending), glsl_declared_names(line), {}});
      pending.clear();
      open = &items.back();
      depth = 0;
    }
    open->text += line + "\n";
    identifiers(code, open->uses);
    for (char c : code) depth += (c == '{' || c == '(') ? 1 : (c == '}' || c == ')') ? -1 : 0;
    const size_t last = code.find_last_not_of(" \t\r");
    if (depth == 0 && last != std::string_view::npos && (code[last] == ';' || code[last] == '}')) open = nullptr;
  }
  // What `used` needs, transitively: every item declaring a name it mentions (all overloads).
  std::set<std::string> wanted;
  std::vector<std::string> todo;
  std::set<std::string> first;
  std::istringstream uin{std::string(used)};
  while (std::getline(uin, line)) identifiers(code_part(line), first);
  todo.assign(first.begin(), first.end());
  std::vector<bool> keep(items.size(), false);
  while (!todo.empty()) {
    const std::string name = todo.back();
    todo.pop_back();
    if (!wanted.insert(name).second) continue;
    for (size_t i = 0; i < items.size(); ++i) {
      if (keep[i] || !items[i].names.count(name)) continue;
      keep[i] = true;
      todo.insert(todo.end(), items[i].uses.begin(), items[i].uses.end());
    }
  }
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (keep[i] || items[i].names.empty()) out += items[i].text;  // an item without a name: kept
  }
  return out;
}

std::string glsl_preamble(GlslDialect dialect) {
  switch (dialect) {
    case GlslDialect::Core330: return "#version 330 core\n";
    case GlslDialect::Es300: return "#version 300 es\nprecision highp float;\nprecision highp int;\n";
    case GlslDialect::Core450Compute: return "#version 450 core\n";
  }
  return "";
}

std::set<std::string> glsl_declared_names(std::string_view source) {
  // File-scope declarations start in column 0 in the library and in the generated code:
  //   struct Name {         const T Name = ...;        uniform [highp] T Name;        T Name(args) {
  static const std::regex decl(
      R"(^(?:struct\s+(\w+)|const\s+\w+\s+(\w+)\s*=|uniform\s+(?:(?:highp|mediump|lowp)\s+)?\w+\s+(\w+)\s*;|\w+\s+(\w+)\s*\())");
  std::set<std::string> names;
  std::istringstream in{std::string(source)};
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, decl)) continue;
    for (int i = 1; i <= 4; ++i)
      if (m[i].matched) names.insert(m[i].str());
  }
  return names;
}

std::set<std::string> glsl_library_names() {
  static const std::set<std::string> names = glsl_declared_names(glsl_library_source());
  return names;
}

std::string glsl_prefix_names(std::string_view source, std::string_view prefix) {
  const std::set<std::string>& names = glsl_library_names();
  std::string out;
  out.reserve(source.size() + source.size() / 8);
  size_t i = 0;
  while (i < source.size()) {
    const char c = source[i];
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      size_t j = i;
      while (j < source.size() && (std::isalnum(static_cast<unsigned char>(source[j])) || source[j] == '_')) ++j;
      const std::string word(source.substr(i, j - i));
      if (names.count(word)) out += prefix;
      out += word;
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      // A number (with its suffix or exponent, e.g. 1e-12, 0x80000000u) is never renamed.
      size_t j = i;
      while (j < source.size() && (std::isalnum(static_cast<unsigned char>(source[j])) || source[j] == '.' ||
                                   ((source[j] == '-' || source[j] == '+') && (source[j - 1] == 'e' || source[j - 1] == 'E'))))
        ++j;
      out += source.substr(i, j - i);
      i = j;
    } else {
      out += c;
      ++i;
    }
  }
  return out;
}

}  // namespace aniso::gl
