// The shadow pass (gl/shadow_atlas.h): a mesh's triangles into one tile of the atlas, the nearest
// surface kept by GL_MIN blending. Point light: the cube face (u_axes = a, b, c; u_sign) as a
// 90-degree perspective with x = r[b], y = r[c], w = s r[a] (z = 0: the clipper keeps w >= 0, the
// side the face looks at); raster.frag.glsl's cube_face() reads with the same rule. Directional:
// orthographic over the bounding sphere, x, y along Frame_from_normal(to_light) (the GLSL library
// comes before this file).
layout(location = 0) in vec3 a_p;
uniform int u_mode;  // 0 point, 1 directional
uniform vec3 u_light;  // position, or the unit direction towards the light
uniform ivec3 u_axes;
uniform float u_sign;
uniform vec3 u_center;
uniform float u_radius;
out vec3 v_p;
void main() {
  v_p = a_p;
  if (u_mode == 0) {
    vec3 r = a_p - u_light;
    gl_Position = vec4(r[u_axes.y], r[u_axes.z], 0.0, u_sign * r[u_axes.x]);
  } else {
    Frame f = Frame_from_normal(u_light);
    vec3 q = a_p - u_center;
    gl_Position = vec4(dot(q, f.t) / u_radius, dot(q, f.b) / u_radius, 0.0, 1.0);
  }
}
