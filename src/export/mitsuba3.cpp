// export/mitsuba3.cpp: --to mitsuba3, the XML scene with one <bsdf>, and the target models of Mitsuba 3
// and pbrt-v4 (mitsuba_pbrt_model: the conductor or the mix, the same for both) and Mitsuba 3's principled.
#include "export/target_models.h"
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

std::string write_mitsuba(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = xml_escape(identifier(name));
  if (p.contains("filename")) {
    // Mitsuba 3's own measured BSDF (src/bsdfs/measured.cpp @ b45b0a93: the "filename" property,
    // line 86; an rgb file for the RGB variants, a spectral one for the spectral variants, lines
    // 102-116; isotropic when phi_i has at most 2 entries, line 165). The file is relative to the
    // scene's folder (Mitsuba resolves it with the file resolver, line 86).
    std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
    s += "<scene version=\"3.0.0\">\n";
    s += fmt::format("    <bsdf type=\"measured\" id=\"{}\">\n", id);
    s += fmt::format("        <string name=\"filename\" value=\"{}\"/>\n", xml_escape(p["filename"].get<std::string>()));
    s += "    </bsdf>\n</scene>\n";
    return s;
  }
  if (p.contains("principled")) {
    // principled.cpp:20-105: base_color a spectrum, the rest floats; "specular" (not "eta").
    std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
    s += "<scene version=\"3.0.0\">\n";
    s += fmt::format("    <bsdf type=\"principled\" id=\"{}\">\n", id);
    s += fmt::format("        <rgb name=\"base_color\" value=\"{}\"/>\n", fmt3(col(p, "base_color")));
    for (const char* key : {"roughness", "anisotropic", "metallic", "specular", "spec_tint", "sheen", "sheen_tint", "flatness",
                            "clearcoat", "clearcoat_gloss"})
      s += fmt::format("        <float name=\"{}\" value=\"{:.9g}\"/>\n", key, num(p, key));
    s += "    </bsdf>\n</scene>\n";
    return s;
  }
  std::string conductor = "        <string name=\"distribution\" value=\"ggx\"/>\n";
  conductor += fmt::format("        <float name=\"alpha_u\" value=\"{:.9g}\"/>\n", num(p, "alpha_u"));
  conductor += fmt::format("        <float name=\"alpha_v\" value=\"{:.9g}\"/>\n", num(p, "alpha_v"));
  if (p.contains("material"))
    conductor += fmt::format("        <string name=\"material\" value=\"{}\"/>\n", xml_escape(p["material"].get<std::string>()));
  else
    conductor += fmt::format("        <rgb name=\"eta\" value=\"{}\"/>\n        <rgb name=\"k\" value=\"{}\"/>\n",
                             fmt3(col(p, "eta")), fmt3(col(p, "k")));
  std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
  s += "<scene version=\"3.0.0\">\n";
  if (p.contains("weight")) {
    // blendbsdf.cpp:17-21: weight 0 is the first nested BSDF, 1 the second.
    s += fmt::format("    <bsdf type=\"blendbsdf\" id=\"{}\">\n", id);
    s += fmt::format("        <float name=\"weight\" value=\"{:.9g}\"/>\n", num(p, "weight"));
    s += fmt::format("        <bsdf type=\"diffuse\">\n            <rgb name=\"reflectance\" value=\"{}\"/>\n        </bsdf>\n",
                     fmt3(col(p, "diffuse_reflectance")));
    s += "        <bsdf type=\"roughconductor\">\n";
    std::string inner;
    for (size_t i = 0, j; i < conductor.size(); i = j + 1) {
      j = conductor.find('\n', i);
      inner += "    " + conductor.substr(i, j - i + 1);
    }
    s += inner + "        </bsdf>\n    </bsdf>\n";
  } else {
    s += fmt::format("    <bsdf type=\"roughconductor\" id=\"{}\">\n", id);
    s += conductor + "    </bsdf>\n";
  }
  return s + "</scene>\n";
}

// --- the target models: GGX -> roughconductor / blendbsdf (and pbrt-v4's conductor / mix), principled ---

namespace {

// Mitsuba 3's named conductors among aniso's metals (src/bsdfs/conductor.cpp:107-200, the
// conductor-ior-list table), pbrt-v4's named spectra (src/pbrt/util/spectrum.cpp:2670-2683).
bool mitsuba_has(std::string_view sym) {
  for (const char* s : {"Ag", "Al", "Au", "Cr", "Cu", "W"})
    if (sym == s) return true;
  return false;
}
bool pbrt_has(std::string_view sym) {
  for (const char* s : {"Ag", "Al", "Au", "Cu", "CuZn"})
    if (sym == s) return true;
  return false;
}

// For the mixes of Mitsuba 3 and pbrt-v4 (diffuse + specular as (1 - w) A + w B): the largest w
// that keeps the diffuse reflectance kd / (1 - w) <= 1, but at least max(F0) so that the specular
// reflectance F0 / w stays <= 1.
double mix_weight(const GgxSource& g) {
  const double w = 1.0 - max3(g.kd);
  return std::clamp(std::max(w, max3(g.f0)), 1e-3, 1.0 - 1e-3);
}

}  // namespace

// Mitsuba 3 and pbrt-v4 (one model: their masking, names and inputs apart; pbrt-v4's writer is pbrt_v4.cpp).
TargetBrdf mitsuba_pbrt_model(Target t, const GgxSource& g, json& p, std::vector<std::string>& notes) {
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const bool mitsuba = t == Target::Mitsuba3;
  m.lobe.alpha_x = std::max(ax, mitsuba ? 0.0 : 1e-4), m.lobe.alpha_y = std::max(ay, mitsuba ? 0.0 : 1e-4);
  // Mitsuba 3: separable Smith (microfacet.h:329-331); pbrt-v4: height-correlated
  // (scattering.h:152, G = 1 / (1 + Lambda(wo) + Lambda(wi))).
  m.lobe.masking = mitsuba ? Masking::Separable : Masking::HeightCorrelated;
  m.lobe.fresnel = FresnelModel::Conductor;
  const std::string ru = mitsuba ? "alpha_u" : "uroughness", rv = mitsuba ? "alpha_v" : "vroughness";
  p[ru] = ax, p[rv] = ay;
  if (!mitsuba) p["remaproughness"] = false;
  if (g.conductor) {
    m.name = mitsuba ? "Mitsuba 3 roughconductor (GGX, separable Smith G, conductor Fresnel)"
                     : "pbrt-v4 conductor (Trowbridge-Reitz, height-correlated G, conductor Fresnel)";
    m.lobe.eta = g.eta, m.lobe.k = g.k;
    const bool named = mitsuba ? mitsuba_has(g.symbol) : pbrt_has(g.symbol);
    if (named) {
      if (mitsuba)
        p["material"] = g.symbol;
      else
        p["eta"] = "metal-" + g.symbol + "-eta", p["k"] = "metal-" + g.symbol + "-k";
      notes.push_back(
          fmt::format("the renderer's own spectrum for {} ({}) replaces aniso's RGB n, k: a different "
                      "measurement, so the colour may differ slightly from the target model",
                      g.symbol, g.metal));
    } else {
      p["eta"] = j3(g.eta), p["k"] = j3(g.k);
    }
  } else {
    // The Schlick lobe as the exact Fresnel (a dielectric eta, or a conductor with eta 1 and k)
    // whose curve is closest to Schlick's divided by the mix weight, in least squares over the
    // cosine (match_schlick): the whole curve, not F(0) alone (pbrt-v4's "reflectance",
    // materials.h:505-507, would keep F(0) = r and miss the rest), so F(0) is not exactly r.
    const double w = no_diffuse(g) ? 1.0 : mix_weight(g);
    for (int c = 0; c < 3; ++c) {
      const ExactFresnel e = match_schlick(g.f0[c], w, true);
      m.lobe.eta[c] = e.eta, m.lobe.k[c] = e.k;
    }
    m.lobe.weight = glm::dvec3(w);
    p["eta"] = j3(m.lobe.eta), p["k"] = j3(m.lobe.k);
    if (no_diffuse(g)) {
      m.name = mitsuba ? "Mitsuba 3 roughconductor (eta 1, k from F0)" : "pbrt-v4 conductor (reflectance = F0)";
    } else {
      m.name = mitsuba ? "Mitsuba 3 blendbsdf: (1 - w) diffuse + w roughconductor"
                       : "pbrt-v4 mix: (1 - amount) diffuse + amount conductor";
      m.diffuse = g.kd;
      p[mitsuba ? "weight" : "amount"] = w;
      p["diffuse_reflectance"] = j3(g.kd / (1.0 - w));
      glm::dvec3 f0_written(0.0);
      for (int c = 0; c < 3; ++c) f0_written[c] = w * F_Conductor(1.0, m.lobe.eta[c], m.lobe.k[c]);
      notes.push_back(
          fmt::format("no additive BSDF sum in the target: a stochastic mix with weight {:.4g}; the "
                      "specular reflectance at normal incidence is {:.4g} (source {:.4g}, the closest "
                      "exact Fresnel curve to Schlick's over all angles), at grazing it rises to {:.4g} "
                      "instead of 1",
                      w, max3(f0_written), max3(g.f0), w));
    }
    notes.push_back(
        "Schlick's Fresnel is written as the exact (dielectric or conductor) Fresnel closest to its "
        "curve: the target has no Schlick Fresnel");
  }
  // Mitsuba 3's spectral variants turn an <rgb> eta / k into the bounded rgb2spec spectrum
  // (Properties::get_texture_impl, src/core/properties.cpp:628-636, `srgb`; srgb_model_eval,
  // include/mitsuba/render/srgb.h:13-19, a sigmoid in [0, 1]): a component above 1 cannot be
  // represented there. Measured: nickel 0.08 x 0.3 renders at 0.41 of aniso's brightness under
  // scalar_spectral, 0.999 under scalar_rgb (bench/mitsuba3/compare.py).
  if (mitsuba && !p.contains("material") && std::max(max3(m.lobe.eta), max3(m.lobe.k)) > 1.0)
    notes.push_back(
        fmt::format("eta and k are written as <rgb>: render with an RGB variant (scalar_rgb, llvm_ad_rgb); a "
                    "spectral variant upsamples an <rgb> to a spectrum bounded by 1 (rgb2spec), so eta {} and "
                    "k {} would be clipped there",
                    fmt3(m.lobe.eta), fmt3(m.lobe.k)));
  if (g.rotation_deg != 0.0)
    notes.push_back(
        fmt::format("the tangent is dp/du: {} has no rotation input, so rotate the mesh's uv "
                    "parameterisation (or the tangent) by {:.9g} degrees about the normal, towards "
                    "dp/dv",
                    mitsuba ? "Mitsuba 3" : "pbrt-v4", g.rotation_deg));
  else
    notes.push_back("alpha along the tangent dp/du and the bitangent, as aniso's alpha_x and alpha_y");
  return m;
}

// Mitsuba 3's principled (targets.h, mitsuba_principled_f) with these parameters; `turn`: the
// tangent's extra quarter turn (the larger alpha along dp/du).
TargetBrdf mitsuba_principled_model(const MitsubaPrincipled& mp, double turn, double rotation_deg, json& p,
                                    std::vector<std::string>& notes) {
  TargetBrdf m;
  m.name = "Mitsuba 3 principled (GGX, separable Smith G, exact dielectric + Schlick metallic Fresnel, Burley diffuse)";
  m.is_mitsuba_principled = true;
  m.principled = mp;
  m.tangent_turn_deg = turn;
  const glm::dvec2 a = mitsuba_principled_alpha(mp.roughness, mp.anisotropic, true);
  m.lobe.alpha_x = a.x, m.lobe.alpha_y = a.y;
  p = json::object();
  p["principled"] = true;
  p["base_color"] = j3(mp.base_color);
  for (const auto& [key, v] : {std::pair{"roughness", mp.roughness},
                               {"anisotropic", mp.anisotropic},
                               {"metallic", mp.metallic},
                               {"specular", mp.specular},
                               {"spec_tint", mp.spec_tint},
                               {"sheen", mp.sheen},
                               {"sheen_tint", mp.sheen_tint},
                               {"flatness", mp.flatness},
                               {"clearcoat", mp.clearcoat},
                               {"clearcoat_gloss", mp.clearcoat_gloss}})
    p[key] = v;
  if (rotation_deg + turn != 0.0)
    notes.push_back(
        fmt::format("the tangent is dp/du: Mitsuba 3 has no rotation input, so rotate the mesh's uv "
                    "parameterisation (or the tangent) by {:.9g} degrees about the normal, towards dp/dv",
                    rotation_deg + turn));
  return m;
}

// An aniso principled source: the parameters are the same (principled.h against principled.cpp);
// what differs is said in the notes.
MitsubaPrincipled principled_params(const PrincipledT<double>& s) {
  MitsubaPrincipled mp;
  mp.base_color = glm::dvec3(s.base_color.x, s.base_color.y, s.base_color.z);
  mp.roughness = s.roughness, mp.anisotropic = s.anisotropic, mp.metallic = s.metallic, mp.specular = s.specular;
  mp.spec_tint = s.specular_tint, mp.sheen = s.sheen, mp.sheen_tint = s.sheen_tint, mp.flatness = s.subsurface;
  mp.clearcoat = s.clearcoat, mp.clearcoat_gloss = s.clearcoat_gloss;
  return mp;
}

std::vector<std::string> principled_differences(const MitsubaPrincipled& mp) {
  std::vector<std::string> n;
  n.push_back(
      "aniso's principled and Mitsuba 3's share the alphas (calc_dist_params), the separable Smith G, the "
      "metallic Schlick Fresnel, the Burley diffuse with retro-reflection (Mitsuba's f_diff + f_retro expands "
      "to Burley's Fd) and the subsurface approximation (flatness = subsurface)");
  if (mp.metallic < 1.0)
    n.push_back(
        "the dielectric specular: Mitsuba's exact dielectric Fresnel at eta = 2 / (1 - sqrt(0.08 specular)) - 1 "
        "where aniso has Schlick's with the same F0 = 0.08 specular");
  if (mp.spec_tint > 0.0 || (mp.sheen > 0.0 && mp.sheen_tint > 0.0))
    n.push_back(
        "the tint colour: Mitsuba divides by the Rec. 709 luminance (0.2127, 0.7152, 0.0722), aniso by Disney's (0.3, 0.6, 0.1)");
  if (mp.clearcoat > 0.0)
    n.push_back(
        "the clearcoat: Mitsuba's is 0.25 clearcoat F D G1 G1 without Burley's 1 / (4 cos_i cos_o) "
        "(principled.cpp:619-641): a different lobe");
  return n;
}

}  // namespace aniso::exporter
