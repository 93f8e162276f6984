// examples/cpp/glsl.cpp: the GLSL twins of the kernels in one's own shader (CMake aniso::gl).
//
//   glsl MATERIAL OUT.frag      a fragment shader around the material's exported GLSL
//   glsl --library OUT.frag     a fragment shader around the whole GLSL library, its own material
//
// Both write a complete GLSL 3.30 core fragment shader (#version line, library, main) that
// glslangValidator accepts (the ctest runs it when it is installed). The first is what
// `aniso export-glsl` writes, called from a shader: every name it defines starts with aniso_
// (so it sits beside one's own names), the parameters are baked in as constants. The second puts the
// library itself in front of a shader that builds its kernel struct from its own numbers, with the
// library's plain names (Ward, WardLobe, Ward_f, Frame_from_normal_tangent; docs/glsl.md "Naming").
// Exit status 1 when the generated source lacks what it should define, 2 for a bad material.
#include <cstdio>
#include <fstream>
#include <string>

#include <aniso/gl/glsl_export.h>
#include <aniso/gl/glsl_library.h>
#include <aniso/io/input_error.h>
#include <aniso/io/materials.h>

namespace {

// One's own fragment shader, calling the exported entry points:
//   vec3 aniso_f_world(L, V, N, X, Y)   the BRDF (no cosine) from world-space directions and frame
// (aniso_f, aniso_pdf and aniso_sample take local-frame directions, z = normal, x = tangent).
constexpr const char* kMaterialShader = R"(
in vec3 v_normal;    // world space, interpolated
in vec3 v_tangent;   // world space, any length
in vec3 v_to_light;
in vec3 v_to_eye;
uniform vec3 u_light_radiance;
out vec4 frag_color;

void main() {
  vec3 n = normalize(v_normal);
  vec3 t = normalize(v_tangent - dot(v_tangent, n) * n);  // Gram-Schmidt
  vec3 b = cross(n, t);
  vec3 l = normalize(v_to_light);
  vec3 f = aniso_f_world(l, normalize(v_to_eye), n, t, b);
  frag_color = vec4(f * max(dot(n, l), 0.0) * u_light_radiance, 1.0);  // f cos(theta_i) L
}
)";

// The same with the library's own names: a Ward material from the shader's numbers (docs/glsl.md,
// "Minimal example").
constexpr const char* kLibraryShader = R"(
in vec3 v_normal;
in vec3 v_tangent;
in vec3 v_to_light;
in vec3 v_to_eye;
out vec4 frag_color;

void main() {
  Frame frame = Frame_from_normal_tangent(normalize(v_normal), v_tangent);
  vec3 wi = Frame_to_local(frame, normalize(v_to_light));
  vec3 wo = Frame_to_local(frame, normalize(v_to_eye));
  Ward ward = Ward(vec3(0.05), vec3(0.4), WardLobe(0.05, 0.3, WardForm_Vector, WardNormalization_Balanced));
  vec3 radiance = Ward_f(ward, wi, wo) * max(wi.z, 0.0) * vec3(3.0);
  frag_color = vec4(radiance, 1.0);
}
)";

}  // namespace

int main(int argc, char** argv) {
  namespace gl = aniso::gl;
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s MATERIAL|--library OUT.frag\n", argv[0]);
    return 2;
  }
  const std::string what = argv[1];
  std::string shader = gl::glsl_preamble(gl::GlslDialect::Core330);  // "#version 330 core\n"
  int failures = 0;
  if (what == "--library") {
    shader += gl::glsl_library_source() + kLibraryShader;
    for (const char* name : {"Ward_f", "Ward_pdf", "Ward_sample", "Frame_from_normal_tangent", "Material_f"})
      if (!gl::glsl_library_names().count(name)) ++failures, std::printf("the library does not declare %s\n", name);
  } else {
    std::string exported;
    try {
      exported = gl::export_glsl(aniso::load_material(what), what);
    } catch (const aniso::InputError& e) {
      std::fprintf(stderr, "glsl: %s\n", e.what());
      return 2;
    }
    // Everything the export declares carries the aniso_ prefix, so it cannot clash with the shader.
    for (const std::string& name : gl::glsl_declared_names(exported))
      if (name.rfind("aniso_", 0) != 0) ++failures, std::printf("exported name without the aniso_ prefix: %s\n", name.c_str());
    for (const char* name : {"aniso_f", "aniso_pdf", "aniso_sample", "aniso_f_world"})
      if (!gl::glsl_declared_names(exported).count(name)) ++failures, std::printf("the export lacks %s\n", name);
    shader += exported + kMaterialShader;
  }
  std::ofstream(argv[2]) << shader;
  std::printf("wrote %s: %zu bytes of GLSL 3.30 core\n", argv[2], shader.size());
  return failures ? 1 : 0;
}
