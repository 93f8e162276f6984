// rgl/rgl_check.cpp: how well a file reproduces its source: the round-trip score export_rgl
// chooses by, and compare_rgl (export-rgl --check).
#include "rgl/export_detail.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "stats/rng.h"

namespace aniso::rgl {

ViewError compare_view(const SourceModel& src, const std::function<glm::dvec3(const Vec3d& wi, const Vec3d& wo)>& f,
                       const Vec3d& wo, int samples, uint64_t seed) {
  Rng rng(seed);
  double diff = 0.0, ref = 0.0, a_src = 0.0, a_f = 0.0;
  for (int k = 0; k < samples; ++k) {
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    Vec3d wi;
    if (k % 2 == 0) {
      const BSDFSampleT<double> s = src.sample(wo, rng.uniform(), u);
      if (!s.valid) continue;  // counted: the estimator divides by all samples
      wi = s.wi;
    } else {
      wi = sample_cosine_hemisphere(u);
    }
    const double pdf = 0.5 * src.pdf(wi, wo) + 0.5 * cosine_hemisphere_pdf(wi.z);
    if (!(pdf > 0.0) || !(wi.z > 0.0)) continue;
    const glm::dvec3 fs = src.f(wi, wo), ff = f(wi, wo);
    const double w = wi.z / pdf;
    diff += (std::abs(ff.x - fs.x) + std::abs(ff.y - fs.y) + std::abs(ff.z - fs.z)) * w;
    ref += (fs.x + fs.y + fs.z) * w;
    a_src += luminance_of(fs) * w;
    a_f += luminance_of(ff) * w;
  }
  return {ref > 0.0 ? diff / ref : 0.0, a_src > 0.0 ? std::abs(a_f - a_src) / a_src : 0.0};
}

// How well a written file reproduces src: the mean over viewing directions (elevations 10, 30, 50,
// 65, 75 and 85 degrees; 4 azimuths when anisotropic) of the cosine-weighted relative L1 of f plus
// the albedo's relative error, by importance sampling (half the file's own sampler, half cosine;
// 1000 samples, fixed seeds). Only f of the source is needed (negative values clipped to 0).
double roundtrip_score(const BrdfSource& src, const std::vector<TensorField>& fields) {
  const std::shared_ptr<RglData> d = rgl_from_tensor(parse_tensor(serialize_tensor(fields), "candidate.bsdf"));
  const RglT<double> k = rgl_kernel<double>(*d);
  // compare_view samples by the file and measures the file's f against the source's.
  const SourceModel by_file{[&](const Vec3d& wi, const Vec3d& wo) { return glm::max(src.f(wi, wo), glm::dvec3(0.0)); },
                            [&](const Vec3d& wi, const Vec3d& wo) { return k.pdf(wi, wo); },
                            [&](const Vec3d& wo, double uc, const Vec2T<double>& u) { return k.sample(wo, uc, u); }};
  const auto file_f = [&](const Vec3d& wi, const Vec3d& wo) { return k.f(wi, wo); };
  double sum = 0.0;
  int count = 0;
  const int np = d->isotropic ? 1 : 4;
  for (const double th_deg : {10.0, 30.0, 50.0, 65.0, 75.0, 85.0})
    for (int a = 0; a < np; ++a) {
      const Vec3d wo = dir(th_deg * kPiD / 180.0, 2.0 * kPiD * (a + 0.25) / np);
      const ViewError e = compare_view(by_file, file_f, wo, 1000, 4321 + uint64_t(th_deg) * 11 + uint64_t(a));
      sum += e.l1 + e.albedo;
      ++count;
    }
  return sum / count;
}

SourceModel source_model(const MaterialD& m) {
  return {[m](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(wi, wo)); },
          [m](const Vec3d& wi, const Vec3d& wo) { return m.pdf(wi, wo); },
          [m](const Vec3d& wo, double uc, const Vec2T<double>& u) { return m.sample(wo, uc, u); }};
}

RoundTripStats compare_rgl(const SourceModel& src, const RglT<double>& file, int samples) {
  RoundTripStats r;
  int count = 0;
  const auto file_f = [&](const Vec3d& wi, const Vec3d& wo) { return file.f(wi, wo); };
  for (int ti = 0; ti <= 4; ++ti)
    for (const double phi_deg : {0.0, 60.0, 120.0, 210.0, 300.0}) {
      const Vec3d wo = dir(ti * 20.0 * kPiD / 180.0, phi_deg * kPiD / 180.0);
      const ViewError e = compare_view(src, file_f, wo, samples, 1234 + uint64_t(ti) * 7 + uint64_t(phi_deg));
      if (e.l1 > r.l1_max) {
        r.l1_max = e.l1;
        r.worst_theta_deg = ti * 20.0;
        r.worst_phi_deg = phi_deg;
      }
      r.albedo_max = std::max(r.albedo_max, e.albedo);
      r.l1_by_theta[ti] = std::max(r.l1_by_theta[ti], e.l1);
      r.l1_mean += e.l1;
      ++count;
    }
  r.l1_mean /= count;
  return r;
}

}  // namespace aniso::rgl
