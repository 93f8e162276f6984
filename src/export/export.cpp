// export/export.cpp: see export.h; the conventions of each target are in targets.h, with the
// source lines they come from, and in docs/export.md.
#include "aniso/export/export.h"
#include "aniso/version.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/input_error.h"
#include "io/text_escape.h"

namespace aniso::exporter {

using json = nlohmann::json;

namespace {

constexpr TargetInfo kTargets[] = {
    {Target::Blender, "blender", ".py", "Blender (Cycles) Principled BSDF, a Python script for 3.4 and 4.x",
     "Writes a Python script that builds a Principled BSDF material (GGX, not multiscatter GGX), names it after the "
     "source and assigns it to the active object. The tangent comes from the object's active UV map (a Tangent node, "
     "dp/du as aniso's meshes), else Cycles' default. Run: blender -b scene.blend -P FILE, or exec(open(FILE).read()) "
     "after making the object. Blender 4.x: metals use the F82-tint Fresnel (Base Color = F0, Specular Tint = the "
     "edge tint at 82 degrees); 3.4 (the Principled BSDF v1: separable Smith G, Fresnel interpolated from Base "
     "Color to white, Burley diffuse) has no edge tint: its Specular sets the curve's shape. The report measures "
     "--blender-version (default 4.3) and gives the other versions' errors in its notes."},
    {Target::Mitsuba3, "mitsuba3", ".xml",
     "Mitsuba 3 roughconductor (GGX), principled, or blendbsdf of diffuse and roughconductor",
     "Writes a <scene version=\"3.0.0\"> holding one <bsdf> with id = the material name: a roughconductor with "
     "distribution ggx, alpha_u / alpha_v as aniso's alpha_x / alpha_y, and a named material (Ag, Al, Au, Cr, Cu, W) "
     "or rgb eta / k; an aniso principled material as Mitsuba's principled (the same parameters); with a diffuse "
     "part, a principled or a blendbsdf of a diffuse and a roughconductor, whichever is closer to the source (the "
     "report gives both errors). Use it with <include "
     "filename=\"FILE\"/> and <ref id=\"NAME\"/>. The tangent is dp/du of the mesh: rotate the uv map by rotation_deg "
     "to orient the highlight (Mitsuba 3 has no rotation input)."},
    {Target::PbrtV4, "pbrt-v4", ".pbrt", "pbrt-v4 conductor (remaproughness false), or mix of diffuse and conductor",
     "Writes MakeNamedMaterial statements: a conductor with uroughness / vroughness = alpha_x / alpha_y and "
     "remaproughness false, eta / k as named spectra (metal-Au-eta, ...) or rgb values; with a diffuse part, a mix "
     "material of a diffuse and a conductor (pbrt-v4 chooses one of them per hit with probability amount: in the mean "
     "the sum). Use it with Include \"FILE\" and NamedMaterial \"NAME\". The tangent is dp/du of the shape: orient "
     "the uv parameterisation by rotation_deg (pbrt-v4 has no rotation input)."},
    {Target::MaterialX, "materialx", ".mtlx", "MaterialX standard_surface (specular_anisotropy, specular_rotation)",
     "Writes a MaterialX document with a standard_surface shader and a surfacematerial. Metals: metalness 1, base_color "
     "= the reflectivity F0 and specular_color = the edge colour of Gulbrandsen's artistic IOR (mx_artistic_ior), "
     "matched to the source's n, k; dielectrics: base_color = the diffuse albedo, specular_IOR from F0. The tangent is "
     "the geometry's Tworld rotated by specular_rotation (a fraction of a turn)."},
    {Target::OpenPbr, "openpbr", ".mtlx",
     "OpenPBR Surface (MaterialX open_pbr_surface, 1.39): F82-tint metals, tangent from the geometry",
     "Writes a MaterialX 1.39 document with an open_pbr_surface shader and a surfacematerial. Metals: base_metalness 1, "
     "base_color = F0 and specular_color = the F82 edge tint matching the source's reflectance at cos = 1/7; "
     "dielectrics: base_color = the diffuse albedo (Lambert: base_diffuse_roughness 0), specular_ior from F0. "
     "specular_roughness and specular_roughness_anisotropy by the OpenPBR mapping (alpha_t = r^2 sqrt(2 / (1 + (1 - "
     "a)^2)), alpha_b = (1 - a) alpha_t). OpenPBR has no rotation input: the anisotropy follows geometry_tangent "
     "(Tworld by default); a rotation is written as a rotate3d of the world tangent about the world normal feeding "
     "geometry_tangent."},
    {Target::Gltf, "gltf", ".gltf", "glTF 2.0 with KHR_materials_anisotropy: a .gltf and a .bin sphere with tangents",
     "Writes FILE.gltf and a .bin beside it: a UV sphere with NORMAL and TANGENT (dp/du, w = +1) and one material "
     "(pbrMetallicRoughness plus KHR_materials_anisotropy: anisotropyStrength, anisotropyRotation in radians, "
     "counter-clockwise from the tangent). Open it in any glTF viewer that supports the extension. The provenance is "
     "in asset.extras."},
};

double luminance_avg(const glm::dvec3& c) { return (c.x + c.y + c.z) / 3.0; }
double max3(const glm::dvec3& c) { return std::max({c.x, c.y, c.z}); }

// Rotates v about z by angle (radians), counter-clockwise: x towards y.
Vec3d rotate_z(const Vec3d& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// Rusinkiewicz 1998: h from (theta_h, phi_h), wi = d rotated by theta_h about y then phi_h about z.
void half_diff_to_dirs(double th, double ph, double td, double pd, Vec3d& wi, Vec3d& wo) {
  const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  const Vec3d d(std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td));
  // rotate d about y by theta_h
  const Vec3d dy(std::cos(th) * d.x + std::sin(th) * d.z, d.y, -std::sin(th) * d.x + std::cos(th) * d.z);
  wi = rotate_z(dy, ph);
  wo = 2.0 * glm::dot(wi, h) * h - wi;
}

std::string fmt3(const glm::dvec3& c, const char* sep = ", ") {
  return fmt::format("{:.9g}{}{:.9g}{}{:.9g}", c.x, sep, c.y, sep, c.z);
}
json j3(const glm::dvec3& c) { return json::array({c.x, c.y, c.z}); }

bool has_scalar(const ParamValues& p, std::string_view key) {
  const auto it = p.values.find(key);
  return it != p.values.end() && std::holds_alternative<double>(it->second);
}

// The source as built, with its tangent rotation (rotation_deg, when the table has it) taken out:
// the exporter fits the unrotated material and writes the rotation into each target's own input.
MaterialDesc unrotated(const MaterialDesc& d) {
  MaterialDesc u = d;
  if (has_scalar(u.params, "rotation_deg")) u.params.values["rotation_deg"] = 0.0;
  return u;
}

double rotation_of(const MaterialDesc& d) { return has_scalar(d.params, "rotation_deg") ? d.params.scalar("rotation_deg") : 0.0; }

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

// The roughness and anisotropy of the targets whose alphas are r^2 / aspect and r^2 aspect with
// aspect^2 = 1 - scale a (Blender's Principled: scale 0.9; MaterialX: 1): r^2 = sqrt(ax ay), a =
// (1 - ay / ax) / scale, the larger alpha first (extra = the tangent's turn); a capped at `cap`
// (keeping the mean alpha) and r at 1, each with a note.
struct RoughAniso {
  double extra, rough, aniso;
};
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

bool no_diffuse(const GgxSource& g) { return max3(g.kd) < 1e-6; }

// For the mixes of Mitsuba 3 and pbrt-v4 (diffuse + specular as (1 - w) A + w B): the largest w
// that keeps the diffuse reflectance kd / (1 - w) <= 1, but at least max(F0) so that the specular
// reflectance F0 / w stays <= 1.
double mix_weight(const GgxSource& g) {
  const double w = 1.0 - max3(g.kd);
  return std::clamp(std::max(w, max3(g.f0)), 1e-3, 1.0 - 1e-3);
}

std::string xml_escape(std::string_view s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      default: o += c;
    }
  }
  return o;
}
// Text inside an XML comment may not contain "--".
std::string xml_comment_safe(std::string s) {
  for (size_t i; (i = s.find("--")) != std::string::npos;) s.replace(i, 2, "- -");
  return s;
}
std::string identifier(std::string_view s) {
  std::string o;
  for (char c : s) o += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
  if (o.empty()) o = "material";
  return o;
}
// A Python string literal (the Python Language Reference, 2.4.1, "String and Bytes literals") holding
// exactly the text: backslash, quote and every control character (C0, DEL, C1) and line separator
// as an escape sequence, so a name can neither end the literal nor the line. Text that is not UTF-8
// (a script must be, PEP 3120) is made so first by text_escape (its bad bytes become "\xNN").
std::string py_string(std::string_view in) {
  const std::string s = first_invalid_utf8(in) ? text_escape(in) : std::string(in);
  std::string o = "\"";
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '\\' || c == '"')
      o += '\\', o += s[i];
    else if (c == '\n')
      o += "\\n";
    else if (c == '\r')
      o += "\\r";
    else if (c == '\t')
      o += "\\t";
    else if (c < 0x20 || c == 0x7f)
      o += fmt::format("\\x{:02x}", c);
    else if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) < 0xa0)  // U+0080 to U+009F
      o += fmt::format("\\x{:02x}", static_cast<unsigned char>(s[++i]));
    else if (c == 0xe2 && s.compare(i + 1, 1, "\x80") == 0 && i + 2 < s.size() && (s[i + 2] == '\xa8' || s[i + 2] == '\xa9'))
      o += s[i + 2] == '\xa8' ? "\\u2028" : "\\u2029", i += 2;
    else
      o += s[i];
  }
  return o + "\"";
}

}  // namespace

std::span<const TargetInfo> targets() { return kTargets; }

const TargetInfo* find_target(std::string_view name) {
  for (const TargetInfo& t : kTargets)
    if (t.name == name) return &t;
  return nullptr;
}

std::string target_names() {
  std::string s;
  for (const TargetInfo& t : kTargets) s += (s.empty() ? "\"" : ", \"") + std::string(t.name) + "\"";
  return s;
}

// --- sampling and errors ---------------------------------------------------------------------------

SampleSet sample_source(const MaterialD& m, int grid) {
  SampleSet set;
  set.source = "export: source sampled";
  set.format = "synthetic";
  const int nth = 4 * grid, nph = 4 * grid, ntd = 2 * grid, npd = 2 * grid;
  const double half_pi = kPi<double> / 2.0;
  for (int i = 0; i < nth; ++i) {
    // theta_h on MERL's quadratic spacing (dense at the peak): theta = ((i + 0.5) / n)^2 pi / 2.
    const double u = (i + 0.5) / nth, th = u * u * half_pi;
    const double dth = (2.0 * u / nth) * half_pi;  // d theta_h / d i
    for (int j = 0; j < nph; ++j) {
      const double ph = (j + 0.5) * 2.0 * kPi<double> / nph;
      for (int a = 0; a < ntd; ++a) {
        const double td = (a + 0.5) * half_pi / ntd;
        for (int b = 0; b < npd; ++b) {
          const double pd = (b + 0.5) * 2.0 * kPi<double> / npd;
          Vec3d wi, wo;
          half_diff_to_dirs(th, ph, td, pd, wi, wo);
          if (!(wi.z > 0.02) || !(wo.z > 0.02)) continue;
          MeasuredSample s;
          s.wi = glm::normalize(wi), s.wo = glm::normalize(wo);
          const RGBT<double> f = m.f(s.wi, s.wo);
          s.value = glm::dvec3(f.x, f.y, f.z);
          // Solid angle of the bin, dw_i dw_o = 4 cos(theta_d) sin(theta_h) sin(theta_d) dth dph dtd dpd
          // (measured/samples.h, merl_samples), the constant factors dropped (weights are relative).
          s.weight = 4.0 * std::cos(td) * std::sin(th) * std::sin(td) * dth;
          if (!(s.weight > 0.0) || !std::isfinite(s.value.x + s.value.y + s.value.z)) continue;
          set.samples.push_back(s);
        }
      }
    }
  }
  return set;
}

FitErrors target_errors(const TargetBrdf& t, const SampleSet& data) {
  return fit_errors([&t](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(t.f(wi, wo)); }, data);
}

namespace {
// rho(wo) = integral f cos_i dw_i, over the half vector h: wi = reflect(wo, h), dw_i = 4 (wo.h) dw_h,
// theta_h on a quadratic grid (dense near the normal, where the sharp lobes are).
template <typename F> glm::dvec3 albedo_by_half_vector(F&& f, const Vec3d& wo) {
  constexpr int nt = 128, np = 128;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < nt; ++i) {
    const double u = (i + 0.5) / nt, th = u * u * kPi<double> / 2.0, dth = 2.0 * u / nt * kPi<double> / 2.0;
    for (int j = 0; j < np; ++j) {
      const double ph = (j + 0.5) * 2.0 * kPi<double> / np;
      const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const double oh = glm::dot(wo, h);
      if (!(oh > 0.0)) continue;
      const Vec3d wi = 2.0 * oh * h - wo;
      if (!(wi.z > 0.0)) continue;
      sum += f(wi) * (wi.z * 4.0 * oh * std::sin(th) * dth * (2.0 * kPi<double> / np));
    }
  }
  return sum;
}
}  // namespace

double max_albedo_difference(const MaterialD& source, const TargetBrdf& t, double* theta_deg, double* phi_deg) {
  double worst = 0.0;
  for (double th : {0.0, 20.0, 40.0, 60.0, 75.0})
    for (double ph : {0.0, 45.0, 90.0}) {
      const double a = glm::radians(th), p = glm::radians(ph);
      const Vec3d wo(std::sin(a) * std::cos(p), std::sin(a) * std::sin(p), std::cos(a));
      const glm::dvec3 s = albedo_by_half_vector(
          [&](const Vec3d& wi) {
            const RGBT<double> f = source.f(wi, wo);
            return glm::dvec3(f.x, f.y, f.z);
          },
          wo);
      const glm::dvec3 g = albedo_by_half_vector([&](const Vec3d& wi) { return t.f(wi, wo); }, wo);
      const double d = max3(glm::abs(s - g));
      if (d > worst) {
        worst = d;
        if (theta_deg) *theta_deg = th;
        if (phi_deg) *phi_deg = ph;
      }
    }
  return worst;
}

// --- source -> GGX -----------------------------------------------------------------------------------

namespace {

std::optional<GgxSource> exact_ggx(const MaterialDesc& d) {
  const MaterialD m = build_material<double>(unrotated(d));
  GgxSource g;
  g.rotation_deg = rotation_of(d);
  if (m.kind == ModelKind::GGX) {
    g.alpha_x = m.ggx.lobe.alpha_x, g.alpha_y = m.ggx.lobe.alpha_y;
    g.kd = glm::dvec3(m.ggx.kd.x, m.ggx.kd.y, m.ggx.kd.z);
    g.f0 = glm::dvec3(m.ggx.f0.x, m.ggx.f0.y, m.ggx.f0.z);
    g.origin = "exact: the source is an anisotropic GGX (Schlick F0, Lambertian kd)";
    return g;
  }
  if (m.kind == ModelKind::Metal && m.metal.lobe_kind == SpecularLobeKind::GGX && !m.metal.has_directional_diffuse) {
    g.conductor = true;
    g.alpha_x = m.metal.ggx.alpha_x, g.alpha_y = m.metal.ggx.alpha_y;
    g.eta = glm::dvec3(m.metal.eta.x, m.metal.eta.y, m.metal.eta.z);
    g.k = glm::dvec3(m.metal.k.x, m.metal.k.y, m.metal.k.z);
    if (d.params.has("metal")) {
      const MetalData* md = find_metal(d.params.text("metal"));
      if (md) g.metal = std::string(md->name), g.symbol = std::string(md->symbol);
    }
    g.origin = "exact: the source is a conductor with a GGX lobe (eta, k)";
    return g;
  }
  if (m.kind == ModelKind::Principled) {
    const PrincipledT<double>& p = m.principled;
    if (p.metallic == 1.0 && p.sheen == 0.0 && p.clearcoat == 0.0) {
      const GGXLobeT<double> l = p.specular_lobe();
      g.alpha_x = l.alpha_x, g.alpha_y = l.alpha_y;
      g.kd = glm::dvec3(0.0);
      const RGBT<double> f0 = p.specular_f0();
      g.f0 = glm::dvec3(f0.x, f0.y, f0.z);
      g.origin =
          "exact: the source is a metallic Disney principled material (Schlick F0 = base_color; its separable "
          "Smith G differs from the targets' height-correlated one)";
      return g;
    }
  }
  return std::nullopt;
}

}  // namespace

namespace {

// A GGX as the exporter fits it: error of aniso's GGX kernel (ggx.h / metal.h) against the samples.
FitErrors ggx_errors(const GgxSource& g, const SampleSet& data) {
  TargetBrdf t;
  t.lobe.alpha_x = g.alpha_x, t.lobe.alpha_y = g.alpha_y;
  t.lobe.masking = Masking::HeightCorrelated;
  if (g.conductor)
    t.lobe.fresnel = FresnelModel::Conductor, t.lobe.eta = g.eta, t.lobe.k = g.k;
  else
    t.lobe.fresnel = FresnelModel::Schlick, t.lobe.f0 = g.f0, t.diffuse = g.kd;
  return target_errors(t, data);
}
double metric_of(const FitErrors& e, FitMetric m) { return m == FitMetric::L2Cos ? e.l2cos_all : e.log_all; }

// The fit engine's starts (moments, Ngan's nearest fit, random draws) can miss the basin of a sharp
// anisotropic lobe (Ward 0.05 x 0.3: all 16 starts ended at alpha_y = 1). A second candidate that
// cannot: a search over the two alphas (log grid, 0.002 to 1, then a finer grid around the best),
// where everything else is linear (kd and F0 of the Schlick GGX: f = kd / pi + (F0 (1 - s) + s) L,
// s = (1 - wi.h)^5, solved by weighted least squares per channel, l2cos residuals) or fixed (the
// conductor's eta, k: the source's own). Its result is one of the fit's starts (FitOptions::start).
GgxSource grid_fit(const GgxSource& base, const SampleSet& all) {
  SampleSet data;
  const size_t stride = std::max<size_t>(1, all.samples.size() / 6000);
  for (size_t i = 0; i < all.samples.size(); i += stride) data.samples.push_back(all.samples[i]);
  struct Pre {
    Vec3d wi, wo;
    double c, s5, w;
    glm::dvec3 v;
  };
  std::vector<Pre> pre;
  for (const MeasuredSample& m : data.samples) {
    const Vec3d h = glm::normalize(m.wi + m.wo);
    const double s = 1.0 - std::clamp(glm::dot(m.wi, h), 0.0, 1.0);
    pre.push_back({m.wi, m.wo, m.wi.z, s * s * s * s * s, m.weight, m.value});
  }
  const auto solve = [&](double ax, double ay, GgxSource& g) {
    GGXLobeT<double> lobe;
    lobe.alpha_x = ax, lobe.alpha_y = ay;
    g.alpha_x = ax, g.alpha_y = ay;
    double err = 0.0;
    if (g.conductor) {
      for (const Pre& p : pre) {
        const glm::dvec3 F = F_Conductor(glm::dot(p.wi, glm::normalize(p.wi + p.wo)), RGBT<double>(g.eta), RGBT<double>(g.k));
        const glm::dvec3 r = (F * lobe.eval(p.wi, p.wo) - p.v) * p.c;
        err += p.w * glm::dot(r, r);
      }
      return err;
    }
    // Normal equations of [c / pi, (1 - s) L c] (kd, F0) against (v - s L) c, per channel.
    double a11 = 0, a12 = 0, a22 = 0;
    glm::dvec3 b1(0.0), b2(0.0);
    std::vector<double> L(pre.size());
    for (size_t i = 0; i < pre.size(); ++i) {
      const Pre& p = pre[i];
      L[i] = lobe.eval(p.wi, p.wo);
      const double x1 = p.c * kInvPi<double>, x2 = (1.0 - p.s5) * L[i] * p.c;
      const glm::dvec3 y = (p.v - p.s5 * L[i]) * p.c;
      a11 += p.w * x1 * x1, a12 += p.w * x1 * x2, a22 += p.w * x2 * x2;
      b1 += p.w * x1 * y, b2 += p.w * x2 * y;
    }
    for (int c = 0; c < 3; ++c) {
      const double det = a11 * a22 - a12 * a12;
      double kd = det != 0.0 ? (b1[c] * a22 - b2[c] * a12) / det : 0.0;
      double f0 = det != 0.0 ? (a11 * b2[c] - a12 * b1[c]) / det : 0.0;
      // The box [0, 1]^2: clamp one, re-solve the other.
      if (kd < 0.0 || kd > 1.0)
        kd = std::clamp(kd, 0.0, 1.0), f0 = a22 > 0 ? std::clamp((b2[c] - a12 * kd) / a22, 0.0, 1.0) : 0.0;
      if (f0 < 0.0 || f0 > 1.0)
        f0 = std::clamp(f0, 0.0, 1.0), kd = a11 > 0 ? std::clamp((b1[c] - a12 * f0) / a11, 0.0, 1.0) : 0.0;
      g.kd[c] = kd, g.f0[c] = f0;
    }
    for (size_t i = 0; i < pre.size(); ++i) {
      const Pre& p = pre[i];
      const glm::dvec3 f = g.kd * kInvPi<double> + (g.f0 * (1.0 - p.s5) + p.s5) * L[i];
      const glm::dvec3 r = (f - p.v) * p.c;
      err += p.w * glm::dot(r, r);
    }
    return err;
  };
  constexpr int n = 24;
  const double lo = std::log(0.002), hi = std::log(1.0), step = (hi - lo) / (n - 1);
  GgxSource best = base, g = base;
  double best_err = INFINITY, bx = 0, by = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double e = solve(std::exp(lo + i * step), std::exp(lo + j * step), g);
      if (e < best_err) best_err = e, best = g, bx = lo + i * step, by = lo + j * step;
    }
  constexpr int m = 9;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = std::min(hi, bx + (i - (m - 1) / 2) * step / ((m - 1) / 2));
      const double y = std::min(hi, by + (j - (m - 1) / 2) * step / ((m - 1) / 2));
      const double e = solve(std::exp(x), std::exp(y), g);
      if (e < best_err) best_err = e, best = g;
    }
  return best;
}

}  // namespace

GgxSource ggx_source(const MaterialDesc& d, const SampleSet& samples, const ExportOptions& o) {
  if (std::optional<GgxSource> g = exact_ggx(d)) return *g;
  if (samples.samples.empty())
    throw InputError(
        fmt::format("{}: the material reflects nothing above the horizon: there is nothing to export", d.params.where));
  double total = 0.0;
  for (const MeasuredSample& s : samples.samples) total += s.value.x + s.value.y + s.value.z;
  if (!(total > 0.0))
    throw InputError(
        fmt::format("{}: the material is black (f = 0 at every sampled pair): no target can represent it "
                    "other than as black, and a fit has nothing to fit",
                    d.params.where.empty() ? d.model : d.params.where));
  FitOptions fo;
  // The target is anisotropic whatever the data say (an isotropic source gives equal alphas), and
  // it follows the source where that gains energy: the export reproduces the source, it does not
  // correct it.
  fo.anisotropy = Anisotropy::Yes;
  fo.allow_energy_gain = true;
  fo.metric = o.metric;
  fo.starts = o.starts;
  fo.seed = o.seed;
  fo.threads = o.threads;
  fo.max_iterations = 100;
  GgxSource g;
  g.rotation_deg = rotation_of(d);
  if (d.model == "metal") {
    fo.model = "metal";
    fo.metal_lobe = "ggx";
    if (d.params.has("metal")) fo.metal = d.params.text("metal");
  } else {
    fo.model = "ggx";
  }
  if (d.params.has("metal")) {
    if (const MetalData* md = find_metal(d.params.text("metal")))
      g.metal = std::string(md->name), g.symbol = std::string(md->symbol);
  }
  // The alpha grid search first (the conductor keeps the source's own eta, k), then Ceres with its
  // result as one more start beside its own (Levenberg-Marquardt does not raise the cost of a start
  // on the solver's samples).
  GgxSource start = g;
  if (fo.model == "metal") {
    start.conductor = true;
    const MaterialD src = build_material<double>(unrotated(d));
    start.eta = glm::dvec3(src.metal.eta.x, src.metal.eta.y, src.metal.eta.z);
    start.k = glm::dvec3(src.metal.k.x, src.metal.k.y, src.metal.k.z);
  }
  const GgxSource grid = grid_fit(start, samples);
  const char* ch[3] = {"r", "g", "b"};
  fo.start = {{"alpha_x", grid.alpha_x}, {"alpha_y", grid.alpha_y}, {"rotation_deg", 0.0}};
  for (int c = 0; c < 3; ++c) {
    if (fo.model == "ggx")
      fo.start.emplace_back(fmt::format("kd.{}", ch[c]), grid.kd[c]),
          fo.start.emplace_back(fmt::format("f0.{}", ch[c]), grid.f0[c]);
    else if (fo.metal.empty())
      fo.start.emplace_back(fmt::format("eta.{}", ch[c]), grid.eta[c]),
          fo.start.emplace_back(fmt::format("k.{}", ch[c]), grid.k[c]);
  }
  const FitResult r = fit_samples(samples, fo);
  const MaterialDesc fitted = parse_material(r.material, "fitted GGX");
  std::optional<GgxSource> e = exact_ggx(fitted);
  if (!e) throw std::logic_error("export: the fitted material is not a GGX");
  g.alpha_x = e->alpha_x, g.alpha_y = e->alpha_y;
  // The source was sampled unturned, so the fitted turn is 0 or a quarter turn: the fit writes its
  // canonical form, the narrower direction along the tangent (src/fit/models.h, Orientation), which
  // for a source wider along the tangent is the swapped pair turned by 90 degrees.
  if (r.anisotropic && std::abs(std::remainder(r.material.value("rotation_deg", 0.0), 180.0)) > 45.0)
    std::swap(g.alpha_x, g.alpha_y);
  g.conductor = e->conductor;
  g.kd = e->kd, g.f0 = e->f0, g.eta = e->eta, g.k = e->k;
  g.exact = false;
  g.source_fit = r.errors;
  const FitErrors grid_err = ggx_errors(grid, samples);
  const std::string how =
      fmt::format("Ceres from {} starts and the alpha grid search's result (l2cos {:.4g}, log {:.4g}), best {}", fo.starts,
                  grid_err.l2cos_all, grid_err.log_all, r.best_start);
  g.origin = fmt::format(
      "fitted: aniso's anisotropic {} to {} samples of the {} source ({} metric; {}): l2cos {:.4g}, "
      "log {:.4g}",
      fo.model == "metal" ? "GGX conductor" : "GGX", samples.samples.size(), d.model,
      o.metric == FitMetric::L2Cos ? "l2cos" : "log", how, g.source_fit.l2cos_all, g.source_fit.log_all);
  return g;
}

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
    const double eta = match_schlick(luminance_avg(g.f0), 1.0, false).eta;
    m.name = "OpenPBR Surface, dielectric (exact Fresnel, G2 at the mean alpha) layered over Lambert";
    m.lobe.fresnel = FresnelModel::Dielectric;
    m.lobe.eta = glm::dvec3(eta);
    m.diffuse = glm::clamp(g.kd, 0.0, 1.0);
    m.diffuse_times_openpbr_throughput = true;
    p["base_metalness"] = 0.0, p["base_color"] = j3(m.diffuse), p["specular_color"] = j3(glm::dvec3(1.0));
    p["specular_ior"] = eta;
    notes.push_back(fmt::format("Schlick's F0 {:.4g} becomes the dielectric Fresnel of specular_ior {:.4g} closest to its curve",
                                luminance_avg(g.f0), eta));
    notes.push_back(
        "OpenPBR layers the specular over the diffuse: the diffuse is scaled by 1 - the specular's directional "
        "albedo at the view (mx_dielectric_bsdf.glsl:47-49, mx_layer_bsdf.glsl:5), which the target model does "
        "and aniso's GGX (a sum) does not");
    if (max3(g.f0) - std::min({g.f0.x, g.f0.y, g.f0.z}) > 1e-3)
      notes.push_back("the coloured dielectric F0 is written as its mean (specular_ior)");
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

TargetBrdf target_model(Target t, const GgxSource& g, json* params_out, std::vector<std::string>* notes_out,
                        double blender_version) {
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
        // Dielectric: F0 = F0_from_ior(IOR) 2 level (closure.h, "Apply IOR adjustment"), exact Fresnel.
        const double eta = match_schlick(luminance_avg(g.f0), 1.0, false).eta;
        const double f0 = F_Conductor(1.0, eta, 0.0);
        // 3.4: F0 = 0.08 Specular (closure.h:317, 333-334), Specular in [0, 1].
        const double specular = std::clamp(luminance_avg(g.f0) / 0.08, 0.0, 1.0);
        m.diffuse = g.kd;
        p["Base Color"] = j3(g.kd), p["Metallic"] = 0.0, p["IOR"] = eta, p["Specular IOR Level"] = 0.5;
        p["Specular"] = specular;
        if (v1) {
          m.name = "Cycles 3.4 Principled BSDF v1, dielectric (exact Fresnel, separable Smith G) + Burley diffuse";
          m.lobe.fresnel = FresnelModel::CyclesV1;
          m.lobe.f0 = cycles_v1_cspec0(g.kd, 0.0, specular, 0.0);
          m.lobe.eta = glm::dvec3(cycles_v1_ior(specular));
          m.burley_roughness = rough;
          if (luminance_avg(g.f0) > 0.08)
            notes.push_back(
                fmt::format("Blender 3.4's Specular stops at 1 (F0 0.08); this F0 {:.4g} needs 4.x's IOR", luminance_avg(g.f0)));
          notes.push_back(
              "Blender 3.4: the Fresnel is the exact dielectric one at ior = 2 / (1 - sqrt(0.08 Specular)) - 1 "
              "(closure.h:317), the diffuse Burley's with retro-reflection at the same Roughness "
              "(bsdf_principled_diffuse.h:45-86), added to the specular");
        } else {
          m.name = "Cycles 4.x Principled BSDF, dielectric (exact Fresnel, height-correlated G) + Lambert";
          m.lobe.fresnel = FresnelModel::Dielectric;
          m.lobe.eta = glm::dvec3(eta);
          if (f0 > 0.08)
            notes.push_back(fmt::format("Blender 3.4's Specular stops at 1 (F0 0.08); this F0 {:.4g} needs 4.x's IOR", f0));
          notes.push_back(
              fmt::format("Schlick's F0 {:.4g} becomes the dielectric Fresnel of IOR {:.4g} closest to its "
                          "curve (F0 {:.4g})",
                          luminance_avg(g.f0), eta, f0));
          notes.push_back(
              "Cycles layers the diffuse under the specular (its weight times 1 - the specular albedo, "
              "closure_layering_weight); the target model adds them as aniso's GGX does");
        }
        if (max3(g.f0) - std::min({g.f0.x, g.f0.y, g.f0.z}) > 1e-3)
          notes.push_back("the coloured dielectric F0 is written as its mean (Specular IOR Level; 3.4: Specular)");
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
        const double eta = match_schlick(luminance_avg(g.f0), 1.0, false).eta;
        m.name = "MaterialX standard_surface, dielectric (exact Fresnel, G2 at the mean alpha) + Lambert";
        m.lobe.fresnel = FresnelModel::Dielectric;
        m.lobe.eta = glm::dvec3(eta);
        m.diffuse = g.kd;
        p["metalness"] = 0.0, p["base_color"] = j3(g.kd), p["specular_color"] = j3(glm::dvec3(1.0));
        p["specular_IOR"] = eta;
        notes.push_back(
            "standard_surface layers the diffuse under the specular (scaled by 1 - its albedo); the "
            "target model adds them");
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
          const auto [specular, color] = gltf_specular_for(g.f0);
          m.name = "glTF 2.0 dielectric_brdf (metallic 0) with KHR_materials_specular: Schlick F0 = 0.04 specularColor";
          m.lobe.f0 = gltf_dielectric_f0(specular, color);
          m.diffuse_times_one_minus_f = false, m.diffuse_times_one_minus_max_f = true;
          p["specularFactor"] = specular, p["specularColorFactor"] = j3(color);
          notes.push_back(fmt::format(
              "the source's dielectric F0 {} is not glTF's 0.04: written with KHR_materials_specular (specularColorFactor "
              "= F0 / 0.04); viewers without the extension show F0 = 0.04",
              fmt3(g.f0)));
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

// --- reports -----------------------------------------------------------------------------------------

json ExportReport::to_json() const {
  json j = {{"target", target},
            {"target_model", target_model},
            {"path", exact ? "exact" : "fitted"},
            {"origin", origin},
            {"parameters", parameters},
            {"error", {{"l2cos", errors.l2cos_all}, {"log", errors.log_all}, {"relative_l2cos", errors.relative_l2cos}}},
            {"max_albedo_difference",
             {{"value", max_albedo_difference}, {"theta_o_deg", albedo_theta_deg}, {"phi_o_deg", albedo_phi_deg}}},
            {"samples", samples},
            {"notes", notes}};
  if (!blender_version.empty()) j["blender_version"] = blender_version;  // --to blender only
  return j;
}

std::string ExportReport::text(std::string_view pre) const {
  std::string s;
  const auto line = [&](const std::string& l) { s += std::string(pre) + l + "\n"; };
  line(fmt::format("aniso export, target {}: {}", target, target_model));
  if (!blender_version.empty()) line(fmt::format("  the numbers below hold for {}", blender_version));
  line(fmt::format("  {}", origin));
  line(fmt::format("  parameters: {}", parameters.dump()));
  line(fmt::format("  error of the export against the source ({} samples): l2cos {:.4g} (relative {:.3g}), log {:.4g}", samples,
                   errors.l2cos_all, errors.relative_l2cos, errors.log_all));
  line(fmt::format("  largest directional-albedo difference: {:.4g} (theta_o {:g}, phi_o {:g} deg)", max_albedo_difference,
                   albedo_theta_deg, albedo_phi_deg));
  for (const std::string& n : notes) line("  note: " + n);
  return s;
}

// --- writers -----------------------------------------------------------------------------------------

namespace {

// The report as a comment of the written file, `pre` starting each line ("# " for Python and pbrt-v4,
// whose comments end at '\n' or '\r'; spaces inside an XML comment). The source's label (a file
// name, a scene object's name) and every other line go through text_escape: no line break, control
// byte or invalid UTF-8 from an input can end the comment, so no input text becomes code.
std::string comment_block(const ExportReport& r, const std::string& source, std::string_view pre) {
  const std::string raw = "Exported by aniso " ANISO_VERSION " from " + text_escape(source) + "\n" + r.text("");
  std::string s;
  for (size_t i = 0, j; i < raw.size(); i = j + 1) {
    j = raw.find('\n', i);
    if (j == std::string::npos) j = raw.size();
    s += std::string(pre) + text_escape(std::string_view(raw).substr(i, j - i)) + "\n";
  }
  return s;
}

double num(const json& p, const char* k) { return p.at(k).get<double>(); }
glm::dvec3 col(const json& p, const char* k) {
  const json& a = p.at(k);
  return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}

std::string write_blender(const std::string& name, const json& p, const std::string& comment) {
  const glm::dvec3 base = col(p, "Base Color");
  const bool metallic = num(p, "Metallic") > 0.5;
  std::string s = comment;
  s += "#\n# Builds the material for Blender 3.4 and 4.x (Principled BSDF input names differ: checked by\n"
       "# bpy.app.version), assigns it to the active object if there is one, and takes the tangent from\n"
       "# that object's active UV map (dp/du) when it has one.\n";
  s += "import bpy\n\n";
  s += fmt::format("NAME = {}\n", py_string(name));
  s += "V4 = bpy.app.version >= (4, 0, 0)\n\n";
  s += "mat = bpy.data.materials.get(NAME) or bpy.data.materials.new(NAME)\n"
       "mat.use_nodes = True\n"
       "nodes, links = mat.node_tree.nodes, mat.node_tree.links\n"
       "nodes.clear()\n"
       "out = nodes.new(\"ShaderNodeOutputMaterial\")\n"
       "out.location = (300, 0)\n"
       "bsdf = nodes.new(\"ShaderNodeBsdfPrincipled\")\n"
       "bsdf.distribution = \"GGX\"  # single-scattering GGX, as the target model (not MULTI_GGX)\n"
       "links.new(bsdf.outputs[\"BSDF\"], out.inputs[\"Surface\"])\n\n"
       "def put(name, value):\n"
       "    if name not in bsdf.inputs:\n"
       "        raise KeyError(\"%s of Blender %s has no input %r\" % (bsdf.bl_idname, bpy.app.version_string, name))\n"
       "    bsdf.inputs[name].default_value = value\n\n";
  s += fmt::format("put(\"Base Color\", ({:.9g}, {:.9g}, {:.9g}, 1.0))\n", base.x, base.y, base.z);
  s += fmt::format("put(\"Metallic\", {:.9g})\n", num(p, "Metallic"));
  s += fmt::format("put(\"Roughness\", {:.9g})\n", num(p, "Roughness"));
  s += fmt::format("put(\"Anisotropic\", {:.9g})\n", num(p, "Anisotropic"));
  s += fmt::format("put(\"Anisotropic Rotation\", {:.9g})\n", num(p, "Anisotropic Rotation"));
  s += "if V4:\n";
  if (metallic) {
    const glm::dvec3 t = col(p, "Specular Tint");
    s += fmt::format("    put(\"Specular Tint\", ({:.9g}, {:.9g}, {:.9g}, 1.0))  # the F82 edge tint\n", t.x, t.y, t.z);
  } else {
    s += fmt::format("    put(\"IOR\", {:.9g})\n    put(\"Specular IOR Level\", {:.9g})\n", num(p, "IOR"),
                     num(p, "Specular IOR Level"));
  }
  s += "else:\n";
  if (metallic)
    s += fmt::format(
        "    put(\"Specular\", {:.9g})  # 3.4: the ior of the Fresnel curve's shape (no edge tint: Specular Tint is a float)\n",
        num(p, "Specular"));
  else
    s += fmt::format("    put(\"Specular\", {:.9g})  # F0 = 0.08 Specular\n", num(p, "Specular"));
  if (p.contains("Extinction")) {
    // Blender 4.3+: the Metallic BSDF (node_shader_bsdf_metallic.cc: IOR and Extinction are
    // vectors, Anisotropy and Rotation as the Principled BSDF's) replaces the Principled one.
    const glm::dvec3 n = col(p, "IOR"), k = col(p, "Extinction");
    s += "\nif bpy.app.version >= (4, 3, 0):  # the physical conductor: n, k themselves\n"
         "    nodes.remove(bsdf)\n"
         "    bsdf = nodes.new(\"ShaderNodeBsdfMetallic\")\n"
         "    bsdf.distribution = \"GGX\"\n"
         "    bsdf.fresnel_type = \"PHYSICAL_CONDUCTOR\"\n"
         "    links.new(bsdf.outputs[\"BSDF\"], out.inputs[\"Surface\"])\n";
    s += fmt::format("    put(\"IOR\", ({:.9g}, {:.9g}, {:.9g}))\n", n.x, n.y, n.z);
    s += fmt::format("    put(\"Extinction\", ({:.9g}, {:.9g}, {:.9g}))\n", k.x, k.y, k.z);
    s += fmt::format("    put(\"Roughness\", {:.9g})\n", num(p, "Roughness"));
    s += fmt::format("    put(\"Anisotropy\", {:.9g})\n", num(p, "Anisotropic"));
    s += fmt::format("    put(\"Rotation\", {:.9g})\n", num(p, "Anisotropic Rotation"));
  }
  s += "\nobj = bpy.context.view_layer.objects.active\n"
       "if obj is not None and obj.type == \"MESH\":\n"
       "    uv = obj.data.uv_layers.active\n"
       "    if uv is not None:\n"
       "        tangent = nodes.new(\"ShaderNodeTangent\")\n"
       "        tangent.location = (-300, -300)\n"
       "        tangent.direction_type = \"UV_MAP\"\n"
       "        tangent.uv_map = uv.name\n"
       "        links.new(tangent.outputs[\"Tangent\"], bsdf.inputs[\"Tangent\"])\n"
       "    if obj.data.materials:\n"
       "        obj.data.materials[0] = mat\n"
       "    else:\n"
       "        obj.data.materials.append(mat)\n";
  return s;
}

std::string write_mitsuba(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = xml_escape(identifier(name));
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

std::string pbrt_conductor(const json& p) {
  std::string s = "    \"string type\" \"conductor\"\n";
  if (p.contains("reflectance"))
    s += fmt::format("    \"rgb reflectance\" [ {} ]\n", fmt3(col(p, "reflectance"), " "));
  else if (p["eta"].is_string())
    s += fmt::format("    \"spectrum eta\" \"{}\"\n    \"spectrum k\" \"{}\"\n", p["eta"].get<std::string>(),
                     p["k"].get<std::string>());
  else
    s += fmt::format("    \"rgb eta\" [ {} ]\n    \"rgb k\" [ {} ]\n", fmt3(col(p, "eta"), " "), fmt3(col(p, "k"), " "));
  s += fmt::format("    \"float uroughness\" {:.9g}\n    \"float vroughness\" {:.9g}\n    \"bool remaproughness\" false\n",
                   num(p, "uroughness"), num(p, "vroughness"));
  return s;
}

std::string write_pbrt(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = identifier(name);
  std::string s = comment + "\n";
  if (p.contains("amount")) {
    s += fmt::format("MakeNamedMaterial \"{}-diffuse\"\n    \"string type\" \"diffuse\"\n    \"rgb reflectance\" [ {} ]\n", id,
                     fmt3(col(p, "diffuse_reflectance"), " "));
    s += fmt::format("MakeNamedMaterial \"{}-specular\"\n", id) + pbrt_conductor(p);
    // materials.h:285-293: amount is the probability of materials[1].
    s += fmt::format(
        "MakeNamedMaterial \"{}\"\n    \"string type\" \"mix\"\n    \"string materials\" [ \"{}-diffuse\" "
        "\"{}-specular\" ]\n    \"float amount\" {:.9g}\n",
        id, id, id, num(p, "amount"));
  } else {
    s += fmt::format("MakeNamedMaterial \"{}\"\n", id) + pbrt_conductor(p);
  }
  return s;
}

// A MaterialX element name: letters, digits, '_' and ':' only (MaterialX source/MaterialXCore/
// Util.cpp:25-28, invalidNameChar, which Element::validate checks), the rest replaced by '_' as
// createValidName does.
std::string materialx_name(std::string_view s) {
  std::string o(s.empty() ? std::string_view("material") : s);
  for (char& c : o)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != ':') c = '_';
  return o;
}

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

}  // namespace

void write_preview(const std::string& path, const MaterialD& source, const TargetBrdf& target, const std::string& left,
                   const std::string& right, int size) {
  const int label = size / 8, w = 2 * size, h = size + label;
  render::Image img(w, size);
  const glm::dvec3 lights[2] = {glm::normalize(glm::dvec3(-0.5, 0.6, 1.0)), glm::normalize(glm::dvec3(0.7, -0.3, 0.8))};
  const double power[2] = {2.5, 1.0};
  for (int side = 0; side < 2; ++side)
    for (int py = 0; py < size; ++py)
      for (int px = 0; px < size; ++px) {
        const double x = (px + 0.5) / size * 2.0 - 1.0, y = 1.0 - (py + 0.5) / size * 2.0, r2 = x * x + y * y;
        if (r2 >= 1.0) continue;
        const glm::dvec3 n(x, y, std::sqrt(1.0 - r2));
        const glm::dvec3 t = glm::normalize(glm::dvec3(n.z, 0.0, -n.x)), b = glm::cross(n, t);
        const auto local = [&](const glm::dvec3& v) { return Vec3d(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); };
        const Vec3d wo = local(glm::dvec3(0.0, 0.0, 1.0));
        glm::dvec3 c(0.0);
        for (int l = 0; l < 2; ++l) {
          const Vec3d wi = local(lights[l]);
          if (!(wi.z > 0.0) || !(wo.z > 0.0)) continue;
          glm::dvec3 f;
          if (side == 0) {
            const RGBT<double> s = source.f(wi, wo);
            f = glm::dvec3(s.x, s.y, s.z);
          } else {
            f = target.f(wi, wo);
          }
          c += f * wi.z * power[l];
        }
        img.set(side * size + px, py, RGB(float(c.x), float(c.y), float(c.z)));
      }
  if (!path.ends_with(".png")) {
    // .pfm / .exr: the linear radiance of both spheres, without labels (the Blender check of
    // tests/blender_export_render.py compares it with Cycles' rendering, pixel by pixel).
    render::write_image(path, img);
    return;
  }
  const render::DisplayImage shaded = render::tonemap(img, {});
  render::DisplayImage out(w, h, 255);
  render::blit(out, shaded, 0, 0);
  const float ph = float(label) * 0.55f;
  render::draw_text(out, 6, size + label / 5, left, ph, {0, 0, 0});
  render::draw_text(out, size + 6, size + label / 5, right, ph, {0, 0, 0});
  render::write_png(path, out);
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

// The fitted path, last step: the target's own model (its masking, its Fresnel) against the source,
// over the roughness and the colours. The GGX fit is aniso's (height-correlated Smith, Schlick,
// Lambert); the target model differs (Mitsuba 3's separable G, MaterialX's G2 at the mean alpha,
// exact Fresnel curves, Blender 3.4's Burley diffuse and interpolated Fresnel), so the alphas are
// searched again with the written model itself: factors 0.6 to 1.5 on each alpha (a 9 x 9 log grid,
// then 7 x 7 around the best), on at most o.refine_samples of the samples, in the chosen metric. At
// each alpha pair the colours (kd and F0 of the Schlick GGX, per channel, which every target writes
// as its diffuse colour and its F0 / specular / base colour) are re-solved by weighted least squares
// in the target model (relinearise), and kept when that lowers the error.
GgxSource refine_for_target(Target t, const GgxSource& g, const SampleSet& all, const ExportOptions& o) {
  SampleSet data;
  const size_t stride = std::max<size_t>(1, all.samples.size() / size_t(std::max(o.refine_samples, 100)));
  for (size_t i = 0; i < all.samples.size(); i += stride) data.samples.push_back(all.samples[i]);
  const auto model = [&](const GgxSource& x) { return target_model(t, x, nullptr, nullptr, o.blender_version); };
  const auto error = [&](const GgxSource& x) { return metric_of(target_errors(model(x), data), o.metric); };
  // The other metric, which a re-solve of the colours may not raise: the report gives both, and a
  // change that trades one for the other is not an improvement.
  const FitMetric other = o.metric == FitMetric::L2Cos ? FitMetric::Log : FitMetric::L2Cos;
  // The colours a conductor does not have (its eta, k are the source's); a source without a diffuse
  // part keeps none (a diffuse colour would change what the target writes: a metal becomes a
  // dielectric), one with a diffuse part keeps some (kd >= 1e-5, above no_diffuse's 1e-6).
  const bool has_kd = !no_diffuse(g);
  std::vector<int> vars;  // 0..2 kd, 3..5 f0
  if (!g.conductor)
    for (int v = has_kd ? 0 : 3; v < 6; ++v) vars.push_back(v);
  const auto get = [](GgxSource& x, int v) -> double& { return v < 3 ? x.kd[v] : x.f0[v - 3]; };
  const size_t n_s = data.samples.size();
  std::vector<glm::dvec3> f0v(n_s), f1v(n_s);
  const auto eval_all = [&](const GgxSource& x, std::vector<glm::dvec3>& out) {
    const TargetBrdf m = model(x);
    for (size_t i = 0; i < n_s; ++i) out[i] = m.f(data.samples[i].wi, data.samples[i].wo);
  };
  // One Gauss-Newton step on the l2cos residuals (f - v) cos_i, weight w, over the colours, with
  // forward-difference columns: exact for the targets whose model is affine in them (the diffuse
  // colour everywhere; Schlick, F82-tint and 3.4's interpolated Fresnel in F0), a linearisation for
  // the others (an exact Fresnel fitted to Schlick's curve). Clamped to [0, 1] (kd >= 1e-5 where the
  // source has one); returns x unchanged when the step does not lower the error.
  const auto relinearise = [&](const GgxSource& x, double ex) {
    if (vars.empty()) return std::pair{x, ex};
    const int n = int(vars.size());
    eval_all(x, f0v);
    std::vector<std::vector<glm::dvec3>> J(n, std::vector<glm::dvec3>(n_s));
    for (int j = 0; j < n; ++j) {
      GgxSource y = x;
      double& v = get(y, vars[j]);
      const double h = v > 0.5 ? -1e-4 : 1e-4;
      v += h;
      eval_all(y, f1v);
      for (size_t i = 0; i < n_s; ++i) J[j][i] = (f1v[i] - f0v[i]) / h;
    }
    double A[6][6] = {}, b[6] = {};
    for (size_t i = 0; i < n_s; ++i) {
      const MeasuredSample& sm = data.samples[i];
      const double c2w = sm.weight * sm.wi.z * sm.wi.z;
      const glm::dvec3 r = sm.value - f0v[i];
      for (int j = 0; j < n; ++j) {
        b[j] += c2w * glm::dot(J[j][i], r);
        for (int k = j; k < n; ++k) A[j][k] += c2w * glm::dot(J[j][i], J[k][i]);
      }
    }
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < j; ++k) A[j][k] = A[k][j];
    // Gaussian elimination with partial pivoting; a singular system (a colour the target ignores,
    // such as the F0 channels a grey IOR averages) gets a small ridge first.
    double trace = 0.0;
    for (int j = 0; j < n; ++j) trace += A[j][j];
    for (int j = 0; j < n; ++j) A[j][j] += 1e-9 * trace / n + 1e-300;
    double d[6];
    for (int j = 0; j < n; ++j) d[j] = b[j];
    for (int c = 0; c < n; ++c) {
      int piv = c;
      for (int r = c + 1; r < n; ++r)
        if (std::abs(A[r][c]) > std::abs(A[piv][c])) piv = r;
      std::swap(A[c], A[piv]), std::swap(d[c], d[piv]);
      if (!(std::abs(A[c][c]) > 0.0)) return std::pair{x, ex};
      for (int r = c + 1; r < n; ++r) {
        const double f = A[r][c] / A[c][c];
        for (int k = c; k < n; ++k) A[r][k] -= f * A[c][k];
        d[r] -= f * d[c];
      }
    }
    for (int c = n - 1; c >= 0; --c) {
      for (int k = c + 1; k < n; ++k) d[c] -= A[c][k] * d[k];
      d[c] /= A[c][c];
    }
    GgxSource y = x;
    for (int j = 0; j < n; ++j) {
      double& v = get(y, vars[j]);
      v = std::clamp(v + d[j], vars[j] < 3 ? 1e-5 : 0.0, 1.0);
      if (!std::isfinite(v)) return std::pair{x, ex};
    }
    const FitErrors fy = target_errors(model(y), data);
    if (metric_of(fy, o.metric) < ex && metric_of(fy, other) <= metric_of(target_errors(model(x), data), other))
      return std::pair{y, metric_of(fy, o.metric)};
    return std::pair{x, ex};
  };
  // The alpha search, with the colours re-solved at each pair or (colours = false) kept.
  const auto search = [&](bool colours) {
    const auto err = [&](double fx, double fy, GgxSource& out) {
      out = g;
      out.alpha_x = std::clamp(g.alpha_x * fx, 1e-3, 1.0), out.alpha_y = std::clamp(g.alpha_y * fy, 1e-3, 1.0);
      if (!colours) return error(out);
      auto [y, e] = relinearise(out, error(out));
      out = y;
      return e;
    };
    GgxSource best = g, trial;
    double best_err = err(1.0, 1.0, trial), bx = 0.0, by = 0.0;
    best = trial;
    const double lo = std::log(0.6), hi = std::log(1.5);
    constexpr int n = 9;
    const double step = (hi - lo) / (n - 1);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = lo + i * step, y = lo + j * step, e = err(std::exp(x), std::exp(y), trial);
        if (e < best_err) best_err = e, best = trial, bx = x, by = y;
      }
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j) {
        const double e = err(std::exp(bx + i * step / 3), std::exp(by + j * step / 3), trial);
        if (e < best_err) best_err = e, best = trial;
      }
    // A second step at the best alphas (the linearisation of an exact Fresnel).
    return colours ? relinearise(best, best_err).first : best;
  };
  // Kept only if better on every sample, not just on the subset searched: the alphas alone when
  // they lower the chosen metric, the colours too when that is no worse in either metric.
  const auto full = [&](const GgxSource& x) { return target_errors(model(x), all); };
  const FitErrors e_g = full(g);
  const GgxSource alphas = search(false);
  const FitErrors e_a = full(alphas);
  const bool alphas_better = metric_of(e_a, o.metric) < metric_of(e_g, o.metric);
  const GgxSource& base = alphas_better ? alphas : g;
  const FitErrors& e_base = alphas_better ? e_a : e_g;
  if (vars.empty()) return base;
  const GgxSource both = search(true);
  const FitErrors e_b = full(both);
  const bool both_better =
      metric_of(e_b, o.metric) < metric_of(e_base, o.metric) && metric_of(e_b, other) <= metric_of(e_base, other);
  return both_better ? both : base;
}

namespace {

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

}  // namespace

void check_export_options(const ExportOptions& o) {
  if (!find_target(o.target))
    throw InputError(fmt::format("--to: unknown target \"{}\"; the targets are {}", o.target, target_names()));
  if (o.grid < kExportGridMin || o.grid > kExportGridMax)
    throw InputError(fmt::format("grid: expected {} to {}, got {}", kExportGridMin, kExportGridMax, o.grid));
  if (o.starts < 1 || o.starts > kExportStartsMax)
    throw InputError(fmt::format("starts: expected 1 to {}, got {}", kExportStartsMax, o.starts));
  if (!(o.blender_version >= kBlenderVersionMin && o.blender_version <= kBlenderVersionMax))
    throw InputError(
        fmt::format("blender_version: expected {} to {}, got {}", kBlenderVersionMin, kBlenderVersionMax, o.blender_version));
  if (!std::isfinite(o.tangent_angle_deg))
    throw InputError(fmt::format("tangent_angle_deg: expected a finite angle in degrees, got {}", o.tangent_angle_deg));
  if (const std::optional<size_t> bad = first_invalid_utf8(o.name))
    throw InputError(fmt::format("name: expected UTF-8 text, got the byte 0x{:02x} at offset {} in \"{}\"",
                                 static_cast<unsigned char>(o.name[*bad]), *bad, text_escape(o.name)));
}

ExportResult export_material(const MaterialDesc& desc, const std::string& source_label, const ExportOptions& o,
                             const std::string& bin_name_in) {
  check_export_options(o);
  const TargetInfo* info = find_target(o.target);
  const MaterialDesc plain = unrotated(desc);
  const MaterialD source = build_material<double>(plain);
  ExportResult res;
  const SampleSet samples = sample_source(source, o.grid);
  res.ggx = ggx_source(desc, samples, o);
  res.ggx.rotation_deg += o.tangent_angle_deg;  // the surface's turn composed with the material's
  json params;
  std::vector<std::string> notes, notes_before;
  if (!res.ggx.exact) {
    const GgxSource refined = refine_for_target(info->target, res.ggx, samples, o);
    if (refined.alpha_x != res.ggx.alpha_x || refined.alpha_y != res.ggx.alpha_y)
      notes_before.push_back(fmt::format("alphas refined with the target model: {:.4g} x {:.4g} (the GGX fit's {:.4g} x {:.4g})",
                                         refined.alpha_x, refined.alpha_y, res.ggx.alpha_x, res.ggx.alpha_y));
    if (refined.kd != res.ggx.kd || refined.f0 != res.ggx.f0)
      notes_before.push_back(fmt::format("colours re-solved in the target model: kd {} (the GGX fit's {}), F0 {} (the fit's {})",
                                         fmt3(refined.kd), fmt3(res.ggx.kd), fmt3(refined.f0), fmt3(res.ggx.f0)));
    res.ggx = refined;
  }
  res.model = target_model(info->target, res.ggx, &params, &notes, o.blender_version);
  std::string mitsuba_origin;
  if (info->target == Target::Mitsuba3 && source.kind == ModelKind::Principled) {
    // The same model: the parameters carry over (principled_differences says what still differs).
    const MitsubaPrincipled mp = principled_params(source.principled);
    notes = principled_differences(mp);
    notes_before.clear();  // the GGX path's refinement: not what is written
    res.model = mitsuba_principled_model(mp, 0.0, rotation_of(desc) + o.tangent_angle_deg, params, notes);
    mitsuba_origin = "exact: the source is aniso's principled; Mitsuba 3's principled takes the same parameters";
  } else if (info->target == Target::Mitsuba3 && !res.ggx.conductor && !no_diffuse(res.ggx)) {
    // A GGX with a diffuse part: Mitsuba 3's principled (metallic 0, base_color kd, specular from
    // F0 = 0.08 specular) beside the blendbsdf; the one closer to the source's samples in the
    // chosen metric is written.
    MitsubaPrincipled mp;
    mp.base_color = glm::clamp(res.ggx.kd, 0.0, 1.0);
    mp.metallic = 0.0;
    mp.specular = std::clamp(luminance_avg(res.ggx.f0) / 0.08, 0.0, 12.0);  // eta finite: 0.08 specular < 1
    double ax = res.ggx.alpha_x, ay = res.ggx.alpha_y;
    std::vector<std::string> pnotes;
    const RoughAniso ra = invert_aspect(ax, ay, 0.9, 1.0, "Mitsuba 3's principled", pnotes);
    mp.roughness = ra.rough, mp.anisotropic = ra.aniso;
    json pparams;
    const TargetBrdf principled = mitsuba_principled_model(mp, ra.extra, res.ggx.rotation_deg, pparams, pnotes);
    const double e_blend = metric_of(target_errors(res.model, samples), o.metric);
    const double e_principled = metric_of(target_errors(principled, samples), o.metric);
    const std::string which = fmt::format("{} error: principled {:.4g}, blendbsdf {:.4g}",
                                          o.metric == FitMetric::L2Cos ? "l2cos" : "log", e_principled, e_blend);
    if (e_principled < e_blend) {
      res.model = principled, params = pparams, notes = pnotes;
      notes.push_back(fmt::format("principled written: it is closer to the source than the blendbsdf ({})", which));
      notes.push_back(
          "the principled's diffuse is Burley's (retro-reflection, Schlick darkening at grazing), its specular "
          "the exact dielectric Fresnel at eta = 2 / (1 - sqrt(0.08 specular)) - 1 for the source's Schlick "
          "F0 (grey: the mean of the source's)");
    } else {
      notes.push_back(fmt::format("blendbsdf written: it is closer to the source than the principled ({})", which));
    }
  }
  ExportReport& r = res.report;
  r.target = std::string(info->name);
  r.target_model = res.model.name;
  r.exact = res.ggx.exact || !mitsuba_origin.empty();
  r.origin = mitsuba_origin.empty() ? res.ggx.origin : mitsuba_origin;
  r.parameters = params;
  r.notes = notes;
  r.notes.insert(r.notes.end(), notes_before.begin(), notes_before.end());
  r.notes.insert(r.notes.end(), o.extra_notes.begin(), o.extra_notes.end());
  if (o.tangent_angle_deg != 0.0)
    r.notes.push_back(
        fmt::format("the surface's tangent angle {:.9g} degrees composed with the material's rotation_deg {:.9g}: {:.9g} degrees "
                    "carried to the target's orientation",
                    o.tangent_angle_deg, rotation_of(desc), rotation_of(desc) + o.tangent_angle_deg));
  else if (res.ggx.exact && (res.ggx.rotation_deg != 0.0))
    r.notes.push_back(fmt::format("rotation_deg {:.9g} carried to the target's orientation", res.ggx.rotation_deg));
  r.errors = target_errors(res.model, samples);
  if (info->target == Target::Blender) {
    // The numbers hold for one Blender (o.blender_version); the script builds a different model in
    // the others: their errors too, for the same written values.
    const bool cond = res.ggx.conductor;
    const auto span = [cond](double v) {
      return v < 3.5   ? std::string("Blender 3.4 (Principled BSDF v1)")
             : !cond   ? std::string("Blender 4.x (Principled BSDF)")
             : v < 4.3 ? std::string("Blender 4.0 to 4.2 (Principled BSDF)")
                       : std::string("Blender 4.3 and later (Metallic BSDF)");
    };
    r.blender_version = span(o.blender_version);
    std::vector<double> others;
    if (o.blender_version >= 3.5) others.push_back(3.4);
    if (o.blender_version < 3.5 || (cond && o.blender_version >= 4.3)) others.push_back(4.0);
    if (cond && o.blender_version < 4.3) others.push_back(4.3);
    for (const double v : others) {
      const TargetBrdf other = target_model(Target::Blender, res.ggx, nullptr, nullptr, v);
      const FitErrors e = target_errors(other, samples);
      r.notes.push_back(fmt::format("{}: {}: l2cos {:.4g} (relative {:.3g}), log {:.4g}", span(v), other.name, e.l2cos_all,
                                    e.relative_l2cos, e.log_all));
    }
  }
  r.samples = samples.samples.size();
  r.max_albedo_difference = max_albedo_difference(source, res.model, &r.albedo_theta_deg, &r.albedo_phi_deg);
  std::string name = o.name;
  if (name.empty()) {
    name = source_label;
    const size_t slash = name.find_last_of('/');
    if (name.size() > 0 && name.front() != '{' && slash != std::string::npos && name.find(".json") != std::string::npos)
      name = name.substr(slash + 1);
    if (name.size() > 5 && name.ends_with(".json")) name.resize(name.size() - 5);
    if (name.empty() || name.front() == '{') name = "aniso-" + desc.model;
    name = text_escape(name);  // a file name need not be UTF-8; the written name is
  }
  switch (info->target) {
    case Target::Blender: res.files.push_back({"", write_blender(name, params, comment_block(r, source_label, "# "))}); break;
    case Target::Mitsuba3: res.files.push_back({"", write_mitsuba(name, params, comment_block(r, source_label, "  "))}); break;
    case Target::PbrtV4: res.files.push_back({"", write_pbrt(name, params, comment_block(r, source_label, "# "))}); break;
    case Target::MaterialX:
      res.files.push_back({"", write_materialx(name, params, comment_block(r, source_label, "    "))});
      break;
    case Target::OpenPbr: res.files.push_back({"", write_openpbr(name, params, comment_block(r, source_label, "    "))}); break;
    case Target::Gltf: {
      const std::string bin_name = bin_name_in.empty() ? identifier(name) + ".bin" : bin_name_in;
      write_gltf(name, params, r, source_label, bin_name, res.files);
      break;
    }
  }
  return res;
}

}  // namespace aniso::exporter
