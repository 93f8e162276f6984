// gl/shader_sources.h: the GL backend's shaders (src/gl/shaders/*.glsl), embedded in the binary at
// build time by CMakeLists.txt (aniso_embed_text), so that nothing is read at run time. Each is a
// part of a program: gl/scene_raster.cpp, gl/shadow_atlas.cpp and gl/tonemap_pass.cpp put the
// preamble and, where a shader calls it, the GLSL library in front.
#pragma once

#include <string_view>

namespace aniso::embedded {
extern const std::string_view gl_shader_raster_vert, gl_shader_raster_frag, gl_shader_shadow_map_vert, gl_shader_shadow_map_frag,
    gl_shader_fullscreen_vert, gl_shader_accumulate_frag, gl_shader_tonemap_pass_frag;
}  // namespace aniso::embedded
