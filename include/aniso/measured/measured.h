// aniso/measured/measured.h: a measured BRDF as a material: the MERL table, its sampling tables, and
// where it came from (file, sha256, the MERL material it is recognised as). docs/measured.md.
//
// Lifetime rule: MeasuredT<T> (the kernel, aniso/brdf/measured.h) points into a MeasuredData. A
// MeasuredData is shared (shared_ptr); MaterialDesc holds one, and load_measured() keeps every file
// it loaded in a process-wide registry until the program ends, so a MaterialT built from a loaded
// file stays valid for the whole run (and a file used twice is read once). A MeasuredData made by
// make_measured() (tables in memory: tests, the fitter) lives as long as its last shared_ptr:
// keep one beside every MaterialT built from it.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "aniso/brdf/measured.h"
#include "aniso/measured/merl.h"

namespace aniso {

struct MeasuredData {
  std::string source;     // the file it was read from, or a label for tables made in memory
  std::string sha256;     // of the file (lower-case hex); empty for tables made in memory
  std::string merl_name;  // the MERL database material with this sha256 ("gold-metallic-paint"), or empty
  MerlBrdf brdf;
  size_t missing = 0;  // missing bins (any channel negative)

  // Sampling tables (aniso/brdf/measured.h, docs/measured.md "Sampling").
  int theta_o_bins = 0, phi_h_bins = 0;
  std::vector<double> marginal_cdf, conditional_cdf, v_edges, cell_solid_angle;
  double table_build_seconds = 0.0;
  size_t sampling_bytes() const;
};

// Viewing-angle bins and phi_h cells of the sampling tables (docs/measured.md gives the reasons).
inline constexpr int kMeasuredThetaOBins = 64;
inline constexpr int kMeasuredPhiHBins = 96;

// Builds the sampling tables of a MERL table (oneTBB over the viewing-angle bins).
std::shared_ptr<const MeasuredData> make_measured(MerlBrdf brdf, std::string source);

// Reads a MERL .binary file (read_merl: InputError on a bad file), hashes it, recognises it by its
// sha256 and builds the sampling tables; each file once per process (the registry, above).
std::shared_ptr<const MeasuredData> load_measured(const std::string& path);

// The kernel view of the data (pointers into d).
template <typename T> MeasuredT<T> measured_kernel(const MeasuredData& d) {
  MeasuredT<T> m;
  m.table = d.brdf.table.data();
  m.marginal_cdf = d.marginal_cdf.data();
  m.conditional_cdf = d.conditional_cdf.data();
  m.v_edges = d.v_edges.data();
  m.cell_solid_angle = d.cell_solid_angle.data();
  m.theta_o_bins = d.theta_o_bins;
  m.phi_h_bins = d.phi_h_bins;
  return m;
}

// sha256 of a file's bytes as lower-case hex (OpenSSL's EVP interface); InputError if unreadable.
std::string sha256_file(const std::string& path);
// The MERL database material whose file has this sha256 (data/merl/merl100_sha256.csv), or "".
std::string merl_material_name(std::string_view sha256_hex);
// Number of materials in that table (100).
size_t merl_known_count();

// One line for stderr: "x.binary: MERL BRDF database material gold-metallic-paint (sha256 ...)".
std::string describe_measured(const MeasuredData& d);

}  // namespace aniso
