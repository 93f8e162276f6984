// fuzz/fuzz_tangent_map.cpp: tangent maps (render/scene.cpp, read_tangent_map; docs/scenes.md,
// "Tangent maps"). The first byte chooses the file format (PNG or PFM) and the encoding ("angle"
// or "xy"); the rest is the map file, referenced from a fixed scene with a mapped rectangle.
// An accepted map must look up finite unit directions everywhere (bilinear, wrapping UVs
// outside [0, 1] included), and a tiny render of the rectangle must stay finite.
#include <fmt/format.h>

#include "aniso/io/params.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "fuzz_render.h"
#include "fuzz_util.h"
#include "io/json_read.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  using namespace aniso::render;
  if (size == 0) return 0;
  const char* ext = (data[0] & 1) ? ".pfm" : ".png";
  const char* encoding = (data[0] & 2) ? "xy" : "angle";
  fuzz::write_scratch_file(std::string("map") + ext, data + 1, size - 1);
  const std::string doc = fmt::format(
      R"({{"camera": {{"position": [0, 2, 3], "look_at": [0, 0, 0]}},
          "lights": [{{"type": "directional", "to_light": [0.3, 1, 0.2], "irradiance": 3}}],
          "objects": [{{"shape": "rectangle", "center": [0, 0, 0], "normal": [0, 1, 0], "u": [1, 0, 0],
                       "size": [2, 2], "material": "brushed-gold",
                       "tangent": {{"map": "map{}", "encoding": "{}"}}}}]}})",
      ext, encoding);
  Scene scene;
  try {
    scene = parse_scene(parse_json_text(doc, "fuzz.json"), "fuzz.json", fuzz::scratch_dir());
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
    return 0;
  }
  const TangentMap& map = *scene.objects.at(0).tangent.map;
  for (int i = -4; i <= 12; ++i)
    for (int j = -4; j <= 12; ++j) {
      const Vec2 t = map.lookup(Vec2(float(i) / 8.0f, float(j) / 8.0f));
      FUZZ_CHECK(std::isfinite(t.x) && std::isfinite(t.y));
      const float len = glm::length(t);
      // lookup() returns a unit direction, or 0 where opposite texels cancel (scene.h).
      FUZZ_CHECK(len == 0.0f || std::abs(len - 1.0f) < 1e-3f);
    }
  fuzz::check_tiny_render(scene);
  return 0;
}
