// examples/cpp/batch.cpp: f, pdf and sample of many direction pairs in one call (CMake
// aniso::host for load_material; the batch functions alone are aniso::batch).
//
//   batch [MATERIAL [N]]     default: brushed-gold 200000
//
// The batch API (include/aniso/batch/batch.h) takes structure-of-arrays input (one array per
// coordinate) and runs Highway SIMD twins of the kernels on all cores through oneTBB. This program
// evaluates N random direction pairs both ways, batch and the scalar MaterialT::f / pdf / sample,
// and checks that they agree within 1e-5 relative (the bound batch.h states; values below 1e-12 of
// the largest are compared absolutely). Exit status 1 otherwise, 2 for a bad material.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <aniso/batch/batch.h>
#include <aniso/io/input_error.h>
#include <aniso/io/materials.h>

namespace {

// Largest |a - b| / max(|b|, floor) seen, for the report.
struct Worst {
  double relative = 0.0;
  void add(double a, double b, double floor) { relative = std::max(relative, std::abs(a - b) / std::max(std::abs(b), floor)); }
};

}  // namespace

int main(int argc, char** argv) {
  namespace batch = aniso::batch;
  const std::string spec = argc > 1 ? argv[1] : "brushed-gold";
  const size_t n = argc > 2 ? size_t(std::atol(argv[2])) : 200000;

  aniso::MaterialD material;
  try {
    material = aniso::build_material<double>(aniso::load_material(spec));
  } catch (const aniso::InputError& e) {
    std::fprintf(stderr, "batch: %s\n", e.what());
    return 2;
  }

  // N random pairs on the upper hemisphere (uniform in solid angle: z uniform in [0, 1)), held in
  // the owning SoA buffers of batch.h; set(i, w) writes direction i.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const auto random_direction = [&] {
    const double z = uniform(rng), phi = 2.0 * std::numbers::pi * uniform(rng), r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return aniso::Vec3d(r * std::cos(phi), r * std::sin(phi), z);
  };
  batch::DirectionArray<double> wi(n), wo(n);
  std::vector<double> uc(n), u0(n), u1(n);
  for (size_t i = 0; i < n; ++i) {
    wi.set(i, random_direction());
    wo.set(i, random_direction());
    uc[i] = uniform(rng), u0[i] = uniform(rng), u1[i] = uniform(rng);
  }

  // The three calls. Threads::All (the default) splits the pairs into fixed blocks over the cores;
  // the result does not depend on the thread count.
  batch::ColorArray<double> f(n);
  std::vector<double> pdf(n);
  batch::SampleArray<double> samples(n);
  batch::evaluate(material, wi.view(), wo.view(), n, f.view());
  batch::pdf(material, wi.view(), wo.view(), n, pdf.data());
  batch::sample(material, wo.view(), uc.data(), u0.data(), u1.data(), n, samples.view());

  // The scalar kernels on the same input.
  double peak_f = 0.0, peak_pdf = 0.0;
  for (size_t i = 0; i < n; ++i) {
    peak_f = std::max(peak_f, aniso::max_component(material.f(wi.get(i), wo.get(i))));
    peak_pdf = std::max(peak_pdf, material.pdf(wi.get(i), wo.get(i)));
  }
  Worst worst_f, worst_pdf, worst_sample;
  size_t validity_flips = 0;
  for (size_t i = 0; i < n; ++i) {
    const aniso::RGBT<double> scalar_f = material.f(wi.get(i), wo.get(i));
    for (int c = 0; c < 3; ++c) worst_f.add(f.get(i)[c], scalar_f[c], 1e-12 * peak_f);
    worst_pdf.add(pdf[i], material.pdf(wi.get(i), wo.get(i)), 1e-12 * peak_pdf);
    const aniso::BSDFSampleT<double> s = material.sample(wo.get(i), uc[i], aniso::Vec2T<double>(u0[i], u1[i]));
    const aniso::BSDFSampleT<double> b = samples.get(i);
    if (s.valid != b.valid) {
      ++validity_flips;  // a sampled wi within rounding of the horizon may go either way
      continue;
    }
    if (!s.valid) continue;
    for (int c = 0; c < 3; ++c) worst_sample.add(b.wi[c], s.wi[c], 1e-6);  // unit vectors: 1e-6 absolute near 0
  }

  std::printf("material %s, %zu pairs, SIMD target %s (%zu double lanes)\n", spec.c_str(), n, batch::simd_target(),
              batch::simd_lanes_double());
  std::printf("batch vs scalar, largest relative difference: f %.2e, pdf %.2e, sampled wi %.2e; validity flips %zu\n",
              worst_f.relative, worst_pdf.relative, worst_sample.relative, validity_flips);
  const bool ok =
      worst_f.relative <= 1e-5 && worst_pdf.relative <= 1e-5 && worst_sample.relative <= 1e-5 && validity_flips <= n / 100000;
  if (!ok) std::printf("MISMATCH: beyond 1e-5 relative\n");
  return ok ? 0 : 1;
}
