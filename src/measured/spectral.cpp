// measured/spectral.cpp: the C++ twin of scripts/reduce_ior.py's rgb_weights() (see spectral.h).
#include "aniso/measured/spectral.h"

#include <cmath>
#include <stdexcept>

namespace aniso {
namespace {

// g(lambda; mu, s1, s2) of Wyman, Sloan & Shirley 2013, Eq. 2: a Gaussian of width s1 below the
// mean and s2 above it.
double piecewise_gaussian(double lambda, double mu, double sigma_lo, double sigma_hi) {
  const double t = (lambda - mu) / (lambda < mu ? sigma_lo : sigma_hi);
  return std::exp(-0.5 * t * t);
}

// XYZ -> linear sRGB (Rec. 709 primaries, D65 white), IEC 61966-2-1, to 7 decimals: the matrix of
// scripts/reduce_ior.py (XYZ_TO_LINEAR_SRGB).
constexpr double kXyzToLinearSrgb[3][3] = {
    {3.2404542, -1.5371385, -0.4985314},
    {-0.9692660, 1.8760108, 0.0415560},
    {0.0556434, -0.2040259, 1.0572252},
};

}  // namespace

glm::dvec3 cie1931_cmf(double l) {
  const auto g = piecewise_gaussian;
  const double x = 1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7) - 0.065 * g(l, 501.1, 20.4, 26.2);
  const double y = 0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1);
  const double z = 1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8);
  return {x, y, z};
}

SpectralToRgb::SpectralToRgb(std::span<const double> lambda) {
  const size_t n = lambda.size();
  if (n < 2) throw std::invalid_argument("SpectralToRgb: at least two wavelengths");
  weights.assign(n, glm::dvec3(0.0));
  glm::dvec3 white(0.0);
  for (size_t j = 0; j < n; ++j) {
    if (j > 0 && !(lambda[j] > lambda[j - 1])) throw std::invalid_argument("SpectralToRgb: wavelengths must increase");
    // Composite trapezoidal rule: half of each neighbouring interval.
    const double dx = 0.5 * ((j + 1 < n ? lambda[j + 1] - lambda[j] : 0.0) + (j > 0 ? lambda[j] - lambda[j - 1] : 0.0));
    const glm::dvec3 xyz = cie1931_cmf(lambda[j]) * dx;
    for (int c = 0; c < 3; ++c)
      weights[j][c] = kXyzToLinearSrgb[c][0] * xyz.x + kXyzToLinearSrgb[c][1] * xyz.y + kXyzToLinearSrgb[c][2] * xyz.z;
    white += weights[j];
  }
  for (glm::dvec3& w : weights) w /= white;  // R(lambda) = 1 maps to (1, 1, 1)
}

glm::dvec3 SpectralToRgb::operator()(std::span<const double> values) const {
  if (values.size() != weights.size()) throw std::invalid_argument("SpectralToRgb: wrong number of values");
  glm::dvec3 rgb(0.0);
  for (size_t j = 0; j < values.size(); ++j) rgb += weights[j] * values[j];
  return rgb;
}

}  // namespace aniso
