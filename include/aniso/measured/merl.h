// aniso/measured/merl.h: the MERL BRDF database's .binary files (Matusik et al. 2003): read, write,
// look up, and write an analytic model in the same layout. docs/measured.md has the format.
//
// File: three little-endian int32 (90, 90, 180: theta_h, theta_d, phi_d resolutions), then
// 3 x 90 x 90 x 180 little-endian doubles, the R block, the G block, the B block, each indexed
// phi_d fastest (merl_index()). The stored numbers are multiplied by MERL's scale factors 1/1500,
// 1.15/1500, 1.66/1500 (BRDFRead.cpp RED_SCALE, GREEN_SCALE, BLUE_SCALE) to give RGB reflectance
// in 1/sr. A negative number marks a missing sample: lookup() gives 0 there, valid() says false,
// and the sampler's tables count it as 0 (docs/measured.md, "Missing samples").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "aniso/brdf/material.h"
#include "aniso/brdf/measured.h"

namespace aniso {

struct MerlBrdf {
  static constexpr int kThetaH = MerlLayout::kThetaH, kThetaD = MerlLayout::kThetaD, kPhiD = MerlLayout::kPhiD;
  static constexpr int kBins = MerlLayout::kBins;
  // MERL's scale factors (BRDFRead.cpp): stored number * scale = reflectance / sr.
  static constexpr double kScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
  // Size of a file: 12 header bytes and 3 kBins doubles (34,992,012 bytes).
  static constexpr size_t kFileBytes = 12 + sizeof(double) * 3 * size_t(kBins);
  // Largest stored number accepted: 1e15 (1e15 / 1500 ~ 7e11 per sr). A measurement stores
  // reflectance times about 1500, far below this even at a mirror-like peak; random bytes (a corrupt
  // file) often decode to 1e100 or 1e300, which would overflow the float kernels (3.4e38) and the
  // sampling tables' sums. Negative numbers of any size mark a missing sample.
  static constexpr double kMaxStored = 1e15;

  std::vector<double> table;  // 3 * kBins values, channel-major, already scaled (RGB reflectance / sr)

  // f(wi, wo) by MERL's nearest-bin lookup (local frame, z = n); 0 below the horizon and for a
  // missing bin. The same function as the kernel's (merl_lookup(), aniso/brdf/measured.h).
  RGBT<double> lookup(const Vec3T<double>& wi, const Vec3T<double>& wo) const;
  static int index(int i_theta_h, int i_theta_d, int i_phi_d) { return merl_index(i_theta_h, i_theta_d, i_phi_d); }
  // The (wi, wo) at the centre of a bin (phi_h = 0), for fitting and tests: theta_h = ((i + 1/2) /
  // 90)^2 pi / 2, theta_d = (j + 1/2) / 90 pi / 2, phi_d = (k + 1/2) / 180 pi (HalfDiffGrid{} below).
  // Either direction may lie below the horizon (large theta_h + theta_d): such bins are never
  // looked up from above it.
  static std::pair<Vec3T<double>, Vec3T<double>> bin_directions(int i_theta_h, int i_theta_d, int i_phi_d);
  // Not a missing sample: every channel >= 0.
  bool valid(int i_theta_h, int i_theta_d, int i_phi_d) const;
  // Number of missing bins.
  size_t missing_count() const;
};

// MERL's layout of direction pairs at any resolution: Rusinkiewicz 1998's half and difference
// angles at the centres of n_theta_h x n_theta_d x n_phi_d bins, theta_h square-root spaced as
// MERL's (((i + 1/2) / n_theta_h)^2 pi / 2: fine bins at the highlight), theta_d = (j + 1/2) /
// n_theta_d pi / 2, phi_d = (k + 1/2) / n_phi_d phi_d_range; and n_phi_h half-vector azimuths
// phi_h = 2 pi l / n_phi_h (MERL's tables are isotropic: phi_h = 0 alone). The default is MERL's own
// grid (bin_directions). The fitter samples tables on it (measured/samples.h).
struct HalfDiffGrid {
  int n_theta_h = MerlLayout::kThetaH, n_theta_d = MerlLayout::kThetaD, n_phi_d = MerlLayout::kPhiD, n_phi_h = 1;
  // pi: MERL's tables hold phi_d in [0, pi), reciprocity (swapping wi and wo) giving phi_d + pi;
  // 2 pi: both orders of the pair, for a table that need not be reciprocal.
  double phi_d_range = 3.14159265358979323846;

  size_t size() const { return size_t(n_theta_h) * size_t(n_theta_d) * size_t(n_phi_d) * size_t(n_phi_h); }
  // The pair (wi, wo) at bin (i, j, k) and azimuth l. Either may lie below the horizon.
  std::pair<Vec3T<double>, Vec3T<double>> directions(int i_theta_h, int i_theta_d, int i_phi_d, int i_phi_h = 0) const;
  // The solid angle dw_i dw_o the bin stands for, up to a constant factor (the same for every bin
  // of the grid): dw_i dw_o = 4 cos theta_d dw_h dw_d (Rusinkiewicz 1998)
  // = 4 cos theta_d sin theta_h sin theta_d dtheta_h dphi_h dtheta_d dphi_d, with dtheta_h
  // proportional to 2 i + 1 (the square-root spacing): cos theta_d sin theta_h sin theta_d (2 i + 1).
  double weight(int i_theta_h, int i_theta_d) const;
};

// Reads and validates a .binary file: header (90, 90, 180), exact size, every value finite and
// at most 1e15 (stored; negative = missing).
// Throws InputError naming the file and the byte offset of the problem.
MerlBrdf read_merl(const std::string& path);

// Writes the file with io::AtomicFile (io/atomic_file.h: never a half-written file); throws
// std::runtime_error on a write error, InputError on a table of the wrong size or a non-finite value.
// Stored numbers are table / scale, chosen (within 2 ulps) so that read_merl gives the table back
// bit for bit whenever the value is a product number * scale, as every table read_merl or
// tabulate_merl makes is.
void write_merl(const std::string& path, const MerlBrdf& brdf);

// An analytic model written in the MERL layout: f at each bin's centre (bin_directions), rounded
// as a file would store it; bins whose centre has a direction below the horizon are missing.
MerlBrdf tabulate_merl(const MaterialD& m);

}  // namespace aniso
