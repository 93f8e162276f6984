// aniso/gl/glsl_material.h: a material's parameters on the GLSL side, generated from the parameter
// tables (the model files, src/models/<member>.h). One slot per table entry (nested objects and
// list items flattened with '_': lobe_alpha_x, lobes0_cx, directional_diffuse_albedo), declared as
// uniforms or baked constants, and the GLSL that builds the model's kernel struct from them the
// way build_material() does (generated from the table's rows bound to the kernel's fields, or the
// model file's own). A table entry that the builder does not use is an
// error (std::logic_error naming it): adding a parameter to a table without its GLSL counterpart
// fails the GLSL tests.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/io/materials.h"

namespace aniso::gl {

class ComputeProgram;

enum class GlslStorage {
  Uniform,       // `uniform float <prefix>alpha_x;` set by the host (set_uniforms)
  UniformBlock,  // the same members in `layout(std140) uniform AnisoMaterialParams { ... };`,
                 // filled from pack_std140() in one buffer (glBindBufferBase(GL_UNIFORM_BUFFER))
  Const,         // `const float <prefix>alpha_x = 0.15;` (export-glsl)
  BrdfExplorer,  // declared and set by Disney's BRDF Explorer from the .brdf parameter lines
};

struct GlslSlot {
  enum class Type { Float, Vec3, Bool, Int };
  std::string name;       // GLSL name without prefix: "alpha_x", "lobe_alpha_x", "lobes0_cx"
  std::string table_key;  // where it comes from: "ward.alpha_x", "metal.lobe.alpha_x", "lafortune.lobes[0].cx"
  const ParamSpec* spec = nullptr;
  Type type = Type::Float;
  glm::dvec3 value{0.0};  // Float, Bool (0 / 1), Int (the choice's index): .x; Vec3: all three
  // BrdfExplorer: a colour whose range is [0, 1] is a `color` line; any other range is three
  // `float` sliders <name>_r, _g, _b.
  bool unit_color() const { return type == Type::Vec3 && spec && spec->min >= 0.0 && spec->max <= 1.0; }
};

struct GlslMaterial {
  std::string model_struct;  // the kernel struct: "Ward", "Metal", ...
  std::string model_kind;    // its ModelKind_ constant: "ModelKind_Ward", ...
  std::vector<GlslSlot> slots;
  // Declarations (uniforms or constants; empty for BrdfExplorer) and the functions
  //   <Model> aniso_model()                          the kernel struct from the slots
  //   Material aniso_material()                      the same behind the Material dispatch
  //   vec3 aniso_f(vec3 wi, vec3 wo)                 (local frame; no cosine)
  //   float aniso_pdf(vec3 wi, vec3 wo)
  //   vec3 aniso_sample(vec3 wo, vec3 u, out vec3 weight, out float pdf)   (u.x picks the lobe)
  //   vec3 aniso_f_world(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
  // written with the library's unprefixed names (glsl_prefix_names() renames them).
  std::string declarations;
  std::string code;
  // A measured material (models measured and rgl): its kernel reads the tables texture (sampler
  // uniform kGlslTablesSampler), whose contents glsl_tables() makes from the material's file.
  bool needs_tables = false;
};

// The material's GLSL. `prefix` is put in front of every slot name (uniforms and constants).
GlslMaterial glsl_material(const MaterialDesc& m, GlslStorage storage, std::string_view prefix);
// The same with an explicit table (tests use a table with an extra entry to see the error).
GlslMaterial glsl_material(const MaterialDesc& m, const ModelSpec& spec, GlslStorage storage, std::string_view prefix);

// The measured tables texture (docs/glsl.md, "Measured materials"; include/aniso/brdf/measured.glsl):
// an R32F texture kGlslTablesWidth texels wide, float i at texel (i % width, i / width), read by
// texelFetch through the sampler uniform kGlslTablesSampler.
inline constexpr int kGlslTablesWidth = 4096;
inline constexpr const char* kGlslTablesSampler = "MeasuredTables_texture";
// The largest part a header can address: its offsets are floats, exact up to 2^24.
inline constexpr size_t kGlslTablesMaxFloats = size_t(1) << 24;

// The tables of a measured material as the texture holds them, from base 0: the header and tables
// of measured.glsl (a MERL table: 5.0 M floats) or rgl.glsl (a tensor file); empty for an analytic
// material. InputError when the material lacks its data or the part exceeds kGlslTablesMaxFloats.
std::vector<float> glsl_tables(const MaterialDesc& m);

// A float as a GLSL literal that reads back as the same float ("0.150000006", "1.0", "1e+06").
std::string glsl_float_literal(double x);

// The std140 layout of a UniformBlock material: one offset per slot (in slot order), the block's
// size, and the bytes to upload. std140 (OpenGL 4.5 core, Sec. 7.6.2.2): float, int and bool
// (as a 32-bit 0 / 1) take 4 bytes aligned to 4; vec3 takes 12 bytes aligned to 16.
struct Std140Block {
  std::vector<size_t> offsets;
  std::vector<unsigned char> bytes;
};
Std140Block pack_std140(const GlslMaterial& material);
inline constexpr const char* kGlslMaterialBlock = "AnisoMaterialParams";

// Sets every slot of a Uniform-storage material on the program.
void set_uniforms(const ComputeProgram& program, const GlslMaterial& material, std::string_view prefix);

}  // namespace aniso::gl
