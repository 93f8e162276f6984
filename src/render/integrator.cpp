// render/integrator.cpp: path tracing with next-event estimation and MIS (see integrator.h); the
// light sampling it calls is lights.cpp.
#include "aniso/render/integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <new>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "aniso/core/sampling.h"
#include "render/lights.h"

namespace aniso::render {
namespace {

// Power heuristic with beta = 2 (Veach 1997, Eq. 9.13), for one sample of each technique.
float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  if (!(a > 0.0f)) return 0.0f;
  if (std::isinf(a)) return 1.0f;
  return a / (a + b);
}

// The roughness a BSDF-sample pdf along the path asks for under the glossy filter: Cycles'
// surface_shader_prepare_closures (blender/cycles 97dbe6f5, src/kernel/integrator/
// surface_shader.h:189-200): blur_pdf = min_ray_pdf / filter_glossy, and where it is below 1 every
// closure's roughness is raised to sqrt(1 - blur_pdf) / 2 (bsdf_blur). 0: no blur.
float blur_roughness(float min_ray_pdf, float filter_glossy) {
  if (!(filter_glossy > 0.0f) || !std::isfinite(min_ray_pdf)) return 0.0f;
  const float blur_pdf = min_ray_pdf / filter_glossy;
  return blur_pdf < 1.0f ? std::sqrt(1.0f - blur_pdf) * 0.5f : 0.0f;
}

// The models whose lobe choice and pdf share weights that depend on wo alone (MetalT and
// LafortuneT: `sampling_weights(wo)`, a Fresnel term or a pow per channel), with pdf() and sample()
// overloads that take them.
template <typename M>
concept HasSamplingWeights = requires(const M& m, const Vec3& w) {
  m.sampling_weights(w);
};

template <typename M> constexpr size_t sampling_weights_size() {
  if constexpr (HasSamplingWeights<M>) return sizeof(typename M::SamplingWeights);
  return 1;
}
constexpr size_t kSamplingWeightsSize = std::max({
#define ANISO_X(Tag, Type, member, name, batch, glsl) sampling_weights_size<Type<float>>(),
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
});

// A material at one shading point, wo fixed: its f, f with pdf, and sample as Material's (bit for bit),
// with the model's wo-dependent weights computed once here and shared by every next-event pdf and
// the BRDF sample of the vertex (four uses with two lights and the sky, each sampled at every
// vertex as light_selection "auto" does for so few emitters).
class MaterialAtWo {
  // Defined before the generic lambdas below call it: clang 14 leaves a member template first
  // declared after its use in a lambda's body uninstantiated (an undefined reference at link time).
  template <typename M> const typename M::SamplingWeights& weights() const {
    return *std::launder(reinterpret_cast<const typename M::SamplingWeights*>(weights_));
  }

 public:
  MaterialAtWo(const Material& m, const Vec3& wo) : m_(m), o_(m.rotation.to_model(wo)) {
    m.visit([&](const auto& model) {
      using M = std::decay_t<decltype(model)>;
      if constexpr (HasSamplingWeights<M>) {
        using W = typename M::SamplingWeights;
        static_assert(std::is_trivially_destructible_v<W> && alignof(W) <= alignof(std::max_align_t));
        ::new (static_cast<void*>(weights_)) W(model.sampling_weights(o_));
      }
    });
  }
  RGB f(const Vec3& wi) const {
    const Vec3 i = m_.rotation.to_model(wi);
    return m_.visit([&](const auto& model) { return model.f(i, o_); });
  }
  // f(wi) and pdf(wi) together, each bit for bit (model_f_pdf: the models whose value and density
  // share terms compute them once).
  RGB f_pdf(const Vec3& wi, float* pdf_out) const {
    const Vec3 i = m_.rotation.to_model(wi);
    return m_.visit([&](const auto& model) -> RGB {
      using M = std::decay_t<decltype(model)>;
      if constexpr (HasSamplingWeights<M>) {
        if constexpr (requires { model.f_pdf(weights<M>(), i, o_, pdf_out); }) {
          return model.f_pdf(weights<M>(), i, o_, pdf_out);
        } else {
          *pdf_out = model.pdf(weights<M>(), i, o_);
          return model.f(i, o_);
        }
      } else {
        return model_f_pdf(model, i, o_, pdf_out);
      }
    });
  }
  BSDFSampleT<float> sample(float uc, const Vec2& u) const {
    BSDFSampleT<float> s = m_.visit([&](const auto& model) -> BSDFSampleT<float> {
      using M = std::decay_t<decltype(model)>;
      if constexpr (HasSamplingWeights<M>) {
        return model.sample(weights<M>(), o_, uc, u);
      } else {
        return model.sample(o_, uc, u);
      }
    });
    s.wi = m_.rotation.from_model(s.wi);
    return s;
  }

 private:
  const Material& m_;
  Vec3 o_;  // wo turned into the model's frame
  alignas(std::max_align_t) unsigned char weights_[kSamplingWeightsSize];
};

}  // namespace

PathTracer::PathTracer(const Scene& scene, const SceneGeometry& geometry) : scene_(scene), geo_(geometry) {
  const Camera& c = scene.camera;
  cam_fwd_ = glm::normalize(c.look_at - c.position);
  cam_right_ = glm::normalize(glm::cross(cam_fwd_, c.up));
  cam_up_ = glm::cross(cam_right_, cam_fwd_);
  cam_tan_half_ = std::tan(glm::radians(c.fov_deg) * 0.5f);
  cam_aspect_ = float(scene.film.width) / float(scene.film.height);
  cam_two_over_w_ = 2.0f / float(scene.film.width);
  cam_two_over_h_ = 2.0f / float(scene.film.height);
  const float R = std::max(geometry.bounding_radius(), 1e-6f);  // a point-sized scene still lets light in
  std::vector<double> power;
  for (const Light& l : scene.lights) power.push_back(std::max(0.0, double(light_power(l, R))));
  // A (nearly) constant environment is found by BRDF sampling alone unless the strategy is light
  // (integrator.h, "Environment").
  const bool env_by_bsdf_only = scene.environment.nearly_constant() && scene.integrator.strategy != Strategy::Light;
  power.push_back(scene.environment.is_black() || env_by_bsdf_only
                      ? 0.0
                      : std::max(0.0, double(kPi<float> * R * R * scene.environment.luminance_integral())));
  double total = 0.0;
  for (double p : power) total += std::isfinite(p) ? p : 0.0;
  light_prob_.assign(power.size(), 0.0f);
  light_cdf_.assign(power.size() + 1, 0.0f);
  if (!(total > 0.0)) return;  // nothing emits: next-event estimation finds nothing
  double acc = 0.0;
  for (size_t i = 0; i < power.size(); ++i) {
    const double p = std::isfinite(power[i]) ? power[i] : 0.0;
    light_prob_[i] = float(p / total);
    acc += p;
    light_cdf_[i + 1] = float(acc / total);
  }
  light_cdf_.back() = 1.0f;  // exactly: every u < 1 finds a candidate
  // "all": every candidate with power is sampled at every vertex, its "probability" 1.
  size_t candidates = 0;
  for (float p : light_prob_) candidates += p > 0.0f ? 1 : 0;
  sample_all_ = scene.integrator.light_selection == LightSelection::All ||
                (scene.integrator.light_selection == LightSelection::Auto && candidates <= kAutoAllCandidates);
  if (sample_all_)
    for (float& p : light_prob_) p = p > 0.0f ? 1.0f : 0.0f;
  // The environment behind a sphere light as a control variate (integrator.h): where BRDF
  // sampling alone finds the environment, for lights next-event estimation samples, at least as
  // bright as the environment in every channel (no negative sample).
  env_behind_light_.assign(scene.lights.size(), 0);
  if (env_by_bsdf_only && !scene.environment.is_black() && scene.integrator.strategy == Strategy::Mis) {
    const RGB env_max = scene.environment.max_radiance();
    for (size_t i = 0; i < scene.lights.size(); ++i) {
      const Light& l = scene.lights[i];
      env_behind_light_[i] = l.kind == LightKind::Sphere && light_prob_[i] > 0.0f && l.power.x >= env_max.x &&
                             l.power.y >= env_max.y && l.power.z >= env_max.z;
    }
  }
}

Ray PathTracer::camera_ray(float px, float py) const {
  // Film position to [-1, 1] by multiplications with 2 / size (a division per ray and axis was a
  // visible part of a path that misses everything); within an ulp of 2 px / W.
  const float sx = (px * cam_two_over_w_ - 1.0f) * cam_tan_half_ * cam_aspect_;
  const float sy = (1.0f - py * cam_two_over_h_) * cam_tan_half_;
  return Ray{scene_.camera.position, glm::normalize(cam_fwd_ + sx * cam_right_ + sy * cam_up_)};
}

RGB PathTracer::li(Ray ray, Sampler& rng, uint64_t* rays, std::vector<RecordedRay>* record) const {
  const Strategy strategy = scene_.integrator.strategy;
  // No candidate (nothing emits, or only a constant environment): no next-event estimation, and
  // no random numbers drawn for it, so that mis and bsdf give the same image.
  const bool use_nee = strategy != Strategy::Bsdf && light_cdf_.back() > 0.0f;
  const Environment& env = scene_.environment;
  const float env_prob = light_prob_.back();
  // Read once (a vector's size is a subtraction and a division by the element size at every use).
  const Light* const lights = scene_.lights.data();
  const size_t light_count = scene_.lights.size(), candidates = light_prob_.size();
  RGB L(0.0f), beta(1.0f);
  float prev_pdf = 0.0f;     // solid-angle pdf of the BRDF sample that made `ray` (0: camera ray)
  float min_pdf = INFINITY;  // the smallest of the path's BRDF-sample pdfs (Cycles' min_ray_pdf)
  Vec3 prev_p(0.0f);
  const float clamp = scene_.integrator.clamp;
  // Adds a contribution; indirect ones (integrator.h, "Fireflies") capped at R + G + B <= clamp.
  const auto add = [&](RGB c, bool indirect) {
    if (indirect && clamp > 0.0f) {
      const float sum = c.x + c.y + c.z;
      if (sum > clamp) c *= clamp / sum;
    }
    L += c;
  };
  Material blurred;
  for (int bounces = 0;; ++bounces) {
    // Emission found by this ray counts fully on the camera ray and for the bsdf strategy, with
    // the MIS weight for mis, and not at all for light (next-event estimation already has it).
    const auto emitted_weight = [&](float light_pdf) {
      if (prev_pdf == 0.0f || strategy == Strategy::Bsdf) return 1.0f;
      if (strategy == Strategy::Light) return 0.0f;
      return power_heuristic(prev_pdf, light_pdf);
    };
    SurfaceHit hit;
    ++*rays;
    if (record) record->push_back({ray, INFINITY, false});
    if (!geo_.intersect(ray, INFINITY, &hit, SceneGeometry::HitUV::WhereRead)) {
      if (!env.is_black()) {
        const Environment::Lookup e = env.lookup(ray.d);
        const float w = emitted_weight(prev_pdf > 0.0f ? env_prob * e.pdf : 0.0f);
        if (w > 0.0f) add(beta * e.radiance * w, bounces >= 2);
      }
      break;
    }
    if (hit.light >= 0) {
      const Light& l = scene_.lights[size_t(hit.light)];
      const float w = emitted_weight(prev_pdf > 0.0f ? light_prob_[size_t(hit.light)] * sphere_light_pdf(l, prev_p) : 0.0f);
      // With the environment behind the light as a control variate (integrator.h), E(w) counts in
      // full and only L - E(w) is weighted; on the camera ray (w = 1) the sum is L.
      const RGB behind = env_behind_light_[size_t(hit.light)] ? env.eval(ray.d) : RGB(0.0f);
      const RGB c = behind + (l.power - behind) * w;
      if (c != RGB(0.0f)) add(beta * c, bounces >= 2);
      break;
    }
    if (bounces >= scene_.integrator.max_depth) break;

    const Object& obj = scene_.objects[size_t(hit.object)];
    const float blur = blur_roughness(min_pdf, scene_.integrator.filter_glossy);
    if (blur > 0.0f) {
      blurred = obj.material;
      blurred.regularize(blur);  // each model's own rule (aniso/core/kernel.h)
    }
    const Material& m = blur > 0.0f ? blurred : obj.material;
    const Frame& frame = hit.frame;
    const Vec3 wo = frame.to_local(-ray.d);
    if (!(wo.z > 0.0f)) break;  // seen from behind its shading normal: no reflection defined
    const MaterialAtWo at(m, wo);

    if (use_nee) {
      // light_pdf: the solid-angle density of the direction times the probability of its light
      // (1 for delta lights: then only the probability).
      // sphere: the sphere light sampled (else nullptr), whose distance is measured from the
      // shadow ray's origin.
      const auto add_direct = [&](const Vec3& wi_world, const RGB& li, float light_pdf, bool delta, float dist,
                                  const Light* sphere) {
        if (li == RGB(0.0f)) return;  // e.g. a light exactly as bright as the environment behind it
        // Light through the surface is blocked: wi must leave on the side of the geometric normal.
        if (!(glm::dot(wi_world, hit.ng) > 0.0f)) return;
        const Vec3 wi = frame.to_local(wi_world);
        if (!(wi.z > 0.0f)) return;
        // The BRDF's density of wi weighs the sample against BRDF sampling (power heuristic),
        // except for delta lights and the light strategy (weight 1).
        const bool weighted = !delta && strategy != Strategy::Light;
        float bsdf_pdf = 0.0f;
        const RGB f = weighted ? at.f_pdf(wi, &bsdf_pdf) : at.f(wi);
        if (f == RGB(0.0f)) return;
        const Vec3 o = SceneGeometry::offset_origin(hit.p, hit.ng, wi_world);
        // A sphere light's distance from o, not from hit.p: near the light's rim the ray is
        // almost tangent to it, and the offset (2e-4 for a unit scene) moves where a ray along
        // wi enters the sphere by some 30 times as much. Measured from hit.p, samples near the rim
        // of a light seen at 8 degrees ended past the entry point and were shadowed by the light
        // itself: 1.5e-4 of its light lost, in rare outliers that were most of the per-pixel spread
        // of a Lambert sphere's direct light at 64 spp (docs/benchmarks.md, "Cycles").
        if (sphere) {
          dist = sphere_entry_distance(*sphere, o, wi_world);
          if (!(dist > 0.0f)) return;  // o on or in the light (rounding only: p is outside it)
        }
        ++*rays;
        const float tmax = std::isinf(dist) ? INFINITY : dist * (1.0f - 1e-3f);
        if (record) record->push_back({Ray{o, wi_world}, tmax, true});
        // Stop short of the light's surface: 1e-3 relative keeps the light's own sphere out of
        // the shadow test (its intersection is as inexact as any other).
        if (geo_.occluded(Ray{o, wi_world}, tmax)) return;
        const float w = weighted ? power_heuristic(light_pdf, bsdf_pdf) : 1.0f;
        add(beta * f * li * (wi.z * w / light_pdf), bounces >= 1);
      };
      // One sample of candidate i (a light, or the environment for i == lights.size()).
      const auto sample_candidate = [&](size_t i, const Vec2& ul) {
        const float p_choice = light_prob_[i];
        if (i < light_count) {
          const Light& l = lights[i];
          LightSample ls;
          if (sample_light(l, hit.p, ul, &ls)) {
            // L - E(w) with the environment behind the light as a control variate (integrator.h).
            if (env_behind_light_[i]) ls.li -= env.eval(ls.wi);
            add_direct(ls.wi, ls.li, ls.pdf * p_choice, ls.delta, ls.dist, l.kind == LightKind::Sphere ? &l : nullptr);
          }
        } else {
          // Directions below the surface, which add_direct rejects, come back without a lookup.
          const EnvSample es = env.sample_above(ul, hit.ng);
          if (es.pdf > 0.0f) add_direct(es.w, es.radiance, es.pdf * p_choice, false, INFINITY, nullptr);
        }
      };
      if (sample_all_) {
        for (size_t i = 0; i < candidates; ++i) {
          if (!(light_prob_[i] > 0.0f)) continue;
          // A sphere light wholly below the surface: add_direct would reject its sample whatever u
          // is, so the request is passed over (every later request gets the same numbers).
          if (i < light_count && lights[i].kind == LightKind::Sphere && sphere_light_below(lights[i], hit.p, hit.ng)) {
            rng.skip2();
            continue;
          }
          sample_candidate(i, rng.uniform2());
        }
      } else {
        // One emitter, chosen by power (integrator.h), from the same 2D sample that then places
        // the point on it: u.x picks the candidate whose cdf interval holds it and is rescaled to
        // [0, 1) within that interval (PBR 4th ed., Sec. 2.2.2's sample remapping). A pixel's
        // stratified (u.x, u.y) pairs stay stratified over each light's own square, where a
        // separate 1D pick would hand each light a random subset of the 2D points.
        Vec2 ul = rng.uniform2();
        const int chosen = pick_light(ul.x);
        if (chosen >= 0) {
          const float lo = light_cdf_[size_t(chosen)], width = light_cdf_[size_t(chosen) + 1] - lo;
          ul.x = width > 0.0f ? std::min((ul.x - lo) / width, 0x1.fffffep-1f) : 0.0f;  // [0, 1): below 1
          ul.x = std::max(ul.x, 0.0f);  // u.x == lo - 1 ulp can only come from rounding of the cdf
          sample_candidate(size_t(chosen), ul);
        }
      }
    }

    // Continue the path by sampling the BRDF.
    const float uc = rng.uniform();
    const BSDFSampleT<float> s = at.sample(uc, rng.uniform2());
    if (!s.valid) break;
    const Vec3 wi_world = frame.to_world(s.wi);
    if (!(glm::dot(wi_world, hit.ng) > 0.0f)) break;
    beta *= s.weight;
    prev_pdf = s.pdf;
    min_pdf = std::min(min_pdf, s.pdf);
    prev_p = hit.p;
    // Russian roulette from the fourth vertex on (pbrt-v4: survival probability = throughput,
    // capped at 0.95 so that no path is certain to continue).
    if (bounces >= 3) {
      const float q = std::min(0.95f, max_component(beta));
      if (!(rng.uniform() < q)) break;
      beta /= q;
    }
    ray = Ray{SceneGeometry::offset_origin(hit.p, hit.ng, wi_world), wi_world};
  }
  return L;
}

int next_pass_end(int spp_so_far, int spp_max) {
  // 1, 2, 4, 8, 16 after the passes so far, then kMaxPassSpp more per pass.
  const int step = std::clamp(spp_so_far, 1, kMaxPassSpp);
  return int(std::min<int64_t>(int64_t(spp_so_far) + step, spp_max));
}

int automatic_min_spp(float noise_threshold) { return std::max(4, int(std::ceil(16.0f / std::pow(noise_threshold, 0.3f)))); }

Image render(const Scene& scene, const RenderOptions& opt, RenderStats* stats_out) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  SceneGeometry geometry(scene);
  PathTracer tracer(scene, geometry);
  const int W = scene.film.width, H = scene.film.height;
  const size_t npix = size_t(W) * size_t(H);
  const int spp = opt.spp > 0 ? opt.spp : scene.film.spp;
  const float threshold = scene.film.noise_threshold;
  const int min_spp = threshold > 0.0f ? (scene.film.min_spp > 0 ? scene.film.min_spp : automatic_min_spp(threshold)) : spp;
  const double time_budget = scene.film.time_s;
  constexpr int kTile = 16;
  const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile, tiles = tiles_x * tiles_y;
  std::vector<double> sum(npix * 3, 0.0);
  std::vector<double> sum_i2(threshold > 0.0f ? npix : 0, 0.0);  // sum of (R + G + B)^2 per pixel
  std::vector<int> count(npix, 0);
  std::vector<uint8_t> active(npix, 1);
  std::atomic<uint64_t> rays{0}, paths{0}, nonfinite{0}, tiles_done{0};
  std::mutex progress_mutex;
  RenderStats stats;
  const auto cancelled = [&] { return opt.cancel && opt.cancel->load(std::memory_order_relaxed); };

  tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
  int s_begin = 0;
  uint64_t active_pixels = npix;
  // The time per pixel sample, measured over every pass so far (not the last pass alone): on a
  // loaded machine one pass may stall (a thread descheduled for a while), and a prediction from
  // that pass alone stops the render long before its budget; over all passes a stall is diluted by
  // the samples around it.
  double passes_seconds = 0.0;
  uint64_t passes_samples = 0;
  while (s_begin < spp) {
    const int s_end = next_pass_end(s_begin, spp);
    if (time_budget > 0.0 && stats.passes > 0) {
      const double seconds_per_sample = passes_samples > 0 ? passes_seconds / double(passes_samples) : 0.0;
      const double predicted = seconds_per_sample * double(active_pixels) * double(s_end - s_begin);
      if (elapsed() + predicted > time_budget) {
        stats.out_of_time = true;
        break;
      }
    }
    const double pass_t0 = elapsed();
    const uint64_t paths_before = paths.load();
    tiles_done = 0;
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
        for (int tile = r.begin(); tile != r.end(); ++tile) {
          const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
          uint64_t local_rays = 0, local_bad = 0, local_paths = 0;
          for (int y = y0; y < std::min(y0 + kTile, H); ++y)
            for (int x = x0; x < std::min(x0 + kTile, W); ++x) {
              // Before every pixel: a pixel's samples of one pass take milliseconds at most.
              if (cancelled()) break;
              const size_t pix = size_t(y) * size_t(W) + size_t(x);
              if (!active[pix]) continue;
              RGB acc(0.0f);
              double acc_i2 = 0.0;
              PixelSeeds pixel_seeds(opt.seed, pix, scene.integrator.sampler);
              for (int s = s_begin; s < s_end; ++s) {
                Sampler rng(pixel_seeds, uint64_t(s));
                const Vec2 j = rng.uniform2();
                const RGB l = tracer.li(tracer.camera_ray(float(x) + j.x, float(y) + j.y), rng, &local_rays);
                if (std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z)) {
                  acc += l;
                  const double i = double(l.x) + double(l.y) + double(l.z);
                  acc_i2 += i * i;
                } else {
                  ++local_bad;
                }
              }
              sum[3 * pix] += acc.x, sum[3 * pix + 1] += acc.y, sum[3 * pix + 2] += acc.z;
              if (!sum_i2.empty()) sum_i2[pix] += acc_i2;
              count[pix] += s_end - s_begin;
              local_paths += uint64_t(s_end - s_begin);
            }
          rays += local_rays;
          nonfinite += local_bad;
          paths += local_paths;
          const uint64_t done = ++tiles_done;
          if (opt.progress && progress_mutex.try_lock()) {
            double f = (double(s_begin) + double(s_end - s_begin) * double(done) / double(tiles)) / double(spp);
            if (time_budget > 0.0) f = std::max(f, std::min(1.0, elapsed() / time_budget));
            opt.progress(std::min(f, 1.0));
            progress_mutex.unlock();
          }
        }
      });
    });
    if (cancelled()) {
      stats.cancelled = true;
      break;
    }
    ++stats.passes;
    stats.spp_done = s_end;
    const uint64_t pass_paths = paths.load() - paths_before;
    passes_seconds += elapsed() - pass_t0;
    passes_samples += pass_paths;
    s_begin = s_end;
    if (threshold > 0.0f && s_end >= min_spp && s_end < spp) {
      // Converged: the standard error of the mean of I = R + G + B, normalised (integrator.h).
      std::vector<uint8_t> converged(npix, 0);
      for (size_t p = 0; p < npix; ++p) {
        const double n = count[p];
        if (n < 2.0) continue;  // no variance estimate yet
        const double mean = (sum[3 * p] + sum[3 * p + 1] + sum[3 * p + 2]) / n;
        const double var = (sum_i2[p] - n * mean * mean) / (n - 1.0);
        converged[p] = adaptive_error(mean, var, n) < threshold;
      }
      active_pixels = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          bool all = true;
          for (int dy = -1; dy <= 1 && all; ++dy)
            for (int dx = -1; dx <= 1 && all; ++dx) {
              const int xx = x + dx, yy = y + dy;
              if (xx >= 0 && yy >= 0 && xx < W && yy < H) all = converged[size_t(yy) * size_t(W) + size_t(xx)] != 0;
            }
          active[size_t(y) * size_t(W) + size_t(x)] = !all;
          active_pixels += all ? 0 : 1;
        }
    }
    if (opt.on_pass) opt.on_pass(PassReport{stats.passes, s_end, double(active_pixels) / double(npix), elapsed()});
    if (active_pixels == 0) {
      stats.converged = s_end < spp;
      break;
    }
  }
  Image img(W, H);
  uint64_t total_count = 0;
  for (size_t i = 0; i < count.size(); ++i) {
    total_count += uint64_t(count[i]);
    if (count[i] > 0)
      for (int c = 0; c < 3; ++c) img.rgb[3 * i + size_t(c)] = float(sum[3 * i + size_t(c)] / count[i]);
  }
  stats.seconds = elapsed();
  stats.paths = paths;
  stats.rays = rays;
  stats.nonfinite = nonfinite;
  stats.mean_spp = double(total_count) / double(npix);
  if (stats_out) *stats_out = stats;
  return img;
}

}  // namespace aniso::render
