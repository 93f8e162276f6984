// aniso/gl/glsl_export.h: a material as one self-contained GLSL source (`aniso export-glsl`) and as a
// Disney BRDF Explorer .brdf file (`aniso export-brdf`). Formats: docs/glsl.md.
#pragma once

#include <string>

#include "aniso/io/materials.h"

namespace aniso::gl {

// GLSL without #version and main: the library and the material with its parameters baked in as
// constants; every name it defines starts with "aniso_". `what` names the material in the header.
// Only the library functions the material needs (glsl_library_subset), unless `full`.
std::string export_glsl(const MaterialDesc& m, const std::string& what, bool full = false);

// A BRDF Explorer file: "analytic", ::begin parameters (one line per table entry: float sliders,
// [0, 1] colours, bools; defaults from m), ::begin shader with vec3 BRDF(L, V, N, X, Y).
std::string export_brdf(const MaterialDesc& m, const std::string& what);

}  // namespace aniso::gl
