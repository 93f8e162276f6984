// fuzz/fuzz_scene.cpp: the scene reader (render/scene.cpp, docs/scenes.md). The input is a scene
// JSON document; relative file names resolve against a scratch directory that holds one small
// valid asset of each kind (mesh.obj, env.hdr, env.pfm, map.pfm), so mutations can reach
// the mesh, environment-map and tangent-map paths. An accepted scene is checked further: every
// object's material satisfies the kernel contract (fuzz_util.h), a tangent map looks up finite
// unit directions, and a tiny render (8 x 8 pixels, 1 sample, 3 vertices, one thread) drops no
// NaN / Inf sample and gives a finite, non-negative image.
#include "aniso/io/params.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "fuzz_render.h"
#include "fuzz_util.h"
#include "io/json_read.h"

namespace {
using namespace aniso;

void write_assets() {
  static const char obj[] =
      "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\n"
      "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
  fuzz::write_scratch_file("mesh.obj", reinterpret_cast<const uint8_t*>(obj), sizeof obj - 1);
  // 2 x 1 Radiance HDR (RLE-free scanlines): two texels of (1, 1, 1).
  static const char hdr[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n\x80\x80\x80\x81\x80\x80\x80\x81";
  fuzz::write_scratch_file("env.hdr", reinterpret_cast<const uint8_t*>(hdr), sizeof hdr - 1);
  // 2 x 1 PFM, little endian (negative scale): (0.5, 0.5, 0.5) and (1, 0, 0.25).
  std::string pfm = "PF\n2 1\n-1.0\n";
  const float px[6] = {0.5f, 0.5f, 0.5f, 1.0f, 0.0f, 0.25f};
  pfm.append(reinterpret_cast<const char*>(px), sizeof px);
  fuzz::write_scratch_file("env.pfm", reinterpret_cast<const uint8_t*>(pfm.data()), pfm.size());
  // A 2 x 1 tangent map valid in both encodings: xy (1, 0.5) and (0.5, 1), angle 1 and 0.5.
  std::string map = "PF\n2 1\n-1.0\n";
  const float texels[6] = {1.0f, 0.5f, 0.0f, 0.5f, 1.0f, 0.0f};
  map.append(reinterpret_cast<const char*>(texels), sizeof texels);
  fuzz::write_scratch_file("map.pfm", reinterpret_cast<const uint8_t*>(map.data()), map.size());
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso::render;
  static const bool assets = (write_assets(), true);
  (void)assets;
  Scene scene;
  try {
    scene = parse_scene(parse_json_text(fuzz::as_text(data, size), "fuzz.json"), "fuzz.json", fuzz::scratch_dir());
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
    return 0;
  }
  size_t triangles = 0;
  for (const Object& o : scene.objects) {
    fuzz::check_material(o.material);
    if (o.mesh) triangles += o.mesh->indices.size() / 3;
    if (o.tangent.map)
      for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
          const Vec2 t = o.tangent.map->lookup(Vec2(float(i) / 8.0f * 3.0f - 1.0f, float(j) / 8.0f));
          FUZZ_CHECK(std::isfinite(t.x) && std::isfinite(t.y));
        }
  }
  // The render is the expensive part: only for scenes of the seed corpus's size.
  if (scene.objects.size() > 16 || triangles > 20000) return 0;
  scene.integrator.max_depth = std::min(scene.integrator.max_depth, 3);
  fuzz::check_tiny_render(scene);
  return 0;
}
