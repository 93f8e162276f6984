// render/integrator.h: the path tracer.
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
// wins with the gallery's three candidates and "power" from seven on.
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

#include <atomic>
#include <cstdint>
#include <functional>

#include "render/geometry.h"
#include "render/image.h"
#include "render/sampler.h"
#include "render/scene.h"

namespace aniso::render {

struct RenderOptions {
  int threads = 0;        // 0 = all cores
  uint64_t seed = 1;
  int spp = -1;           // -1: the scene's film.spp
  const std::atomic<bool>* cancel = nullptr;  // set (e.g. by SIGINT) to stop early
  // Called now and then (from one thread at a time) with the fraction done, for progress bars.
  std::function<void(double fraction)> progress;
};

struct RenderStats {
  double seconds = 0.0;
  uint64_t paths = 0;          // camera samples traced
  uint64_t rays = 0;           // closest-hit and shadow rays cast into the BVH
  uint64_t nonfinite = 0;      // samples dropped for a NaN or Inf (a bug if ever > 0)
  int spp_done = 0;            // full passes completed (less than asked when cancelled)
  bool cancelled = false;
};

// Radiance arriving through the camera at each pixel: the average over the pixel's footprint
// (box filter) of spp samples. Pixels finish in passes of samples over the whole image, so a
// cancelled render is a complete image with fewer samples per pixel (pixels of the interrupted
// pass may carry one pass more than others; each is divided by its own count).
Image render(const Scene& scene, const RenderOptions& opt, RenderStats* stats = nullptr);

// A ray as cast into the BVH: closest hit (shadow = false) or any hit (shadow = true) in (0, tmax).
struct RecordedRay {
  Ray ray;
  float tmax = INFINITY;
  bool shadow = false;
};

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
};

}  // namespace aniso::render
