// examples/cpp/path_tracer_loop.cpp: the kernels in one's own path tracer (CMake aniso::host).
//
//   path_tracer_loop [MATERIAL [THETA_O_DEG [PHI_O_DEG]]]     default: brushed-gold 60 30
//
// A surface lit by a uniform white environment of radiance 1 reflects, towards wo, its directional
// albedo rho(wo) = integral of f(wi, wo) cos(theta_i) dwi (docs/conventions.md). This program
// estimates it the way a path tracer shades one bounce, in float as a renderer would:
//   1. BSDF sampling: wi from material.sample(), the path's throughput times sample.weight
//      (= f cos / pdf);
//   2. multiple importance sampling (Veach 1997, Sec. 9.2, the balance heuristic) of the BSDF
//      sampler with a cosine-weighted "light" sampler, which needs f() and pdf() as well;
// and checks both against the library's own estimator, aniso::albedo_importance
// (include/aniso/stats/albedo.h, what `aniso albedo` prints): each must agree within 5 standard
// errors. Exit status 1 otherwise, 2 for a bad material.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>

#include <aniso/io/input_error.h>
#include <aniso/io/materials.h>
#include <aniso/kernels.h>
#include <aniso/stats/albedo.h>

namespace {

using aniso::Vec3;  // float, as in a renderer

// Mean and standard error of the mean, per channel.
struct Estimate {
  glm::dvec3 sum{0.0}, sum2{0.0};
  long n = 0;
  void add(const glm::dvec3& x) { sum += x, sum2 += x * x, ++n; }
  glm::dvec3 mean() const { return sum / double(n); }
  glm::dvec3 std_error() const { return glm::sqrt(glm::max(sum2 / double(n) - mean() * mean(), 0.0) / double(n)); }
};

}  // namespace

int main(int argc, char** argv) {
  const std::string spec = argc > 1 ? argv[1] : "brushed-gold";
  const float theta_o = float((argc > 2 ? std::atof(argv[2]) : 60.0) * std::numbers::pi / 180.0);
  const float phi_o = float((argc > 3 ? std::atof(argv[3]) : 30.0) * std::numbers::pi / 180.0);

  aniso::MaterialDesc desc;
  try {
    desc = aniso::load_material(spec);
  } catch (const aniso::InputError& e) {
    std::fprintf(stderr, "path_tracer_loop: %s\n", e.what());
    return 2;
  }
  const aniso::Material material = aniso::build_material<float>(desc);  // MaterialT<float>

  // The hit point's shading frame: the world normal and the mesh's tangent (any length, not
  // orthogonal to n: Gram-Schmidt makes the frame, aniso/core/frame.h). The kernels work in this
  // frame's coordinates: z = normal, x = tangent.
  const Vec3 normal = glm::normalize(Vec3(0.3f, -0.2f, 1.0f));
  const aniso::Frame frame = aniso::Frame::from_normal_tangent(normal, Vec3(1.0f, 0.5f, 0.0f));
  // The camera ray arrives along -wo; wo points away from the surface, towards the viewer.
  const Vec3 wo_local(std::sin(theta_o) * std::cos(phi_o), std::sin(theta_o) * std::sin(phi_o), std::cos(theta_o));
  const Vec3 wo_world = frame.to_world(wo_local);

  std::mt19937_64 rng(7);
  // Uniform floats in [0, 1), what sample() expects: a double in [0, 1) can round up to 1.0f, so
  // the largest float below 1 caps it.
  std::uniform_real_distribution<double> uniform_double(0.0, 1.0);
  const auto uniform = [&] { return std::min(float(uniform_double(rng)), 0x1.fffffep-1f); };
  constexpr long kSamples = 1 << 20;
  Estimate bsdf_sampling, mis;
  for (long i = 0; i < kSamples; ++i) {
    const Vec3 wo = frame.to_local(wo_world);  // world -> local, as at every hit

    // 1. BSDF sampling. uc picks the lobe, u places the direction. "No sample" (valid == false:
    // wo or the sampled wi at or below the horizon) ends the path: it counts as 0, which keeps the
    // estimator unbiased.
    const float uc = uniform();
    const aniso::BSDFSampleT<float> s = material.sample(wo, uc, aniso::Vec2(uniform(), uniform()));
    glm::dvec3 throughput(0.0);
    if (s.valid) {
      throughput = glm::dvec3(s.weight);                 // f cos / pdf; the environment's radiance is 1
      const Vec3 next_direction = frame.to_world(s.wi);  // the continuation ray, in world space
      (void)next_direction;
    }
    bsdf_sampling.add(throughput);

    // 2. MIS: one BSDF sample (the one above) and one cosine-weighted sample (a stand-in for a
    // light sampler), each weighted by the balance heuristic p_own / (p_bsdf + p_cos).
    glm::dvec3 combined(0.0);
    if (s.valid) {
      const float p_cos = aniso::cosine_hemisphere_pdf(s.wi.z);
      combined += glm::dvec3(material.f(s.wi, wo) * s.wi.z) / double(s.pdf + p_cos);
    }
    const Vec3 wl = aniso::sample_cosine_hemisphere(aniso::Vec2(uniform(), uniform()));
    const float p_light = aniso::cosine_hemisphere_pdf(wl.z), p_bsdf = material.pdf(wl, wo);
    if (p_light > 0.0f) combined += glm::dvec3(material.f(wl, wo) * wl.z) / double(p_light + p_bsdf);
    mis.add(combined);
  }

  // The library's estimator on the same direction (stratified importance sampling, batch path).
  const aniso::AlbedoEstimate reference = aniso::albedo_importance(material, wo_local, int64_t(1) << 20, 1);

  std::printf("material %s, theta_o %.1f deg, phi_o %.1f deg\n", spec.c_str(), theta_o * 180.0 / std::numbers::pi,
              phi_o * 180.0 / std::numbers::pi);
  int failures = 0;
  const auto report = [&](const char* name, const glm::dvec3& mean, const glm::dvec3& se) {
    std::printf("%-24s %.5f %.5f %.5f  (std. error %.1e %.1e %.1e)\n", name, mean.x, mean.y, mean.z, se.x, se.y, se.z);
    for (int c = 0; c < 3; ++c) {
      const double tolerance = 5.0 * std::sqrt(se[c] * se[c] + reference.std_error[c] * reference.std_error[c]);
      if (std::abs(mean[c] - reference.mean[c]) > tolerance) {
        std::printf("  MISMATCH channel %d: %.6f vs albedo_importance %.6f (tolerance %.1e)\n", c, mean[c], reference.mean[c],
                    tolerance);
        ++failures;
      }
    }
  };
  report("aniso::albedo_importance", reference.mean, reference.std_error);
  report("BSDF sampling", bsdf_sampling.mean(), bsdf_sampling.std_error());
  report("MIS (BSDF + cosine)", mis.mean(), mis.std_error());
  return failures ? 1 : 0;
}
