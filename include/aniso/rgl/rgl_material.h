// aniso/rgl/rgl_material.h: an RGL tensor file (.bsdf) as a material: the checks every reader makes, the
// interpolants pbrt-v4 builds from the fields, and the kernel view (aniso/brdf/rgl.h). docs/rgl.md.
//
// Lifetime: RglT<T> points into an RglData, held by shared_ptr as a MeasuredData is
// (include/aniso/measured/measured.h): keep one beside every kernel built from it.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "aniso/brdf/rgl.h"
#include "aniso/rgl/tensor.h"

namespace aniso::rgl {

// The tables of one PL2D and the constructor of pbrt-v4's PiecewiseLinear2D
// (src/pbrt/util/sampling.h:1335-1455): per slice, conditional cdfs along x, the marginal cdf
// along y, normalised (build_cdf) or scaled so that evaluate() returns the stored values
// (normalize = false, build_cdf = false: ndf, sigma, spectra).
struct PL2DTables {
  std::vector<float> data, marginal_cdf, conditional_cdf;
  std::array<std::vector<float>, 3> param_values;
  PL2D view;  // points into the vectors above: do not copy a PL2DTables after building it

  PL2DTables() = default;
  PL2DTables(const PL2DTables&) = delete;
  PL2DTables& operator=(const PL2DTables&) = delete;
  // data: slices x size_y x size_x (C order, slices in the order of params, last fastest).
  void build(const float* in, int size_x, int size_y, const std::vector<std::vector<float>>& params, bool normalize,
             bool build_cdf);
};

struct RglData {
  std::string source;       // the file, or a label
  std::string description;  // the file's description field
  bool spectral = false;    // wavelengths + spectra (reduced to RGB at load), else rgb
  bool isotropic = true;
  bool jacobian = true;
  std::vector<float> theta_i, phi_i, wavelengths;
  int ndf_shape[2] = {0, 0}, sigma_shape[2] = {0, 0}, vndf_grid[2] = {0, 0}, colour_grid = 0;
  std::vector<std::string> field_summary;  // "name dtype [shape]" per field, in file order
  // What was read otherwise than it stands in the file (rounding noise read as 0, sigma raised to
  // its floor), one line per field, each naming the file: load_rgl hands them to the note sink.
  std::vector<std::string> notes;
  std::vector<TensorField> read_as;  // those fields as they were read (the tables a writer copies)
  uint64_t file_size = 0;
  PL2DTables ndf, sigma, vndf, luminance, rgb;
  RglTables tables;  // the views of the five above, what the kernel points to
};

// Rounding noise. Real tables hold values a little below 0 where the true value is 0 (the RGL
// database's chm files: 16 luminance values down to -4e-10 against a largest value of order 1): a
// float32 sum or interpolation whose exact result is 0 comes out with an error of a few units in
// the last place of its largest terms (Higham, "Accuracy and Stability of Numerical Algorithms",
// 2nd ed. 2002, section 4.2: |error| <= (n - 1) eps sum |x_i| for n terms). The terms of a table
// entry are at most the table's largest value, so a negative value is rounding of 0 when
//     |v| <= kRoundingNoiseUlps x FLT_EPSILON x max |table|   (64 x 1.19e-7 = 7.6e-6 relative),
// 64 allowing sums of up to 64 terms of the table's largest size. -4e-10 is 1e4 times below that
// for a table whose largest value is 1 (the chm files' luminance: 1.05 to 27.5); a value below the
// bound is a negative measurement, not rounding, and stays an error. pbrt-v4 and Mitsuba 3 check
// no value at all (bxdfs.cpp MeasuredBxDFData::Create, measured.cpp MeasuredBSDF(): only the
// dtypes and shapes): aniso reads these files as they do and says so once.
inline constexpr double kRoundingNoiseUlps = 64.0;
// The largest magnitude accepted in a table: f multiplies colour by ndf and divides by sigma (>=
// kMinSigma) and a cosine, all in float; 1e15 keeps that product below float's 3.4e38 for cosines
// down to 0.1 (a GGX with alpha 0.001 peaks at D = 3e5: real tables are far below).
inline constexpr float kMaxTableValue = 1e15f;
// The floor of sigma (f divides by it; smaller values are raised to it, with a note): sigma(w) >=
// cos(theta) for every normalised D, so only the horizon row of a mirror-like table comes near it.
inline constexpr float kMinSigma = 1e-6f;
// kRoundingNoiseUlps x FLT_EPSILON x the largest finite |value| of v.
double rounding_noise_bound(std::span<const float> v);
// Sets the values in [-rounding_noise_bound(v), 0) to 0; returns "" when there were none, else the
// note: "<where>: field "<field>": N negative values read as 0 (... the most negative V at flat
// index I)".
std::string zero_rounding_noise(const std::string& where, const std::string& field, std::vector<float>& v);

// Where load_rgl's notes go (one call per note, the first time each file is read): the command
// line sets a sink that prints "aniso: note: ..." on stderr (apps/aniso/cmd_rgl.cpp); without one
// the notes stay in RglData::notes. Library code writes nothing to stderr itself.
void set_note_sink(std::function<void(const std::string&)> sink);

// Checks the fields as pbrt-v4 (MeasuredBxDFData::Create, bxdfs.cpp:885-937) and Mitsuba 3
// (measured.cpp:98-188) do, plus what both assume without checking (finite, non-negative tables,
// increasing angle grids within range, a full phi circle when anisotropic, a positive vndf and
// luminance mass in every slice, sigma > 0), and builds the interpolants. InputError naming the
// file, the field and the problem.
std::shared_ptr<RglData> rgl_from_tensor(const TensorFile& t);
// read_tensor_file + rgl_from_tensor; each path read once per process (a registry, as
// load_measured()'s), so a kernel built from it stays valid for the whole run.
std::shared_ptr<const RglData> load_rgl(const std::string& path);

// A path ending in .bsdf (any case).
bool is_rgl_file_name(const std::string& spec);

template <typename T> RglT<T> rgl_kernel(const RglData& d) {
  RglT<T> k;
  k.t = &d.tables;
  return k;
}

// What `aniso presets --show file.bsdf` prints: fields, grids, isotropic or not, the description.
std::string describe_rgl(const RglData& d);

}  // namespace aniso::rgl
