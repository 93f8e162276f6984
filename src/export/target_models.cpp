// export/target_models.cpp: GGX -> each target, the parameters a target writes and the model the
// target renders with them (targets.h), and Mitsuba 3's principled.
#include "export/common.h"

#include <cmath>

#include <fmt/format.h>

namespace aniso::exporter {

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

// The anisotropic GGX of the target's "major axis along the tangent" convention: the larger alpha
// along the (rotated) tangent; returns the extra rotation (0 or 90 degrees) this needs.
double major_first(double& ax, double& ay) {
  if (ax >= ay * (1.0 - 1e-9)) return 0.0;  // (nearly) isotropic fits stay unturned
  std::swap(ax, ay);
  return 90.0;
}

}  // namespace

RoughAniso invert_aspect(double& ax, double& ay, double scale, double cap, std::string_view who,
                         std::vector<std::string>& notes) {
  RoughAniso r;
  r.extra = major_first(ax, ay);
  r.aniso = std::max(0.0, (1.0 - ay / ax) / scale);
  if (r.aniso < 1e-9) r.aniso = 0.0;
  if (r.aniso > cap) {
    notes.push_back(
        fmt::format("alpha ratio {:.3g} exceeds {}'s largest, {:.3g} (anisotropy {:.3g}): written with "
                    "anisotropy {:.3g} and the same mean alpha",
                    ax / ay, who, 1.0 / (1.0 - scale * cap), cap, cap));
    r.aniso = cap;
  }
  r.rough = std::sqrt(std::sqrt(ax * ay));
  if (r.rough > 1.0) notes.push_back("roughness above 1 clamped to 1"), r.rough = 1.0;
  return r;
}

namespace {

double wrap_turn(double t) {
  t = std::fmod(t, 1.0);
  if (t < 0.0) t += 1.0;
  if (t >= 1.0 - 1e-12) t = 0.0;
  return t + 0.0;  // -0 is written as "-0"
}

// The exact Fresnel (a dielectric of index eta, or a conductor of eta 1 and extinction k) closest
// to Schlick's curve s(c) = (f0 + (1 - f0)(1 - c)^5) / scale over c in [0, 1] (least squares on 64
// points, a 1-D golden-section search per form): the targets that have no Schlick Fresnel get the
// curve, not only its F0 (F0 = 0 with Schlick's grazing rise is not eta = 1, which reflects nothing).
struct ExactFresnel {
  double eta = 1.5, k = 0.0;
};
ExactFresnel match_schlick(double f0, double scale, bool allow_conductor) {
  const auto cost = [&](double eta, double k) {
    double e = 0.0;
    for (int i = 0; i < 64; ++i) {
      const double c = (i + 0.5) / 64.0, m = 1.0 - c;
      const double want = std::min(1.0, (f0 + (1.0 - f0) * m * m * m * m * m) / scale);
      e += sqr(F_Conductor(c, eta, k) - want);
    }
    return e;
  };
  const auto golden = [](auto&& f, double lo, double hi) {
    const double r = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = lo, b = hi, x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = f(x1), f2 = f(x2);
    for (int i = 0; i < 80; ++i) {
      if (f1 < f2)
        b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = f(x1);
      else
        a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = f(x2);
    }
    return (a + b) / 2.0;
  };
  ExactFresnel d;
  d.eta = golden([&](double e) { return cost(e, 0.0); }, 1.0001, 60.0);
  if (!allow_conductor) return d;
  ExactFresnel c;
  c.eta = 1.0;
  c.k = golden([&](double k) { return cost(1.0, k); }, 0.0, 60.0);
  return cost(c.eta, c.k) < cost(d.eta, 0.0) ? c : d;
}

// A dielectric F0 colour for the targets whose dielectric Fresnel takes a tint (Blender 4.x's Specular
// Tint, OpenPBR's specular_color; targets.h): the index whose exact Fresnel is closest to Schlick's
// curve of the largest channel (match_schlick; a grey F0 gets the index of its own curve, as before
// the tint) and the tint F0 / max(F0), every channel in [0, 1]: the written reflectance at normal
// incidence has the source's hue exactly, its largest channel the index's F0.
struct TintedDielectric {
  double eta = 1.5;
  glm::dvec3 tint{1.0};
};
TintedDielectric tinted_dielectric(const glm::dvec3& f0_in) {
  const glm::dvec3 f0 = glm::clamp(f0_in, 0.0, 1.0);
  const double m = max3(f0);
  return {match_schlick(m, 1.0, false).eta, m > 0.0 ? f0 / m : glm::dvec3(1.0)};
}

// For the mixes of Mitsuba 3 and pbrt-v4 (diffuse + specular as (1 - w) A + w B): the largest w
// that keeps the diffuse reflectance kd / (1 - w) <= 1, but at least max(F0) so that the specular
// reflectance F0 / w stays <= 1.
double mix_weight(const GgxSource& g) {
  const double w = 1.0 - max3(g.kd);
  return std::clamp(std::max(w, max3(g.f0)), 1e-3, 1.0 - 1e-3);
}

}  // namespace

// --- GGX -> OpenPBR -----------------------------------------------------------------------------------

namespace {

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

// Blender 3.4's metallic Principled: the Specular (in [0, 1]) whose interpolated Fresnel with cspec0
// = f0 (cycles_v1_fresnel) is closest to the source's curve (the conductor's, or Schlick's with f0)
// over the cosine: least squares on 64 points, golden-section search.
double v1_metal_specular(const GgxSource& g, const glm::dvec3& f0) {
  const auto cost = [&](double specular) {
    const double ior = cycles_v1_ior(specular);
    double e = 0.0;
    for (int i = 0; i < 64; ++i) {
      const double c = (i + 0.5) / 64.0;
      const glm::dvec3 want = g.conductor ? glm::dvec3(F_Conductor(c, RGBT<double>(g.eta), RGBT<double>(g.k)))
                                          : glm::dvec3(F_Schlick(RGBT<double>(g.f0), c));
      const glm::dvec3 d = cycles_v1_fresnel(c, f0, ior) - want;
      e += glm::dot(d, d);
    }
    return e;
  };
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = 1e-4, b = 1.0, x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < 60; ++i) {
    if (f1 < f2)
      b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = cost(x1);
    else
      a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = cost(x2);
  }
  const double best = (a + b) / 2.0;
  return cost(1.0) < cost(best) ? 1.0 : best;
}
}  // namespace

// --- GGX -> each target ----------------------------------------------------------------------------

bool blender_v1_add_shader_candidate(const GgxSource& g) {
  if (g.conductor || no_diffuse(g)) return false;
  const CyclesV1Specular spec = cycles_v1_dielectric_specular(g.f0, g.kd);
  const glm::dvec3 miss = glm::abs(cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint) - glm::clamp(g.f0, 0.0, 1.0));
  return max3(miss) > kBlenderV1ColourMiss;
}

TargetBrdf target_model(Target t, const GgxSource& g, json* params_out, std::vector<std::string>* notes_out,
                        double blender_version, BlenderV1Nodes nodes) {
  json p = json::object();
  std::vector<std::string> notes;
  TargetBrdf m;
  double ax = g.alpha_x, ay = g.alpha_y;
  const glm::dvec3 cond_f0 = g.conductor ? glm::dvec3(F_Conductor(1.0, RGBT<double>(g.eta), RGBT<double>(g.k))) : g.f0;
  switch (t) {
    case Target::Blender: {
      // Principled BSDF (closure.h @ 02e6985c; 3.4.1: closure.h:321-325, the same formula):
      // alpha_x = r^2 / aspect >= alpha_y = r^2 aspect, aspect^2 = alpha_y / alpha_x = 1 - 0.9
      // anisotropic, anisotropic <= 1.
      const auto [extra, rough, aniso] = invert_aspect(ax, ay, 0.9, 1.0, "the Principled BSDF", notes);
      const double turn = wrap_turn((g.rotation_deg + extra) / 360.0);
      const glm::dvec2 a = cycles_principled_alpha(rough, aniso);
      // Blender before 3.5: the Principled BSDF v1 (targets.h, "Blender 3.4"): separable Smith G,
      // the interpolated Fresnel, Burley's diffuse; 3.4's bsdf_microfacet_ggx_fresnel_setup
      // saturates both alphas (bsdf_microfacet.h:315-316).
      const bool v1 = blender_version < 3.5;
      m.lobe.alpha_x = v1 ? std::min(a.x, 1.0) : a.x, m.lobe.alpha_y = v1 ? std::min(a.y, 1.0) : a.y;
      m.tangent_turn_deg = extra;
      m.lobe.masking = v1 ? Masking::Separable : Masking::HeightCorrelated;
      p["Roughness"] = rough, p["Anisotropic"] = aniso, p["Anisotropic Rotation"] = turn;
      p["distribution"] = "GGX";
      if (g.conductor || no_diffuse(g)) {
        // Metallic: F0 = min(Base Color, 1), F82-tint with f82 = min(Specular Tint, 1).
        const glm::dvec3 f0 = glm::clamp(cond_f0, 0.0, 1.0);
        glm::dvec3 tint(1.0);
        if (g.conductor) {
          const double c82 = 1.0 / 7.0;
          tint = cycles_tint_for(f0, glm::dvec3(F_Conductor(c82, RGBT<double>(g.eta), RGBT<double>(g.k))));
        }
        // 3.4: cspec0 = Base Color; the curve's shape is the dielectric Fresnel at the Specular
        // input's ior: the Specular in [0, 1] whose curve is closest to the source's (conductor or
        // Schlick) over the cosine.
        const double specular = v1_metal_specular(g, f0);
        p["Base Color"] = j3(f0), p["Metallic"] = 1.0, p["Specular Tint"] = j3(tint), p["Specular"] = specular;
        if (v1) {
          m.name = "Cycles 3.4 Principled BSDF v1, metallic (interpolated Fresnel, separable Smith G)";
          m.lobe.fresnel = FresnelModel::CyclesV1;
          m.lobe.f0 = f0, m.lobe.eta = glm::dvec3(cycles_v1_ior(specular));
          notes.push_back(
              fmt::format("Blender 3.4: F = Base Color (1 - FH) + FH, FH the dielectric Fresnel of the Specular input's ior "
                          "normalised to [F0, 1] (bsdf_util.h:94-105); Specular {:.4g} (ior {:.4g}) gives the curve closest to "
                          "the source's",
                          specular, cycles_v1_ior(specular)));
        } else {
          m.name = "Cycles 4.x Principled BSDF, metallic (F82-tint Fresnel, height-correlated Smith G)";
          m.lobe.fresnel = FresnelModel::F82Tint;
          m.lobe.f0 = f0;
          m.lobe.f82_b = cycles_f82tint_b(f0, tint);
        }
        if (g.conductor && !v1 && blender_version >= 4.3) {
          // Blender 4.3+: the Metallic BSDF with fresnel_type PHYSICAL_CONDUCTOR takes n and k
          // (closure.h, CLOSURE_BSDF_PHYSICAL_CONDUCTOR: the same aspect mapping as the Principled
          // BSDF, bsdf_microfacet_setup_fresnel_conductor with ior = {n, k}): aniso's conductor exactly.
          m.name = "Cycles 4.3+ Metallic BSDF, physical conductor (exact n, k Fresnel, height-correlated Smith G)";
          m.lobe.fresnel = FresnelModel::Conductor;
          m.lobe.eta = g.eta, m.lobe.k = g.k;
          p["IOR"] = j3(g.eta), p["Extinction"] = j3(g.k);
          notes.push_back(
              "Blender 4.3+: a Metallic BSDF with the physical conductor Fresnel (n, k); before 4.3 the "
              "script builds a Principled BSDF with F0 and the F82 tint matching the reflectance at cos = "
              "1/7 instead (--blender-version 4.0 reports that one; 3.4 has no tint)");
        } else if (g.conductor) {
          p["IOR"] = j3(g.eta), p["Extinction"] = j3(g.k);  // the script's 4.3+ branch, whatever is reported
          notes.push_back(
              "the conductor's n, k become F0 and the F82 tint matching its reflectance at cos = 1/7 (the "
              "script uses 4.3's Metallic BSDF with n, k where it exists; Blender 3.4 has no tint: its "
              "Specular Tint is a float, its Specular sets the curve's shape)");
        }
      } else {
        // 4.x: F = mix(F0_from_ior(IOR) Specular Tint, 1, s), s = (F_dielectric(IOR) - F0(IOR)) / (1 -
        // F0(IOR)) (closure.h, "Apply IOR adjustment" and the Specular component: f0 = F0_from_ior(eta)
        // specular_tint, f90 1, exponent -eta; bsdf_microfacet.h, microfacet_fresnel, the
        // GENERALIZED_SCHLICK case with exponent < 0; cycles_dielectric_tint_fresnel): the exact
        // dielectric Fresnel where the tint is white. The IOR and the tint: tinted_dielectric (the F0's
        // hue exactly, every channel in [0, 1]).
        const TintedDielectric td = tinted_dielectric(g.f0);
        const double eta = td.eta, f0 = F_Conductor(1.0, eta, 0.0);
        m.diffuse = g.kd;
        p["Base Color"] = j3(g.kd), p["Metallic"] = 0.0, p["IOR"] = eta, p["Specular IOR Level"] = 0.5;
        p["Specular Tint"] = j3(td.tint);
        // 3.4, one node: cspec0 = 0.08 Specular mix(1, Base Color / its luminance, Specular Tint)
        // (closure.h:317, 327-334), Specular above 1 where F0 is above 0.08 (cycles_v1_dielectric_specular).
        // 3.4, the Add Shader (BlenderV1Nodes): the diffuse node with Specular 0 and a metallic node with
        // Base Color = F0 (bsdf_microfacet_ggx_fresnel_setup saturates cspec0, bsdf_microfacet.h:315)
        // whose Specular shapes the interpolated Fresnel: the curve closest to Schlick's with this F0
        // (v1_metal_specular, as for a metal).
        const bool add_shader = nodes == BlenderV1Nodes::AddShader;
        const CyclesV1Specular spec = cycles_v1_dielectric_specular(g.f0, g.kd);
        const glm::dvec3 metal_f0 = glm::clamp(g.f0, 0.0, 1.0);
        const double metal_specular = add_shader ? v1_metal_specular(g, metal_f0) : 0.0;
        p["Specular"] = add_shader ? 0.0 : spec.specular;
        p["Specular Tint (3.4)"] = add_shader ? 0.0 : spec.tint;
        if (add_shader) p["Add Shader (3.4)"] = {{"Base Color", j3(metal_f0)}, {"Metallic", 1.0}, {"Specular", metal_specular}};
        if (v1 && add_shader) {
          m.name =
              "Cycles 3.4 Add Shader: Principled BSDF v1 diffuse (Burley) + Principled BSDF v1 metallic (Base Color = F0, "
              "interpolated Fresnel, separable Smith G)";
          m.lobe.fresnel = FresnelModel::CyclesV1;
          m.lobe.f0 = metal_f0, m.lobe.eta = glm::dvec3(cycles_v1_ior(metal_specular));
          m.burley_roughness = rough;
          notes.push_back(fmt::format(
              "Blender 3.4: one Principled BSDF cannot write this F0 {} over this Base Color (its dielectric F0 is white mixed "
              "with the Base Color's hue, closure.h:327-334: the closest is {}): the script adds a diffuse-only Principled "
              "BSDF (Specular 0) and a metallic one (Base Color = F0, Specular {:.4g} for the Fresnel curve's shape, ior "
              "{:.4g}) with an Add Shader, which Cycles sums",
              fmt3(g.f0), fmt3(cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint)), metal_specular,
              cycles_v1_ior(metal_specular)));
        } else if (v1) {
          m.name = "Cycles 3.4 Principled BSDF v1, dielectric (exact Fresnel, separable Smith G) + Burley diffuse";
          m.lobe.fresnel = FresnelModel::CyclesV1;
          m.lobe.f0 = cycles_v1_cspec0(g.kd, 0.0, spec.specular, spec.tint);
          m.lobe.eta = glm::dvec3(cycles_v1_ior(spec.specular));
          m.burley_roughness = rough;
          if (spec.specular > 1.0)
            notes.push_back(fmt::format(
                "Blender 3.4: Specular {:.4g} (F0 {:.4g}) is above the slider's 1: the socket takes it (its hard range is "
                "unbounded) and Cycles reads it unclamped (closure.h:317)",
                spec.specular, 0.08 * spec.specular));
          if (const glm::dvec3 d = m.lobe.f0 - glm::clamp(g.f0, 0.0, 1.0); glm::dot(d, d) > 1e-6)
            notes.push_back(fmt::format(
                "Blender 3.4's dielectric F0 is white mixed with the Base Color's hue (Specular Tint {:.3g}, closure.h:327-334): "
                "the source's F0 {} is written as {}, the closest such colour",
                spec.tint, fmt3(g.f0), fmt3(m.lobe.f0)));
        } else {
          m.name =
              "Cycles 4.x Principled BSDF, dielectric (exact Fresnel times the Specular Tint, height-correlated G) + Lambert";
          m.lobe.fresnel = FresnelModel::CyclesDielectricTint;
          m.lobe.f0 = f0 * td.tint, m.lobe.eta = glm::dvec3(eta);
          notes.push_back(fmt::format(
              "Schlick's F0 {} becomes the dielectric Fresnel of IOR {:.4g} closest to the curve of its largest channel (F0 "
              "{:.4g}), F0 times Specular Tint {} (F0 / its largest channel: the F0's hue)",
              fmt3(g.f0), eta, f0, fmt3(td.tint)));
          notes.push_back(
              "Cycles layers the diffuse under the specular (its weight times 1 - the specular albedo, "
              "closure_layering_weight); the target model adds them as aniso's GGX does");
        }
        if (v1)
          notes.push_back(
              "Blender 3.4: the Fresnel is the dielectric one at ior = 2 / (1 - sqrt(0.08 Specular)) - 1 interpolated from "
              "F0 to 1 (closure.h:317, bsdf_util.h:94-105), the diffuse Burley's with retro-reflection at the same Roughness "
              "(bsdf_principled_diffuse.h:45-86), added to the specular");
      }
      notes.push_back(v1 ? "the target model is Blender 3.4's Principled BSDF v1 (separable Smith G, interpolated Fresnel, "
                           "Burley diffuse), distribution GGX (set by the script; Multiscatter GGX adds the energy of the "
                           "lobe's multiple bounces, which the single-scattering model leaves out)"
                         : "the target model is Blender 4.x's Principled BSDF; Blender 3.4's (Principled v1: separable "
                           "Smith G, interpolated Fresnel, Burley diffuse) is reported in a note");
      break;
    }
    case Target::Mitsuba3:
    case Target::PbrtV4: {
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
      break;
    }
    case Target::MaterialX: {
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
      break;
    }
    case Target::OpenPbr: m = openpbr_model(g, p, notes); break;
    case Target::Gltf: {
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
      break;
    }
  }
  if (params_out) *params_out = p;
  if (notes_out) *notes_out = notes;
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
