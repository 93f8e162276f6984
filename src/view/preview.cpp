// view/preview.cpp: the progressive path-traced preview (view/preview.h).
#include "view/preview.h"

#include <algorithm>

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
  std::shared_ptr<const render::Scene> scene;
  render::Image sum;
  int done = 0;
  uint64_t pass = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [&] { return stop_ || pending_ || (scene && done < max_spp_); });
      if (stop_) return;
      if (pending_) {
        scene = std::move(pending_);
        pending_.reset();
        cancel_ = false;
        sum = render::Image(scene->film.width, scene->film.height);
        done = 0;
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
    render::RenderStats stats;
    const render::Image img = render::render(*scene, opt, &stats);
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
    done += opt.spp;
    average_ = sum;
    for (float& x : average_.rgb) x /= float(done);
    spp_ = done;
    working_ = done < max_spp_;
    ++generation_;
    cv_.notify_all();
  }
}

}  // namespace aniso::view
