// aniso/brdf/registry.h: the one list of the models. Everything that dispatches on the model is
// derived from ANISO_MODELS: the ModelKind tags and the tagged union with its constructors and
// visit (material.h), the model names of JSON and the CLI (model_name), the model files (one per
// row, src/models/<member>.h: its parameter table, cross-key rules and builders; their list and
// dispatch src/models/all.h; the tables in registry order and the material builders
// src/models/models.cpp), the batch dispatch (src/batch/dispatch-inl.h), the GLSL library table
// and the GLSL Material dispatch (src/gl/glsl_library.cpp), the GLSL builders
// (src/gl/glsl_material.cpp) and the registry tests (tests/test_registry.cpp). Every row's kernel
// has the methods of core/kernel.h (ModelKernel, checked below for float and double): how it
// roughens and whether it is a GGX, asked by the renderer and the exporters through MaterialT.
// Adding a model: docs/architecture.md, "Adding a model".
//
// One row per model:
//   X(Tag, Type, member, name, batch, glsl)
//     Tag     the ModelKind enumerator; also the kernel struct's name in GLSL (Ward, Ward_f, ...)
//     Type    the kernel template, Type<T> for T = float or double (include/aniso/brdf/<member>.h)
//     member  the union member and the header's file name (<member>.h, <member>.glsl)
//     name    the "model" value of JSON materials and of the CLI (its parameter table's name)
//     batch   Simd: a Highway twin in src/batch/twins/ (SimdTwin<Type<T>>);
//             Scalar: no twin, the batch functions run the scalar kernel per row (declared here,
//             so that a model without a twin is never dispatched to another model's)
//     glsl    Glsl: a GLSL twin <member>.glsl, in the Material dispatch; NoGlsl: none (exports and
//             the GL renderer refuse the material with a message)
// The enumerators' values are the rows' positions: GLSL and saved data do not depend on them
// (GLSL's ModelKind_* constants are generated from this list).
#pragma once

#include <cstddef>

// Every model's header (a row's Type comes from its header, include/aniso/brdf/<member>.h).
#include "aniso/brdf/ashikhmin_shirley.h"
#include "aniso/brdf/ggx.h"
#include "aniso/brdf/lafortune.h"
#include "aniso/brdf/lambert.h"
#include "aniso/brdf/measured.h"
#include "aniso/brdf/metal.h"
#include "aniso/brdf/phong.h"
#include "aniso/brdf/principled.h"
#include "aniso/brdf/rgl.h"
#include "aniso/brdf/ward.h"
#include "aniso/core/kernel.h"

#define ANISO_MODELS(X)                                                                      \
  X(Lambert, LambertT, lambert, "lambert", Simd, Glsl)                                       \
  X(Phong, PhongT, phong, "phong", Simd, Glsl)                                               \
  X(Ward, WardT, ward, "ward", Simd, Glsl)                                                   \
  X(AshikhminShirley, AshikhminShirleyT, ashikhmin_shirley, "ashikhmin-shirley", Simd, Glsl) \
  X(Lafortune, LafortuneT, lafortune, "lafortune", Simd, Glsl)                               \
  X(GGX, GGXT, ggx, "ggx", Simd, Glsl)                                                       \
  X(Metal, MetalT, metal, "metal", Simd, Glsl)                                               \
  X(Principled, PrincipledT, principled, "principled", Scalar, Glsl)                         \
  X(Measured, MeasuredT, measured, "measured", Scalar, Glsl)                                 \
  X(Rgl, RglT, rgl, "rgl", Scalar, Glsl)

namespace aniso {

enum class ModelKind : int {
#define ANISO_X(Tag, Type, member, name, batch, glsl) Tag,
  ANISO_MODELS(ANISO_X)
#undef ANISO_X
};

// How the batch functions evaluate a model (the `batch` column).
enum class BatchPath : int { Simd, Scalar };

struct ModelInfo {
  ModelKind kind;
  const char* tag;     // "AshikhminShirley": the GLSL struct and ModelKind_* constant
  const char* member;  // "ashikhmin_shirley": the union member, the header and the GLSL file
  const char* name;    // "ashikhmin-shirley": JSON and the CLI
  BatchPath batch;
  bool glsl;
};

namespace registry_detail {
constexpr bool Glsl = true, NoGlsl = false;
constexpr BatchPath Simd = BatchPath::Simd, Scalar = BatchPath::Scalar;
}  // namespace registry_detail

inline constexpr ModelInfo kModels[] = {
#define ANISO_X(Tag, Type, member, name, batch, glsl) \
  {ModelKind::Tag, #Tag, #member, name, registry_detail::batch, registry_detail::glsl},
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
};
inline constexpr size_t kModelCount = sizeof(kModels) / sizeof(kModels[0]);

constexpr const ModelInfo& model_info(ModelKind k) { return kModels[static_cast<int>(k)]; }
constexpr const char* model_name(ModelKind k) { return model_info(k).name; }

// Every row's kernel has the whole interface (core/kernel.h): f, pdf, sample, regularize and
// ggx_distribution, so that no model is skipped where they are asked.
#define ANISO_X(Tag, Type, member, name, batch, glsl)                                                      \
  static_assert(ModelKernel<Type<float>, float> && ModelKernel<Type<double>, double>, #Tag                 \
                ": the kernel lacks a method of core/kernel.h's ModelKernel (f, pdf, sample, regularize, " \
                "ggx_distribution)");
ANISO_MODELS(ANISO_X)
#undef ANISO_X

// The rows' positions are the enumerators' values (model_info indexes by them).
static_assert([] {
  for (size_t i = 0; i < kModelCount; ++i)
    if (static_cast<size_t>(kModels[i].kind) != i) return false;
  return true;
}());

}  // namespace aniso
