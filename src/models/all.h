// models/all.h: every model file, one per registry row (aniso/brdf/registry.h), and the dispatch
// from a row to its model file. A row whose model file is missing here does not compile
// (models::Tag is named by visit_model).
#pragma once

#include <utility>

#include "aniso/brdf/registry.h"
#include "models/ashikhmin_shirley.h"
#include "models/ggx.h"
#include "models/lafortune.h"
#include "models/lambert.h"
#include "models/measured.h"
#include "models/metal.h"
#include "models/model.h"
#include "models/phong.h"
#include "models/principled.h"
#include "models/rgl.h"
#include "models/ward.h"

namespace aniso::models {

// A registry row's model file P and kernel template K (Type<T>).
template <typename P, template <typename> class K> struct ModelFile {
  using plugin = P;
  template <typename T> using kernel = K<T>;
};

// Calls fn(ModelFile<models::Tag, Type>{}) for the row of kind k (no default: every row).
template <typename Fn> decltype(auto) visit_model(ModelKind k, Fn&& fn) {
  switch (k) {
#define ANISO_X(Tag, Type, member_, name_, batch_, glsl_) \
  case ModelKind::Tag: return fn(ModelFile<Tag, Type>{});
    ANISO_MODELS(ANISO_X)
#undef ANISO_X
  }
  return fn(ModelFile<Lambert, LambertT>{});
}

// A model file with hand-written builders: build<T> and its GLSL twin glsl().
template <typename P>
concept HandWritten = requires(const MaterialDesc& d, const ParamValues& pv, const SlotFn& s) {
  P::template build<float>(d);
  P::glsl(pv, s);
};

// A model file whose kernel reads the tables texture (measured.glsl, rgl.glsl): glsl_tables(m)
// writes its contents (gl::glsl_tables).
template <typename P>
concept HasTables = requires(const MaterialDesc& m) {
  P::glsl_tables(m);
};

// Each row's model file: its table is named like the row, and it has a builder and a GLSL twin,
// generated from its bound rows or hand-written.
#define ANISO_X(Tag, Type, member_, name_, batch_, glsl_)                                                          \
  static_assert(Tag::spec.name == std::string_view(name_), #Tag ": the model file's table is named like its row"); \
  static_assert(Generated<Tag> || HandWritten<Tag>, #Tag ": a model file has bound rows or hand-written builders");
ANISO_MODELS(ANISO_X)
#undef ANISO_X

// The keys of P's table that the host resolves before the GPU sees them (P::host_keys; none by
// default): they have no GLSL slot.
template <typename P> constexpr std::span<const std::string_view> host_keys() {
  if constexpr (requires { P::host_keys; })
    return P::host_keys;
  else
    return {};
}

}  // namespace aniso::models
