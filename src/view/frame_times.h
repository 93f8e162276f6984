// view/frame_times.h: the explorer's frame time, one measurement for the figure in the window and
// the line a scripted run prints on stderr (docs/explorer.md, "Speed"). A frame's time is the wall
// time of its ImGui and GL work up to glFinish (GL timer queries are unreliable on llvmpipe).
//
// The first `skip` frames compile shaders and build the rasterisers and are left out; the figure is
// the mean of the frames after them, the last `window` of them when window > 0 (an interactive
// session: a figure that follows what is being done) or all of them (a scripted run).
#pragma once

#include <cstddef>
#include <deque>
#include <string>

#include <fmt/format.h>

namespace aniso::view {

class FrameTimes {
 public:
  explicit FrameTimes(size_t skip = 2, size_t window = 0) : skip_(skip), window_(window) {}

  void add(double ms) {
    if (seen_++ < skip_) return;
    times_.push_back(ms);
    sum_ += ms;
    if (window_ > 0 && times_.size() > window_) sum_ -= times_.front(), times_.pop_front();
  }
  size_t frames() const { return times_.size(); }
  double mean_ms() const { return times_.empty() ? 0.0 : sum_ / double(times_.size()); }
  // "84.0 ms a frame, 11.9 fps (mean of 37 frames)", or what is still missing.
  std::string text() const {
    if (times_.empty()) return "frame time: after the first frames";
    const double m = mean_ms();
    return fmt::format("{:.1f} ms a frame, {:.1f} fps (mean of {} frame{})", m, m > 0.0 ? 1000.0 / m : 0.0, times_.size(),
                       times_.size() == 1 ? "" : "s");
  }

 private:
  size_t skip_, window_, seen_ = 0;
  std::deque<double> times_;
  double sum_ = 0.0;
};

}  // namespace aniso::view
