// aniso/render/integrator.h: the path tracer.
//
// Unidirectional path tracing with next-event estimation at every vertex and multiple importance
// sampling of lights and BRDFs with the power heuristic (Veach & Guibas 1995; Veach's thesis,
// Ch. 9; pbrt-v4 PathIntegrator). Russian roulette from the fourth vertex on. The integrator knows
// nothing of the models: it sees a MaterialT and a shading frame.
//
// Light selection (integrator.light_selection, scene.h). "power": next-event estimation picks ONE
// emitter per vertex, the lights and the environment being the candidates, with probability
// proportional to its power (pbrt-v4 PowerLightSampler; PBR 4th ed., Sec. 12.6.2),
// luminance-weighted:
//   point        4 pi I                     (intensity I over the sphere)
//   sphere       pi L * 4 pi r^2            (exitance pi L over its area)
//   directional  pi R^2 E                   (irradiance E through the scene's bounding disc)
//   environment  pi R^2 * integral of L dw  (its radiance through the scene's bounding disc)
// R the radius of the bounding sphere of the scene's geometry (Embree's bounds, sphere lights
// included). The sample's contribution is divided by the probability of its light, and the MIS
// weight of emission found by BRDF sampling uses P(light) * pdf(direction), so the estimator is
// unbiased for any positive probabilities (tests/test_render.cpp, RenderLights.*); the power only
// decides the variance. "all": one sample of every emitter at every vertex (probability 1 each).
// "auto" (default): all when there are at most kAutoAllCandidates candidates, else power. Why:
// with few lights a highlight lit by one of them loses a share of its samples to the others
// under power selection. Measured at equal time (docs/benchmarks.md, "Light selection"), "all"
// wins with the gallery's three candidates and with seven, "power" from thirteen on.
//
// Environment. A constant or nearly constant environment (Environment::nearly_constant: every
// channel within 2% over the sphere) is not a candidate for next-event estimation under the mis
// and bsdf strategies: BRDF sampling alone finds it, and with a cosine- or lobe-proportional
// density it is the better technique there (a Lambert surface under a constant environment gets
// zero variance from it; light sampling's uniform directions add noise through the MIS weights,
// measured in docs/benchmarks.md, "Environment sampling"). Cycles does the same: its background
// light is enabled only when the background shader varies over directions (blender/cycles
// 97dbe6f5, src/scene/light.cpp:548, LightManager::test_enabled_lights:
// `light->is_enabled = has_portal || (light->use_mis && shader->has_surface_spatial_varying)`).
// Under the light strategy it stays a candidate (nothing else would find it).
//
// A sphere light in front of such an environment. BRDF sampling is then the only technique for
// the environment, and a sphere light is a hole in it: a BRDF sample that hits the light gets
// the light's radiance (MIS-weighted) but not the environment's, a rare all-or-nothing event that
// was most of the noise of a Lambert surface lit by a small sphere light and a uniform sky
// (docs/benchmarks.md, "Cycles": 1.1e-3 per-pixel spread at 64 spp, 2.2e-4 with the sky off, 0
// with the light off). Such a light is estimated with the environment behind it as a control
// variate (in the sense of Veach's thesis, Sec. 2.5.3, except that the part split off is not
// integrated analytically but by the BRDF samples that already estimate the environment): over
// the directions in which the light is the first thing seen, its radiance L is split into E(w),
// the environment's radiance in that direction, plus L - E(w). A BRDF sample that hits the
// light counts E(w) in full, as if it had passed through to the sky, and L - E(w) with the MIS
// weight; next-event estimation counts L - E(w) with its MIS weight. The two still sum to L in
// every direction that reaches the light (every scene, every geometry behind the light: E is
// only evaluated, never traced to), so the estimator stays unbiased, and for a constant
// environment the BRDF-sampled sky no longer has a hole. (Cycles' point lamps are transparent
// instead: a path that hits one continues behind it, blender/cycles v3.4.0 df60698d,
// src/kernel/integrator/shade_light.h:83-100, so they do not occlude the sky at all.) Only lights
// at least as bright as the environment in every channel (L >= Environment::max_radiance), so
// that no sample is negative; under mis only (bsdf never light-samples, light samples the
// environment too).
//
// Fireflies (both off by default: the image is then unbiased).
// - integrator.clamp C: every contribution of indirect light (next-event estimation from the
//   second vertex on, emission found by a ray from the second vertex on) is scaled down so that
//   its R + G + B is at most C: Cycles' "Clamp Indirect" (film_clamp_light, src/kernel/film/
//   light_passes.h:126-148, bounce > 0). Direct light is never clamped. Biased: energy is lost
//   where indirect paths are bright, by design.
// - integrator.filter_glossy F: Cycles' "Filter Glossy": after bounces whose BRDF-sample pdf was
//   small (min over the path's pdfs p < F), the material is roughened to at least alpha =
//   sqrt(1 - p / F) / 2 by its model's own rule (MaterialT::regularize, aniso/core/kernel.h:
//   Ward and GGX alphas; Ashikhmin-Shirley and Phong exponents through n = 2 / alpha^2 - 2; the
//   principled model's roughness, anisotropic and clearcoat gloss; Lambert, Lafortune, MERL and
//   RGL tables left as they are). Biased: glossy reflections seen through rough bounces are
//   blurred.
//
// Strategies: mis (both techniques, weighted), bsdf (emission found by BRDF sampling only: point
// and directional lights are invisible to it, having zero area), light (next-event estimation
// only; BRDF sampling still extends paths but the emission it finds is not counted beyond the
// camera ray). All three estimate the same image where every light can be reached by both.
//
// Determinism: every pixel sample draws its random numbers from its own Sampler (render/sampler.h:
// Owen-scrambled Sobol' by default), a function of (seed, pixel, sample index) alone, so the image
// is the same for any thread count or tile order.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>

#include "aniso/image/image.h"
#include "aniso/render/geometry.h"
#include "aniso/render/sampler.h"
#include "aniso/render/scene.h"

namespace aniso::render {

// What a finished pass reports (RenderOptions::on_pass), for progress displays.
struct PassReport {
  int pass = 0;                  // passes finished
  int spp = 0;                   // samples per pixel of the pixels still sampled (the pass's end)
  double active_fraction = 1.0;  // share of pixels still sampled in the next pass (adaptive sampling)
  double seconds = 0.0;          // since the render started
};

struct RenderOptions {
  int threads = 0;  // 0 = all cores
  uint64_t seed = 1;
  int spp = -1;                               // -1: the scene's film.spp
  const std::atomic<bool>* cancel = nullptr;  // set (e.g. by SIGINT) to stop early
  // Called now and then (from one thread at a time) with the fraction done, for progress bars.
  std::function<void(double fraction)> progress;
  // Called after every pass (from the calling thread).
  std::function<void(const PassReport&)> on_pass;
};

struct RenderStats {
  double seconds = 0.0;
  uint64_t paths = 0;      // camera samples traced
  uint64_t rays = 0;       // closest-hit and shadow rays cast into the BVH
  uint64_t nonfinite = 0;  // samples dropped for a NaN or Inf (a bug if ever > 0)
  int spp_done = 0;        // samples per pixel of the passes completed over the whole image (0:
                           // not even the first pass finished; the image is then not whole)
  int passes = 0;          // passes completed
  double mean_spp = 0.0;   // samples per pixel on average (below spp_done with adaptive sampling)
  bool cancelled = false;
  bool converged = false;    // adaptive sampling stopped every pixel before film.spp
  bool out_of_time = false;  // film.time_s ended the render before film.spp
};

// Radiance arriving through the camera at each pixel: the average over the pixel's footprint
// (box filter) of spp samples.
//
// Passes. Samples are taken in passes over the whole image: 1, 1, 2, 4, 8 samples per pixel, then
// 16 per pass (kMaxPassSpp), so that a whole picture exists after the first sample of every pixel.
// A cancelled render (RenderOptions::cancel, checked before every pixel: Ctrl-C is seen within one
// pixel's samples of a pass) is a whole image when stats.spp_done > 0; pixels of the interrupted
// pass may carry one pass more than others (each is divided by its own count).
//
// Adaptive sampling (film.noise_threshold T > 0): after each pass from film.min_spp on, a pixel
// whose error estimate is below T stops being sampled, as do its 3 x 3 neighbours once they all are
// (Cycles' dilation, kernel/film/adaptive_sampling.h, film_adaptive_sampling_filter_x/_y). The
// error estimate is the standard error of the pixel's mean of I = R + G + B (from the sample
// variance of I), divided by sqrt(I) where I < 1 and by I above: Cycles' normalisation
// (film_adaptive_sampling_convergence_check: "Filmic-like curves need maximum sampling rate at
// intensity near 0.1-0.2"), whose error itself is |mean - mean of the even samples| instead.
//
// Time budget (film.time_s > 0, wall clock from the call): passes until the budget; a pass whose
// predicted end lies past the budget is not started. The prediction is the pass's samples times the
// time per sample measured over all passes so far (sum of their seconds over sum of their samples),
// so that one pass slowed by other processes does not end the render early. The first pass
// always runs.
//
// Determinism: the decisions are taken between passes from the samples alone, so the image is
// the same for a seed whatever the thread count; a time-limited render equals the render with
// spp = its stats.spp_done (same passes).
Image render(const Scene& scene, const RenderOptions& opt, RenderStats* stats = nullptr);

// The pass schedule: the sample index at which the pass after the one ending at `spp_so_far` ends.
inline constexpr int kMaxPassSpp = 16;
int next_pass_end(int spp_so_far, int spp_max);
// film.min_spp = 0 with a noise threshold: Cycles' automatic minimum, max(4, ceil(16 / T^0.3))
// (scene/integrator.cpp, Integrator::get_adaptive_sampling: "Threshold 0.1 -> 32, 0.01 -> 64").
int automatic_min_spp(float noise_threshold);
// Adaptive sampling's error estimate of a pixel (above): the standard error sqrt(variance / n) of
// the mean of I = R + G + B over n samples, divided by sqrt(mean) below 1 and by the mean above,
// plus Cycles' 1e-4 against a division by zero (a black pixel with zero variance converges).
inline double adaptive_error(double mean, double variance, double n) {
  const double norm = mean < 1.0 ? std::sqrt(std::max(mean, 0.0)) : mean;
  return std::sqrt(std::max(variance, 0.0) / n) / (1e-4 + norm);
}

// A ray as cast into the BVH: closest hit (shadow = false) or any hit (shadow = true) in (0, tmax).
struct RecordedRay {
  Ray ray;
  float tmax = INFINITY;
  bool shadow = false;
};

// Next-event estimation's test for passing over a sphere light (integrator.cpp): every direction
// from p towards l lies below the plane of the geometric normal ng, where any sample of it would be
// rejected. Exposed for tests, with the direction next-event estimation samples for u (zero when
// l gives no sample from p).
bool sphere_light_below(const Light& l, const Vec3& p, const Vec3& ng);
Vec3 sphere_light_sample_direction(const Light& l, const Vec3& p, const Vec2& u);

class PathTracer {
 public:
  PathTracer(const Scene& scene, const SceneGeometry& geometry);
  // One path's radiance estimate along a camera ray; *rays counts the rays cast. With `record`,
  // every ray cast is also appended to it (the benchmark replays them through Embree alone).
  RGB li(Ray ray, Sampler& rng, uint64_t* rays, std::vector<RecordedRay>* record = nullptr) const;
  // The probability next-event estimation picks light i (i == lights.size(): the environment).
  float light_probability(size_t i) const { return i < light_prob_.size() ? light_prob_[i] : 0.0f; }
  Ray camera_ray(float px, float py) const;  // px, py in pixels from the top-left corner

 private:
  // Picks a candidate with probability light_prob_ (-1: none has power).
  int pick_light(float u) const;

  const Scene& scene_;
  const SceneGeometry& geo_;
  std::vector<float> light_prob_, light_cdf_;  // lights, then the environment
  bool sample_all_ = false;                    // every candidate at every vertex (light_prob_ all 1)
  // Per light: estimated with the environment behind it as a control variate ("A sphere light in
  // front of such an environment" above).
  std::vector<uint8_t> env_behind_light_;
  // The camera's basis and screen scales, fixed per scene (camera_ray).
  Vec3 cam_fwd_{0.0f}, cam_right_{0.0f}, cam_up_{0.0f};
  float cam_tan_half_ = 0.0f, cam_aspect_ = 1.0f;
  float cam_two_over_w_ = 0.0f, cam_two_over_h_ = 0.0f;  // 2 / film width and height (camera_ray)
};

}  // namespace aniso::render
