// accum += u_weight * scene (additive blending, gl/scene_raster.cpp): one sub-sample pass into the
// float accumulation target, alpha (coverage) included.
uniform sampler2D u_src;
uniform float u_weight;
layout(location = 0) out vec4 o_color;
void main() { o_color = u_weight * texelFetch(u_src, ivec2(gl_FragCoord.xy), 0); }
