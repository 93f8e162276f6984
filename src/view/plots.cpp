// view/plots.cpp: the explorer's plot data (view/plots.h).
#include "view/plots.h"

#include <algorithm>
#include <cmath>

#include "aniso/batch/batch.h"

namespace aniso::view {

std::vector<PolarSample> polar_slice(const MaterialT<double>& m, const Vec3T<double>& wi, double plane_phi_deg, int samples,
                                     bool times_cos) {
  std::vector<PolarSample> out;
  out.reserve(size_t(std::max(samples, 2)));
  const double phi = glm::radians(plane_phi_deg);
  const int n = std::max(samples, 2);
  for (int i = 0; i < n; ++i) {
    PolarSample s;
    s.theta_deg = -90.0 + 180.0 * double(i) / double(n - 1);
    const double t = glm::radians(s.theta_deg);
    // Signed theta in the slice: sin t along (cos phi, sin phi), so negative t lies at phi + 180.
    s.wo = Vec3T<double>(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
    const RGBT<double> f = m.f(wi, s.wo);
    s.f = glm::dvec3(f.x, f.y, f.z);
    s.value = luminance(s.f) * (times_cos ? std::max(0.0, s.wo.z) : 1.0);
    out.push_back(s);
  }
  return out;
}

double plot_radius(double value, double max_value, bool log_scale) {
  if (!(max_value > 0.0) || !(value > 0.0)) return 0.0;
  if (!log_scale) return std::min(value / max_value, 1.0);
  return std::clamp((std::log10(value / max_value) + kLogDecades) / kLogDecades, 0.0, 1.0);
}

void albedo_uniforms(int j, int n, double* uc, double* u0, double* u1) {
  // A k x k grid of strata over (u0, u1), one sample at each stratum's centre, and uc stratified
  // over [0, 1) in an order decorrelated from the grid (multiplicative step by a prime).
  const int k = std::max(1, int(std::lround(std::sqrt(double(n)))));
  const int cell = j % (k * k);
  *u0 = (double(cell % k) + 0.5) / double(k);
  *u1 = (double(cell / k) + 0.5) / double(k);
  const long long perm = (static_cast<long long>(j) * 7919LL) % static_cast<long long>(n);
  *uc = (double(perm) + 0.5) / double(n);
}

std::vector<AlbedoPoint> albedo_curve(const MaterialT<double>& m, double phi_deg, int thetas, int samples_per_theta) {
  const int nt = std::max(thetas, 2), ns = std::max(samples_per_theta, 1);
  const size_t total = size_t(nt) * size_t(ns);
  std::vector<double> wx(total), wy(total), wz(total), uc(total), u0(total), u1(total);
  std::vector<double> ix(total), iy(total), iz(total), r(total), g(total), b(total), pdf(total);
  std::vector<uint8_t> valid(total);
  const double phi = glm::radians(phi_deg);
  std::vector<AlbedoPoint> out(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    // 0 to 89 degrees: at 90 the albedo of every model is 0 by the cosine of wo (docs/conventions.md).
    out[size_t(t)].theta_deg = 89.0 * double(t) / double(nt - 1);
    const double th = glm::radians(out[size_t(t)].theta_deg);
    for (int j = 0; j < ns; ++j) {
      const size_t i = size_t(t) * size_t(ns) + size_t(j);
      wx[i] = std::sin(th) * std::cos(phi), wy[i] = std::sin(th) * std::sin(phi), wz[i] = std::cos(th);
      albedo_uniforms(j, ns, &uc[i], &u0[i], &u1[i]);
    }
  }
  batch::Samples<double> s{ix.data(), iy.data(), iz.data(), r.data(), g.data(), b.data(), pdf.data(), valid.data()};
  batch::sample(m, batch::Directions<double>{wx.data(), wy.data(), wz.data()}, uc.data(), u0.data(), u1.data(), total, s);
  for (int t = 0; t < nt; ++t) {
    glm::dvec3 sum(0.0);
    for (int j = 0; j < ns; ++j) {
      const size_t i = size_t(t) * size_t(ns) + size_t(j);
      if (valid[i]) sum += glm::dvec3(r[i], g[i], b[i]);
    }
    out[size_t(t)].albedo = sum / double(ns);
  }
  return out;
}

LobeMesh lobe_mesh(const MaterialT<double>& m, const Vec3T<double>& wi, int n_theta, int n_phi, bool times_cos) {
  LobeMesh mesh;
  const int nt = std::max(n_theta, 2), np = std::max(n_phi, 3);
  std::vector<double> v;
  std::vector<Vec3T<double>> dirs;
  v.reserve(size_t(nt + 1) * size_t(np));
  for (int i = 0; i <= nt; ++i) {
    const double th = 0.5 * kPi<double> * double(i) / double(nt);
    for (int j = 0; j < np; ++j) {
      const double ph = 2.0 * kPi<double> * double(j) / double(np);
      const Vec3T<double> wo(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const RGBT<double> f = m.f(wi, wo);
      double value = luminance(glm::dvec3(f.x, f.y, f.z)) * (times_cos ? wo.z : 1.0);
      if (!std::isfinite(value) || value < 0.0) value = 0.0;  // a degenerate model value draws nothing
      v.push_back(value);
      dirs.push_back(wo);
      mesh.max_value = std::max(mesh.max_value, value);
    }
  }
  const double scale = mesh.max_value > 0.0 ? 1.0 / mesh.max_value : 0.0;
  for (size_t k = 0; k < v.size(); ++k) {
    const double rad = v[k] * scale;
    mesh.positions.insert(mesh.positions.end(), {float(dirs[k].x * rad), float(dirs[k].y * rad), float(dirs[k].z * rad)});
    mesh.values.push_back(float(rad));
  }
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const uint32_t a = uint32_t(i * np + j), b = uint32_t(i * np + (j + 1) % np);
      const uint32_t c = a + uint32_t(np), d = b + uint32_t(np);
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  return mesh;
}

}  // namespace aniso::view
