// fit/energy.cpp: the albedo grid and the watched directions of the energy constraint (energy.h).
#include "fit/energy.h"

#include <algorithm>
#include <cmath>

#include "aniso/core/sampling.h"
#include "aniso/stats/albedo.h"

namespace aniso::fit_detail {

std::vector<AlbedoAt> albedo_grid(const MaterialD& m, bool anisotropic) {
  std::vector<AlbedoAt> out;
  uint64_t seed = 0xa1bed0;
  for (double theta : kAlbedoThetaDeg)
    for (int k = 0; k < (anisotropic ? kAlbedoPhiSteps : 1); ++k) {
      AlbedoAt a;
      a.theta_deg = theta, a.phi_deg = 180.0 * k / kAlbedoPhiSteps,
      a.wo = direction_from_angles(a.theta_deg * M_PI / 180.0, a.phi_deg * M_PI / 180.0);
      const AlbedoEstimate e = albedo_importance(m, a.wo, kAlbedoSamples, seed++);
      a.value = std::max({e.mean.x, e.mean.y, e.mean.z});
      out.push_back(a);
    }
  std::sort(out.begin(), out.end(), [](const AlbedoAt& a, const AlbedoAt& b) { return a.value > b.value; });
  return out;
}

WatchedDirection watch(const MaterialD& m, const Vec3d& wo, int count, uint64_t seed) {
  WatchedDirection w{wo, {}, {}};
  Rng rng(seed);
  for (int j = 0; j < count; ++j) {
    Vec3d wi;
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    if (j % 2 == 0) {
      const BSDFSampleT<double> s = m.sample(wo, rng.uniform(), u);
      if (!s.valid) continue;  // counts as a zero of the estimator (the denominator stays `count`)
      wi = s.wi;
    } else {
      wi = sample_cosine_hemisphere(u);
    }
    const double q = 0.5 * m.pdf(wi, wo) + 0.5 * std::max(wi.z, 0.0) / M_PI;
    if (!(q > 0.0) || !(wi.z > 0.0)) continue;
    w.wi.push_back(wi);
    w.inv_q.push_back(1.0 / (q * count));
  }
  return w;
}

}  // namespace aniso::fit_detail
