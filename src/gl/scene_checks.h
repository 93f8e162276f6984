// gl/scene_checks.h: the GLSL of an object's material as the GL backend compiles it (private to
// src/gl). The scene checks themselves (check_gl_materials, gl_has_lights, gl_unsupported) are
// declared in scene_raster.h and defined in scene_checks.cpp.
#pragma once

#include <cstddef>

#include "aniso/gl/glsl_material.h"
#include "aniso/io/materials.h"
#include "aniso/render/scene.h"

namespace aniso::gl {

// The prefix of the material's uniforms in the scene program (shaders/raster.frag.glsl).
constexpr const char* kMaterialPrefix = "mat_";

// glsl_material(desc) with uniforms named kMaterialPrefix + slot; a material without a GLSL twin
// is an InputError naming the scene, the object and its material.
GlslMaterial object_glsl(const render::Scene& scene, size_t i, const MaterialDesc& desc);

}  // namespace aniso::gl
