// gl/gl_shader.h: compiling and linking GLSL programs in the current GL context, with the
// driver's log in the error. One implementation for the compute programs of the headless host
// (gl_context.cpp), the scene rasteriser (scene_raster.cpp) and the explorer's display passes.
#pragma once

#include <initializer_list>
#include <string>

namespace aniso::gl {

// One shader stage (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER). On failure the shader
// is deleted and a GlError says "<what> does not compile:\n<log>".
unsigned compile_shader(unsigned stage, const std::string& source, const std::string& what);

// A program linked from compiled shaders, which are deleted afterwards (also on failure). On
// failure the program is deleted and a GlError says "<what> does not link:\n<log>".
unsigned link_program(std::initializer_list<unsigned> shaders, const std::string& what);

// A vertex + fragment program: compile_shader both (the vertex shader is deleted when the fragment
// shader fails), then link_program. `what` names it in errors ("<what>: vertex shader ...").
unsigned vertex_fragment_program(const std::string& vertex, const std::string& fragment, const std::string& what);

}  // namespace aniso::gl
