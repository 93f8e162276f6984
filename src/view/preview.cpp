// view/preview.cpp: the progressive path-traced preview (view/preview.h).
#include "view/preview.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include "aniso/render/integrator.h"

namespace aniso::view {

ProgressivePreview::ProgressivePreview(int threads, int max_spp)
    : threads_(threads > 0 ? threads : std::max(1, int(std::thread::hardware_concurrency()) - 1)),
      max_spp_(std::max(1, max_spp)) {
  thread_ = std::thread([this] { run(); });
}

ProgressivePreview::~ProgressivePreview() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    cancel_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void ProgressivePreview::restart(std::shared_ptr<const render::Scene> scene) {
  {
    std::lock_guard lock(mutex_);
    pending_ = std::move(scene);
    cancel_ = true;  // the pass in flight stops at its next check
    // The old picture is gone at once: spp() and wait_for() count the new scene's samples only.
    average_ = render::Image();
    spp_ = 0;
    ++generation_;
  }
  cv_.notify_all();
}

void ProgressivePreview::pause() {
  std::lock_guard lock(mutex_);
  pending_.reset();
  cancel_ = true;
}

bool ProgressivePreview::snapshot(render::Image* out, int* spp, uint64_t* generation) const {
  std::lock_guard lock(mutex_);
  if (*generation == generation_) return false;
  *out = average_;
  *spp = spp_;
  *generation = generation_;
  return true;
}

int ProgressivePreview::spp() const {
  std::lock_guard lock(mutex_);
  return spp_;
}

void ProgressivePreview::wait_for(int spp) const {
  std::unique_lock lock(mutex_);
  cv_.wait(lock, [&] { return spp_ >= spp || (!working_ && !pending_); });
}

void ProgressivePreview::run() {
  using clock = std::chrono::steady_clock;
  std::shared_ptr<const render::Scene> scene;
  // What each pass renders: the scene without its noise threshold and time budget, which apply to
  // the accumulated image instead (below), not to each pass's few samples.
  std::shared_ptr<render::Scene> pass_scene;
  render::Image sum;
  std::vector<double> sum_i2;  // per pixel: sum over passes of n_k m_k^2, m_k the pass's mean of R + G + B
  int done = 0, passes = 0, limit = max_spp_, min_spp = 0;
  clock::time_point started;
  double pass_seconds = 0.0;  // all passes of this scene, for the time budget's prediction
  uint64_t pass = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [&] { return stop_ || pending_ || (scene && done < limit); });
      if (stop_) return;
      if (pending_) {
        scene = std::move(pending_);
        pending_.reset();
        cancel_ = false;
        pass_scene = std::make_shared<render::Scene>(*scene);
        pass_scene->film.noise_threshold = 0.0f;
        pass_scene->film.time_s = 0.0f;
        sum = render::Image(scene->film.width, scene->film.height);
        sum_i2.assign(scene->film.noise_threshold > 0.0f ? size_t(scene->film.width) * size_t(scene->film.height) : 0, 0.0);
        done = passes = 0;
        limit = max_spp_;
        const float t = scene->film.noise_threshold;
        min_spp = t > 0.0f ? (scene->film.min_spp > 0 ? scene->film.min_spp : render::automatic_min_spp(t)) : 0;
        started = clock::now();
        pass_seconds = 0.0;
        average_ = render::Image();
        spp_ = 0;
        ++generation_;
      }
      working_ = true;
      busy_ = true;
    }
    // Passes of 1, 1, 2, 4, ... samples: the first picture comes after one sample per pixel, and
    // the number of passes (and of BVH builds, one per render() call) grows only as log2(spp).
    render::RenderOptions opt;
    opt.threads = threads_;
    opt.spp = std::min(std::max(1, done), max_spp_ - done);
    opt.seed = 0x9E3779B97F4A7C15ULL ^ ++pass;  // a different sample set per pass
    opt.cancel = &cancel_;
    const double budget = scene->film.time_s;
    if (budget > 0.0 && done > 0) {
      // As the renderer's time budget (render/integrator.h): a pass predicted to end past the
      // budget (time per sample over all passes so far) is not started.
      const double since = std::chrono::duration<double>(clock::now() - started).count();
      if (since + pass_seconds / double(done) * double(opt.spp) > budget) {
        std::lock_guard lock(mutex_);
        busy_ = false;
        limit = done;
        working_ = false;
        cv_.notify_all();
        continue;
      }
    }
    render::RenderStats stats;
    const auto pass_t0 = clock::now();
    const render::Image img = render::render(*pass_scene, opt, &stats);
    pass_seconds += std::chrono::duration<double>(clock::now() - pass_t0).count();
    std::lock_guard lock(mutex_);
    busy_ = false;
    // A cancelled pass is dropped: a restart is pending (or the preview was paused).
    if (stats.cancelled || pending_ || cancel_) {
      if (!pending_) scene.reset();
      working_ = pending_ != nullptr;
      cv_.notify_all();
      continue;
    }
    const float w = float(opt.spp);
    for (size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += img.rgb[i] * w;
    for (size_t p = 0; p < sum_i2.size(); ++p) {
      const double m = double(img.rgb[3 * p]) + double(img.rgb[3 * p + 1]) + double(img.rgb[3 * p + 2]);
      sum_i2[p] += double(opt.spp) * m * m;
    }
    done += opt.spp;
    ++passes;
    // The noise threshold on the accumulated image: it is done when every pixel's error estimate
    // (render::adaptive_error, as the renderer's adaptive sampling) is below the threshold. The
    // variance per sample comes from the spread of the passes' means: with K passes of n_k samples,
    // sum n_k (m_k - M)^2 = sum n_k m_k^2 - N M^2 has the expectation (K - 1) variance.
    if (!sum_i2.empty() && done >= min_spp && passes >= 2) {
      bool all = true;
      const double n = double(done);
      for (size_t p = 0; p < sum_i2.size() && all; ++p) {
        const double mean = (double(sum.rgb[3 * p]) + double(sum.rgb[3 * p + 1]) + double(sum.rgb[3 * p + 2])) / n;
        const double var = (sum_i2[p] - n * mean * mean) / double(passes - 1);
        all = render::adaptive_error(mean, var, n) < double(scene->film.noise_threshold);
      }
      if (all) limit = done;
    }
    average_ = sum;
    for (float& x : average_.rgb) x /= float(done);
    spp_ = done;
    working_ = done < limit;
    ++generation_;
    cv_.notify_all();
  }
}

}  // namespace aniso::view
