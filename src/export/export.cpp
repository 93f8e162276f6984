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
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "aniso/io/input_error.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
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
     "Color to white, Burley diffuse) has no edge tint: its Specular sets the curve's shape. Dielectrics: Base Color "
     "= the diffuse, 4.x: IOR and a colour Specular Tint for the F0; 3.4: Specular and Specular Tint, or, where one "
     "node cannot write the F0's colour and the pair is the better choice, a diffuse and a metallic Principled BSDF "
     "joined by an Add Shader. The report measures --blender-version (default 4.3) and gives the other versions' "
     "errors in its notes."},
    {Target::Mitsuba3, "mitsuba3", ".xml",
     "Mitsuba 3 roughconductor (GGX), principled, or blendbsdf of diffuse and roughconductor",
     "Writes a <scene version=\"3.0.0\"> holding one <bsdf> with id = the material name: a roughconductor with "
     "distribution ggx, alpha_u / alpha_v as aniso's alpha_x / alpha_y, and a named material (Ag, Al, Au, Cr, Cu, W) "
     "or rgb eta / k; an aniso principled material as Mitsuba's principled (the same parameters); with a diffuse "
     "part, a principled or a blendbsdf of a diffuse and a roughconductor, whichever is closer to the source in the fit's "
     "error and the image check's colour (the principled's F0 is grey; the report gives both errors and both "
     "chromaticities). Use it with <include "
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
     "matched to the source's n, k; dielectrics: base_color = the diffuse albedo, specular_IOR from F0 and "
     "specular_color its hue (F0 / its largest channel). The tangent is "
     "the geometry's Tworld rotated by specular_rotation (a fraction of a turn)."},
    {Target::OpenPbr, "openpbr", ".mtlx",
     "OpenPBR Surface (MaterialX open_pbr_surface, 1.39): F82-tint metals, tangent from the geometry",
     "Writes a MaterialX 1.39 document with an open_pbr_surface shader and a surfacematerial. Metals: base_metalness 1, "
     "base_color = F0 and specular_color = the F82 edge tint matching the source's reflectance at cos = 1/7; "
     "dielectrics: base_color = the diffuse albedo (Lambert: base_diffuse_roughness 0), specular_ior from F0 and "
     "specular_color its hue (F0 / its largest channel). "
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
  if (o.measured_grid != 0 && (o.measured_grid < 4 || o.measured_grid > 256 || o.measured_grid % 2 != 0))
    throw InputError(
        fmt::format("measured_grid: expected 0 (the defaults) or an even number from 4 to 256, got {}", o.measured_grid));
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

bool writes_measured(Target t, const MaterialDesc& desc, const ExportOptions& o) {
  return (t == Target::Mitsuba3 || t == Target::PbrtV4) && !o.analytic && (desc.rgl || desc.measured);
}

std::string measured_file_name(Target t, const std::string& main_stem) {
  if (t != Target::Mitsuba3 && t != Target::PbrtV4) return "";
  std::string out;
  for (const char c : main_stem) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    out += keep ? c : '_';
  }
  if (out.empty()) out = "material";
  return out + (t == Target::Mitsuba3 ? "_rgb.bsdf" : "_spec.bsdf");
}

std::string measured_file_name_for_path(Target t, const std::string& main_path) {
  return measured_file_name(t, std::filesystem::path(main_path).stem().string());
}

namespace {

// The material's name in the file: --name, else the scene object's, else the source's: a preset's
// name, a file's stem (its name without the folder and the material file's extension: .json, an RGL
// tensor file's .bsdf, a MERL table's .binary, in any case), "aniso-MODEL" for inline JSON.
std::string material_name(const MaterialDesc& desc, const std::string& source_label, const ExportOptions& o) {
  std::string name = o.name;
  if (name.empty()) {
    name = source_label;
    if (name.empty() || name.front() == '{') name = "aniso-" + desc.model;
    if (const size_t slash = name.find_last_of('/'); slash != std::string::npos) name = name.substr(slash + 1);
    std::string lower = name;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const std::string_view ext : {".json", ".bsdf", ".binary"})
      if (name.size() > ext.size() && lower.ends_with(ext)) {
        name.resize(name.size() - ext.size());
        break;
      }
    if (name.empty()) name = "aniso-" + desc.model;
    name = text_escape(name);  // a file name need not be UTF-8; the written name is
  }
  return name;
}

// A measured source to Mitsuba 3 or pbrt-v4: the renderer's own measured BSDF with the tensor file
// beside the scene (writes_measured). The tensor is export-rgl's (src/rgl): a tensor-file source
// from its own tables (transcode_tensor; its isotropy kept by decide_isotropy), RGB for Mitsuba 3's
// RGB variants, spectral (box spectra that reduce back to the file's RGB) for pbrt-v4; a MERL table
// resampled. The target model is the written file read back as pbrt-v4 reads it.
void export_measured(const TargetInfo& info, const MaterialDesc& desc, const MaterialD& source, const SampleSet& samples,
                     const std::string& source_label, const ExportOptions& o, const std::string& side_name, ExportResult& res) {
  rgl::ExportOptions ro;
  ro.spectral = info.target == Target::PbrtV4;
  rgl::BrdfSource src = rgl::brdf_source(source);
  src.tensor = desc.rgl;
  src.description =
      fmt::format("{} (written by aniso {} export --to {})",
                  resolved_json(desc).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), ANISO_VERSION, info.name);
  rgl::ExportReport rep;
  const std::vector<rgl::TensorField> fields = rgl::export_rgl(src, ro, &rep);
  const std::vector<uint8_t> bytes = rgl::serialize_tensor(fields);
  const std::shared_ptr<const rgl::RglData> back = rgl::rgl_from_tensor(rgl::parse_tensor(bytes, side_name));
  const RglT<double> kernel = rgl::rgl_kernel<double>(*back);
  res.model = TargetBrdf{};
  res.model.name = info.target == Target::Mitsuba3 ? "Mitsuba 3 measured (the RGL tensor file beside the scene, rgb)"
                                                   : "pbrt-v4 measured (the RGL tensor file beside the scene, spectral)";
  res.model.measured = [back, kernel](const Vec3d& wi, const Vec3d& wo) {
    const RGBT<double> f = kernel.f(wi, wo);
    return glm::dvec3(f.x, f.y, f.z);
  };
  json params = {
      {"filename", side_name}, {"form", ro.spectral ? "spectral" : "rgb"}, {"isotropic", rep.isotropic}, {"bytes", bytes.size()}};
  ExportReport& r = res.report;
  r.target = std::string(info.name);
  r.target_model = res.model.name;
  r.exact = rep.transcoded;
  r.origin = rep.transcoded
                 ? fmt::format("exact: the source's own tables, {} ({})", ro.spectral ? "as spectra" : "as rgb", rep.isotropy)
                 : fmt::format("resampled: the source written as an RGL tensor file ({}; D: {})", rep.isotropy, rep.d_method);
  r.parameters = params;
  r.measured_file = side_name;
  r.notes.push_back(
      fmt::format("the renderer's own measured BSDF: write {} beside the scene file (it is named relative to it); `aniso export "
                  "--analytic` writes the fitted analytic material instead",
                  side_name));
  if (info.target == Target::Mitsuba3)
    r.notes.push_back(
        "an rgb tensor file: Mitsuba 3's RGB variants read it (scalar_rgb, llvm_ad_rgb, ...); a spectral variant needs "
        "the spectral form (`aniso export-rgl --spectral`, measured.cpp:102-116)");
  else
    r.notes.push_back(fmt::format("spectra: {}", rep.spectra));
  r.notes.insert(r.notes.end(), o.extra_notes.begin(), o.extra_notes.end());
  if (rotation_of(desc) + o.tangent_angle_deg != 0.0)
    r.notes.push_back(fmt::format("the tensor file has no rotation input: turn the uv parameterisation by {:.9g} degrees",
                                  rotation_of(desc) + o.tangent_angle_deg));
  r.errors = target_errors(res.model, samples);
  r.samples = samples.samples.size();
  r.max_albedo_difference = max_albedo_difference(source, res.model, &r.albedo_theta_deg, &r.albedo_phi_deg);
  if (o.check_size > 0) r.image = image_check(source, res.model, o.check_size);
  const std::string name = material_name(desc, source_label, o);
  if (info.target == Target::Mitsuba3)
    res.files.push_back({"", write_mitsuba(name, params, comment_block(r, source_label, "  "))});
  else
    res.files.push_back({"", write_pbrt(name, params, comment_block(r, source_label, "# "))});
  res.files.push_back({side_name, std::string(bytes.begin(), bytes.end())});
}

// The colour clauses of the rule for one BSDF against a pair (kExportColourOff, export.h): whether
// the pair (error e2, image check c2) is to be written over the single BSDF (error e1, image check
// c1) for its colour although its error is not lower.
bool pair_wins_on_colour(double e1, const ImageCheck& c1, double e2, const ImageCheck& c2) {
  const double k1 = c1.chromaticity_difference;
  const bool closer_in_colour = c2.chromaticity_difference <= k1 - kExportChromaticityGain;
  const bool within_check = c2.mean_difference <= std::max(kCheckWarnMean, c1.mean_difference) &&
                            c2.lit_difference <= std::max(kCheckWarnLit, c1.lit_difference);
  return closer_in_colour && within_check && (e2 <= kExportColourErrorRatio * e1 || k1 > kExportColourOff);
}

// Blender 3.4's node setup (BlenderV1Nodes) for the script's 3.4 branch: the Add Shader where one
// Principled BSDF v1 cannot write the source's F0 (blender_v1_add_shader_candidate, on the GGX fit
// `fitted`) and where the pair's 3.4 target model is the better choice (kExportColourOff's rule):
// it fits the samples better in o.metric and renders no further from the source's colour (the image
// check's chromaticity_difference), or it wins on colour (pair_wins_on_colour). Reported as 3.4
// (o.blender_version < 3.5) on the fitted path, each setup is refined in its own model and `refined`
// becomes the Add Shader's when it is chosen; otherwise (an exact source, or 4.x reported) both
// setups are measured on `refined`. A note gives both errors.
void blender_v1_nodes(const MaterialD& source, const GgxSource& fitted, GgxSource& refined, const SampleSet& samples,
                      const ExportOptions& o, BlenderV1Nodes& nodes, std::vector<std::string>& notes) {
  nodes = BlenderV1Nodes::Principled;
  if (!blender_v1_add_shader_candidate(fitted)) return;
  const bool v1 = o.blender_version < 3.5;
  const GgxSource add =
      v1 && !fitted.exact ? refine_for_target(Target::Blender, fitted, samples, o, BlenderV1Nodes::AddShader) : refined;
  const TargetBrdf m1 = target_model(Target::Blender, refined, nullptr, nullptr, 3.4);
  const TargetBrdf m2 = target_model(Target::Blender, add, nullptr, nullptr, 3.4, BlenderV1Nodes::AddShader);
  const FitErrors one = target_errors(m1, samples), two = target_errors(m2, samples);
  // The colour in image space (ImageCheck::chromaticity_difference), at the check's scene and 32 px.
  const ImageCheck c1 = image_check(source, m1, 32), c2 = image_check(source, m2, 32);
  const double e1 = metric_of(one, o.metric), e2 = metric_of(two, o.metric);
  const double k1 = c1.chromaticity_difference, k2 = c2.chromaticity_difference;
  const bool better = (e2 < e1 && k2 <= k1) || pair_wins_on_colour(e1, c1, e2, c2);
  notes.push_back(fmt::format(
      "Blender 3.4: the source's F0 {} is not white mixed with the Base Color's hue: {} (relative l2cos {:.4g}, log {:.4g}, "
      "chromaticity {:.3f} in the image check; one Principled BSDF: {:.4g}, {:.4g}, {:.3f})",
      fmt3(fitted.f0),
      better ? "a diffuse and a metallic Principled BSDF with an Add Shader are written, the better choice"
             : "one Principled BSDF is written: a diffuse and a metallic one with an Add Shader are not the better choice",
      two.relative_l2cos, two.log_all, c2.chromaticity_difference, one.relative_l2cos, one.log_all, c1.chromaticity_difference));
  if (!better) return;
  nodes = BlenderV1Nodes::AddShader;
  if (v1) refined = add;
}

}  // namespace

ExportResult export_material(const MaterialDesc& desc, const std::string& source_label, const ExportOptions& o,
                             const std::string& bin_name_in) {
  check_export_options(o);
  const TargetInfo* info = find_target(o.target);
  const MaterialDesc plain = unrotated(desc);
  const MaterialD source = build_material<double>(plain);
  ExportResult res;
  // A measurement: fitted, refined and measured on its own samples within Ngan 2005's range, as
  // `aniso fit` fits and measures it (export_samples): beyond 80 degrees measurements are least reliable.
  const SampleSet samples = export_samples(desc, source, o);
  if (writes_measured(info->target, desc, o)) {
    const std::string side =
        bin_name_in.empty() ? measured_file_name(info->target, identifier(material_name(desc, source_label, o))) : bin_name_in;
    export_measured(*info, desc, source, samples, source_label, o, side, res);
    return res;
  }
  res.ggx = ggx_source(desc, samples, o);
  res.ggx.rotation_deg += o.tangent_angle_deg;  // the surface's turn composed with the material's
  json params;
  std::vector<std::string> notes, notes_before;
  BlenderV1Nodes nodes = BlenderV1Nodes::Principled;
  if (!res.ggx.conductor && !no_diffuse(res.ggx) && negligible_diffuse(res.ggx)) {
    // The metal / dielectric branch, decided once with a margin (negligible_diffuse): a diffuse this
    // small is written as none, so that a negligible change of the source never flips the branch.
    notes_before.push_back(fmt::format(
        "the diffuse {} is negligible (at most {:g} + {:g} x max F0 = {:.3g}): written as a metal without it", fmt3(res.ggx.kd),
        kNegligibleDiffuseAbs, kNegligibleDiffuseShare, kNegligibleDiffuseAbs + kNegligibleDiffuseShare * max3(res.ggx.f0)));
    res.ggx.kd = glm::dvec3(0.0);
  }
  if (!res.ggx.isotropy.empty()) notes_before.push_back(res.ggx.isotropy);
  if (!res.ggx.exact) {
    GgxSource refined = refine_for_target(info->target, res.ggx, samples, o);
    if (info->target == Target::Blender) blender_v1_nodes(source, res.ggx, refined, samples, o, nodes, notes_before);
    if (refined.alpha_x != res.ggx.alpha_x || refined.alpha_y != res.ggx.alpha_y)
      notes_before.push_back(fmt::format("alphas refined with the target model: {:.4g} x {:.4g} (the GGX fit's {:.4g} x {:.4g})",
                                         refined.alpha_x, refined.alpha_y, res.ggx.alpha_x, res.ggx.alpha_y));
    if (refined.kd != res.ggx.kd || refined.f0 != res.ggx.f0)
      notes_before.push_back(fmt::format("colours re-solved in the target model: kd {} (the GGX fit's {}), F0 {} (the fit's {})",
                                         fmt3(refined.kd), fmt3(res.ggx.kd), fmt3(refined.f0), fmt3(res.ggx.f0)));
    res.ggx = refined;
  } else if (info->target == Target::Blender) {
    GgxSource same = res.ggx;
    blender_v1_nodes(source, res.ggx, same, samples, o, nodes, notes_before);
  }
  res.model = target_model(info->target, res.ggx, &params, &notes, o.blender_version, nodes);
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
    // F0 = 0.08 specular: a grey F0) beside the blendbsdf (the F0's colour in its conductor's eta,
    // k); the principled is written where it is closer to the source's samples in the chosen metric
    // and the blendbsdf does not win on colour (pair_wins_on_colour, the image check at 32 px).
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
    const ImageCheck c_blend = image_check(source, res.model, 32), c_principled = image_check(source, principled, 32);
    const std::string which = fmt::format(
        "{} error: principled {:.4g}, blendbsdf {:.4g}; chromaticity in the image check: principled {:.3f}, "
        "blendbsdf {:.3f}",
        o.metric == FitMetric::L2Cos ? "l2cos" : "log", e_principled, e_blend, c_principled.chromaticity_difference,
        c_blend.chromaticity_difference);
    if (e_principled < e_blend && !pair_wins_on_colour(e_principled, c_principled, e_blend, c_blend)) {
      res.model = principled, params = pparams, notes = pnotes;
      notes.push_back(fmt::format("principled written: it is closer to the source than the blendbsdf ({})", which));
      notes.push_back(
          "the principled's diffuse is Burley's (retro-reflection, Schlick darkening at grazing), its specular "
          "the exact dielectric Fresnel at eta = 2 / (1 - sqrt(0.08 specular)) - 1 for the source's Schlick "
          "F0 (grey: the mean of the source's)");
    } else {
      notes.push_back(fmt::format("blendbsdf written: it is {} than the principled ({})",
                                  e_blend <= e_principled ? "closer to the source" : "closer to the source's colour", which));
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
      const TargetBrdf other = target_model(Target::Blender, res.ggx, nullptr, nullptr, v, nodes);
      const FitErrors e = target_errors(other, samples);
      r.notes.push_back(fmt::format("{}: {}: l2cos {:.4g} (relative {:.3g}), log {:.4g}", span(v), other.name, e.l2cos_all,
                                    e.relative_l2cos, e.log_all));
    }
  }
  r.samples = samples.samples.size();
  r.max_albedo_difference = max_albedo_difference(source, res.model, &r.albedo_theta_deg, &r.albedo_phi_deg);
  if (o.check_size > 0) r.image = image_check(source, res.model, o.check_size);
  const std::string name = material_name(desc, source_label, o);
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
