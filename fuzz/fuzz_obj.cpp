// fuzz/fuzz_obj.cpp: OBJ meshes as scenes load them (render/scene.cpp, load_obj through
// tinyobjloader; UV tangents). The input is the .obj file, referenced from a fixed scene as a mesh
// with {"field": "uv"} tangents when the first byte is odd. An accepted mesh must have finite
// positions, unit normals (when it has them), valid indices, finite tangents, and a tiny render
// of it must stay finite.
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
  const bool uv = (data[0] & 1) != 0;
  fuzz::write_scratch_file("mesh.obj", data + 1, size - 1);
  const std::string doc = fmt::format(
      R"({{"camera": {{"position": [0, 2, 3], "look_at": [0, 0, 0]}},
          "lights": [{{"type": "point", "position": [1, 3, 2], "intensity": 10}}],
          "objects": [{{"shape": "mesh", "file": "mesh.obj", "material": "brushed-gold"{}}}]}})",
      uv ? R"(, "tangent": {"field": "uv"})" : "");
  Scene scene;
  try {
    scene = parse_scene(parse_json_text(doc, "fuzz.json"), "fuzz.json", fuzz::scratch_dir());
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
    return 0;
  }
  const Mesh& m = *scene.objects.at(0).mesh;
  for (const Vec3& p : m.positions) FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  for (const Vec3& n : m.normals) FUZZ_CHECK(std::abs(glm::length(n) - 1.0f) < 1e-3f);
  for (const Vec3& t : m.tangents) FUZZ_CHECK(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z));
  for (const uint32_t i : m.indices) FUZZ_CHECK(i < m.positions.size());
  if (m.indices.size() / 3 > 20000) return 0;
  fuzz::check_tiny_render(scene);
  return 0;
}
