// tests/chi2.h: chi-square goodness-of-fit of a sampler against its pdf, binned over the upper
// hemisphere, after pbrt-v4's bsdfs_test.cpp (Pearson's test with pooling of sparse bins, Sidak
// correction for the number of tests) and Mitsuba's ChiSquareTest.
//
// Samples that sample() rejects ("no sample") land in an extra cell whose expected frequency is
// N (1 - integral of pdf): so the test also checks that the pdf integrates to the acceptance rate.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <boost/math/special_functions/gamma.hpp>

#include "aniso/brdf/material.h"
#include "stats/rng.h"

namespace aniso::test {

struct Chi2Result {
  double p_value = 0.0;
  double chi2 = 0.0;
  int dof = 0;
  double pdf_integral = 0.0;  // integral of pdf over the hemisphere (numerical)
  double accepted_fraction = 0.0;
  std::string message;
};

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

  // Pool cells with expected < 5 (Pearson's rule of thumb, as pbrt-v4 does), smallest first.
  std::vector<int> order(nb + 1);
  for (int i = 0; i <= nb; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pooled_exp = 0.0, pooled_obs = 0.0, chi2 = 0.0;
  int dof = 0;
  for (int idx : order) {
    if (expected[idx] == 0.0) {
      if (observed[idx] > double(n_samples) * 1e-5) {
        r.message = "samples fell where the pdf is zero (cell " + std::to_string(idx) + ", " + std::to_string(observed[idx]) +
                    " samples)";
        return r;
      }
      continue;
    }
    if (expected[idx] < 5.0) {
      pooled_exp += expected[idx];
      pooled_obs += observed[idx];
    } else {
      chi2 += (observed[idx] - expected[idx]) * (observed[idx] - expected[idx]) / expected[idx];
      ++dof;
    }
  }
  if (pooled_exp > 0.0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  }
  dof -= 1;  // the total is fixed
  r.chi2 = chi2;
  r.dof = dof;
  r.p_value = dof > 0 ? boost::math::gamma_q(dof / 2.0, chi2 / 2.0) : 1.0;
  return r;
}

}  // namespace aniso::test
