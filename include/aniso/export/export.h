// aniso/export/export.h: `aniso export --to TARGET`: a material written in a renderer's own format with
// that renderer's conventions (targets.h), and a report of how close the export is.
//
// Two paths (docs/export.md):
//   exact   the source has the targets' distribution (model "ggx"; "metal" with a GGX lobe and no
//           directional diffuse; "principled" with metallic 1 and no sheen, clearcoat or
//           subsurface): its alphas, colours and complex IOR carry over by formula.
//   fitted  anything else (Ward, Ashikhmin-Shirley, Lafortune, Phong, measured data, other
//           principled materials): the source is sampled over the hemisphere pair (a grid in
//           Rusinkiewicz's half / difference angles, weighted by solid angle like MERL's bins,
//           measured/samples.h) and aniso's anisotropic GGX ("ggx", or "metal" with a GGX lobe for
//           metals) is fitted to it with the fitting engine (fit/fit.h); the fitted GGX then goes
//           the exact way.
// Either way the report gives the written target model (targets.h) against the source samples in
// both fit metrics (l2cos, log) and the largest directional-albedo difference over 15 views.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "aniso/export/targets.h"
#include "aniso/fit/fit.h"
#include "aniso/io/materials.h"
#include "aniso/measured/samples.h"

namespace aniso::exporter {

enum class Target { Blender, Mitsuba3, PbrtV4, MaterialX, OpenPbr, Gltf };

struct TargetInfo {
  Target target;
  std::string_view name;       // --to
  std::string_view extension;  // of -o
  std::string_view summary;    // one line for --list-targets
  std::string_view help;       // what is written and how to use it (--help-target)
};
std::span<const TargetInfo> targets();
// nullptr for an unknown name.
const TargetInfo* find_target(std::string_view name);
// "\"blender\", \"mitsuba3\", ..." for messages.
std::string target_names();

// The anisotropic GGX every target maps from: a Schlick lobe with a Lambertian term, or a
// conductor (exact Fresnel with eta, k). Frame: aniso's (x the tangent).
struct GgxSource {
  double alpha_x = 0.1, alpha_y = 0.1;
  double rotation_deg = 0.0;  // the material's rotation_deg (tangent rotated towards the bitangent)
  bool conductor = false;
  glm::dvec3 kd{0.0}, f0{0.04};  // Schlick
  glm::dvec3 eta{1.0}, k{0.0};   // conductor
  std::string metal, symbol;     // aniso's metal name and its chemical symbol, when named
  bool exact = true;
  std::string origin;    // how it was obtained, one line
  FitErrors source_fit;  // of the aniso GGX fit against the source samples (fitted only)
};

// The ranges export_material accepts (the CLI's option checks use the same).
inline constexpr int kExportGridMin = 1, kExportGridMax = 12;
inline constexpr int kExportStartsMax = 100;
inline constexpr double kBlenderVersionMin = 3.0, kBlenderVersionMax = 10.0;

struct ExportOptions {
  std::string target;  // a TargetInfo::name
  std::string name;    // material name in the file ("" = from the source)
  FitMetric metric = FitMetric::L2Cos;
  int starts = 4;  // fitted path: starts of the fit
  uint64_t seed = 1;
  int threads = 0;
  // The source sampling grid: theta_h x phi_h x theta_d x phi_d = 4 n x 4 n x 2 n x 2 n pairs (n = 6:
  // 20736 before the horizon cut). Tests use n = 3.
  int grid = 6;
  // --to blender: the version the report's target model is (the script itself adapts to the
  // Blender that runs it): 4.3 and later use the Metallic BSDF with n, k for conductors; before
  // 3.5 (3.4, Debian 12's) the Principled BSDF v1 (targets.h, "Blender 3.4").
  double blender_version = 4.3;
  // Fitted path: the samples (at most) the alphas are refined on with the target model.
  int refine_samples = 4000;
  // The surface's own turn of the tangent about the normal (a scene object's tangent.angle_deg,
  // docs/scenes.md), degrees towards the bitangent: added to the material's rotation_deg, as the
  // renderer composes them (io/params.cpp, kOrientation), and written into the target's rotation.
  double tangent_angle_deg = 0.0;
  std::vector<std::string> extra_notes;  // added to the report's notes (what the caller could not carry)
};

struct ExportReport {
  std::string target, target_model;
  bool exact = true;
  std::string origin;
  nlohmann::json parameters;  // the values written, by the target's own names
  FitErrors errors;           // the written target model against the source samples
  double max_albedo_difference = 0.0;
  double albedo_theta_deg = 0.0, albedo_phi_deg = 0.0;  // where it is largest
  size_t samples = 0;
  std::vector<std::string> notes;  // what differs, how to orient the mesh, ...
  // --to blender: the Blender versions the numbers hold for ("Blender 3.4 (Principled BSDF v1)",
  // "Blender 4.0 to 4.2 (Principled BSDF)", "Blender 4.3 and later"); the other versions' errors
  // for the same script are in the notes. Empty for the other targets.
  std::string blender_version;

  nlohmann::json to_json() const;
  // A few lines for the terminal and, prefixed, for the file's comment.
  std::string text(std::string_view line_prefix = "") const;
};

struct ExportFile {
  std::string path;  // "" for the main file (-o), else a sibling (glTF's .bin), relative to -o's folder
  std::string content;
};

struct ExportResult {
  std::vector<ExportFile> files;  // files[0] is the main file
  ExportReport report;
  TargetBrdf model;  // the target model of the written parameters
  GgxSource ggx;
};

// InputError naming the option (as the CLI spells it, without "--") when one is out of its range or
// not finite; export_material calls it first.
void check_export_options(const ExportOptions& o);

// The samples the exporter compares (and fits) against: the source over a half / difference grid.
SampleSet sample_source(const MaterialD& m, int grid);

// The GGX the targets map from: exact where the source has one, else fitted (InputError: a source
// that no GGX can stand for, with the reason).
GgxSource ggx_source(const MaterialDesc& desc, const SampleSet& samples, const ExportOptions& o);

// The fitted path's last step: the alphas searched again with the target's own model (its masking and
// Fresnel), factors 0.6 to 1.5 around the GGX fit's, in o.metric.
GgxSource refine_for_target(Target t, const GgxSource& g, const SampleSet& samples, const ExportOptions& o);

// The written target model's errors against the samples (fit_errors' formulas, fit.cpp).
FitErrors target_errors(const TargetBrdf& t, const SampleSet& data);

// max over 15 views (theta_o 0..75 deg, phi_o 0, 45, 90 deg) and channels of |albedo_source -
// albedo_target|, by a quadrature over the half vector (sharp lobes included).
double max_albedo_difference(const MaterialD& source, const TargetBrdf& t, double* theta_deg = nullptr,
                             double* phi_deg = nullptr);

// The whole export. `bin_name`: the glTF buffer's file name (the .gltf names it; "" = "<name>.bin").
ExportResult export_material(const MaterialDesc& desc, const std::string& source_label, const ExportOptions& o,
                             const std::string& bin_name = "");

// For tests and the docs: the target model and parameters for a GGX, without the file.
// blender_version: which of the script's node setups the model is (4.3 and later: the Metallic BSDF
// with n, k for conductors; earlier: the Principled BSDF).
TargetBrdf target_model(Target t, const GgxSource& g, nlohmann::json* parameters = nullptr,
                        std::vector<std::string>* notes = nullptr, double blender_version = 4.3);

// A picture for the docs and `--preview`: two spheres, the source (left) and the written target
// model (right), shaded by aniso with the same two directional lights, tangent dp/du of a sphere
// whose u runs around the vertical axis (aniso's meshes), viewed orthographically along -z.
// Each sphere `size` pixels; PNG through render::write_png, or (a .pfm or .exr path) the linear
// radiance through render::write_image, without labels. The lights (directions to the light in the
// view frame: x right, y up, z towards the viewer; irradiance at normal incidence): normalize(-0.5,
// 0.6, 1) with 2.5, normalize(0.7, -0.3, 0.8) with 1; the tangent normalize(y x n). The Blender
// check (tests/blender_export_render.py) builds the same scene in Cycles.
void write_preview(const std::string& path, const MaterialD& source, const TargetBrdf& target, const std::string& left,
                   const std::string& right, int size = 256);

// The sphere the glTF export carries (positions, normals, tangents (w = +1), uvs, indices).
struct SphereMesh {
  std::vector<float> positions, normals, tangents, uvs;
  std::vector<uint16_t> indices;
};
SphereMesh uv_sphere(int rings, int segments);

}  // namespace aniso::exporter
