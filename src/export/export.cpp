// export/export.cpp: see export.h; the conventions of each target are in targets.h, with the
// source lines they come from, and in docs/export.md. This file holds the target table and the
// driver, export_material; its steps are ggx_source.cpp (source -> GGX), refine.cpp (the fitted
// path's refinement), target_models.cpp (GGX -> each target), report.cpp and preview.cpp, and one
// writer per target (writers.h).
#include "aniso/export/export.h"
#include "aniso/version.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>

#include <fmt/format.h>

#include "aniso/io/input_error.h"
#include "export/common.h"
#include "export/writers.h"
#include "io/text_escape.h"

namespace aniso::exporter {

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
