// export/gltf.cpp: --to gltf, the .gltf with KHR_materials_anisotropy and its .bin UV sphere, and its
// target model (gltf_model).
#include "aniso/version.h"
#include "export/target_models.h"
#include "export/writers.h"

#include <cmath>
#include <cstdint>

#include "io/text_escape.h"

namespace aniso::exporter {

void write_gltf(const std::string& name, const json& p, const ExportReport& r, const std::string& source,
                const std::string& bin_name, std::vector<ExportFile>& files) {
  const SphereMesh mesh = uv_sphere(48, 96);
  std::string bin;
  const auto append = [&](const void* data, size_t bytes) {
    bin.append(static_cast<const char*>(data), bytes);
    while (bin.size() % 4) bin.push_back('\0');
  };
  const size_t nv = mesh.positions.size() / 3;
  json views = json::array(), accessors = json::array();
  const auto add = [&](const void* data, size_t bytes, int components, int ctype, const char* type, size_t count, int target,
                       bool minmax) {
    const size_t offset = bin.size();
    append(data, bytes);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
    json a = {{"bufferView", views.size() - 1}, {"componentType", ctype}, {"count", count}, {"type", type}};
    if (minmax) a["min"] = {-1.0, -1.0, -1.0}, a["max"] = {1.0, 1.0, 1.0};
    (void)components;
    accessors.push_back(a);
  };
  // 5126 FLOAT, 5123 UNSIGNED_SHORT; 34962 ARRAY_BUFFER, 34963 ELEMENT_ARRAY_BUFFER (glTF 2.0, 3.6.2).
  add(mesh.positions.data(), mesh.positions.size() * 4, 3, 5126, "VEC3", nv, 34962, true);
  add(mesh.normals.data(), mesh.normals.size() * 4, 3, 5126, "VEC3", nv, 34962, false);
  add(mesh.tangents.data(), mesh.tangents.size() * 4, 4, 5126, "VEC4", nv, 34962, false);
  add(mesh.uvs.data(), mesh.uvs.size() * 4, 2, 5126, "VEC2", nv, 34962, false);
  add(mesh.indices.data(), mesh.indices.size() * 2, 1, 5123, "SCALAR", mesh.indices.size(), 34963, false);
  const glm::dvec3 base = col(p, "baseColorFactor");
  json material = {
      {"name", name},
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {base.x, base.y, base.z, 1.0}},
        {"metallicFactor", num(p, "metallicFactor")},
        {"roughnessFactor", num(p, "roughnessFactor")}}},
      {"extensions",
       {{"KHR_materials_anisotropy",
         {{"anisotropyStrength", num(p, "anisotropyStrength")}, {"anisotropyRotation", num(p, "anisotropyRotation")}}}}}};
  json used = {"KHR_materials_anisotropy"};
  if (p.contains("specularFactor")) {
    material["extensions"]["KHR_materials_specular"] = {{"specularFactor", num(p, "specularFactor")},
                                                        {"specularColorFactor", p.at("specularColorFactor")}};
    used.push_back("KHR_materials_specular");
  }
  if (p.contains("ior")) {
    // KHR_materials_ior: its ior replaces the 0.04 of KHR_materials_specular (targets.h, gltf_specular_for).
    material["extensions"]["KHR_materials_ior"] = {{"ior", num(p, "ior")}};
    used.push_back("KHR_materials_ior");
  }
  json doc = {{"asset",
               {{"version", "2.0"},
                {"generator", "aniso " ANISO_VERSION " export --to gltf"},
                {"extras", {{"source", text_escape(source)}, {"aniso_export", r.to_json()}}}}},
              {"extensionsUsed", used},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}, {"name", name}}}},
              {"meshes",
               {{{"name", "sphere"},
                 {"primitives",
                  {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TANGENT", 2}, {"TEXCOORD_0", 3}}},
                    {"indices", 4},
                    {"material", 0}}}}}}},
              {"materials", {material}},
              {"buffers", {{{"uri", bin_name}, {"byteLength", bin.size()}}}},
              {"bufferViews", views},
              {"accessors", accessors}};
  files.push_back({"", doc.dump(2) + "\n"});
  files.push_back({bin_name, bin});
}

SphereMesh uv_sphere(int rings, int segments) {
  SphereMesh m;
  // glTF is y-up. theta from +y, phi around it; u = phi / 2 pi, v = theta / pi. p = (sin t sin f,
  // cos t, sin t cos f): dp/du ~ (cos f, 0, -sin f), the tangent, perpendicular to the normal
  // everywhere (also at the poles, where each vertex of the seam row has its own phi).
  for (int i = 0; i <= rings; ++i) {
    const double t = kPi<double> * i / rings;
    for (int j = 0; j <= segments; ++j) {
      const double f = 2.0 * kPi<double> * j / segments;
      const glm::dvec3 n(std::sin(t) * std::sin(f), std::cos(t), std::sin(t) * std::cos(f));
      const glm::dvec3 tan(std::cos(f), 0.0, -std::sin(f));
      for (int k = 0; k < 3; ++k) m.positions.push_back(float(n[k])), m.normals.push_back(float(n[k]));
      for (int k = 0; k < 3; ++k) m.tangents.push_back(float(tan[k]));
      m.tangents.push_back(1.0f);
      m.uvs.push_back(float(double(j) / segments)), m.uvs.push_back(float(double(i) / rings));
    }
  }
  const int row = segments + 1;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint16_t a = uint16_t(i * row + j), b = uint16_t(a + row), c = uint16_t(a + 1), d = uint16_t(b + 1);
      // Counter-clockwise seen from outside (glTF front faces).
      if (i != 0) m.indices.insert(m.indices.end(), {a, b, c});
      if (i != rings - 1) m.indices.insert(m.indices.end(), {c, b, d});
    }
  return m;
}

// --- the target model: GGX -> pbrMetallicRoughness with KHR_materials_anisotropy ----------------------

TargetBrdf gltf_model(const GgxSource& g, json& p, std::vector<std::string>& notes) {
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const glm::dvec3 cond_f0 = source_f0(g);
  const double extra = major_first(ax, ay);
  // README.md:88-100: at = mix(ab, 1, s^2), ab = roughness^2.
  double ab = ay, at = std::min(ax, 1.0);
  const double s = ab < 1.0 ? std::sqrt(std::clamp((at - ab) / (1.0 - ab), 0.0, 1.0)) : 0.0;
  const double rough = std::sqrt(std::min(ab, 1.0));
  const double rot = glm::radians(std::fmod(g.rotation_deg + extra, 360.0));
  const glm::dvec2 a = gltf_alpha(rough, s);
  m.lobe.alpha_x = a.x, m.lobe.alpha_y = a.y;
  m.tangent_turn_deg = extra;
  m.lobe.masking = Masking::HeightCorrelated;  // V_GGX_anisotropic (README.md:174-181)
  m.lobe.fresnel = FresnelModel::Schlick;
  p["roughnessFactor"] = rough, p["anisotropyStrength"] = s, p["anisotropyRotation"] = rot;
  if (g.conductor || no_diffuse(g)) {
    glm::dvec3 f0 = glm::clamp(cond_f0, 0.0, 1.0);
    if (g.conductor) {
      // The Schlick F0 closest to the conductor's Fresnel curve: Schlick = F0 (1 - m) + m, m = (1 - c)^5,
      // is linear in F0; least squares over c in [0, 1] (64 points).
      glm::dvec3 num(0.0);
      double den = 0.0;
      for (int i = 0; i < 64; ++i) {
        const double c = (i + 0.5) / 64.0, m5 = std::pow(1.0 - c, 5.0);
        const glm::dvec3 F = F_Conductor(c, RGBT<double>(g.eta), RGBT<double>(g.k));
        num += (F - m5) * (1.0 - m5), den += sqr(1.0 - m5);
      }
      f0 = glm::clamp(num / den, 0.0, 1.0);
    }
    m.name = "glTF 2.0 metal_brdf (metallic 1): Schlick F0 = baseColor, height-correlated G";
    m.lobe.f0 = f0;
    p["metallicFactor"] = 1.0, p["baseColorFactor"] = j3(f0);
    if (g.conductor)
      notes.push_back(
          "the conductor becomes Schlick's Fresnel with the F0 closest to its curve (least "
          "squares over the cosine)");
  } else {
    // Appendix B: dielectric_brdf = fresnel_mix(ior 1.5, diffuse, specular): (1 - F) diffuse + F specular.
    m.name = "glTF 2.0 dielectric_brdf (metallic 0): fresnel_mix(ior 1.5) of Lambert and GGX";
    m.lobe.f0 = glm::dvec3(0.04);
    m.diffuse = g.kd, m.diffuse_times_one_minus_f = true;
    p["metallicFactor"] = 0.0, p["baseColorFactor"] = j3(glm::clamp(g.kd, 0.0, 1.0));
    // glTF's default dielectric F0 is 0.04 (ior 1.5); any other goes into KHR_materials_specular,
    // whose Fresnel is then Schlick's with the source's F0 exactly (targets.h, gltf_specular_for).
    if (glm::any(glm::greaterThan(glm::abs(g.f0 - 0.04), glm::dvec3(1e-4)))) {
      const GltfSpecular sp = gltf_specular_for(g.f0);
      m.name = sp.ior == 1.5
                   ? "glTF 2.0 dielectric_brdf (metallic 0) with KHR_materials_specular: Schlick F0 = 0.04 specularColor"
                   : "glTF 2.0 dielectric_brdf (metallic 0) with KHR_materials_specular and KHR_materials_ior: Schlick F0 "
                     "= F0(ior) specularColor";
      m.lobe.f0 = gltf_dielectric_f0(sp.specular, sp.color, sp.ior);
      m.diffuse_times_one_minus_f = false, m.diffuse_times_one_minus_max_f = true;
      p["specularFactor"] = sp.specular, p["specularColorFactor"] = j3(sp.color);
      if (sp.ior != 1.5) p["ior"] = sp.ior;
      notes.push_back(fmt::format(
          "the source's dielectric F0 {} is not glTF's 0.04: written with KHR_materials_specular{}; viewers without "
          "the extension{} show F0 = 0.04",
          fmt3(g.f0),
          sp.ior == 1.5 ? " (specularColorFactor = F0 / 0.04)"
                        : fmt::format(" and KHR_materials_ior (ior {:.6g} for the largest F0, specularColorFactor = F0 / "
                                      "max F0: every factor in [0, 1])",
                                      sp.ior),
          sp.ior == 1.5 ? "" : "s"));
    }
  }
  if (ax > 1.0) notes.push_back("alpha along the tangent above 1 clamped to 1 (glTF's mix(alpha, 1, s^2) <= 1)");
  return m;
}

}  // namespace aniso::exporter
