// aniso/gl/glsl_library.h: the GLSL twin of include/aniso (the .glsl files beside the headers), embedded
// in the binary at build time, in the order a shader concatenates them (docs/glsl.md).
#pragma once

#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace aniso::gl {

struct GlslFile {
  std::string_view path;    // relative to the repository root, e.g. "include/aniso/brdf/ward.glsl"
  std::string_view source;  // the file's text
};

// The GLSL Material (the twin of material.h: a struct with one member per model and the tag
// dispatch of f, pdf and sample), generated from the registry (aniso/brdf/registry.h).
std::string glsl_material_dispatch();

// How a model's C++ type uses lobe_mixture.h: not at all; a diffuse + specular mixture of its own
// f and lobe choice (a `lobe` member and specular_probability(wo), as GGXT); or a
// LambertPlusLobeT<T, Lobe> (PhongT, WardT).
enum class LobeMixture { None, DiffuseSpecular, LambertPlusLobe };

// The GLSL of that mixture for the model `model` (its GLSL struct) and its lobe `model`Lobe, from
// one template per C++ template: pdf_diffuse_specular, sample_diffuse_specular, <model>_pdf and
// <model>_sample, and for LambertPlusLobe also the struct, <model>_f and
// <model>_specular_probability. Empty for None. The model's own file holds its lobe (and for
// DiffuseSpecular its struct, f and specular_probability).
std::string glsl_lobe_mixture(std::string_view model, LobeMixture mixture);

// Every library file, dependencies first: the core, the models' twins in registry order (each
// followed by its generated mixture, if any), the generated Material dispatch, the tangent fields.
std::span<const GlslFile> glsl_library_files();

// The concatenation of every library file (no #version, no main).
std::string glsl_library_source();

// The GLSL twin of render::tonemap's per-channel curve (include/aniso/image/tonemap.glsl:
// ToneMap_apply(radiance, gain, aces) and its helpers; no #version, no main). Not part of the
// library: the display passes of the GL backend and of the web explorer put it in front of theirs.
std::string_view glsl_tonemap_source();

// The library items (functions, structs, constants, each with the comment above it) that the
// GLSL `used` refers to, and everything they refer to, in library order: what a shader using only
// those names needs. Overloads are kept together.
std::string glsl_library_subset(std::string_view used);

enum class GlslDialect { Core330, Es300, Core450Compute };

// The #version line (and for ES, the precision statements) a shader puts in front of the library.
std::string glsl_preamble(GlslDialect dialect);

// The names the library declares at file scope (structs, functions, constants).
std::set<std::string> glsl_library_names();

// Renames every identifier in `source` that the library declares to prefix + name (token by token,
// comments included), so that the library can sit in another program's namespace: the exports
// use the prefix "aniso_".
std::string glsl_prefix_names(std::string_view source, std::string_view prefix);

// Names declared at file scope in `source` (functions, structs, constants, uniforms): what the
// prefix check of the exports reads.
std::set<std::string> glsl_declared_names(std::string_view source);

}  // namespace aniso::gl
