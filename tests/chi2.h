// tests/chi2.h: the suite's one Pearson chi-square test (pearson_chi2), and the harness that bins a
// sampler's directions over the upper hemisphere against its pdf (chi2_test), after pbrt-v4's
// src/pbrt/bsdfs_test.cpp (Chi2Test, FrequencyTable, IntegrateFrequencyTable) and Mitsuba's
// ChiSquareTest. Every statistical test of a sampler or a histogram calls pearson_chi2: the
// sampling, batch, GLSL, measured, RGL, environment and renderer tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include <boost/math/special_functions/gamma.hpp>

#include "aniso/brdf/material.h"
#include "stats/rng.h"

namespace aniso::test {

struct PearsonOptions {
  // Cells expected to hold fewer draws are pooled: the chi-square approximation of Pearson's
  // statistic needs expected counts of about 5 or more (pbrt-v4 CHI2_MINFREQ, Mitsuba's
  // min_exp_frequency).
  double min_expected = 5.0;
  // A cell whose expected count is 0 may hold at most this many draws (rounding in a sampler can
  // put a few on the edge of the support: pbrt-v4 allows sampleCount * 1e-5); more rejects the
  // test outright. 0: not a single draw.
  double max_in_empty_cell = 0.0;
  // Draws the caller could not place in any cell but whose expected counts lie among the pooled
  // cells' (the measured sampler's rejected draws): counted in the pooled cell.
  double pooled_extra_observed = 0.0;
};

struct PearsonResult {
  double chi2 = 0.0;
  int dof = 0;
  double p_value = 0.0;
  // Non-empty when the test rejects without a statistic: draws in a cell of expected count 0, or
  // too few cells left for a degree of freedom. p_value is then 0.
  std::string message;
};

// Pearson's chi-square of observed counts against expected ones (same cells, same total). Cells
// sorted by expected count; those below min_expected are pooled into one cell, and pooling goes
// on past them until the pooled cell itself reaches min_expected (pbrt-v4 bsdfs_test.cpp,
// Chi2Test). One degree of freedom per cell (the pooled one included), less one for the fixed
// total. p = Q(dof / 2, chi2 / 2), the regularised upper incomplete gamma function
// (boost::math::gamma_q): the chi-square distribution's survival function.
inline PearsonResult pearson_chi2(const std::vector<double>& observed, const std::vector<double>& expected,
                                  const PearsonOptions& o = {}) {
  PearsonResult r;
  if (observed.size() != expected.size()) {
    r.message = "observed and expected counts differ in size (" + std::to_string(observed.size()) + " and " +
                std::to_string(expected.size()) + " cells)";
    return r;
  }
  std::vector<size_t> order(expected.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pooled_exp = 0.0, pooled_obs = o.pooled_extra_observed, chi2 = 0.0;
  int dof = 0;
  for (const size_t i : order) {
    const double e = expected[i], n = observed[i];
    if (e == 0.0) {
      if (n > o.max_in_empty_cell) {
        r.message = "cell " + std::to_string(i) + " holds " + std::to_string(n) + " draws where the expected count is 0";
        return r;
      }
      continue;
    }
    if (e < o.min_expected || (pooled_exp > 0.0 && pooled_exp < o.min_expected)) {
      pooled_exp += e;
      pooled_obs += n;
      continue;
    }
    chi2 += (n - e) * (n - e) / e;
    ++dof;
  }
  if (pooled_exp > 0.0 || pooled_obs > 0.0) {
    if (pooled_exp == 0.0) {
      r.message = std::to_string(pooled_obs) + " draws outside every cell of non-zero expected count";
      return r;
    }
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  }
  dof -= 1;  // the total is fixed
  r.chi2 = chi2;
  r.dof = dof;
  if (dof < 1) {
    r.message = "too few cells for a degree of freedom (" + std::to_string(dof) + ")";
    return r;
  }
  r.p_value = boost::math::gamma_q(dof / 2.0, chi2 / 2.0);
  return r;
}

struct Chi2Result {
  double p_value = 0.0;
  double chi2 = 0.0;
  int dof = 0;
  double pdf_integral = 0.0;  // integral of pdf over the hemisphere (numerical)
  double accepted_fraction = 0.0;
  std::string message;
};

// A sampler against its pdf: n_samples draws binned in (cos theta, phi) over the upper hemisphere,
// expected counts from the pdf integrated over each bin, then pearson_chi2. Samples that sample()
// rejects ("no sample") land in an extra cell whose expected count is N (1 - integral of pdf): so
// the test also checks that the pdf integrates to the acceptance rate. A bin of pdf 0 may hold
// N 1e-5 draws (pbrt-v4's allowance for rounding at the edge of the support).
//
// 3-point Gauss-Legendre per axis of each bin's sub-cells: exact for polynomials of degree 5, and the
// sub-cells resolve the lobes used in the tests (checked by pdf_integral ~ acceptance).
inline Chi2Result chi2_test(const std::function<BSDFSampleT<float>(float, Vec2)>& sample,
                            const std::function<double(const Vec3d&)>& pdf, int64_t n_samples, uint64_t seed, int theta_bins = 40,
                            int phi_bins = 80, int sub = 6) {
  Chi2Result r;
  // Bins in (cos theta, phi): cos theta in [0, 1], so each bin's solid angle is d(cos) d(phi).
  const int nb = theta_bins * phi_bins;
  std::vector<double> observed(nb + 1, 0.0), expected(nb + 1, 0.0);
  Rng rng(seed);
  int64_t accepted = 0;
  for (int64_t i = 0; i < n_samples; ++i) {
    const float uc = rng.uniform_as<float>();
    const Vec2 u(rng.uniform_as<float>(), rng.uniform_as<float>());
    const BSDFSampleT<float> s = sample(uc, u);
    if (!s.valid) {
      observed[nb] += 1.0;
      continue;
    }
    ++accepted;
    const double z = std::clamp(double(s.wi.z), 0.0, 1.0);
    double phi = std::atan2(double(s.wi.y), double(s.wi.x));
    if (phi < 0) phi += 2.0 * M_PI;
    const int ti = std::min(theta_bins - 1, int(z * theta_bins));
    const int pi = std::min(phi_bins - 1, int(phi / (2.0 * M_PI) * phi_bins));
    observed[ti * phi_bins + pi] += 1.0;
  }
  static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  double integral = 0.0;
  for (int ti = 0; ti < theta_bins; ++ti)
    for (int pi = 0; pi < phi_bins; ++pi) {
      const double z0 = double(ti) / theta_bins, dz = 1.0 / theta_bins / sub;
      const double p0 = 2.0 * M_PI * pi / phi_bins, dp = 2.0 * M_PI / phi_bins / sub;
      double acc = 0.0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b)
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const double z = z0 + dz * (a + 0.5 + 0.5 * gx[i]);
              const double phi = p0 + dp * (b + 0.5 + 0.5 * gx[j]);
              const double rr = std::sqrt(std::max(0.0, 1.0 - z * z));
              acc += gw[i] * gw[j] * 0.25 * dz * dp * pdf(Vec3d(rr * std::cos(phi), rr * std::sin(phi), z));
            }
      expected[ti * phi_bins + pi] = acc * double(n_samples);
      integral += acc;
    }
  expected[nb] = std::max(0.0, 1.0 - integral) * double(n_samples);
  r.pdf_integral = integral;
  r.accepted_fraction = double(accepted) / double(n_samples);

  PearsonOptions o;
  o.max_in_empty_cell = double(n_samples) * 1e-5;
  const PearsonResult p = pearson_chi2(observed, expected, o);
  r.chi2 = p.chi2;
  r.dof = p.dof;
  r.p_value = p.p_value;
  r.message = p.message;
  return r;
}

}  // namespace aniso::test
