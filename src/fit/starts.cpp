// fit/starts.cpp: the statistics of the data the starts are built from (starts.h).
#include "fit/starts.h"

#include <algorithm>
#include <cmath>

namespace aniso::fit_detail {

DataMoments data_moments(const SampleSet& data) {
  DataMoments m;
  const size_t n = data.samples.size();
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = data.samples[i].value[c];
    const size_t k = n / 20;  // the 5th percentile
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    m.floor_albedo[c] = std::clamp(v[k] * M_PI, 0.0, 1.0);
    double peak = 0.0;
    for (const MeasuredSample& s : data.samples) peak = std::max(peak, s.value[c] - m.floor_albedo[c] / M_PI);
    m.peak[c] = std::max(peak, 1e-6);
  }
  // The mirror exponent: the excess e over the floor against the cosine a to the mirror direction,
  // ln(e / peak) = n ln(a), least squares through the origin over the samples whose excess is at
  // least 1% of the peak.
  const double peak = average(m.peak);
  double num = 0.0, den = 0.0;
  for (const MeasuredSample& s : data.samples) {
    const double e = average(s.value) - average(m.floor_albedo) / M_PI;
    const double a = glm::dot(s.wi, Vec3d(-s.wo.x, -s.wo.y, s.wo.z));
    if (!(e > 0.01 * peak) || !(a > 0.0) || !(a < 1.0)) continue;
    const double la = std::log(a);
    num += std::log(std::min(e / peak, 1.0)) * la;
    den += la * la;
  }
  m.mirror_exponent = den > 0.0 ? std::clamp(num / den, 1.0, 1e4) : 10.0;
  return m;
}

}  // namespace aniso::fit_detail
