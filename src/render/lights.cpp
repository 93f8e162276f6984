// render/lights.cpp: the path tracer's light sampling (lights.h): points and directions of the
// delta lights, the sphere lights' cones, the power light selection weighs the lights by, and the
// pick of one light by that power (PathTracer::pick_light).
#include "render/lights.h"

#include <algorithm>
#include <cmath>

#include "aniso/core/sampling.h"

namespace aniso::render {
namespace {

// Sphere seen from p: the cone of directions it subtends, about the unit axis from p to the
// centre. 1 - cos theta_max is written sin^2 / (1 + cos), equal to it but free of the cancellation
// of 1 - cos in float for small cones (pbrt-v4 Sphere::Sample switches to the Taylor expansion
// sin^2 / 2 below 1.5 degrees for the same reason).
struct SphereCone {
  Vec3 axis{0.0f};
  float dist = 0.0f;  // from p to the centre
  float one_minus_cos_max = 0.0f;
  bool valid = false;
};
SphereCone sphere_cone(const Light& l, const Vec3& p) {
  SphereCone c;
  const Vec3 to_c = l.position - p;
  const float d2 = glm::dot(to_c, to_c);
  const float r2 = l.radius * l.radius;
  if (!(d2 > r2)) return c;  // inside the light: it is not sampled (and not visible from inside)
  const float sin2_max = r2 / d2;
  c.one_minus_cos_max = sin2_max / (1.0f + safe_sqrt(1.0f - sin2_max));
  c.dist = std::sqrt(d2);
  c.axis = to_c / c.dist;
  c.valid = c.one_minus_cos_max > 0.0f && std::isfinite(c.dist);
  return c;
}

// The concentric disc map's point (concentric_disk_polar, core/sampling.h: Shirley & Chiu 1997) as
// its radius r = max(|2u - 1|) (exact in float, and so is 1 - r) and the cosine and sine of its
// azimuth, which the map has before it multiplies them by the signed radius: the point is
// r (cos_phi, sin_phi) up to rounding, with no length to take and divide by. At the centre (1, 0).
struct ConcentricPolar {
  float r = 0.0f, cos_phi = 1.0f, sin_phi = 0.0f;
};
ConcentricPolar concentric_polar(const Vec2& u) {
  const DiskPolarT<float> p = concentric_disk_polar(u);
  const float sign = p.r < 0.0f ? -1.0f : 1.0f;  // a negative signed radius turns the angle by pi
  return {std::fabs(p.r), sign * std::cos(p.theta), sign * std::sin(p.theta)};
}

// Rec.709 / sRGB luminance (ITU-R BT.709-6, item 3.2): the weight of a colour in light selection.
float luminance(const RGB& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

// Distance along the unit direction w from o to where it enters the sphere light l, or, if it
// passes by, to its closest approach to the centre: a shadow ray towards l stops short of this.
// In double: near the rim the entry distance is the difference of nearly equal numbers.
float sphere_entry_distance(const Light& l, const Vec3& o, const Vec3& w) {
  const glm::dvec3 oc = glm::dvec3(o) - glm::dvec3(l.position), wd(w);
  const double b = glm::dot(wd, oc), disc = b * b - (glm::dot(oc, oc) - double(l.radius) * double(l.radius));
  return float(disc > 0.0 ? -b - std::sqrt(disc) : -b);
}

bool sample_light(const Light& l, const Vec3& p, const Vec2& u, LightSample* s) {
  switch (l.kind) {
    case LightKind::Point: {
      const Vec3 d = l.position - p;
      const float d2 = glm::dot(d, d);
      if (!(d2 > 0.0f)) return false;
      s->dist = std::sqrt(d2);
      s->wi = d / s->dist;
      s->li = l.power / d2;  // I / d^2 (docs/scenes.md: units)
      s->pdf = 1.0f;
      s->delta = true;
      return true;
    }
    case LightKind::Directional:
      s->wi = l.to_light;
      s->li = l.power;  // irradiance E perpendicular to to_light
      s->dist = INFINITY;
      s->pdf = 1.0f;
      s->delta = true;
      return true;
    case LightKind::Sphere: {
      // Uniform in the cone of directions the sphere subtends (pbrt-v4 Sphere::Sample), the square
      // mapped to the cone through the concentric disc (Shirley & Chiu 1997), as Mitsuba 3's
      // square_to_uniform_cone (include/mitsuba/core/warp.h): a disc point of radius r, uniform
      // in area, gives 1 - cos theta = r^2 (1 - cos theta_max) and phi = its angle. The density
      // is that of pbrt's polar map (u.x -> cos theta, u.y -> phi); a stratum of the square stays
      // a compact patch of the cone rather than a thin wedge.
      const SphereCone c = sphere_cone(l, p);
      if (!c.valid) return false;
      const ConcentricPolar disc = concentric_polar(u);
      const float cos_phi = disc.cos_phi, sin_phi = disc.sin_phi;
      const float omc = c.one_minus_cos_max, r2 = disc.r * disc.r;
      const float omc_t = r2 * omc;  // 1 - cos theta
      const float cos_t = 1.0f - omc_t, sin_t = safe_sqrt(omc_t * (2.0f - omc_t));
      Vec3 t, b;
      orthonormal_basis(c.axis, t, b);
      s->wi = cos_t * c.axis + sin_t * (cos_phi * t + sin_phi * b);
      // The radiance is the same everywhere on the light: only the direction and the distance to
      // where it enters the sphere (the caller's) matter.
      s->li = l.power;
      s->pdf = 1.0f / (2.0f * kPi<float> * omc);
      s->delta = false;
      return true;
    }
  }
  return false;
}

float sphere_light_pdf(const Light& l, const Vec3& p) {
  const SphereCone c = sphere_cone(l, p);
  return c.valid ? 1.0f / (2.0f * kPi<float> * c.one_minus_cos_max) : 0.0f;
}

// The power of a light for selection (integrator.h), R the scene's bounding radius.
float light_power(const Light& l, float R) {
  switch (l.kind) {
    case LightKind::Point: return 4.0f * kPi<float> * luminance(l.power);
    case LightKind::Directional: return kPi<float> * R * R * luminance(l.power);
    case LightKind::Sphere: return 4.0f * kPi<float> * kPi<float> * l.radius * l.radius * luminance(l.power);
  }
  return 0.0f;
}

// Every direction from p towards the sphere light l below the plane of the geometric normal ng,
// where next-event estimation rejects it (dot(wi, ng) > 0 fails): the cone about the axis to the
// centre, of half-angle theta_max with sin theta_max = r / d, is wholly below when cos(axis, ng) <
// -sin theta_max, that is dot(to_centre, ng) < -r. The margin of 1e-3 d (an angle of 1e-3 rad) is
// far above the rounding of a sampled direction, so that no sample this skips could have passed
// the test (tests/test_render.cpp, RenderLights.SphereLightPassedOverOnlyWhenEverySampleIsBelow).
bool sphere_light_below(const Light& l, const Vec3& p, const Vec3& ng) {
  const Vec3 to_c = l.position - p;
  const float c = glm::dot(to_c, ng);
  if (!(c < 0.0f)) return false;
  const float d = std::sqrt(glm::dot(to_c, to_c));
  return c < -l.radius - 1e-3f * d;
}

Vec3 sphere_light_sample_direction(const Light& l, const Vec3& p, const Vec2& u) {
  LightSample s;
  return sample_light(l, p, u, &s) ? s.wi : Vec3(0.0f);
}

int PathTracer::pick_light(float u) const {
  if (light_cdf_.empty() || !(light_cdf_.back() > 0.0f)) return -1;
  // The candidate i with cdf[i] <= u < cdf[i + 1]; zero-probability ones have an empty interval.
  const auto it = std::upper_bound(light_cdf_.begin(), light_cdf_.end(), u);
  int i = int(it - light_cdf_.begin()) - 1;
  i = std::clamp(i, 0, int(light_prob_.size()) - 1);
  while (i > 0 && !(light_prob_[size_t(i)] > 0.0f)) --i;  // u == cdf[i] of an empty interval: rounding only
  return light_prob_[size_t(i)] > 0.0f ? i : -1;
}

}  // namespace aniso::render
