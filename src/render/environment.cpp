// render/environment.cpp: piecewise-constant distributions (pbrt-v4 util/sampling.h,
// PiecewiseConstant1D/2D; Pharr et al., PBR 4th ed., Sec. A.4.2 and A.4.7) and the environments
// built on them: uniform radiance, equirectangular maps (pbrt-v4 lights.cpp, ImageInfiniteLight;
// PBR 4th ed., Sec. 12.5.2) and a tabulated gradient sky with a sun disc.
//
// Why maps are looked up nearest-texel, not bilinearly: the sampling density is constant over a
// texel in (u, v), so with piecewise-constant radiance the estimator radiance / pdf_uv is constant
// over each texel (in solid angle it varies only as sin(theta) / sin(theta_centre) across the
// texel's latitude band). Bilinear radiance would make radiance / pdf vary inside a texel and, at
// the edge of a bright texel next to a black one, put radiance where the texel grid has little
// density: exactly the high-weight samples MIS is meant to avoid.
#include "aniso/render/environment.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

namespace aniso::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr double kPiD = std::numbers::pi;
// The largest float below 1: continuous samples live in [0, 1), and (o + du) / n can round to 1.
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// Bin of x in [0, 1] over n bins; x = 1 (u at phi = pi, v at theta = pi) belongs to the last bin,
// anything outside (only rounding puts it there) to the nearest bin.
inline int bin_of(float x, int n) { return std::clamp(int(x * float(n)), 0, n - 1); }

// Rec.709 / sRGB luminance (ITU-R BT.709-6, item 3.2), the weight of a texel in the distribution.
inline float luminance(const RGB& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Where a world direction falls on the map: u in the map's own frame (rotation undone), and
// sin(theta) of the direction for the Jacobian of the lat-long mapping. The row (v) comes from
// Environment::row_of.
struct MapCoords {
  float u = 0.0f;
  float sin_theta = 0.0f;
};

// The mapping documented in environment.h. Rotating the map by +a about +y shows the map's
// (phi_map) at world phi = phi_map - a, so the lookup adds a to the world phi. Rotation about y
// leaves w.y, hence theta and v, unchanged.
// with_u false leaves u at 0 (the azimuth's atan2 skipped): for a table of one column, where
// bin_of(u, 1) is 0 whatever u is.
inline MapCoords map_coords(const Vec3& w, float rotation_rad, bool with_u) {
  MapCoords m;
  if (with_u) {
    const float phi = std::atan2(w.x, -w.z) + rotation_rad;
    m.u = 0.5f + phi * (0.5f / kPi);
    m.u -= std::floor(m.u);  // wrap into [0, 1) (it can still round to 1: bin_of maps that to the last column)
  }
  // sqrt(x^2 + z^2) rather than sin(acos(y)) or sqrt(1 - y^2): no cancellation near the poles.
  m.sin_theta = std::sqrt(w.x * w.x + w.z * w.z);
  return m;
}

// Slices of w.y in [-1, 1] per row of the map in the row guide: a slice holds at most a few rows
// (near the poles, where rows are narrowest in w.y: about 2 h / (pi sqrt(G)) with G = 4 h slices,
// 4 rows of a 128-row map, 10 of a 1024-row one) and one row or two elsewhere.
constexpr int kRowGuidePerRow = 4;

// The inverse: the world direction of map coordinates (u, v).
inline Vec3 direction_of(const Vec2& uv, float rotation_rad) {
  const float phi = (uv.x - 0.5f) * (2.0f * kPi) - rotation_rad;
  const float theta = uv.y * kPi;
  const float st = std::sin(theta);
  return Vec3(st * std::sin(phi), std::cos(theta), -st * std::cos(phi));
}

// ---- sky ------------------------------------------------------------------------------------

// The gradient sky at elevation e (sin e = w.y):
//   w.y >= 0:  L = horizon + (zenith - horizon) * sqrt(w.y)      (= mix(horizon, zenith, sin(e)^0.5))
//   w.y <  0:  L = ground
// The square root makes the sky approach the zenith colour quickly above the horizon and keeps the
// brightening near the horizon in a thin band, as clear skies look; it is continuous at the
// horizon from above (L = horizon there) and only the ground is a step.
RGB sky_gradient(double y, const SkyParams& p) {
  if (y < 0.0) return p.ground;
  const float t = float(std::sqrt(std::min(y, 1.0)));
  return p.horizon + (p.zenith - p.horizon) * t;
}

Image tabulate_sky(const SkyParams& p) {
  // No validation here (the scene reader does it), only what keeps the table non-empty.
  const int width = std::max(p.resolution, 2);
  const int height = std::max(width / 2, 1);
  Image img(width, height);
  const double dtheta = kPiD / height, dphi = 2.0 * kPiD / width;

  // The gradient depends on theta alone: one value per row, the solid-angle mean over the row's
  // band (midpoint rule in theta, weight sin(theta)), so that a row straddling the horizon (odd
  // heights) gets the right mix of sky and ground.
  constexpr int kRowSub = 16;
  for (int y = 0; y < height; ++y) {
    glm::dvec3 acc(0.0);
    double wsum = 0.0;
    for (int k = 0; k < kRowSub; ++k) {
      const double theta = (y + (k + 0.5) / kRowSub) * dtheta;
      const double wgt = std::sin(theta);
      acc += wgt * glm::dvec3(sky_gradient(std::cos(theta), p));
      wsum += wgt;
    }
    const RGB row = wsum > 0.0 ? RGB(acc / wsum) : sky_gradient(std::cos((y + 0.5) * dtheta), p);
    for (int x = 0; x < width; ++x) img.set(x, y, row);
  }

  // The sun: a disc of angular radius r around s. Each texel gets sun_radiance times the fraction
  // of its solid angle inside the disc, so that the disc's power, sun_radiance * 2 pi (1 - cos r),
  // survives tabulation even when the disc is only a few texels wide (point-sampling the texel
  // centres would make the power jump by whole texels as the sun moves). Texels are classified by
  // the angular distance d of their centre from s: a point of the texel is at most
  // h = dtheta / 2 + dphi / 2 from its centre (along the meridian, then along the parallel, whose
  // length sin(theta) dphi / 2 is at most dphi / 2), so d + h <= r is fully inside, d - h >= r fully
  // outside, and only the texels in between are supersampled (kSunSub^2 midpoints, weighted by
  // sin(theta): the solid-angle fraction). In double: 1 - cos r is ~4e-5 for the real sun.
  const double len = glm::length(glm::dvec3(p.sun_to));
  if (max_component(p.sun_radiance) > 0.0f && len > 0.0 && std::isfinite(len) && p.sun_radius_deg > 0.0f) {
    const glm::dvec3 s = glm::dvec3(p.sun_to) / len;
    const double r = std::min(double(p.sun_radius_deg), 180.0) * kPiD / 180.0;
    const double cos_r = std::cos(r);
    const double h = 0.5 * dtheta + 0.5 * dphi;
    const double theta_s = std::acos(std::clamp(s.y, -1.0, 1.0));
    const int y0 = std::max(0, int(std::floor((theta_s - r - h) / dtheta)));
    const int y1 = std::min(height - 1, int(std::ceil((theta_s + r + h) / dtheta)));
    auto dir = [](double theta, double phi) {
      const double st = std::sin(theta);
      return glm::dvec3(st * std::sin(phi), std::cos(theta), -st * std::cos(phi));
    };
    constexpr int kSunSub = 16;
    for (int y = y0; y <= y1; ++y)
      for (int x = 0; x < width; ++x) {
        const double theta_c = (y + 0.5) * dtheta, phi_c = (x + 0.5) * dphi - kPiD;
        const glm::dvec3 c = dir(theta_c, phi_c);
        // atan2(|c x s|, c.s): accurate for small angles, where acos(c.s) is not.
        const double d = std::atan2(glm::length(glm::cross(c, s)), glm::dot(c, s));
        double coverage;
        if (d - h >= r) continue;
        if (d + h <= r) {
          coverage = 1.0;
        } else {
          double in = 0.0, all = 0.0;
          for (int a = 0; a < kSunSub; ++a) {
            const double theta = (y + (a + 0.5) / kSunSub) * dtheta;
            const double wgt = std::sin(theta);
            for (int b = 0; b < kSunSub; ++b) {
              const double phi = (x + (b + 0.5) / kSunSub) * dphi - kPiD;
              all += wgt;
              if (glm::dot(dir(theta, phi), s) >= cos_r) in += wgt;
            }
          }
          coverage = all > 0.0 ? in / all : 0.0;
        }
        if (coverage > 0.0) img.set(x, y, img.at(x, y) + p.sun_radiance * float(coverage));
      }
  }
  return img;
}

}  // namespace

// ---- Distribution1D -------------------------------------------------------------------------

Distribution1D::Distribution1D(std::vector<float> f) : func_(std::move(f)) {
  if (func_.empty()) func_.push_back(0.0f);  // an empty function is a zero one: uniform
  // Negative or NaN entries (the contract says f >= 0) would make the CDF non-monotone or NaN.
  for (float& v : func_)
    if (!(v > 0.0f)) v = 0.0f;
  const size_t n = func_.size();
  cdf_.resize(n + 1);
  // Accumulated in double: a float running sum over a 2048-wide row loses the small entries.
  double sum = 0.0;
  std::vector<double> acc(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) acc[i + 1] = sum += double(func_[i]);
  integral_ = float(sum / double(n));
  if (sum > 0.0 && std::isfinite(sum)) {
    for (size_t i = 0; i <= n; ++i) cdf_[i] = float(acc[i] / sum);
  } else {
    // Zero everywhere (or overflowing: not expected from validated input): uniform.
    integral_ = 0.0f;
    for (size_t i = 0; i <= n; ++i) cdf_[i] = float(double(i) / double(n));
  }
  cdf_[n] = 1.0f;  // exactly, so that every u < 1 finds a bin
  // The guide table: G the power of two at or above n (at most 2^20), guide_[k] the bin of k / G
  // found by the full search, guide_[G] the last bin (u < 1 never reaches bin n).
  size_t g = 1;
  while (g < n && g < (size_t(1) << 20)) g <<= 1;
  guide_.resize(g + 1);
  for (size_t k = 0; k < g; ++k) {
    const float t = float(k) / float(g);  // exact: k < 2^20 < 2^24 and g a power of two
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), t);
    guide_[k] = uint32_t(std::clamp(int(it - cdf_.begin()) - 1, 0, int(n) - 1));
  }
  guide_[g] = uint32_t(n - 1);
  uniform_pow2_ = g == n && integral_ > 0.0f && std::all_of(func_.begin(), func_.end(), [&](float v) { return v == func_[0]; });
}

float Distribution1D::sample(float u, float* pdf, int* offset) const {
  const int n = size();
  if (n == 0) {  // default-constructed: no distribution, no sample
    if (pdf) *pdf = 0.0f;
    if (offset) *offset = 0;
    return 0.0f;
  }
  u = std::clamp(u, 0.0f, kOneMinusEpsilon);
  if (uniform_pow2_) {
    // The search below, worked out: with equal weights and n = 2^m, cdf[i] = float(i n f / (n f)) is
    // i / n exactly, so the bin is o = int(u n) (exact: a power-of-two scale), u - cdf[o] and its
    // division by the width 1 / n are exact, and o + du = u n is representable, so (o + du) / n is
    // u; func / integral is f / f = 1.
    const int o = std::min(int(u * float(n)), n - 1);
    if (pdf) *pdf = func_[size_t(o)] / integral_;
    if (offset) *offset = o;
    return u;
  }
  // The bin o with cdf[o] <= u < cdf[o + 1]: the first entry above u, minus one. Bins of zero
  // weight have cdf[o] == cdf[o + 1] and are never chosen. With k = int(u G) (exact, G a power of
  // two), k / G <= u < (k + 1) / G, so the first entry above u is entry guide_[k] + 1 or later
  // (cdf[guide_[k]] <= k / G <= u) and guide_[k + 1] + 1 or earlier (cdf[guide_[k + 1] + 1] >
  // (k + 1) / G > u, or it is cdf[n] = 1 > u): the search of that range finds the same entry as
  // the search of all of cdf_. NaN (never from the samplers) takes the full search.
  auto first = cdf_.begin(), last = cdf_.end();
  if (u == u) {
    const size_t g = guide_.size() - 1;
    const size_t k = std::min(size_t(u * float(g)), g - 1);
    first = cdf_.begin() + ptrdiff_t(guide_[k]) + 1;
    last = cdf_.begin() + ptrdiff_t(guide_[k + 1]) + 2;
  }
  const auto it = std::upper_bound(first, last, u);
  const int o = std::clamp(int(it - cdf_.begin()) - 1, 0, n - 1);
  float du = u - cdf_[size_t(o)];
  const float width = cdf_[size_t(o) + 1] - cdf_[size_t(o)];
  if (width > 0.0f) du /= width;
  if (pdf) *pdf = integral_ > 0.0f ? func_[size_t(o)] / integral_ : 1.0f;
  if (offset) *offset = o;
  return std::min((float(o) + du) / float(n), kOneMinusEpsilon);
}

bool Distribution1D::samples_like(const Distribution1D& other) const {
  if (cdf_ != other.cdf_ || func_.size() != other.func_.size()) return false;
  // sample()'s pdf: 1 where the integral is 0, else func / integral (the same division).
  for (size_t i = 0; i < func_.size(); ++i) {
    const float a = integral_ > 0.0f ? func_[i] / integral_ : 1.0f;
    const float b = other.integral_ > 0.0f ? other.func_[i] / other.integral_ : 1.0f;
    if (std::memcmp(&a, &b, sizeof(float)) != 0) return false;
  }
  return true;
}

// ---- Distribution2D -------------------------------------------------------------------------

Distribution2D::Distribution2D(const std::vector<float>& f, int nu, int nv) {
  nu = std::max(nu, 1);
  nv = std::max(nv, 1);
  conditional_.reserve(size_t(nv));
  std::vector<float> marginal(static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    std::vector<float> row(size_t(nu), 0.0f);
    for (int u = 0; u < nu; ++u) {
      const size_t i = size_t(v) * size_t(nu) + size_t(u);
      if (i < f.size()) row[size_t(u)] = f[i];
    }
    conditional_.emplace_back(std::move(row));
    marginal[size_t(v)] = conditional_.back().integral();
    // The previous distinct row is the candidate: repeated rows come in runs (a sky's bands).
    const uint32_t prev = v > 0 ? sampling_row_.back() : 0;
    sampling_row_.push_back(v > 0 && conditional_.back().samples_like(conditional_[prev]) ? prev : uint32_t(v));
  }
  marginal_ = Distribution1D(std::move(marginal));
}

Vec2 Distribution2D::sample(const Vec2& u, float* pdf) const {
  float pdf_v = 0.0f, pdf_u = 0.0f;
  int v = 0;
  if (conditional_.empty()) {  // default-constructed: no distribution, no sample
    if (pdf) *pdf = 0.0f;
    return Vec2(0.0f);
  }
  // Without `pdf` the densities' divisions are skipped (Environment::sample looks the density up).
  const float d1 = marginal_.sample(u.y, pdf ? &pdf_v : nullptr, &v);
  const float d0 = conditional_[sampling_row_[size_t(v)]].sample(u.x, pdf ? &pdf_u : nullptr, nullptr);
  if (pdf) *pdf = pdf_u * pdf_v;
  return Vec2(d0, d1);
}

float Distribution2D::pdf(const Vec2& uv) const {
  if (conditional_.empty()) return 0.0f;  // default-constructed
  return pdf_of_bin(bin_of(uv.x, conditional_.front().size()), bin_of(uv.y, marginal_.size()));
}

float Distribution2D::pdf_of_bin(int iu, int iv) const {
  if (conditional_.empty()) return 0.0f;  // default-constructed
  // pdf_u * pdf_v = (f / I_row) (I_row / I) = f / I, I the marginal's integral (the mean of f).
  // A zero function samples uniformly (pdf 1 in both factors): say so here too.
  if (!(marginal_.integral() > 0.0f)) return 1.0f;
  return conditional_[size_t(iv)].func(iu) / marginal_.integral();
}

// ---- Environment ----------------------------------------------------------------------------

Environment Environment::uniform(const RGB& radiance) {
  Environment e;
  if (radiance == RGB(0.0f)) return e;  // black: is_black(), never sampled
  e.kind_ = Kind::Uniform;
  e.uniform_ = radiance;
  e.max_radiance_ = radiance;
  e.luminance_integral_ = 4.0f * kPi * luminance(radiance);
  return e;
}

Environment Environment::from_image(Image img, float scale, float rotation_deg) {
  Environment e;
  if (img.width <= 0 || img.height <= 0 || img.rgb.size() < size_t(img.width) * size_t(img.height) * 3) return e;
  for (float& c : img.rgb) c *= scale;
  const int w = img.width, h = img.height;

  // Texel weights for sampling: luminance times sin(theta) at the texel centre (the lat-long
  // Jacobian, dw = 2 pi^2 sin(theta) du dv), with a floor for every texel that is not black:
  //   f = max(luminance, 1e-3 * mean luminance) * sin(theta_centre)   if any channel > 0
  //   f = 0                                                           otherwise
  // The floor keeps pdf > 0 wherever eval() > 0 (dim texels, or saturated blue / red ones with
  // tiny luminance), which MIS needs to stay unbiased; 1e-3 of the mean (the solid-angle mean
  // over the sphere) costs at most 0.1% of the samples and bounds radiance / pdf of dim texels
  // at 1000x that of an average one.
  std::vector<float> lum(size_t(w) * size_t(h));
  std::vector<float> sin_c(static_cast<size_t>(h));
  double lum_sum = 0.0, sin_sum = 0.0;
  bool any = false;
  for (int y = 0; y < h; ++y) {
    sin_c[size_t(y)] = std::sin((float(y) + 0.5f) * kPi / float(h));
    for (int x = 0; x < w; ++x) {
      const RGB c = img.at(x, y);
      const float l = std::max(luminance(c), 0.0f);
      lum[size_t(y) * size_t(w) + size_t(x)] = l;
      lum_sum += double(l) * sin_c[size_t(y)];
      sin_sum += sin_c[size_t(y)];
      any = any || max_component(c) > 0.0f;
    }
  }
  if (!any) return e;  // black map: is_black(), never sampled
  // Non-black texels but no positive luminance only happens with negative channels (invalid
  // input); any positive floor then gives those texels equal weight.
  const float floor_lum = lum_sum > 0.0 ? float(1e-3 * lum_sum / sin_sum) : 1.0f;
  std::vector<float> f(lum.size(), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (max_component(img.at(x, y)) > 0.0f) f[i] = std::max(lum[i], floor_lum) * sin_c[size_t(y)];
    }

  for (int c = 0; c < 3; ++c) {
    float lo = INFINITY, hi = 0.0f;
    for (size_t i = size_t(c); i < img.rgb.size(); i += 3) lo = std::min(lo, img.rgb[i]), hi = std::max(hi, img.rgb[i]);
    if (hi > 0.0f) e.variation_ = std::max(e.variation_, (hi - lo) / hi);
    e.max_radiance_[c] = hi;
  }
  e.kind_ = Kind::Map;
  e.luminance_integral_ = float(lum_sum * (2.0 * kPiD * kPiD) / (double(w) * double(h)));
  e.rotation_rad_ = rotation_deg * (kPi / 180.0f);
  e.dist_ = std::make_shared<const Distribution2D>(f, w, h);
  e.width_ = w;
  e.height_ = h;
  // Row boundaries in w.y (row_of): cos(k pi / h) in double, rounded once; the ends exact.
  e.row_cos_.resize(size_t(h) + 1);
  for (int k = 0; k <= h; ++k) e.row_cos_[size_t(k)] = float(std::cos(double(k) * kPiD / double(h)));
  e.row_cos_.front() = 1.0f;
  e.row_cos_.back() = -1.0f;
  const int slices = kRowGuidePerRow * h;
  e.row_guide_.resize(size_t(slices));
  for (int j = 0; j < slices; ++j) {
    // The row at the slice's top: the first guess for every y of the slice (row_of corrects it).
    const float y_top = float(-1.0 + 2.0 * double(j + 1) / double(slices));
    int r = 0;
    while (r < h - 1 && e.row_cos_[size_t(r) + 1] >= y_top) ++r;
    e.row_guide_[size_t(j)] = uint32_t(r);
  }
  e.texels_.resize(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      e.texels_[size_t(y) * size_t(w) + size_t(x)] = Texel{img.at(x, y), e.dist_->pdf_of_bin(x, y)};
    }
  // A map whose every row is one texel repeated, bit for bit (the gradient sky without a sun: it
  // depends on theta alone) keeps one texel per row and a width of 1 for the lookup: bin_of(u, 1)
  // is 0, so every lookup reads the same texel values as from the full table, from one small
  // enough to stay in cache (the full one is read at random and misses it).
  bool rows_constant = true;
  for (int y = 0; y < h && rows_constant; ++y)
    for (int x = 1; x < w && rows_constant; ++x)
      rows_constant =
          std::memcmp(&e.texels_[size_t(y) * size_t(w) + size_t(x)], &e.texels_[size_t(y) * size_t(w)], sizeof(Texel)) == 0;
  if (rows_constant && w > 1) {
    for (int y = 0; y < h; ++y) e.texels_[size_t(y)] = e.texels_[size_t(y) * size_t(w)];
    e.texels_.resize(size_t(h));
    e.texels_.shrink_to_fit();
    e.width_ = 1;
  }
  return e;
}

Environment Environment::sky(const SkyParams& params) { return from_image(tabulate_sky(params), 1.0f, 0.0f); }

// The row r of the map whose band of directions holds w.y = y: theta = acos(y) in [r pi / h,
// (r + 1) pi / h), that is row_cos_[r + 1] < y <= row_cos_[r] (row 0 takes y = 1, row h - 1 takes
// y = -1). Found from the guide's first guess by comparisons with the boundaries: no acos (lookup
// and acos were 6.9% of the gallery's time, lookup and row_of are 4.5%: docs/benchmarks.md, "The
// fifth round"). The result satisfies
// those inequalities whatever the guess, so the guide only saves steps. Out-of-range y (rounding
// of a unit vector) belongs to the nearest pole's row, NaN to the bottom row.
int Environment::row_of(float y) const {
  const int h = height_;
  y = y >= -1.0f ? std::min(y, 1.0f) : -1.0f;
  const int slices = int(row_guide_.size());
  const int j = std::min(int((y + 1.0f) * (0.5f * float(slices))), slices - 1);
  int r = int(row_guide_[size_t(j)]);
  while (r > 0 && row_cos_[size_t(r)] < y) --r;
  while (r < h - 1 && row_cos_[size_t(r) + 1] >= y) ++r;
  return r;
}

Environment::Lookup Environment::lookup(const Vec3& w) const {
  switch (kind_) {
    case Kind::None: return {};
    case Kind::Uniform: return {uniform_, 1.0f / (4.0f * kPi)};
    case Kind::Map: break;
  }
  // One texel per row (width_ 1): the column is 0 for every direction, and the azimuth is not needed.
  const MapCoords m = map_coords(w, rotation_rad_, width_ > 1);
  const Texel& t = texels_[size_t(row_of(w.y)) * size_t(width_) + size_t(bin_of(m.u, width_))];
  // At the poles the lat-long map squeezes a whole row into a point: the density in solid angle is
  // unbounded there and the direction is never sampled (probability zero), so report 0.
  if (!(m.sin_theta > 0.0f)) return {t.radiance, 0.0f};
  return {t.radiance, t.pdf_uv / (2.0f * kPi * kPi * m.sin_theta)};
}

RGB Environment::eval(const Vec3& w) const { return lookup(w).radiance; }

float Environment::pdf(const Vec3& w) const { return lookup(w).pdf; }

template <bool kAbove> EnvSample Environment::sample_impl(const Vec2& u, const Vec3& n) const {
  EnvSample s;
  switch (kind_) {
    case Kind::None: return s;
    case Kind::Uniform: {
      // Uniform sphere (PBR 4th ed., Sec. A.5.2), y up.
      const float y = 1.0f - 2.0f * u.x;
      const float r = safe_sqrt(1.0f - y * y);
      const float phi = 2.0f * kPi * u.y;
      s.w = Vec3(r * std::cos(phi), y, r * std::sin(phi));
      if (kAbove && !(glm::dot(s.w, n) > 0.0f)) return EnvSample{};
      s.radiance = uniform_;
      s.pdf = 1.0f / (4.0f * kPi);
      return s;
    }
    case Kind::Map: break;
  }
  // The sample's density in (u, v) is not needed: the lookup below gives the direction's (and a
  // map's distribution never picks a texel of weight 0).
  const Vec2 uv = dist_->sample(u, nullptr);
  s.w = direction_of(uv, rotation_rad_);
  if (kAbove && !(glm::dot(s.w, n) > 0.0f)) return EnvSample{};
  // Radiance and pdf through eval() and pdf() of the direction itself, not from (uv, pdf_uv): a
  // sample that lands on a texel edge may round into the neighbour texel, and the estimator
  // radiance / pdf and the MIS weights need the values eval() and pdf() give for s.w exactly.
  const Lookup l = lookup(s.w);
  s.radiance = l.radiance;
  s.pdf = l.pdf;
  if (!(s.pdf > 0.0f)) return EnvSample{};  // rounded into a black texel or onto a pole
  return s;
}

EnvSample Environment::sample(const Vec2& u) const { return sample_impl<false>(u, Vec3(0.0f)); }

EnvSample Environment::sample_above(const Vec2& u, const Vec3& n) const { return sample_impl<true>(u, n); }

}  // namespace aniso::render
