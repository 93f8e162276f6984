// view/preview.h: the explorer's progressive path-traced preview. A background thread renders
// the current scene with the CPU renderer (render/integrator.h) in passes of 1, 1, 2, 4, ... samples
// per pixel with different seeds and keeps their running average; restart() with a new scene
// cancels the pass in flight (RenderOptions::cancel) and starts again from zero samples.
// A scene's film.noise_threshold and film.time_s apply to the accumulated image, not to each pass:
// the preview stops when every pixel of the average is below the threshold (from film.min_spp on,
// the renderer's error estimate, render::adaptive_error, with the variance from the spread of the
// passes' means) or when the next pass would end past the time budget (from the restart).
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "aniso/image/image.h"
#include "aniso/render/scene.h"

namespace aniso::view {

class ProgressivePreview {
 public:
  // threads: the renderer's worker threads (0: all cores but one, which the window keeps).
  explicit ProgressivePreview(int threads = 0, int max_spp = 1024);
  ~ProgressivePreview();
  ProgressivePreview(const ProgressivePreview&) = delete;
  ProgressivePreview& operator=(const ProgressivePreview&) = delete;

  // Starts over with this scene (its film gives the size).
  void restart(std::shared_ptr<const render::Scene> scene);
  // Stops rendering (the last image stays).
  void pause();

  // The average so far; returns false when nothing new has arrived since `generation_seen`.
  // *spp: samples per pixel in it; *generation: pass this back next time.
  bool snapshot(render::Image* out, int* spp, uint64_t* generation) const;
  int spp() const;
  bool busy() const { return busy_.load(); }
  // Blocks until the image has at least `spp` samples or the preview is idle (tests).
  void wait_for(int spp) const;

 private:
  void run();

  const int threads_, max_spp_;
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::shared_ptr<const render::Scene> pending_;  // set by restart(), taken by the thread
  bool stop_ = false;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> busy_{false};
  bool working_ = false;   // under mutex_: a scene is being rendered and has not reached max_spp_
  render::Image average_;  // under mutex_
  int spp_ = 0;            // under mutex_
  uint64_t generation_ = 0;
  std::thread thread_;
};

}  // namespace aniso::view
