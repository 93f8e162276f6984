// The scene pass's vertex shader (gl/scene_raster.cpp): a proxy's or a mesh's vertices (gl/raster_geometry.h
// Vertex, the attributes in order) to clip space, their shading attributes passed on.
layout(location = 0) in vec3 a_p;
layout(location = 1) in vec3 a_n;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_dpdu;
layout(location = 4) in vec3 a_ng;
uniform mat4 u_clip_from_world;
out vec3 v_p;
out vec3 v_n;
out vec2 v_uv;
out vec3 v_dpdu;
out vec3 v_ng;
void main() {
  v_p = a_p;
  v_n = a_n;
  v_uv = a_uv;
  v_dpdu = a_dpdu;
  v_ng = a_ng;
  gl_Position = u_clip_from_world * vec4(a_p, 1.0);
}
