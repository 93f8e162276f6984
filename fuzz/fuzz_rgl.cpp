// fuzz/fuzz_rgl.cpp: the RGL tensor file reader (rgl/tensor.h, rgl/rgl_material.h; docs/rgl.md)
// on arbitrary bytes: the container (header, field table, shapes, offsets) and the readers' rules
// (fields, dtypes, shapes, angle grids, finite tables). Every input is either rejected with an
// InputError (no crash, no allocation from an unchecked size, no hang) or accepted, and then f,
// pdf and sample of the file are finite at a few directions. The seeds (fuzz/corpus/rgl/, written by
// fuzz/make_seeds.py) are small valid files, isotropic and anisotropic, and broken variants.
#include <cmath>

#include "aniso/io/params.h"
#include "aniso/rgl/rgl_material.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  try {
    const auto d = rgl::rgl_from_tensor(rgl::parse_tensor(std::span(data, size), "fuzz.bsdf"));
    const RglT<float> k = rgl::rgl_kernel<float>(*d);
    const Vec3 dirs[3] = {Vec3(0.f, 0.f, 1.f), glm::normalize(Vec3(0.5f, -0.3f, 0.8f)), glm::normalize(Vec3(-0.9f, 0.2f, 0.1f))};
    for (const Vec3& wo : dirs)
      for (const Vec3& wi : dirs) {
        const RGB f = k.f(wi, wo);
        FUZZ_CHECK(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z));
        FUZZ_CHECK(std::isfinite(k.pdf(wi, wo)));
      }
    for (const Vec3& wo : dirs) {
      const BSDFSampleT<float> s = k.sample(wo, 0.5f, Vec2(0.3f, 0.7f));
      if (s.valid) FUZZ_CHECK(std::isfinite(s.pdf) && std::isfinite(s.weight.x));
    }
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
  }
  return 0;
}
