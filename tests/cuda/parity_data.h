// tests/cuda/parity_data.h: the file format shared by parity_dump (host, g++) and parity.cu (GPU):
// materials as the kernels hold them, direction pairs and uniforms, and the CPU's float results.
// Same headers on both sides, so the structs have the same layout (checked through their sizes).
#pragma once

#include <cstdint>

#include "aniso/brdf/material.h"

namespace aniso::cuda_parity {

inline constexpr uint32_t kMagic = 0x50434e41;  // "ANCP"

struct Header {
  uint32_t magic = kMagic;
  uint32_t material_size = sizeof(MaterialT<float>);
  uint32_t materials = 0;
  uint32_t pairs_per_material = 0;
};

// One query: a direction pair for f / pdf, and (wo, uc, u) for sample.
struct Query {
  Vec3 wi, wo;
  float uc, u0, u1;
};

// What the CPU's float kernels returned for it.
struct Result {
  RGB f;
  float pdf;
  Vec3 s_wi;
  RGB s_weight;
  float s_pdf;
  int32_t s_valid;
};

}  // namespace aniso::cuda_parity
