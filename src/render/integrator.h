// render/integrator.h: the path tracer.
//
// Unidirectional path tracing with next-event estimation at every vertex (every light and the
// environment, one sample each) and multiple importance sampling of lights and BRDFs with the power
// heuristic (Veach & Guibas 1995; Veach's thesis, Ch. 9; pbrt-v4 PathIntegrator). Russian roulette
// from the fourth vertex on. The integrator knows nothing of the models: it sees a MaterialT and a
// shading frame.
//
// Strategies: mis (both techniques, weighted), bsdf (emission found by BRDF sampling only: point
// and directional lights are invisible to it, having zero area), light (next-event estimation
// only; BRDF sampling still extends paths but the emission it finds is not counted beyond the
// camera ray). All three estimate the same image where every light can be reached by both.
//
// Determinism: every pixel sample draws its random numbers from its own generator, seeded from
// (seed, pixel, sample index) alone, so the image is the same for any thread count or tile order.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>

#include "render/geometry.h"
#include "render/image.h"
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

// The per-sample random numbers: PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation", pcg32 XSH-RR), its state and stream
// derived from (seed, pixel, sample) by SplitMix64 (Steele et al. 2014) so that neighbouring
// pixels get unrelated sequences.
class Sampler {
 public:
  Sampler(uint64_t seed, uint64_t pixel, uint64_t sample);
  uint32_t next_u32();
  float uniform() { return float(next_u32() >> 8) * 0x1.0p-24f; }  // [0, 1), 24 bits: never 1
  Vec2 uniform2() {
    const float a = uniform();
    return Vec2(a, uniform());
  }

 private:
  uint64_t state_ = 0, inc_ = 1;
};

class PathTracer {
 public:
  PathTracer(const Scene& scene, const SceneGeometry& geometry) : scene_(scene), geo_(geometry) {}
  // One path's radiance estimate along a camera ray; *rays counts the rays cast.
  RGB li(Ray ray, Sampler& rng, uint64_t* rays) const;
  Ray camera_ray(float px, float py) const;  // px, py in pixels from the top-left corner

 private:
  const Scene& scene_;
  const SceneGeometry& geo_;
};

}  // namespace aniso::render
