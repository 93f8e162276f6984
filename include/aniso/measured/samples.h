// aniso/measured/samples.h: measured reflectance as a set of samples, the one type every data source
// produces (a CSV of the user's own measurements, the Cornell gonioreflectometer files, MERL
// tables, RGL tensor files) and the fitter (fit/fit.h) consumes.
//
// Directions are in the local shading frame of docs/conventions.md (z = normal, x = tangent, phi
// measured from x towards y): wi towards the light, wo towards the viewer, both unit, above the
// horizon. `value` is the BRDF f(wi, wo) without the cosine, linear sRGB, in 1/sr.
//
// Every reader validates what it reads: a malformed file is an InputError whose message names the
// file, the line and the problem (the CLI exits 2 on it, docs/fitting.md lists the cases).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/core/math.h"

namespace aniso {

struct MeasuredSample {
  Vec3d wi, wo;
  glm::dvec3 value{0.0};
  double weight = 1.0;  // relative weight in the error metrics (docs/fitting.md); 1 unless given
};

struct SampleSet {
  std::string source;  // the path it was read from, or a name ("tabulated ward")
  std::string format;  // "csv", "cornell", "merl", "rgl", "synthetic"
  // What the samples are, where they are not the file's own records: a table sampled on a grid
  // says which grid (empty for CSV, Cornell and MERL files, whose samples are their rows or bins).
  std::string description;
  std::vector<MeasuredSample> samples;
  std::vector<std::string> warnings;  // what was accepted but ignored (extra columns, skipped bins)
};

// CSV of samples: a header line naming the columns, then one sample per line.
//   theta_i, phi_i, theta_o, phi_o   radians (or theta_i_deg, ... in degrees), any order
//   r, g, b                          the BRDF (1/sr), finite and >= 0
//   weight                           optional, finite and > 0
// theta in [0, pi/2) (strictly above the horizon, where every model is 0), phi in [-2 pi, 2 pi].
// Blank lines and lines starting with '#' are skipped; other columns are ignored with a warning.
SampleSet read_samples_csv(const std::string& path);

// A Cornell gonioreflectometer file as shipped with pbrt-v2 (scenes/brdfs/*.brdf): '#' comments,
// the number of wavelengths, the wavelengths (nm), then rows "theta_i phi_i theta_s phi_s v_1 ...
// v_n" (radians; spectral BRDF values), reduced to RGB by measured/spectral.h. theta_i is the light
// (wi), theta_s the viewer (wo).
SampleSet read_cornell(const std::string& path);

struct MerlBrdf;
// A MERL table's bins as samples (measured/merl.h): each valid bin whose centre has both
// directions above the horizon, at its centre (MerlBrdf::bin_directions, phi_h = 0), weighted by
// the solid angle the bin stands for, dw_i dw_o = 4 cos(theta_d) dw_h dw_d (Rusinkiewicz 1998)
// = 4 cos theta_d sin theta_h sin theta_d dtheta_h dphi_h dtheta_d dphi_d, with the MERL theta_h
// bin width dtheta_h proportional to (2 i + 1) (theta_h = (i / 90)^2 pi / 2). Missing bins are
// skipped, and counted in a warning.
SampleSet merl_samples(const MerlBrdf& brdf, const std::string& source);

struct HalfDiffGrid;
namespace rgl {
struct RglData;
}
// An RGL tensor file's table (aniso/rgl/rgl_material.h) sampled where MERL's tables hold their
// values: f (pbrt-v4's MeasuredBxDF, aniso/brdf/rgl.h) at the centres of a HalfDiffGrid
// (measured/merl.h), every pair with both directions above the horizon, weighted by the solid
// angle its bin stands for (HalfDiffGrid::weight). rgl_sample_grid(isotropic) is the grid
// read_measured uses: an isotropic file at phi_h = 0 alone (as a MERL table: f depends on phi_d
// only, and the fitter's anisotropy rule sees one azimuth), an anisotropic one at 24 half-vector
// azimuths over the full circle. phi_d covers the full circle (a file holds f(wi, wo) and f(wo, wi)
// separately, and need not be reciprocal). The description names the grid and the file's kind.
// n_theta_h > 0 sets the resolution (`aniso fit --grid N`): N theta_h x N/2 theta_d x N phi_d, the
// same 24 azimuths for an anisotropic file; 0: the defaults, N = 64 isotropic and 32 anisotropic.
HalfDiffGrid rgl_sample_grid(bool isotropic, int n_theta_h = 0);
SampleSet rgl_samples(const rgl::RglData& data, const std::string& source, const HalfDiffGrid& grid);

// By extension: .csv, .brdf (Cornell), .binary (MERL, measured/merl.h), .bsdf (RGL tensor file,
// sampled on rgl_sample_grid(isotropic, rgl_grid)).
SampleSet read_measured(const std::string& path, int rgl_grid = 0);

// The sampling grid asked of a fit (`aniso fit --grid N`, Python aniso.fit(grid=N)): N is even and
// in [4, 256], and the data are an RGL tensor file (.bsdf), the one format without samples of its
// own. Returns N; else an InputError naming `what` (the option as the caller spells it).
int check_rgl_fit_grid(const std::string& data_path, int64_t n, const std::string& what);

// w = (sin theta cos phi, sin theta sin phi, cos theta).
Vec3d direction_from_angles(double theta, double phi);

}  // namespace aniso
