// The shadow pass's value (gl/shadow_atlas.h): the distance from the point light, or the height
// towards the directional light above the plane through the bounding sphere's centre.
in vec3 v_p;
uniform int u_mode;
uniform vec3 u_light;
uniform vec3 u_center;
uniform float u_radius;
layout(location = 0) out vec4 o_value;
void main() {
  float v = u_mode == 0 ? length(v_p - u_light) : u_radius - dot(v_p - u_center, u_light);
  o_value = vec4(v, 0.0, 0.0, 0.0);
}
