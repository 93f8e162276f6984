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

}  // namespace aniso
