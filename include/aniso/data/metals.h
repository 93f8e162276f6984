// aniso/data/metals.h: RGB complex refractive indices of measured metals, reduced from spectra by
// scripts/reduce_ior.py (the one documented place for spectral-to-RGB reduction: docs/metals.md).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

namespace aniso {

struct MetalData {
  std::string_view name;    // "gold"
  std::string_view symbol;  // "Au"
  glm::dvec3 eta;           // RGB real part of n + ik
  glm::dvec3 k;             // RGB extinction coefficient
  // Spectrally reduced reflectance at 0, 45 and 80 degrees: what the RGB eta, k were fitted to,
  // kept as reference values for the tests.
  glm::dvec3 f0, r45, r80;
  std::string_view source;
  double fit_rms;  // RMS error of the RGB Fresnel curve against the spectral one, over angle
};

std::span<const MetalData> metal_table();
// Exact name or an accepted alternative spelling ("aluminum", io/names.h).
const MetalData* find_metal(std::string_view name);
// "unknown metal \"gld\" (did you mean \"gold\"?); the metals are ...".
std::string unknown_metal_message(std::string_view name);
std::string metal_names();  // "\"gold\", \"silver\", ..." for error messages

// The measured n(lambda), k(lambda) the RGB eta, k were reduced from: the data of data/ior/ as
// scripts/reduce_ior.py resamples it (docs/metals.md, step 2: linear in wavelength on 380..780 nm
// every 5 nm; src/data/metal_spectra.inc). Between the samples, linear interpolation; outside
// 380..780 nm, the end value (the script's clamp). m must be a row of metal_table().
constexpr double kMetalSpectrumFirstNm = 380.0, kMetalSpectrumStepNm = 5.0;
constexpr int kMetalSpectrumSamples = 81;
glm::dvec2 metal_nk(const MetalData& m, double lambda_nm);  // (n, k)

}  // namespace aniso
