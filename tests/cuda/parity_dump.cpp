// tests/cuda/parity_dump.cpp: writes the input and the CPU's float results of the CUDA parity check
// (tests/cuda/parity.cu): every preset and every test material, 256 queries each (random pairs,
// near-mirror pairs, grazing pairs down to the horizon cosine, h = n, wi = wo).
//   aniso_cuda_parity_dump out.bin
#include <cstdio>
#include <vector>

#include "../test_util.h"
#include "aniso/io/presets.h"
#include "parity_data.h"

using namespace aniso;
using namespace aniso::cuda_parity;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s out.bin\n", argv[0]);
    return 2;
  }
  std::vector<MaterialT<float>> mats;
  for (const PresetInfo& p : presets()) mats.push_back(test::build<float>(p.json));
  for (const test::NamedMaterial& nm : test::all_model_materials()) mats.push_back(test::build<float>(nm.json));
  constexpr uint32_t kPairs = 256;
  std::vector<Query> queries;
  std::vector<Result> results;
  Rng rng(2026);
  const auto grazing = [&](double zmax) {
    const double z = zmax * (1.0 - rng.uniform()), phi = 2.0 * M_PI * rng.uniform(), r = std::sqrt(1.0 - z * z);
    return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
  };
  for (const MaterialT<float>& m : mats) {
    for (uint32_t i = 0; i < kPairs; ++i) {
      Query q;
      q.wo = (i % 4 == 3) ? grazing(i % 8 == 3 ? 1e-4 : 0.02) : test::random_upper<float>(rng);
      switch (i % 5) {
        case 0: q.wi = reflect_about_normal(q.wo); break;  // h = n
        case 1: q.wi = glm::normalize(reflect_about_normal(q.wo) + 0.05f * test::random_upper<float>(rng)); break;
        case 2: q.wi = grazing(0.05); break;
        default: q.wi = test::random_upper<float>(rng); break;
      }
      if (i == 7) q.wi = q.wo;
      q.uc = rng.uniform_as<float>();
      q.u0 = rng.uniform_as<float>();
      q.u1 = rng.uniform_as<float>();
      Result r;
      r.f = m.f(q.wi, q.wo);
      r.pdf = m.pdf(q.wi, q.wo);
      const BSDFSampleT<float> s = m.sample(q.wo, q.uc, Vec2(q.u0, q.u1));
      r.s_wi = s.wi;
      r.s_weight = s.weight;
      r.s_pdf = s.pdf;
      r.s_valid = s.valid ? 1 : 0;
      queries.push_back(q);
      results.push_back(r);
    }
  }
  Header h;
  h.materials = uint32_t(mats.size());
  h.pairs_per_material = kPairs;
  FILE* f = std::fopen(argv[1], "wb");
  if (!f) return 1;
  const bool ok = std::fwrite(&h, sizeof h, 1, f) == 1 &&
                  std::fwrite(mats.data(), sizeof(mats[0]), mats.size(), f) == mats.size() &&
                  std::fwrite(queries.data(), sizeof(Query), queries.size(), f) == queries.size() &&
                  std::fwrite(results.data(), sizeof(Result), results.size(), f) == results.size();
  if (std::fclose(f) != 0 || !ok) return 1;
  std::printf("%u materials x %u queries written to %s\n", h.materials, kPairs, argv[1]);
  return 0;
}
