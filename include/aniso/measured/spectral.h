// aniso/measured/spectral.h: spectral reflectance (or BRDF) samples to linear sRGB, for measured data
// that comes as spectra (the Cornell gonioreflectometer files, measured/samples.h).
//
// The method is the metals' (scripts/reduce_ior.py, rgb_weights(); docs/metals.md, "Spectral-to-RGB
// reduction: the method"), so that a measured paint and a measured metal are reduced alike:
//  1. CIE 1931 2-degree colour matching functions, the multi-lobe analytic fit of Wyman, Sloan &
//     Shirley 2013, JCGT 2(2), Eq. 2;
//  2. equal-energy illuminant E, integrated by the trapezoidal rule on the data's own wavelengths;
//  3. XYZ -> linear sRGB (IEC 61966-2-1 / Rec. 709 primaries);
//  4. white balance: each channel divided by the value of R(lambda) = 1 on the same wavelengths, so
//     a grey spectrum maps to the same value in every channel.
// R_c = sum_j W_c(lambda_j) R(lambda_j), with sum_j W_c = 1. Some W_c are negative (the sRGB gamut
// does not contain the spectral colours): a saturated spectrum can give a channel slightly below 0.
// tests/test_samples.cpp checks these weights against the Python script's.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace aniso {

// The CIE 1931 x, y, z colour matching functions at lambda (nm), Wyman et al. 2013, Eq. 2.
glm::dvec3 cie1931_cmf(double lambda_nm);

// The per-channel weights W_c(lambda_j) for these wavelengths (nm, strictly increasing, at least 2).
struct SpectralToRgb {
  std::vector<glm::dvec3> weights;  // one RGB weight per wavelength
  explicit SpectralToRgb(std::span<const double> lambda_nm);
  // values[j] at lambda_nm[j]; values.size() must equal the number of wavelengths.
  glm::dvec3 operator()(std::span<const double> values) const;
};

}  // namespace aniso
