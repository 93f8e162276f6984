// export/materialx.cpp: --to materialx (standard_surface, MaterialX 1.38) and --to openpbr
// (open_pbr_surface, MaterialX 1.39): the two MaterialX documents and their target models
// (materialx_model, openpbr_model).
#include "export/target_models.h"
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

std::string write_materialx(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = materialx_name(name);
  std::string s = "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n  <!--\n" + xml_comment_safe(comment) + "  -->\n";
  s += fmt::format("  <standard_surface name=\"SR_{}\" type=\"surfaceshader\">\n", xml_escape(id));
  const auto f = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"float\" value=\"{:.9g}\" />\n", k, num(p, k));
  };
  const auto c = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"color3\" value=\"{}\" />\n", k, fmt3(col(p, k)));
  };
  f("base");
  c("base_color");
  f("metalness");
  f("specular");
  c("specular_color");
  f("specular_roughness");
  if (p.contains("specular_IOR")) f("specular_IOR");
  f("specular_anisotropy");
  f("specular_rotation");
  s += "  </standard_surface>\n";
  s += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", xml_escape(id));
  s += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_{}\" />\n", xml_escape(id));
  s += "  </surfacematerial>\n</materialx>\n";
  return s;
}

// A MaterialX 1.39 document (open_pbr_surface's nodedef is version 1.1.1 in MaterialX 1.39's
// libraries/bxdf/open_pbr_surface.mtlx:2-6); input names and types of its nodedef (lines 8-25, 86).
// A turned tangent: tangent and normal (world space) into rotate3d and normalize, as
// standard_surface.mtlx:153-164 builds its own, into geometry_tangent.
std::string write_openpbr(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = materialx_name(name);
  std::string s = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n  <!--\n" + xml_comment_safe(comment) + "  -->\n";
  const double turn = num(p, "geometry_tangent_rotate3d_deg");
  if (turn != 0.0) {
    s += fmt::format(
        "  <tangent name=\"T_{0}\" type=\"vector3\">\n    <input name=\"space\" type=\"string\" value=\"world\" />\n  "
        "</tangent>\n"
        "  <normal name=\"N_{0}\" type=\"vector3\">\n    <input name=\"space\" type=\"string\" value=\"world\" />\n  </normal>\n"
        "  <rotate3d name=\"T_{0}_rotate\" type=\"vector3\">\n"
        "    <input name=\"in\" type=\"vector3\" nodename=\"T_{0}\" />\n"
        "    <input name=\"amount\" type=\"float\" value=\"{1:.9g}\" />\n"
        "    <input name=\"axis\" type=\"vector3\" nodename=\"N_{0}\" />\n  </rotate3d>\n"
        "  <normalize name=\"T_{0}_rotate_normalize\" type=\"vector3\">\n"
        "    <input name=\"in\" type=\"vector3\" nodename=\"T_{0}_rotate\" />\n  </normalize>\n",
        id, turn);
  }
  s += fmt::format("  <open_pbr_surface name=\"SR_{}\" type=\"surfaceshader\">\n", id);
  const auto f = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"float\" value=\"{:.9g}\" />\n", k, num(p, k));
  };
  const auto c = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"color3\" value=\"{}\" />\n", k, fmt3(col(p, k)));
  };
  f("base_weight");
  c("base_color");
  f("base_diffuse_roughness");
  f("base_metalness");
  f("specular_weight");
  c("specular_color");
  f("specular_roughness");
  if (p.contains("specular_ior")) f("specular_ior");
  f("specular_roughness_anisotropy");
  if (turn != 0.0)
    s += fmt::format("    <input name=\"geometry_tangent\" type=\"vector3\" nodename=\"T_{}_rotate_normalize\" />\n", id);
  s += "  </open_pbr_surface>\n";
  s += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", id);
  s += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_{}\" />\n", id);
  s += "  </surfacematerial>\n</materialx>\n";
  return s;
}

// --- the target models: GGX -> standard_surface, open_pbr_surface ------------------------------------

TargetBrdf materialx_model(const GgxSource& g, json& p, std::vector<std::string>& notes) {
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const glm::dvec3 cond_f0 = source_f0(g);
  // aspect^2 = alpha_y / alpha_x = 1 - anisotropy, anisotropy <= 0.98 (mx_roughness_anisotropy).
  const auto [extra, rough, aniso] = invert_aspect(ax, ay, 1.0, 0.98, "standard_surface", notes);
  // MaterialX's rotate3d turns the tangent clockwise about the normal (mx_rotate_vector3.glsl:12:
  // v c + cross(v, axis) s, and t x n = -b): specular_rotation = -angle / 360.
  const double turn = wrap_turn(-(g.rotation_deg + extra) / 360.0);
  const glm::dvec2 a = materialx_alpha(rough, aniso);
  m.lobe.alpha_x = a.x, m.lobe.alpha_y = a.y;
  m.tangent_turn_deg = extra;
  m.lobe.masking = Masking::HeightCorrelatedMeanAlpha;
  p["specular_roughness"] = rough, p["specular_anisotropy"] = aniso, p["specular_rotation"] = turn;
  p["base"] = 1.0, p["specular"] = 1.0;
  if (g.conductor || no_diffuse(g)) {
    glm::dvec3 refl = glm::clamp(cond_f0, 0.0, 0.99), edge(1.0);
    if (g.conductor) {
      materialx_artistic_from_ior(g.eta, g.k, refl, edge);
    } else {
      // A Schlick metal: the edge colour whose artistic-IOR Fresnel is closest to Schlick's curve.
      for (int c = 0; c < 3; ++c) {
        const auto cost = [&](double e) {
          glm::dvec3 n, k;
          materialx_artistic_ior(glm::dvec3(refl[c]), glm::dvec3(e), n, k);
          double sum = 0.0;
          for (int i = 0; i < 64; ++i) {
            const double cs = (i + 0.5) / 64.0, m5 = std::pow(1.0 - cs, 5.0);
            sum += sqr(F_Conductor(cs, n.x, k.x) - (refl[c] + (1.0 - refl[c]) * m5));
          }
          return sum;
        };
        double best = 1.0, best_cost = cost(1.0);
        for (int i = 0; i <= 100; ++i)
          if (const double v = cost(i / 100.0); v < best_cost) best_cost = v, best = i / 100.0;
        edge[c] = best;
      }
    }
    glm::dvec3 n, k;
    materialx_artistic_ior(refl, edge, n, k);
    m.name = "MaterialX standard_surface, metalness 1 (artistic IOR conductor, G2 at the mean alpha)";
    m.lobe.fresnel = FresnelModel::Conductor;
    m.lobe.eta = n, m.lobe.k = k;
    p["metalness"] = 1.0, p["base_color"] = j3(refl), p["specular_color"] = j3(edge);
    notes.push_back(
        "the conductor goes through Gulbrandsen's artistic IOR (reflectivity, edge colour): two "
        "colours for n, k, so the Fresnel curve is close, not equal");
  } else {
    // MaterialX @ 4177b2cb. standard_surface.mtlx:288-303: specular_bsdf is a dielectric_bsdf with
    // weight = specular (1), tint = specular_color, ior = specular_IOR, and specular_layer layers it
    // over the diffuse (metalness 0: metalness_mix is specular_layer, lines 329-333). The diffuse is
    // oren_nayar_diffuse_bsdf of weight base (1), colour max(base_color, 0) (lines 204-210, 222-227)
    // at diffuse_roughness 0: Lambert (mx_microfacet_diffuse.glsl:8-18, A = 1, B = 0). Its reflection,
    // mx_dielectric_bsdf.glsl:43-51: response = D F G comp tint weight / (4 NdotV) with F the
    // dielectric Fresnel at ior (mx_fresnel_dielectric, mx_microfacet_specular.glsl:212-225),
    // throughput = 1 - dirAlbedo(F0 = mx_ior_to_f0(ior)) comp weight, untinted (the PBR spec,
    // MaterialX.PBRSpec.md:539: the tint multiplies f_r, not F). So specular_color tints the whole
    // Fresnel curve, grazing included; the IOR and the tint as for OpenPBR (tinted_dielectric: the
    // index closest to Schlick's curve of the largest channel, the tint F0 / max(F0)).
    const TintedDielectric td = tinted_dielectric(g.f0);
    m.name =
        "MaterialX standard_surface, dielectric (exact Fresnel times specular_color, G2 at the mean alpha) layered over "
        "Lambert";
    m.lobe.fresnel = FresnelModel::Dielectric;
    m.lobe.eta = glm::dvec3(td.eta);
    m.lobe.weight = td.tint;
    m.diffuse = glm::max(g.kd, 0.0);
    m.diffuse_times_dielectric_throughput = true;
    p["metalness"] = 0.0, p["base_color"] = j3(g.kd), p["specular_color"] = j3(td.tint);
    p["specular_IOR"] = td.eta;
    notes.push_back(
        fmt::format("Schlick's F0 {} becomes the dielectric Fresnel of specular_IOR {:.4g} closest to the curve of its "
                    "largest channel (F0 {:.4g}) times specular_color {} (F0 / its largest channel: the F0's hue, which "
                    "standard_surface's dielectric_bsdf applies at every angle, grazing included)",
                    fmt3(g.f0), td.eta, F_Conductor(1.0, td.eta, 0.0), fmt3(td.tint)));
    notes.push_back(
        "standard_surface layers the specular over the diffuse: the diffuse is scaled by 1 - the specular's "
        "directional albedo at the view (mx_dielectric_bsdf.glsl:47-49, mx_layer_bsdf.glsl:5), which the target "
        "model does and aniso's GGX (a sum) does not");
  }
  notes.push_back(
      "MaterialX's GGX lobes add a multiple-scattering energy compensation "
      "(mx_ggx_energy_compensation, mx_conductor_bsdf.glsl:40) that the target model leaves out");
  return m;
}

// open_pbr_surface (targets.h, the OpenPBR section): the larger alpha along the (turned) tangent;
// r^4 = (ax^2 + ay^2) / 2 and a = 1 - ay / ax invert openpbr_alpha.
TargetBrdf openpbr_model(const GgxSource& g, json& p, std::vector<std::string>& notes) {
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const double extra = major_first(ax, ay);
  double rough = std::pow((ax * ax + ay * ay) / 2.0, 0.25);
  const double aniso = ax > 0.0 ? std::clamp(1.0 - ay / ax, 0.0, 1.0) : 0.0;
  if (rough > 1.0) notes.push_back("roughness above 1 clamped to 1"), rough = 1.0;
  const glm::dvec2 a = openpbr_safe_alpha(openpbr_alpha(rough, aniso));
  if (a.x < openpbr_alpha(rough, aniso).x)
    notes.push_back(
        fmt::format("alpha along the tangent {:.4g} above 1: MaterialX clamps it to 1", openpbr_alpha(rough, aniso).x));
  m.lobe.alpha_x = a.x, m.lobe.alpha_y = a.y;
  m.tangent_turn_deg = extra;
  // mx_generalized_schlick_bsdf.glsl:46, mx_dielectric_bsdf.glsl:45: G2 at mx_average_alpha.
  m.lobe.masking = Masking::HeightCorrelatedMeanAlpha;
  p["base_weight"] = 1.0, p["specular_weight"] = 1.0, p["base_diffuse_roughness"] = 0.0;
  p["specular_roughness"] = rough, p["specular_roughness_anisotropy"] = aniso;
  // rotate3d turns clockwise about its axis (mx_rotate_vector3.glsl:12), as for standard_surface's
  // specular_rotation (standard_surface.mtlx:157-161): amount = -angle degrees.
  const double angle = g.rotation_deg + extra;
  p["geometry_tangent_rotate3d_deg"] = 360.0 * wrap_turn(-angle / 360.0);
  if (g.conductor || no_diffuse(g)) {
    const glm::dvec3 f0 =
        glm::clamp(g.conductor ? glm::dvec3(F_Conductor(1.0, RGBT<double>(g.eta), RGBT<double>(g.k))) : g.f0, 0.0, 1.0);
    glm::dvec3 tint(1.0);
    if (g.conductor) tint = cycles_tint_for(f0, glm::dvec3(F_Conductor(1.0 / 7.0, RGBT<double>(g.eta), RGBT<double>(g.k))));
    m.name = "OpenPBR Surface, base_metalness 1 (MaterialX GLSL: F82-tint Fresnel, G2 at the mean alpha)";
    m.lobe.fresnel = FresnelModel::F82Tint;
    m.lobe.f0 = f0;
    m.lobe.f82_b = cycles_f82tint_b(f0, tint);
    p["base_metalness"] = 1.0, p["base_color"] = j3(f0), p["specular_color"] = j3(tint);
    if (g.conductor)
      notes.push_back(
          "the conductor's n, k become F0 (base_color) and the F82 edge tint (specular_color) matching its "
          "reflectance at cos = 1/7: the Fresnel curve is close, not equal");
    double lowest = 1.0;
    for (int i = 0; i <= 200; ++i) {
      const double x = i / 200.0, s = 1.0 - x;
      const glm::dvec3 F = f0 + (glm::dvec3(1.0) - f0) * std::pow(s, 5.0) - m.lobe.f82_b * (x * std::pow(s, 6.0));
      lowest = std::min({lowest, F.x, F.y, F.z});
    }
    if (lowest < 0.0)
      notes.push_back(
          fmt::format("this F82 curve dips to {:.3g}: MaterialX does not clamp it (a negative reflectance there), the target "
                      "model clamps it to 0",
                      lowest));
  } else {
    // dielectric_reflection: dielectric_bsdf with tint = specular_color (open_pbr_surface.mtlx, the
    // "Dielectric Base"), whose response is D F G tint / (4 NdotV) and whose throughput, which the
    // layer gives the diffuse, has no tint (mx_dielectric_bsdf.glsl, mx_dielectric_bsdf_reflection;
    // the specification tints the Fresnel reflection alone, OpenPBR#145): F = specular_color
    // F_dielectric(specular_ior), the lobe's weight.
    const TintedDielectric td = tinted_dielectric(g.f0);
    m.name = "OpenPBR Surface, dielectric (exact Fresnel times specular_color, G2 at the mean alpha) layered over Lambert";
    m.lobe.fresnel = FresnelModel::Dielectric;
    m.lobe.eta = glm::dvec3(td.eta);
    m.lobe.weight = td.tint;
    m.diffuse = glm::clamp(g.kd, 0.0, 1.0);
    m.diffuse_times_dielectric_throughput = true;
    p["base_metalness"] = 0.0, p["base_color"] = j3(m.diffuse), p["specular_color"] = j3(td.tint);
    p["specular_ior"] = td.eta;
    notes.push_back(
        fmt::format("Schlick's F0 {} becomes the dielectric Fresnel of specular_ior {:.4g} closest to the curve of its "
                    "largest channel (F0 {:.4g}) times specular_color {} (F0 / its largest channel: the F0's hue)",
                    fmt3(g.f0), td.eta, F_Conductor(1.0, td.eta, 0.0), fmt3(td.tint)));
    notes.push_back(
        "OpenPBR layers the specular over the diffuse: the diffuse is scaled by 1 - the specular's directional "
        "albedo at the view (mx_dielectric_bsdf.glsl:47-49, mx_layer_bsdf.glsl:5), which the target model does "
        "and aniso's GGX (a sum) does not");
  }
  notes.push_back(
      "MaterialX's GGX lobes add a multiple-scattering energy compensation (mx_ggx_energy_compensation) that the "
      "target model leaves out of the specular lobe; renderers with their own OpenPBR (OSL closures) use their own");
  notes.push_back(
      angle != 0.0 ? fmt::format("OpenPBR has no rotation input: the anisotropy follows geometry_tangent, written as the world "
                                 "tangent turned by rotate3d {:.9g} degrees about the world normal ({:.9g} degrees towards the "
                                 "bitangent)",
                                 p["geometry_tangent_rotate3d_deg"].get<double>(), angle)
                   : "OpenPBR has no rotation input: the anisotropy follows geometry_tangent (Tworld, dp/du)");
  return m;
}

}  // namespace aniso::exporter
