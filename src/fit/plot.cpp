// fit/plot.cpp: the in-plane slices of `aniso fit --plot` (plot.h), drawn with the renderer's image
// and label-font code (render/image.h).
#include "fit/plot.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "io/materials.h"
#include "render/image.h"

namespace aniso {
namespace {

using render::DisplayImage;
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kInPlaneTolerance = 1.5 * kDeg;  // a sample within this of the plane counts as in it

void dot(DisplayImage& img, int x, int y, int r, const glm::u8vec3& c) { render::fill_rect(img, x - r, y - r, 2 * r + 1, 2 * r + 1, c); }

void line(DisplayImage& img, double x0, double y0, double x1, double y1, const glm::u8vec3& c) {
  const int steps = int(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))) + 1;
  for (int i = 0; i <= steps; ++i) {
    const double t = double(i) / steps;
    render::fill_rect(img, int(std::lround(x0 + t * (x1 - x0))), int(std::lround(y0 + t * (y1 - y0))), 2, 2, c);
  }
}

// The signed in-plane outgoing angle of wo for light in the plane phi = phi_i: positive on the
// mirror side (phi_o = phi_i + pi), negative on the light's side; nullopt off the plane.
std::optional<double> in_plane_angle(const MeasuredSample& s) {
  const double phi_i = std::atan2(s.wi.y, s.wi.x);
  const double theta_o = std::acos(std::clamp(s.wo.z, -1.0, 1.0));
  const double sin_o = std::sqrt(s.wo.x * s.wo.x + s.wo.y * s.wo.y);
  if (sin_o < 1e-9) return 0.0;
  // Component of wo along the light's azimuth (negative on the mirror side) and across it.
  const double along = (s.wo.x * std::cos(phi_i) + s.wo.y * std::sin(phi_i)) / sin_o;
  const double across = (-s.wo.x * std::sin(phi_i) + s.wo.y * std::cos(phi_i)) / sin_o;
  if (std::abs(std::asin(std::clamp(across, -1.0, 1.0))) * std::sin(theta_o) > kInPlaneTolerance) return std::nullopt;
  return along < 0.0 ? theta_o : -theta_o;
}

}  // namespace

void write_slices_plot(const std::string& path, const SampleSet& data, const nlohmann::json& material, const std::string& title) {
  const MaterialD m = build_material<double>(parse_material(material, "fitted material"));
  // The incidence angles: four spread over those (rounded to 1 degree) with at least 3 in-plane
  // samples, from the smallest to the largest.
  std::map<int, int> count;
  for (const MeasuredSample& s : data.samples)
    if (in_plane_angle(s)) ++count[int(std::lround(std::acos(s.wi.z) / kDeg))];
  std::vector<int> populated, angles;
  // At most 85 degrees: nearer the horizon the slices say little and f may grow without bound
  // (Ward-Duer's 1 / (cos_i cos_o)), which would squash every other panel's scale.
  for (const auto& [deg, n] : count)
    if (n >= 3 && deg <= 85) populated.push_back(deg);
  if (populated.size() <= 4) angles = populated;
  else
    for (int i = 0; i < 4; ++i) angles.push_back(populated[size_t(std::lround(i * double(populated.size() - 1) / 3.0))]);
  if (angles.empty()) angles = {0, 30, 60, 75};

  // The common y range: log10 f over the fitted curves and the in-plane samples.
  const auto dir = [](double theta, double phi) { return Vec3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)); };
  const auto fitted = [&](int deg, double signed_o) {
    const Vec3d wi = dir(deg * kDeg, 0.0);
    const Vec3d wo = dir(std::abs(signed_o), signed_o > 0 ? M_PI : 0.0);
    return m.f(wi, wo);
  };
  // The y range: the 0.5th to 99.5th percentile of log10 f over the curves (|theta_o| <= 85 deg) and
  // the panels' in-plane samples, at most six decades (below that is noise), so that a few grazing
  // values do not squash the scale; points beyond it are drawn at the frame's edge.
  std::vector<double> logs;
  const auto include = [&](double v) {
    if (v > 0.0 && std::isfinite(v)) logs.push_back(std::log10(v));
  };
  for (int deg : angles)
    for (int i = -85; i <= 85; ++i) {
      const RGBT<double> f = fitted(deg, i * kDeg);
      for (int c = 0; c < 3; ++c) include(f[c]);
    }
  for (const MeasuredSample& s : data.samples) {
    if (!in_plane_angle(s)) continue;
    const double deg = std::acos(s.wi.z) / kDeg;
    for (int a : angles)
      if (std::abs(deg - a) <= 1.0)
        for (int c = 0; c < 3; ++c) include(s.value[c]);
  }
  double lo = -3, hi = 1;
  if (!logs.empty()) {
    std::sort(logs.begin(), logs.end());
    lo = logs[size_t(0.005 * double(logs.size() - 1))];
    hi = logs[size_t(0.995 * double(logs.size() - 1))];
  }
  lo = std::floor(std::max(lo, hi - 6.0));
  hi = std::ceil(hi + 1e-9);
  if (hi <= lo) hi = lo + 1;

  constexpr int kPanelW = 330, kPanelH = 300, kMarginL = 56, kMarginT = 56, kMarginB = 44, kGap = 20;
  const int width = kMarginL + int(angles.size()) * (kPanelW + kGap) + 10;
  const int height = kMarginT + kPanelH + kMarginB + 24;
  DisplayImage img(width, height, 255);
  const glm::u8vec3 black(0, 0, 0), grey(200, 200, 200);
  const glm::u8vec3 colour[3] = {{210, 40, 40}, {30, 150, 40}, {40, 70, 220}};
  render::draw_text(img, 10, 8, fmt::format("{}: {} vs fitted {} (in the plane of incidence)", data.source, data.format, title), 18.0f, black);
  render::draw_text(img, 10, 30, "lines: fitted f;  dots: measured samples within 1.5\u00b0 of the plane;  red, green, blue channels", 14.0f, black);
  for (size_t p = 0; p < angles.size(); ++p) {
    const int x0 = kMarginL + int(p) * (kPanelW + kGap), y0 = kMarginT;
    const auto px = [&](double signed_o) { return x0 + (signed_o / (90.0 * kDeg) + 1.0) * 0.5 * kPanelW; };
    const auto py = [&](double v) { return y0 + kPanelH - (std::log10(v) - lo) / (hi - lo) * kPanelH; };
    // Frame, grid and labels.
    for (int d = int(lo); d <= int(hi); ++d) {
      const int y = int(std::lround(py(std::pow(10.0, d))));
      render::fill_rect(img, x0, y, kPanelW, 1, grey);
      if (p == 0) render::draw_text(img, 4, y - 8, fmt::format("1e{}", d), 13.0f, black);
    }
    for (int a = -90; a <= 90; a += 30) {
      const int x = int(std::lround(px(a * kDeg)));
      render::fill_rect(img, x, y0, 1, kPanelH, grey);
      const std::string lbl = fmt::format("{}", a);
      render::draw_text(img, x - render::text_width(lbl, 13.0f) / 2, y0 + kPanelH + 4, lbl, 13.0f, black);
    }
    render::fill_rect(img, x0, y0, kPanelW, 1, black);
    render::fill_rect(img, x0, y0 + kPanelH, kPanelW, 1, black);
    render::fill_rect(img, x0, y0, 1, kPanelH, black);
    render::fill_rect(img, x0 + kPanelW, y0, 1, kPanelH + 1, black);
    const std::string head = fmt::format("\u03b8i = {}\u00b0", angles[p]);
    render::draw_text(img, x0 + 8, y0 + 6, head, 15.0f, black);
    render::draw_text(img, x0 + kPanelW / 2 - 80, y0 + kPanelH + 20, "\u03b8o (deg, + = mirror side)", 13.0f, black);
    // Fitted curves.
    for (int c = 0; c < 3; ++c) {
      double prev_x = 0, prev_y = 0;
      bool have = false;
      for (int i = -890; i <= 890; i += 5) {
        const double v = fitted(angles[p], i * 0.1 * kDeg)[c];
        if (!(v > 0.0)) {
          have = false;
          continue;
        }
        const double x = px(i * 0.1 * kDeg), y = std::clamp(py(v), double(y0), double(y0 + kPanelH));
        if (have) line(img, prev_x, prev_y, x, y, colour[c]);
        prev_x = x, prev_y = y, have = true;
      }
    }
    // Measured dots.
    for (const MeasuredSample& s : data.samples) {
      const auto a = in_plane_angle(s);
      if (!a || std::abs(std::acos(s.wi.z) / kDeg - angles[p]) > 1.0) continue;
      for (int c = 0; c < 3; ++c)
        if (s.value[c] > 0.0) {
          const double y = std::clamp(py(s.value[c]), double(y0), double(y0 + kPanelH));
          dot(img, int(std::lround(px(*a))), int(std::lround(y)), 2, colour[c]);
        }
    }
  }
  render::write_png(path, img);
}

}  // namespace aniso
