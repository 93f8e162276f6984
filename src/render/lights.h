// render/lights.h (private): the path tracer's light sampling (lights.cpp): a direction towards
// a light with its radiance and density, a sphere light's density and entry distance, and the
// power that light selection weighs the lights by.
#pragma once

#include "aniso/render/integrator.h"

namespace aniso::render {

struct LightSample {
  Vec3 wi{0.0f};     // towards the light
  RGB li{0.0f};      // radiance (area lights) or irradiance-like term (delta lights), before the BRDF
  float pdf = 0.0f;  // solid angle; 1 for delta lights
  // To a point light; infinity for directional lights. Not set for sphere lights: where the shadow
  // ray enters the sphere depends on the ray's origin, and the caller measures it from there
  // (sphere_entry_distance).
  float dist = 0.0f;
  bool delta = false;
};

// Distance along the unit direction w from o to where it enters the sphere light l, or, if it
// passes by, to its closest approach to the centre (lights.cpp).
float sphere_entry_distance(const Light& l, const Vec3& o, const Vec3& w);
// A direction towards l from p for the 2D sample u; false where there is none (p inside a sphere
// light, or on a point light).
bool sample_light(const Light& l, const Vec3& p, const Vec2& u, LightSample* s);
// The solid-angle density with which sample_light picks a direction towards the sphere light l.
float sphere_light_pdf(const Light& l, const Vec3& p);
// The power of a light for selection (integrator.h), R the scene's bounding radius.
float light_power(const Light& l, float R);

}  // namespace aniso::render
