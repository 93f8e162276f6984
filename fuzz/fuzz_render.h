// fuzz/fuzz_render.h: the render check shared by the targets whose input ends up in a scene
// (scene, tangent_map, obj): an 8 x 8 picture at one sample per pixel, on one thread, must have no
// non-finite sample and only finite, non-negative pixels.
#pragma once

#include <cmath>

#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "fuzz_util.h"

namespace aniso::fuzz {

inline void check_tiny_render(render::Scene& scene) {
  scene.film.width = scene.film.height = 8;
  scene.film.spp = 1;
  render::RenderOptions ro;
  ro.threads = 1;
  render::RenderStats st;
  const render::Image img = render::render(scene, ro, &st);
  FUZZ_CHECK(st.nonfinite == 0);
  for (const float v : img.rgb) FUZZ_CHECK(std::isfinite(v) && v >= 0.0f);
}

}  // namespace aniso::fuzz
