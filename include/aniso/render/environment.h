// aniso/render/environment.h: light arriving from infinitely far away (the "environment" of a scene),
// importance-sampled.
//
// World space is y-up (the default camera's up is +y). Directions `w` point from the scene
// towards the environment. Latitude-longitude mapping of environment maps (equirectangular, as
// .hdr light probes are stored), before `rotation_deg`:
//   phi   = atan2(w.x, -w.z) in (-pi, pi],   u = 0.5 + phi / (2 pi)   (u = 0.5 looks along -z)
//   theta = acos(w.y) in [0, pi],             v = theta / pi            (v = 0 is the zenith, row 0)
// rotation_deg rotates the map about +y (positive = counter-clockwise seen from above, the
// right-hand rule): what the unrotated map shows at (u, v) appears at (u - rotation_deg / 360
// mod 1, v); e.g. +90 moves the map's centre (u = 0.5, looking along -z) to u = 0.25 (along -x).
// Maps are looked up nearest-texel (piecewise-constant radiance, matching the piecewise-constant
// sampling density; environment.cpp says why not bilinear).
//
// Every environment is sampled in proportion to its radiance (luminance) times sin(theta) over a
// tabulated lat-long grid (a piecewise-constant 2D distribution: pbrt-v4 lights.cpp,
// ImageInfiniteLight; Pharr et al., PBR 4th ed., Sec. 12.5), so that eval(), pdf() and sample()
// agree exactly: pdf(w) is the density sample() draws w with, in solid angle. Every texel that is
// not black gets at least 1e-3 of the mean luminance as its weight, so pdf(w) > 0 wherever
// eval(w) > 0 (needed for unbiased MIS). eval, pdf and sample are const and thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "aniso/core/math.h"
#include "aniso/image/image.h"

namespace aniso::render {

// Piecewise-constant 1D distribution over [0, 1) (pbrt-v4 PiecewiseConstant1D).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<float> f);  // f >= 0 (others count as 0); all zero or empty -> uniform
  // Continuous sample in [0, 1); *pdf is the density w.r.t. [0, 1) (func / integral, or 1 when
  // uniform), *offset the bin. Zero-weight bins are never returned. Either pointer may be null.
  // The bin is the one a binary search of the whole CDF finds (the first cdf entry above u, minus
  // one), searched only between two entries of a guide table (Chen & Asau 1974, "On generating
  // random variates from an empirical distribution"; Devroye 1986, "Non-Uniform Random Variate
  // Generation", Ch. III, the guide table method): O(1) expected when no bin is much narrower than 1 / n.
  float sample(float u, float* pdf, int* offset) const;
  float integral() const { return integral_; }
  // Whether sample() gives the same results as other's for every u, bit for bit: the same CDF and
  // the same func / integral in every bin (rows of a map that depend on theta alone).
  bool samples_like(const Distribution1D& other) const;
  int size() const { return int(func_.size()); }
  float func(int i) const { return func_[size_t(i)]; }

 private:
  std::vector<float> func_, cdf_;
  // guide_[k] = the bin of u = k / G (G = guide_.size() - 1, a power of two, so that k = int(u G)
  // is exact and u in [k / G, (k + 1) / G) has its bin in [guide_[k], guide_[k + 1]]).
  std::vector<uint32_t> guide_;
  float integral_ = 0.0f;
  // Every weight the same and positive, n a power of two: the CDF entries are i / n exactly, and
  // the search's result (o + du) / n is u itself, bin int(u n) (a sky's rows, constant in u).
  bool uniform_pow2_ = false;
};

// Piecewise-constant 2D distribution over [0, 1)^2: marginal in v (rows), conditional in u.
// Default-constructed ones (and default Distribution1D) give no sample: pdf 0.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<float>& f, int nu, int nv);  // f[v * nu + u]
  Vec2 sample(const Vec2& u, float* pdf) const;                 // returns (u, v) in [0, 1)^2; pdf may be null
  float pdf(const Vec2& uv) const;                              // density w.r.t. [0, 1)^2, as sample()'s
  float pdf_of_bin(int iu, int iv) const;                       // pdf() anywhere in bin (iu, iv)

 private:
  std::vector<Distribution1D> conditional_;
  // sampling_row_[v]: the first row whose conditional samples like row v's, sampled in its place,
  // so that a map of repeated rows samples from one row's tables, which stay in cache.
  std::vector<uint32_t> sampling_row_;
  Distribution1D marginal_;
};

struct SkyParams {
  Vec3 sun_to{0.3f, 0.8f, 0.5f};   // direction towards the sun (normalised by the reader)
  RGB sun_radiance{0.0f};          // radiance of the sun's disc; 0 = no sun
  float sun_radius_deg = 0.5f;     // angular radius of the disc
  RGB zenith{0.25f, 0.45f, 0.9f};  // sky radiance straight up
  RGB horizon{0.9f, 0.95f, 1.0f};  // sky radiance at the horizon
  RGB ground{0.25f, 0.22f, 0.2f};  // radiance below the horizon
  int resolution = 1024;           // width of the tabulated lat-long grid (height = width / 2)
};

struct EnvSample {
  Vec3 w{0.0f};  // direction towards the environment (unit)
  RGB radiance{0.0f};
  float pdf = 0.0f;  // solid-angle density; 0 = no sample
};

class Environment {
 public:
  // No environment: black, never sampled. uniform(0), an all-black map and a sky whose colours and
  // sun are all zero are this too (is_black()).
  Environment() = default;
  // Constant radiance; sampled uniformly over the sphere (pdf 1 / (4 pi)).
  static Environment uniform(const RGB& radiance);
  // Gradient sky (zenith -> horizon blend in elevation, see environment.cpp for the formula) with
  // an optional sun disc of constant radiance, tabulated at params.resolution for sampling; each
  // texel holds the solid-angle mean over it, so the sun's power is kept even for a disc a few
  // texels wide. Looked up like a map afterwards.
  static Environment sky(const SkyParams& params);
  // An equirectangular map (mapping above); `scale` multiplies it.
  static Environment from_image(Image img, float scale, float rotation_deg);

  bool is_black() const { return kind_ == Kind::None; }
  // The integral of its luminance (Rec.709) over the sphere of directions, in solid angle: the
  // environment's weight in light selection (integrator.h). Maps: the texels' sum weighted by their
  // solid angle, sin(theta_centre) (2 pi / w) (pi / h).
  float luminance_integral() const { return luminance_integral_; }
  // Constant to within kNearlyConstant in every channel ((max - min) / max over the directions):
  // the integrator does not light-sample such an environment (integrator.h, "Environment").
  static constexpr float kNearlyConstant = 0.02f;
  bool nearly_constant() const { return kind_ != Kind::None && variation_ <= kNearlyConstant; }
  // The largest radiance it sends, per channel, over all directions (texels): eval(w) <= this in
  // every channel for every w. Black: 0.
  RGB max_radiance() const { return max_radiance_; }
  RGB eval(const Vec3& w) const;   // radiance arriving from direction w
  float pdf(const Vec3& w) const;  // density of sample() producing w (solid angle)
  // Both at once (one lookup of w on the map): {eval(w), pdf(w)}, bit for bit.
  struct Lookup {
    RGB radiance{0.0f};
    float pdf = 0.0f;
  };
  Lookup lookup(const Vec3& w) const;
  // radiance == eval(w) and pdf == pdf(w) exactly. pdf = 0 means no sample: always for black
  // environments, otherwise only when rounding puts w on a pole or into a black neighbour texel.
  EnvSample sample(const Vec2& u) const;
  // sample(u) where its direction w has dot(w, n) > 0, else no sample (pdf 0) and no lookup of w:
  // for next-event estimation, which rejects directions below the surface (the lookup was half the
  // cost of such a sample).
  EnvSample sample_above(const Vec2& u, const Vec3& n) const;

 private:
  enum class Kind { None, Uniform, Map };
  Kind kind_ = Kind::None;
  RGB uniform_{0.0f};
  // The map's texels, each with its sampling density w.r.t. [0, 1)^2 (Distribution2D::pdf of the
  // texel, the same float) beside its radiance, so that a lookup reads one 16-byte record.
  struct Texel {
    RGB radiance{0.0f};
    float pdf_uv = 0.0f;
  };
  std::vector<Texel> texels_;
  // The row of a direction from its w.y alone, without acos (environment.cpp, row_of): row_cos_[k]
  // = cos(k pi / height), the rows' boundaries, and row_guide_ a first guess per slice of w.y.
  int row_of(float y) const;
  std::vector<float> row_cos_;
  std::vector<uint32_t> row_guide_;
  int width_ = 0, height_ = 0;  // of texels_: width_ is 1 when every row of the map is one texel repeated
  float rotation_rad_ = 0.0f;
  float luminance_integral_ = 0.0f;
  float variation_ = 0.0f;  // max over channels of (max - min) / max over the texels (0: uniform)
  RGB max_radiance_{0.0f};  // per channel, over the texels (uniform: the radiance)
  std::shared_ptr<const Distribution2D> dist_;
  template <bool kAbove> EnvSample sample_impl(const Vec2& u, const Vec3& n) const;
};

}  // namespace aniso::render
