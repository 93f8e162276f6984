// The GL backend's display pass (gl/tonemap_pass.h): the accumulated radiance through the one tone
// map, ToneMap_apply of aniso/image/tonemap.glsl (the twin of render::tonemap), which comes before
// this file in the program.
uniform sampler2D u_src;
uniform float u_scale;  // 2^exposure
uniform bool u_aces;
// One texel per pixel (the viewport is the texture's size): texelFetch, so that a texel is never
// mixed with its neighbours (a NaN or inf beside it would spoil it through the filter's weights).
// Otherwise bilinear over the viewport.
uniform bool u_exact;
uniform vec2 u_viewport_origin;
uniform vec2 u_viewport_size;
layout(location = 0) out vec4 o_color;
void main() {
  vec2 xy = gl_FragCoord.xy - u_viewport_origin;
  vec3 c = u_exact ? texelFetch(u_src, ivec2(xy), 0).rgb : texture(u_src, xy / u_viewport_size).rgb;
  o_color = vec4(ToneMap_apply(c, u_scale, u_aces), 1.0);
}
