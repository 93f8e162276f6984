// aniso/gl/glsl_export.h: a material as one self-contained GLSL source (`aniso export-glsl`) and as a
// Disney BRDF Explorer .brdf file (`aniso export-brdf`). Formats: docs/glsl.md.
#pragma once

#include <string>

#include "aniso/io/materials.h"

namespace aniso::gl {

// GLSL without #version and main: the library and the material with its parameters baked in as
// constants; every name it defines starts with "aniso_". `what` names the material in the header.
// Only the library functions the material needs (glsl_library_subset), unless `full`. A measured
// material (.bsdf, .binary) reads its tables from a texture: its header says how to upload the
// side file `tables_name` (export_glsl_tables(), docs/glsl.md "Measured materials").
std::string export_glsl(const MaterialDesc& m, const std::string& what, bool full = false, const std::string& tables_name = "");

// The side file of a measured material: glsl_tables(m) as raw little-endian float32, zero-padded to
// whole rows of kGlslTablesWidth; "" for an analytic material.
std::string export_glsl_tables(const MaterialDesc& m);

// A BRDF Explorer file: "analytic", ::begin parameters (one line per table entry: float sliders,
// [0, 1] colours, bools; defaults from m), ::begin shader with vec3 BRDF(L, V, N, X, Y). A measured
// material is an InputError (a .brdf file carries no texture).
std::string export_brdf(const MaterialDesc& m, const std::string& what);

}  // namespace aniso::gl
