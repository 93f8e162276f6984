// fit/plot.cpp: the in-plane slices of `aniso fit --plot` (plot.h), drawn and written with the
// image library (image/canvas.h, image/image_io.h).
#include "aniso/fit/plot.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/io/materials.h"

namespace aniso {
namespace {

using render::DisplayImage;
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kInPlaneTolerance = 1.5 * kDeg;  // a sample within this of the plane counts as in it

void dot(DisplayImage& img, int x, int y, int r, const glm::u8vec3& c) {
  render::fill_rect(img, x - r, y - r, 2 * r + 1, 2 * r + 1, c);
}

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

namespace {

// The slices of a panel row, for light at theta_i in the plane phi = 0 of the fitted material's
// frame: the in-plane one (signed theta_o, + towards the mirror direction), the one through the
// mirror direction r across the plane of incidence (wo = cos t r + sin t b, t signed towards +y),
// and the mirror cone (theta_o = theta_i, phi_o from -180 to 180 degrees, 0 the mirror direction).
enum class Slice { InPlane, Across, Cone };

Vec3d slice_direction(Slice slice, double theta_i, double a) {
  switch (slice) {
    case Slice::InPlane: return direction_from_angles(std::abs(a), a > 0 ? M_PI : 0.0);
    case Slice::Across: {
      const Vec3d r = direction_from_angles(theta_i, M_PI);
      return std::cos(a) * r + std::sin(a) * Vec3d(0, 1, 0);
    }
    case Slice::Cone: return direction_from_angles(theta_i, M_PI + a);
  }
  return Vec3d(0, 0, 1);
}

// The slice coordinate of a measured sample, or nullopt when it is off the slice. For an isotropic
// fit the in-plane row takes every light azimuth (the sample turned so that its light is at
// phi = 0); an anisotropic material depends on it, so then a sample counts only when its light is
// within 5 degrees of phi = 0, the curves' plane.
std::optional<double> slice_coordinate(Slice slice, const MeasuredSample& s, double theta_i, bool anisotropic) {
  const double phi_i = std::atan2(s.wi.y, s.wi.x);
  if (anisotropic && std::abs(phi_i) > 5.0 * kDeg) return std::nullopt;
  if (slice == Slice::InPlane) return in_plane_angle(s);
  if (slice == Slice::Across) {
    const Vec3d r = direction_from_angles(theta_i, M_PI), across(0, 1, 0), normal = glm::cross(r, across);
    if (std::abs(glm::dot(s.wo, normal)) > std::sin(kInPlaneTolerance)) return std::nullopt;
    return std::atan2(glm::dot(s.wo, across), glm::dot(s.wo, r));
  }
  if (std::abs(std::acos(std::clamp(s.wo.z, -1.0, 1.0)) - theta_i) > kInPlaneTolerance) return std::nullopt;
  double a = std::atan2(s.wo.y, s.wo.x) - M_PI;
  if (a < -M_PI) a += 2 * M_PI;
  return a;
}

struct Curve {
  MaterialD material;
  std::string label;
};

}  // namespace

void write_slices_plot(const std::string& path, const SampleSet& data, const std::vector<PlotMaterial>& materials) {
  std::vector<Curve> curves;
  bool anisotropic = false;
  for (const PlotMaterial& pm : materials) {
    curves.push_back({build_material<double>(parse_material(pm.material, "fitted material")), pm.label});
    anisotropic = anisotropic || pm.material.contains("rotation_deg");
  }
  const bool several = curves.size() > 1;
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
  if (populated.size() <= 4)
    angles = populated;
  else
    for (int i = 0; i < 4; ++i) angles.push_back(populated[size_t(std::lround(i * double(populated.size() - 1) / 3.0))]);
  if (angles.empty()) angles = {0, 30, 60, 75};
  // Rows: the plane of incidence; for an anisotropic fit also the slice across it and the mirror
  // cone, where an anisotropic lobe shows its two widths.
  std::vector<Slice> rows = {Slice::InPlane};
  if (anisotropic) rows.push_back(Slice::Across), rows.push_back(Slice::Cone);
  const auto range_of = [](Slice slice) { return slice == Slice::Cone ? 180.0 : 90.0; };

  // What a curve shows: each channel for one material, the mean of the channels for several.
  const auto values = [&](const Curve& c, Slice slice, int deg, double a) {
    const RGBT<double> f = c.material.f(direction_from_angles(deg * kDeg, 0.0), slice_direction(slice, deg * kDeg, a));
    return several ? glm::dvec3((f.x + f.y + f.z) / 3.0) : glm::dvec3(f);
  };
  const auto measured = [&](const MeasuredSample& s) {
    return several ? glm::dvec3((s.value.x + s.value.y + s.value.z) / 3.0) : s.value;
  };
  const auto on_panel = [&](const MeasuredSample& s, Slice slice, int deg) -> std::optional<double> {
    if (std::abs(std::acos(s.wi.z) / kDeg - deg) > 1.0) return std::nullopt;
    const auto a = slice_coordinate(slice, s, deg * kDeg, anisotropic);
    if (!a || (slice != Slice::Cone && std::abs(*a) > 90.0 * kDeg)) return std::nullopt;
    if (slice == Slice::Across && slice_direction(slice, deg * kDeg, *a).z <= 0.0) return std::nullopt;
    return a;
  };

  // The y range: the 0.5th to 99.5th percentile of log10 f over the curves (|theta_o| <= 85 deg) and
  // the panels' samples, at most six decades (below that is noise), so that a few grazing values
  // do not squash the scale; points beyond it are drawn at the frame's edge.
  std::vector<double> logs;
  const auto include = [&](double v) {
    if (v > 0.0 && std::isfinite(v)) logs.push_back(std::log10(v));
  };
  for (Slice slice : rows)
    for (int deg : angles)
      for (int i = -85; i <= 85; ++i)
        for (const Curve& c : curves) {
          const double a = i * kDeg * range_of(slice) / 90.0;
          if (slice_direction(slice, deg * kDeg, a).z <= 0.0) continue;
          const glm::dvec3 f = values(c, slice, deg, a);
          for (int k = 0; k < 3; ++k) include(f[k]);
        }
  for (const MeasuredSample& s : data.samples)
    for (Slice slice : rows)
      for (int deg : angles)
        if (on_panel(s, slice, deg))
          for (int k = 0; k < 3; ++k) include(measured(s)[k]);
  double lo = -3, hi = 1;
  if (!logs.empty()) {
    std::sort(logs.begin(), logs.end());
    lo = logs[size_t(0.005 * double(logs.size() - 1))];
    hi = logs[size_t(0.995 * double(logs.size() - 1))];
  }
  lo = std::floor(std::max(lo, hi - 6.0));
  hi = std::ceil(hi + 1e-9);
  if (hi <= lo) hi = lo + 1;

  constexpr int kPanelW = 330, kPanelH = 260, kMarginL = 56, kMarginT = 56, kRowGap = 64, kGap = 20;
  const int legend = several ? 22 * int((curves.size() + 2) / 3) : 0;
  const int width = kMarginL + int(angles.size()) * (kPanelW + kGap) + 10;
  const int height = kMarginT + legend + int(rows.size()) * (kPanelH + kRowGap) + 4;
  DisplayImage img(width, height, 255);
  const glm::u8vec3 black(0, 0, 0), grey(200, 200, 200), dots_grey(90, 90, 90);
  const glm::u8vec3 channel[3] = {{210, 40, 40}, {30, 150, 40}, {40, 70, 220}};
  // One colour per model (--compare): a qualitative palette (Okabe & Ito 2008, colour-blind safe) and more.
  const glm::u8vec3 palette[] = {{230, 159, 0},   {86, 180, 233}, {0, 158, 115},  {213, 94, 0},    {0, 114, 178},
                                 {204, 121, 167}, {120, 80, 20},  {240, 200, 30}, {150, 150, 150}, {0, 0, 0}};
  const std::string what = several ? "every model" : "fitted " + curves[0].label;
  render::draw_text(img, 10, 8, fmt::format("{}: {} vs {}", data.source, data.format, what), 18.0f, black);
  render::draw_text(img, 10, 30,
                    several
                        ? "lines: each model's f (mean of the channels);  dots: measured samples on the slice"
                        : "lines: fitted f;  dots: measured samples within 1.5\u00b0 of the slice;  red, green, blue channels",
                    14.0f, black);
  if (several)
    for (size_t i = 0; i < curves.size(); ++i) {
      const int lx = 10 + int(i % 3) * 360, ly = kMarginT - 6 + 22 * int(i / 3);
      render::fill_rect(img, lx, ly + 7, 24, 3, palette[i % std::size(palette)]);
      render::draw_text(img, lx + 30, ly, curves[i].label, 14.0f, black);
    }
  for (size_t row = 0; row < rows.size(); ++row) {
    const Slice slice = rows[row];
    const double range = range_of(slice);
    for (size_t p = 0; p < angles.size(); ++p) {
      const int x0 = kMarginL + int(p) * (kPanelW + kGap), y0 = kMarginT + legend + int(row) * (kPanelH + kRowGap);
      const auto px = [&](double a) { return x0 + (a / (range * kDeg) + 1.0) * 0.5 * kPanelW; };
      const auto py = [&](double v) { return y0 + kPanelH - (std::log10(v) - lo) / (hi - lo) * kPanelH; };
      // Frame, grid and labels.
      for (int d = int(lo); d <= int(hi); ++d) {
        const int y = int(std::lround(py(std::pow(10.0, d))));
        render::fill_rect(img, x0, y, kPanelW, 1, grey);
        if (p == 0) render::draw_text(img, 4, y - 8, fmt::format("1e{}", d), 13.0f, black);
      }
      const int step = slice == Slice::Cone ? 60 : 30;
      for (int a = -int(range); a <= int(range); a += step) {
        const int x = int(std::lround(px(a * kDeg)));
        render::fill_rect(img, x, y0, 1, kPanelH, grey);
        const std::string lbl = fmt::format("{}", a);
        render::draw_text(img, x - render::text_width(lbl, 13.0f) / 2, y0 + kPanelH + 4, lbl, 13.0f, black);
      }
      render::fill_rect(img, x0, y0, kPanelW, 1, black);
      render::fill_rect(img, x0, y0 + kPanelH, kPanelW, 1, black);
      render::fill_rect(img, x0, y0, 1, kPanelH, black);
      render::fill_rect(img, x0 + kPanelW, y0, 1, kPanelH + 1, black);
      const char* name = slice == Slice::InPlane  ? "in the plane of incidence"
                         : slice == Slice::Across ? "across it, through the mirror direction"
                                                  : "on the mirror cone \u03b8o = \u03b8i";
      render::draw_text(img, x0 + 8, y0 + 6, fmt::format("\u03b8i = {}\u00b0, {}", angles[p], name), 14.0f, black);
      const char* axis = slice == Slice::InPlane  ? "\u03b8o (deg, + = mirror side)"
                         : slice == Slice::Across ? "angle from the mirror direction (deg, + = +y)"
                                                  : "\u03c6o from the mirror direction (deg)";
      render::draw_text(img, x0 + kPanelW / 2 - render::text_width(axis, 13.0f) / 2, y0 + kPanelH + 20, axis, 13.0f, black);
      // Curves.
      for (size_t ci = 0; ci < curves.size(); ++ci)
        for (int k = 0; k < (several ? 1 : 3); ++k) {
          const glm::u8vec3 colour = several ? palette[ci % std::size(palette)] : channel[k];
          double prev_x = 0, prev_y = 0;
          bool have = false;
          for (int i = -890; i <= 890; i += 5) {
            const double a = i * 0.1 * kDeg * range / 90.0;
            const double v =
                slice_direction(slice, angles[p] * kDeg, a).z > 0.0 ? values(curves[ci], slice, angles[p], a)[k] : 0.0;
            if (!(v > 0.0)) {
              have = false;
              continue;
            }
            const double x = px(a), y = std::clamp(py(v), double(y0), double(y0 + kPanelH));
            if (have) line(img, prev_x, prev_y, x, y, colour);
            prev_x = x, prev_y = y, have = true;
          }
        }
      // Measured dots.
      for (const MeasuredSample& s : data.samples) {
        const auto a = on_panel(s, slice, angles[p]);
        if (!a) continue;
        const glm::dvec3 v = measured(s);
        for (int k = 0; k < (several ? 1 : 3); ++k)
          if (v[k] > 0.0) {
            const double y = std::clamp(py(v[k]), double(y0), double(y0 + kPanelH));
            dot(img, int(std::lround(px(*a))), int(std::lround(y)), 2, several ? dots_grey : channel[k]);
          }
      }
    }
  }
  render::write_png(path, img);
}

}  // namespace aniso
