// gl/scene_raster.cpp: the GL backend of the renderer (see scene_raster.h for how it matches the
// CPU renderer). OpenGL 3.3 core only; entry points through libepoxy.
#include "gl/scene_raster.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "aniso/core/sampling.h"
#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "aniso/render/geometry.h"
#include "gl/gl_shader.h"

namespace aniso::gl {
namespace {

using render::LightKind;
using render::ShapeKind;

// Lights per pass: the uniform arrays of the fragment shader. More lights take more passes.
constexpr int kMaxLightsPerPass = 32;
// The proxies of analytic shapes are this much larger than the shape, so that coverage is decided
// by the fragment's exact ray test alone and never by the rasteriser's edge rule at the rim.
constexpr float kProxyGrowth = 1.02f;
constexpr const char* kMaterialPrefix = "mat_";

const char* kVertexShader = R"(
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
)";

// The scene part of the fragment shader; the library and the material's code come before it.
const char* kFragmentShader = R"(
in vec3 v_p;
in vec3 v_n;
in vec2 v_uv;
in vec3 v_dpdu;
in vec3 v_ng;
layout(location = 0) out vec4 o_color;

// Camera (render/integrator.cpp, PathTracer::camera_ray) and this pass's sub-pixel position.
uniform vec3 u_cam_pos;
uniform vec3 u_cam_fwd;
uniform vec3 u_cam_right;
uniform vec3 u_cam_up;
uniform float u_tan_half;
uniform float u_aspect;
uniform vec2 u_film;  // width, height in pixels
uniform vec2 u_sub;   // sub-pixel position in [0, 1)^2, from the pixel's top-left corner
uniform float u_far;  // gl_FragDepth = distance / u_far
uniform float u_alpha;  // written to alpha (1 in a pixel's first light batch: coverage)

// The object.
const int Shape_Sphere = 0;
const int Shape_Disc = 1;
const int Shape_Rectangle = 2;
const int Shape_Mesh = 3;
uniform int u_shape;
uniform vec3 u_center;
uniform vec3 u_normal;  // disc, rectangle
uniform vec3 u_u_axis;  // rectangle
uniform float u_radius;
uniform vec2 u_size;
uniform bool u_has_normals;  // mesh
uniform bool u_has_uvs;      // mesh

// Its tangent source (render/scene.h TangentSource).
uniform int u_tf_kind;
uniform vec3 u_tf_direction;
uniform vec3 u_tf_center;
uniform vec3 u_tf_axis;
uniform float u_tf_swirl;
uniform float u_tf_scale;
uniform float u_tf_strength;
uniform float u_tf_angle;
uniform bool u_has_map;
uniform sampler2D u_map;  // RG32F doubled-angle texels, row 0 = the image's top row (v = 1)
uniform ivec2 u_map_size;

// Lights of this pass: xyz the position (point, w = 0) or the unit direction towards the light
// (directional, w = 1); power the intensity I or the irradiance E.
const int kMaxLights = %MAX_LIGHTS%;
uniform int u_light_count;
uniform vec4 u_light_pos[kMaxLights];
uniform vec3 u_light_power[kMaxLights];

// Occluders: one row of 4 RGBA32F texels each: (kind, radius, size.x, size.y), center, normal, u axis.
uniform int u_occluder_count;
uniform sampler2D u_occluders;

// Shadow maps of the meshes (meshes cannot be ray-tested per fragment): one R32F atlas of square
// tiles, u_shadow_tile texels each, u_shadow_cols to a row. Per light: x = its first tile (-1:
// none); a point light has 6 (cube faces), a directional light 1 (orthographic over the scene's
// bounding sphere u_shadow_center, u_shadow_radius). A texel holds the distance from the light to
// the nearest mesh surface (point) or the height towards the light above the plane through the
// centre (directional).
uniform vec4 u_light_shadow[kMaxLights];
uniform sampler2D u_shadow_atlas;
uniform int u_shadow_tile;
uniform int u_shadow_cols;
uniform vec3 u_shadow_center;
uniform float u_shadow_radius;

// The cube face of direction r (from the light) and the position on it in [-1, 1]^2: the face of
// r's largest component (index a, sign s), (u, v) = (r[b], r[c]) / |r[a]| with (b, c) the other
// two axes in order. The shadow pass (kShadowVertex) projects with the same rule.
int cube_face(vec3 r, out vec2 uv) {
  vec3 m = abs(r);
  int a = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
  int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
  float s = r[a] < 0.0 ? -1.0 : 1.0;
  uv = vec2(r[b], r[c]) / (s * r[a]);
  return 2 * a + (s < 0.0 ? 1 : 0);
}

float shadow_texel(int tile, vec2 uv) {
  ivec2 t = clamp(ivec2(floor((0.5 * uv + 0.5) * float(u_shadow_tile))), ivec2(0), ivec2(u_shadow_tile - 1));
  ivec2 origin = ivec2(tile - (tile / u_shadow_cols) * u_shadow_cols, tile / u_shadow_cols) * u_shadow_tile;
  return texelFetch(u_shadow_atlas, origin + t, 0).r;
}

// Is p, on a surface with geometric normal ng, hidden from light i by a mesh? The bias covers what
// a texel's footprint hides: 3 texels' width at p over the cosine to the light (a slope makes one
// texel span more depth), plus 1e-3 of the distance (the CPU's shadow rays also stop 1e-3 short).
bool mesh_shadowed(int i, vec3 p, vec3 ng, vec3 wi_world) {
  int first = int(u_light_shadow[i].x);
  if (first < 0) return false;
  float slope = 1.0 / max(dot(ng, wi_world), 0.15);
  if (u_light_pos[i].w == 0.0) {
    vec3 r = p - u_light_pos[i].xyz;
    vec2 uv;
    int face = cube_face(r, uv);
    float dist = length(r);
    float texel = dist * 2.0 / float(u_shadow_tile);
    return shadow_texel(first + face, uv) < dist - (3.0 * texel * slope + 1e-3 * dist);
  }
  Frame f = Frame_from_normal(u_light_pos[i].xyz);
  vec3 q = p - u_shadow_center;
  vec2 uv = vec2(dot(q, f.t), dot(q, f.b)) / u_shadow_radius;
  float height = u_shadow_radius - dot(q, f.n);  // distance below the plane facing the light
  float texel = 2.0 * u_shadow_radius / float(u_shadow_tile);
  return shadow_texel(first, uv) < height - (3.0 * texel * slope + 1e-3 * u_shadow_radius);
}

const float kNoHit = -1.0;

// The smallest t > 0 at which o + t d (d unit) meets the sphere, or kNoHit. The discriminant is
// r^2 - |f - (f.d) d|^2 and the roots come from q = -(b + sign(b) sqrt(disc)) (Haines et al.,
// "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems, 2019, Ch. 7), which keep
// their precision when the sphere is small and far away.
float intersect_sphere(vec3 o, vec3 d, vec3 c, float r) {
  vec3 f = o - c;
  float b = dot(f, d);
  vec3 l = f - b * d;
  float disc = r * r - dot(l, l);
  if (disc < 0.0) return kNoHit;
  float q = -(b + (b < 0.0 ? -1.0 : 1.0) * sqrt(disc));
  if (q == 0.0) return kNoHit;  // a grazing ray through the centre of a zero-size sphere
  float t0 = (dot(f, f) - r * r) / q, t1 = q;
  float tn = min(t0, t1), tf = max(t0, t1);
  return tn > 0.0 ? tn : (tf > 0.0 ? tf : kNoHit);
}

// Ray and plane through c with normal n; kNoHit when parallel or behind.
float intersect_plane(vec3 o, vec3 d, vec3 c, vec3 n) {
  float denom = dot(d, n);
  if (denom == 0.0) return kNoHit;
  float t = dot(c - o, n) / denom;
  return t > 0.0 ? t : kNoHit;
}

float intersect_disc(vec3 o, vec3 d, vec3 c, vec3 n, float r) {
  float t = intersect_plane(o, d, c, n);
  if (t == kNoHit) return kNoHit;
  vec3 q = o + t * d - c;
  return dot(q, q) <= r * r ? t : kNoHit;
}

float intersect_rectangle(vec3 o, vec3 d, vec3 c, vec3 n, vec3 u, vec2 size) {
  float t = intersect_plane(o, d, c, n);
  if (t == kNoHit) return kNoHit;
  vec3 q = o + t * d - c;
  return abs(dot(q, u)) <= 0.5 * size.x && abs(dot(q, cross(n, u))) <= 0.5 * size.y ? t : kNoHit;
}

// Anything in (0, tmax) along o + t d? (SceneGeometry::occluded, for the analytic shapes.)
bool occluded(vec3 o, vec3 d, float tmax) {
  for (int i = 0; i < u_occluder_count; ++i) {
    vec4 a = texelFetch(u_occluders, ivec2(0, i), 0);
    vec3 c = texelFetch(u_occluders, ivec2(1, i), 0).xyz;
    vec3 n = texelFetch(u_occluders, ivec2(2, i), 0).xyz;
    vec3 u = texelFetch(u_occluders, ivec2(3, i), 0).xyz;
    int kind = int(a.x + 0.5);
    float t = kNoHit;
    if (kind == Shape_Sphere) t = intersect_sphere(o, d, c, a.y);
    else if (kind == Shape_Disc) t = intersect_disc(o, d, c, n, a.y);
    else t = intersect_rectangle(o, d, c, n, u, a.zw);
    if (t > 0.0 && t < tmax) return true;
  }
  return false;
}

// SceneGeometry::offset_origin: off the surface along ng by 1e-4 of the coordinates' magnitude
// (plus 1e-4 absolute), towards the side d leaves on.
vec3 offset_origin(vec3 p, vec3 ng, vec3 d) {
  float scale = 1e-4 * (1.0 + max(abs(p.x), max(abs(p.y), abs(p.z))));
  return p + (dot(d, ng) >= 0.0 ? scale : -scale) * ng;
}

// The disc's u axis (render/geometry.cpp disc_u_axis): world x projected onto the disc, or world z
// when the normal is within ~2.6 degrees of x.
vec3 disc_u_axis(vec3 n) {
  vec3 ref = abs(n.x) > 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
  return normalize(ref - dot(ref, n) * n);
}

int wrap_texel(float i, float n) {
  float m = i - n * floor(i / n);
  if (m >= n) m -= n;  // i / n rounded up to a whole number
  if (m < 0.0) m += n;
  return int(m);
}

// TangentMap::lookup (render/scene.cpp): texel centres at (i + 0.5) / width, v up (row 0 at v = 1),
// wrap-around, bilinear on the doubled-angle vectors, then back to a unit direction.
vec2 tangent_map_lookup(vec2 uv) {
  float w = float(u_map_size.x), h = float(u_map_size.y);
  float fx = uv.x * w - 0.5, fy = (1.0 - uv.y) * h - 0.5;
  float x0f = floor(fx), y0f = floor(fy);
  float tx = fx - x0f, ty = fy - y0f;
  int x0 = wrap_texel(x0f, w), y0 = wrap_texel(y0f, h);
  int x1 = x0 + 1 == u_map_size.x ? 0 : x0 + 1, y1 = y0 + 1 == u_map_size.y ? 0 : y0 + 1;
  vec2 a00 = texelFetch(u_map, ivec2(x0, y0), 0).xy, a10 = texelFetch(u_map, ivec2(x1, y0), 0).xy;
  vec2 a01 = texelFetch(u_map, ivec2(x0, y1), 0).xy, a11 = texelFetch(u_map, ivec2(x1, y1), 0).xy;
  vec2 q = (1.0 - ty) * ((1.0 - tx) * a00 + tx * a10) + ty * ((1.0 - tx) * a01 + tx * a11);
  return TangentMap_FromDoubled(q);
}

void main() {
  // The primary ray through this fragment's sub-sample, as PathTracer::camera_ray builds it.
  float px = gl_FragCoord.x - 0.5 + u_sub.x;
  float py = u_film.y - gl_FragCoord.y - 0.5 + u_sub.y;
  float sx = (2.0 * px / u_film.x - 1.0) * u_tan_half * u_aspect;
  float sy = (1.0 - 2.0 * py / u_film.y) * u_tan_half;
  vec3 d = normalize(u_cam_fwd + sx * u_cam_right + sy * u_cam_up);

  // The hit and its shading data (SceneGeometry::shade).
  float t;
  vec3 p, ng, ns, dpdu = vec3(0.0);
  vec2 uv = vec2(0.0);
  if (u_shape == Shape_Sphere) {
    t = intersect_sphere(u_cam_pos, d, u_center, u_radius);
    if (t == kNoHit) discard;
    ng = normalize(u_cam_pos + t * d - u_center);
    p = u_center + u_radius * ng;
    ns = ng;
    dpdu = vec3(ng.z, 0.0, -ng.x);
    float phi = atan(ng.x, ng.z);
    // theta = acos(n.y), written with atan: llvmpipe's acos is a coarse polynomial (docs/glsl.md).
    float theta = atan(length(ng.xz), ng.y);
    uv = vec2((phi < 0.0 ? phi + 2.0 * kPi : phi) * kInv2Pi, 1.0 - theta * kInvPi);
  } else if (u_shape == Shape_Disc || u_shape == Shape_Rectangle) {
    t = u_shape == Shape_Disc ? intersect_disc(u_cam_pos, d, u_center, u_normal, u_radius)
                              : intersect_rectangle(u_cam_pos, d, u_center, u_normal, u_u_axis, u_size);
    if (t == kNoHit) discard;
    p = u_cam_pos + t * d;
    ng = ns = u_normal;
    vec3 q = p - u_center;
    if (u_shape == Shape_Disc) {
      vec3 eu = disc_u_axis(u_normal), ev = cross(u_normal, eu);
      dpdu = eu;
      uv = vec2(0.5 + dot(q, eu) / (2.0 * u_radius), 0.5 + dot(q, ev) / (2.0 * u_radius));
    } else {
      vec3 ev = cross(u_normal, u_u_axis);
      dpdu = u_u_axis;
      uv = vec2(0.5 + dot(q, u_u_axis) / u_size.x, 0.5 + dot(q, ev) / u_size.y);
    }
  } else {
    p = v_p;
    t = dot(p - u_cam_pos, d);
    ng = v_ng;  // the triangle's normal (the same at its three vertices)
    ns = ng;
    if (u_has_normals) {
      float nl = length(v_n);
      if (nl > 1e-12) ns = v_n / nl;
      if (dot(ns, ng) < 0.0) ng = -ng;  // the winding decides nothing: the vertex normals do
    }
    if (u_has_uvs) uv = v_uv;
    dpdu = v_dpdu;
  }
  // Two-sided surfaces: the normals face the side the ray came from.
  if (dot(ng, d) > 0.0) {
    ng = -ng;
    ns = -ns;
  }
  if (dot(ns, ng) < 0.0) ns = ng;
  gl_FragDepth = clamp(t / u_far, 0.0, 1.0);

  SurfacePoint sp = SurfacePoint(p, ns, dpdu, uv);
  TangentField field = TangentField(u_tf_kind, u_tf_direction, u_tf_center, u_tf_axis, u_tf_swirl, u_tf_scale,
                                    u_tf_strength, u_tf_angle);
  if (u_has_map) {
    // The map's direction (a, b) is in the (t, b) frame of the natural tangent.
    Frame natural = Frame_from_normal_tangent(ns, dpdu);
    vec2 dm = tangent_map_lookup(uv);
    sp.dpdu = dm.x * natural.t + dm.y * natural.b;
    field.kind = TangentFieldKind_Natural;
  }
  Frame frame = tangent_frame(field, sp);

  // Direct light from every light of the pass (integrator.cpp, add_direct with a delta light).
  vec3 L = vec3(0.0);
  vec3 wo = Frame_to_local(frame, -d);
  if (wo.z > 0.0) {
    for (int i = 0; i < u_light_count; ++i) {
      vec3 wi_world, li;
      float tmax;
      if (u_light_pos[i].w == 0.0) {
        vec3 dl = u_light_pos[i].xyz - p;
        float d2 = dot(dl, dl);
        if (!(d2 > 0.0)) continue;
        float dist = sqrt(d2);
        wi_world = dl / dist;
        li = u_light_power[i] / d2;
        tmax = dist * (1.0 - 1e-3);  // as the CPU: stop short of the light by 1e-3 relative
      } else {
        wi_world = u_light_pos[i].xyz;
        li = u_light_power[i];
        tmax = 3.0e38;  // float's infinity: every hit counts
      }
      if (!(dot(wi_world, ng) > 0.0)) continue;  // light through the surface is blocked
      vec3 wi = Frame_to_local(frame, wi_world);
      if (!(wi.z > 0.0)) continue;
      vec3 fr = aniso_f(wi, wo);
      if (fr == vec3(0.0)) continue;
      if (occluded(offset_origin(p, ng, wi_world), wi_world, tmax)) continue;
      if (mesh_shadowed(i, p, ng, wi_world)) continue;
      L += fr * li * wi.z;
    }
  }
  // The CPU drops a non-finite sample (a bug if ever seen); so does this.
  if (any(isnan(L)) || any(isinf(L))) L = vec3(0.0);
  o_color = vec4(L, u_alpha);
}
)";

// The shadow pass: a mesh's triangles into one tile of the atlas, the nearest surface kept by
// GL_MIN blending. Point light: the cube face (u_axes = a, b, c; u_sign) as a 90-degree perspective
// with x = r[b], y = r[c], w = s r[a] (z = 0: the clipper keeps w >= 0, the side the face looks at).
// Directional: orthographic over the bounding sphere, x, y along Frame_from_normal(to_light).
const char* kShadowVertex = R"(
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
)";
const char* kShadowFragment = R"(
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
)";

const char* kFullscreenVertex = R"(
// One triangle over the whole viewport (no vertex buffer: gl_VertexID).
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";
const char* kAccumulateFragment = R"(
uniform sampler2D u_src;
uniform float u_weight;
layout(location = 0) out vec4 o_color;
void main() { o_color = u_weight * texelFetch(u_src, ivec2(gl_FragCoord.xy), 0); }
)";

// render::tonemap in GLSL (src/image/tonemap.cpp): exposure, Narkowicz 2015's ACES fit or a clamp,
// the sRGB transfer function (IEC 61966-2-1).
const char* kTonemapFragment = R"(
uniform sampler2D u_src;
uniform float u_scale;  // 2^exposure
uniform bool u_aces;
uniform vec2 u_viewport_origin;
uniform vec2 u_viewport_size;
layout(location = 0) out vec4 o_color;
float srgb_encode(float x) {
  if (!(x > 0.0)) return 0.0;
  if (x >= 1.0) return 1.0;
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec2 uv = (gl_FragCoord.xy - u_viewport_origin) / u_viewport_size;
  vec3 c = texture(u_src, uv).rgb;
  vec3 o;
  for (int k = 0; k < 3; ++k) {
    float v = c[k] * u_scale;
    if (!(v > 0.0)) v = 0.0;
    if (u_aces) {
      v = min(v, 1e4);  // the curve reaches 1 near 7.24; far above, v * v would overflow
      v = v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14);
    }
    o[k] = srgb_encode(clamp(v, 0.0, 1.0));
  }
  o_color = vec4(o, 1.0);
}
)";

// A linked vertex + fragment program with its uniform locations looked up once each.
class Program {
 public:
  Program(const std::string& vertex, const std::string& fragment, const std::string& what)
      : id_(vertex_fragment_program(vertex, fragment, what)) {}
  ~Program() {
    if (id_) glDeleteProgram(id_);
  }
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  // -1 for a name the program does not use (optimised away): glUniform* ignores location -1.
  GLint loc(const std::string& name) {
    const auto it = locations_.find(name);
    if (it != locations_.end()) return it->second;
    const GLint l = glGetUniformLocation(id_, name.c_str());
    locations_.emplace(name, l);
    return l;
  }
  // Setters for the bound program (glUseProgram(id()) first).
  void set(const std::string& name, float v) { glUniform1f(loc(name), v); }
  void set(const std::string& name, int v) { glUniform1i(loc(name), v); }
  void set(const std::string& name, const glm::vec2& v) { glUniform2f(loc(name), v.x, v.y); }
  void set(const std::string& name, const glm::vec3& v) { glUniform3f(loc(name), v.x, v.y, v.z); }
  void set(const std::string& name, const glm::ivec2& v) { glUniform2i(loc(name), v.x, v.y); }

 private:
  GLuint id_ = 0;
  std::unordered_map<std::string, GLint> locations_;
};

// Puts back the caller's framebuffer bindings and viewport when a public call ends (the explorer
// draws its window between our calls).
struct FramebufferRestore {
  GLint draw = 0, read = 0, viewport[4] = {0, 0, 0, 0};
  FramebufferRestore() {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    glGetIntegerv(GL_VIEWPORT, viewport);
  }
  ~FramebufferRestore() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  }
  FramebufferRestore(const FramebufferRestore&) = delete;
  FramebufferRestore& operator=(const FramebufferRestore&) = delete;
};

// One vertex of the vertex buffer (the attributes of kVertexShader, in order).
struct Vertex {
  glm::vec3 p{0.0f}, n{0.0f};
  glm::vec2 uv{0.0f};
  glm::vec3 dpdu{0.0f}, ng{0.0f};
};

void push_quad(std::vector<Vertex>& out, const Vec3& c, const Vec3& a, const Vec3& b) {
  const Vec3 q[4] = {c - a - b, c + a - b, c + a + b, c - a + b};
  for (int i : {0, 1, 2, 0, 2, 3}) {
    Vertex v;
    v.p = q[i];
    out.push_back(v);
  }
}

// Triangles that cover the object's projection: a proxy for the analytic shapes (the fragment
// intersects the exact shape), the triangles themselves for a mesh, with their shading attributes.
std::vector<Vertex> object_vertices(const render::Object& o) {
  std::vector<Vertex> out;
  switch (o.shape) {
    case ShapeKind::Sphere: {
      const float h = o.radius * kProxyGrowth;
      const Vec3 x(h, 0, 0), y(0, h, 0), z(0, 0, h);
      // Each face counter-clockwise seen from outside (a x b points out), so that back faces can be
      // culled when the camera is outside the cube (draw_pass).
      push_quad(out, o.center + x, y, z);
      push_quad(out, o.center - x, z, y);
      push_quad(out, o.center + y, z, x);
      push_quad(out, o.center - y, x, z);
      push_quad(out, o.center + z, x, y);
      push_quad(out, o.center - z, y, x);
      break;
    }
    case ShapeKind::Disc: {
      Vec3 a, b;
      orthonormal_basis(o.normal, a, b);
      push_quad(out, o.center, a * (o.radius * kProxyGrowth), b * (o.radius * kProxyGrowth));
      break;
    }
    case ShapeKind::Rectangle: {
      const Vec3 b = glm::cross(o.normal, o.u_axis);
      push_quad(out, o.center, o.u_axis * (0.5f * o.size.x * kProxyGrowth), b * (0.5f * o.size.y * kProxyGrowth));
      break;
    }
    case ShapeKind::Mesh: {
      const render::Mesh& m = *o.mesh;
      out.reserve(m.indices.size());
      for (size_t f = 0; f + 2 < m.indices.size(); f += 3) {
        const uint32_t i[3] = {m.indices[f], m.indices[f + 1], m.indices[f + 2]};
        // The triangle's normal and, without per-vertex tangents, its dp/du from the UVs: the
        // arithmetic of SceneGeometry::shade (render/geometry.cpp).
        const Vec3 e1 = m.positions[i[1]] - m.positions[i[0]], e2 = m.positions[i[2]] - m.positions[i[0]];
        const Vec3 ng = render::SceneGeometry::triangle_normal(e1, e2);
        Vec3 face_dpdu(0.0f);
        if (m.tangents.empty() && !m.uvs.empty()) {
          const Vec2 d1 = m.uvs[i[1]] - m.uvs[i[0]], d2 = m.uvs[i[2]] - m.uvs[i[0]];
          const float det = d1.x * d2.y - d2.x * d1.y;
          if (std::fabs(det) > 0.0f) face_dpdu = (e1 * d2.y - e2 * d1.y) / det;
        }
        for (uint32_t k : i) {
          Vertex v;
          v.p = m.positions[k];
          if (!m.normals.empty()) v.n = m.normals[k];
          if (!m.uvs.empty()) v.uv = m.uvs[k];
          v.dpdu = m.tangents.empty() ? face_dpdu : m.tangents[k];
          v.ng = ng;
          out.push_back(v);
        }
      }
      break;
    }
  }
  return out;
}

// Centre and radius of a sphere around the object's triangles (for the far plane).
std::pair<Vec3, float> bounding_sphere(const std::vector<Vertex>& vs) {
  Vec3 lo(INFINITY), hi(-INFINITY);
  for (const Vertex& v : vs) lo = glm::min(lo, v.p), hi = glm::max(hi, v.p);
  if (vs.empty()) return {Vec3(0.0f), 0.0f};
  return {0.5f * (lo + hi), 0.5f * glm::length(hi - lo)};
}

}  // namespace

glm::vec2 subsample_position(int s, int k) {
  // The midpoint rule on a k x k grid. Measured against the CPU's 256 Sobol' points per pixel on
  // the parity tests (tests/test_gl_render.cpp), it integrates the smooth but narrow highlights far
  // better than point sets that stratify the axes finely (at k = 8 the largest difference on the
  // model tests was 0.03 of the tolerance, against 0.25 for a 64-point Hammersley set and 0.44 for
  // sheared (multi-jittered) grid points); its weakness is an edge along an image axis inside a
  // pixel (a tangent-map seam seen square on), which it places only to 1 / k of the pixel.
  const int i = s % k, j = s / k;
  return glm::vec2((float(i) + 0.5f) / float(k), (float(j) + 0.5f) / float(k));
}

namespace {
GlslMaterial object_glsl(const render::Scene& scene, size_t i, const MaterialDesc& desc) {
  const render::Object& o = scene.objects[i];
  try {
    return glsl_material(desc, GlslStorage::Uniform, kMaterialPrefix);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: objects[{}] (material \"{}\"): the GL backend cannot shade it: {}", scene.source, i,
                                 o.material_name, e.what()));
  }
}
}  // namespace

void check_gl_materials(const render::Scene& scene) {
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].material_desc)
      throw InputError(fmt::format("{}: objects[{}]: no material description (render::Object::material_desc)", scene.source, i));
    object_glsl(scene, i, *scene.objects[i].material_desc);
  }
}

namespace {
RasterShaderSources sources_for(const GlslMaterial& m) {
  std::string scene_part = kFragmentShader;
  scene_part.replace(scene_part.find("%MAX_LIGHTS%"), 12, std::to_string(kMaxLightsPerPass));
  return {glsl_preamble(GlslDialect::Core330) + kVertexShader,
          glsl_preamble(GlslDialect::Core330) + glsl_library_source() + m.declarations + m.code + scene_part};
}
}  // namespace

RasterShaderSources raster_shader_sources(const MaterialDesc& material) {
  return sources_for(glsl_material(material, GlslStorage::Uniform, kMaterialPrefix));
}

int subsamples_for_spp(int spp) { return std::clamp(int(std::lround(std::sqrt(double(std::max(spp, 1))))), 1, 8); }

bool gl_has_lights(const render::Scene& scene) {
  for (const render::Light& l : scene.lights)
    if (l.kind != LightKind::Sphere && (l.power.x > 0.0f || l.power.y > 0.0f || l.power.z > 0.0f)) return true;
  return false;
}

std::vector<std::string> gl_unsupported(const render::Scene& scene) {
  std::vector<std::string> out;
  size_t spheres = 0;
  for (const render::Light& l : scene.lights) spheres += l.kind == LightKind::Sphere ? 1 : 0;
  if (spheres > 0)
    out.push_back(
        fmt::format("{} sphere light{} not rendered (the GL backend draws point and directional lights only; "
                    "sphere lights still cast shadows)",
                    spheres, spheres == 1 ? " is" : "s are"));
  if (!scene.environment.is_black()) out.push_back("the environment is not rendered (neither seen nor lighting the scene)");
  if (scene.integrator.max_depth > 1)
    out.push_back(
        fmt::format("indirect light is not rendered (integrator.max_depth {}: the GL backend renders direct "
                    "light only, as max_depth 1)",
                    scene.integrator.max_depth));
  bool mesh = false;
  for (const render::Object& o : scene.objects) mesh = mesh || o.shape == ShapeKind::Mesh;
  size_t tiles = 0, lights = 0;
  for (const render::Light& l : scene.lights)
    if (l.kind != LightKind::Sphere) tiles += l.kind == LightKind::Point ? 6 : 1, ++lights;
  if (mesh && tiles > 256)
    out.push_back(
        fmt::format("meshes cast shadows from the first lights only: the shadow maps hold 256 tiles "
                    "(a point light takes 6, a directional light 1) and the {} lights need {}",
                    lights, tiles));
  return out;
}

struct SceneRasterizer::Impl {
  struct ObjectGpu {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    GLuint map = 0;
    glm::ivec2 map_size{0};
    GlslMaterial material;
    Program* program = nullptr;
    TangentFieldT<float> field;
    Vec3 bound_center{0.0f};
    float bound_radius = 0.0f;

    // The object's tangent map as an RG32F texture (its doubled-angle encoding, nearest: the
    // shader filters as the CPU does), replacing any earlier one; none without a map.
    void upload_tangent_map(const render::TangentMap* tm) {
      if (map) glDeleteTextures(1, &map);
      map = 0;
      map_size = glm::ivec2(0);
      if (!tm) return;
      glGenTextures(1, &map);
      glBindTexture(GL_TEXTURE_2D, map);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RG32F, tm->width, tm->height, 0, GL_RG, GL_FLOAT, tm->doubled.data());
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      map_size = glm::ivec2(tm->width, tm->height);
    }
  };

  render::Scene scene;
  RasterSettings settings;
  int width = 0, height = 0;
  std::map<std::string, std::unique_ptr<Program>> programs;  // by the material's GLSL (structure)
  std::unique_ptr<Program> accumulate, tonemap;
  std::vector<ObjectGpu> objects;
  std::vector<render::Light> lights;  // point and directional
  GLuint occluders = 0, dummy = 0, empty_vao = 0;
  int occluder_count = 0;
  std::vector<glm::vec4> analytic_occluders;  // the objects' rows (sphere lights added per set_lights)
  GLuint scene_fbo = 0, scene_color = 0, scene_depth = 0, accum_fbo = 0, accum_color = 0;
  // Mesh shadow maps (see kShadowVertex): rebuilt by render() after the lights changed.
  std::unique_ptr<Program> shadow;
  GLuint shadow_atlas = 0, shadow_fbo = 0;
  int shadow_tile = 0, shadow_cols = 1;
  glm::ivec2 shadow_atlas_size{0};
  std::vector<int> shadow_first;  // per light in `lights`: first tile, or -1
  Vec3 shadow_center{0.0f};
  float shadow_radius = 1.0f;
  bool shadows_dirty = true;
  size_t shadowless_lights = 0;  // lights beyond the atlas's budget: meshes cast no shadow from them

  bool has_meshes() const {
    for (const render::Object& o : scene.objects)
      if (o.shape == ShapeKind::Mesh) return true;
    return false;
  }

  // The atlas: tiles of 1024 texels, halved until every light's tiles fit in 4096 x 4096 (64 MB of
  // R32F), down to 256; lights beyond 256 tiles get none (said by gl_unsupported's caller).
  void build_shadow_maps() {
    shadows_dirty = false;
    shadow_first.assign(lights.size(), -1);
    shadowless_lights = 0;
    if (!has_meshes() || lights.empty()) return;
    constexpr int kAtlas = 4096;
    int tiles = 0;
    for (const render::Light& l : lights) tiles += l.kind == LightKind::Point ? 6 : 1;
    shadow_tile = 1024;
    while (shadow_tile > 256 && tiles > (kAtlas / shadow_tile) * (kAtlas / shadow_tile)) shadow_tile /= 2;
    shadow_cols = kAtlas / shadow_tile;
    const int capacity = shadow_cols * shadow_cols;
    int next = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
      const int need = lights[i].kind == LightKind::Point ? 6 : 1;
      if (next + need > capacity) {
        ++shadowless_lights;
        continue;
      }
      shadow_first[i] = next;
      next += need;
    }
    const int rows = (next + shadow_cols - 1) / shadow_cols, cols_used = std::min(next, shadow_cols);
    // The bounding sphere of everything (the directional maps cover it).
    Vec3 lo(INFINITY), hi(-INFINITY);
    for (const ObjectGpu& o : objects)
      lo = glm::min(lo, o.bound_center - o.bound_radius), hi = glm::max(hi, o.bound_center + o.bound_radius);
    shadow_center = 0.5f * (lo + hi);
    shadow_radius = std::max(0.5f * glm::length(hi - lo), 1e-6f) * 1.01f;
    if (!shadow_atlas) glGenTextures(1, &shadow_atlas);
    glBindTexture(GL_TEXTURE_2D, shadow_atlas);
    const glm::ivec2 size(cols_used * shadow_tile, rows * shadow_tile);
    if (size != shadow_atlas_size) {  // the same lights moving (a dragged light) keep the texture
      glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, size.x, size.y, 0, GL_RED, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      shadow_atlas_size = size;
    }
    if (!shadow_fbo) glGenFramebuffers(1, &shadow_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, shadow_atlas, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GlError("the shadow-map atlas framebuffer is incomplete");
    const float far_value[4] = {3.0e38f, 0, 0, 0};  // nothing in the way
    glClearBufferfv(GL_COLOR, 0, far_value);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(shadow->id());
    shadow->set("u_center", shadow_center);
    shadow->set("u_radius", shadow_radius);
    for (size_t i = 0; i < lights.size(); ++i) {
      if (shadow_first[i] < 0) continue;
      const render::Light& l = lights[i];
      const bool point = l.kind == LightKind::Point;
      shadow->set("u_mode", point ? 0 : 1);
      shadow->set("u_light", point ? l.position : l.to_light);
      for (int face = 0; face < (point ? 6 : 1); ++face) {
        const int a = face / 2, b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
        glUniform3i(shadow->loc("u_axes"), a, b, c);
        shadow->set("u_sign", face % 2 == 0 ? 1.0f : -1.0f);
        const int tile = shadow_first[i] + face;
        glViewport((tile % shadow_cols) * shadow_tile, (tile / shadow_cols) * shadow_tile, shadow_tile, shadow_tile);
        for (size_t k = 0; k < objects.size(); ++k) {
          if (scene.objects[k].shape != ShapeKind::Mesh) continue;
          glBindVertexArray(objects[k].vao);
          glDrawArrays(GL_TRIANGLES, 0, objects[k].count);
        }
      }
    }
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_BLEND);
  }

  Program& program_for(const GlslMaterial& m, const std::string& what) {
    const std::string key = m.declarations + m.code;
    auto it = programs.find(key);
    if (it != programs.end()) return *it->second;
    const RasterShaderSources src = sources_for(m);
    auto p = std::make_unique<Program>(src.vertex, src.fragment, what);
    Program& ref = *p;
    programs.emplace(key, std::move(p));
    return ref;
  }

  void upload_occluders() {
    std::vector<glm::vec4> rows = analytic_occluders;
    for (const render::Light& l : scene.lights)
      if (l.kind == LightKind::Sphere) {
        rows.push_back(glm::vec4(0.0f, l.radius, 0.0f, 0.0f));
        rows.push_back(glm::vec4(l.position, 0.0f));
        rows.push_back(glm::vec4(0.0f));
        rows.push_back(glm::vec4(0.0f));
      }
    occluder_count = int(rows.size() / 4);
    if (rows.empty()) rows.assign(4, glm::vec4(0.0f));
    glBindTexture(GL_TEXTURE_2D, occluders);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 4, GLsizei(rows.size() / 4), 0, GL_RGBA, GL_FLOAT, rows.data());
  }

  void allocate_targets() {
    GLint max_texture = 0, max_renderbuffer = 0, max_viewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
    const int limit = std::min({max_texture, max_renderbuffer, max_viewport[0], max_viewport[1]});
    if (width > limit || height > limit)
      throw GlError(
          fmt::format("{}x{} pixels: this GL's largest render target is {}x{} (GL_MAX_TEXTURE_SIZE, "
                      "GL_MAX_RENDERBUFFER_SIZE, GL_MAX_VIEWPORT_DIMS); render smaller or with --backend cpu",
                      width, height, limit, limit));
    const auto color = [&](GLuint& tex) {
      if (!tex) glGenTextures(1, &tex);
      glBindTexture(GL_TEXTURE_2D, tex);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    };
    color(scene_color);
    color(accum_color);
    if (!scene_depth) glGenRenderbuffers(1, &scene_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, scene_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    if (!scene_fbo) glGenFramebuffers(1, &scene_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, scene_color, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, scene_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GlError(fmt::format("the {}x{} float scene framebuffer is incomplete", width, height));
    if (!accum_fbo) glGenFramebuffers(1, &accum_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, accum_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, accum_color, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GlError(fmt::format("the {}x{} float accumulation framebuffer is incomplete", width, height));
    // The targets start cleared: color_texture() before the first render() is black.
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
  }

  // Distance from the camera beyond everything (the far plane of the depth mapping).
  float far_plane() const {
    float far = 1.0f;
    for (const ObjectGpu& o : objects) far = std::max(far, glm::length(o.bound_center - scene.camera.position) + o.bound_radius);
    return 2.0f * far;
  }

  void set_material_slots(Program& p, const GlslMaterial& m) {
    for (const GlslSlot& s : m.slots) {
      const std::string name = std::string(kMaterialPrefix) + s.name;
      switch (s.type) {
        case GlslSlot::Type::Float: p.set(name, float(s.value.x)); break;
        case GlslSlot::Type::Vec3: p.set(name, glm::vec3(s.value)); break;
        case GlslSlot::Type::Bool:
        case GlslSlot::Type::Int: p.set(name, int(s.value.x)); break;
      }
    }
  }

  GlslMaterial material_glsl(size_t i, const MaterialDesc& desc) const { return object_glsl(scene, i, desc); }

  void draw_pass(const glm::mat4& clip_from_world, const glm::vec2& sub, size_t light_begin, size_t light_end, float alpha) {
    const render::Camera& c = scene.camera;
    const Vec3 fwd = glm::normalize(c.look_at - c.position);
    const Vec3 right = glm::normalize(glm::cross(fwd, c.up));
    const Vec3 up = glm::cross(right, fwd);
    const float far = far_plane();
    std::vector<glm::vec4> lpos, lshadow;
    std::vector<glm::vec3> lpow;
    for (size_t i = light_begin; i < light_end; ++i) {
      const render::Light& l = lights[i];
      lpos.push_back(l.kind == LightKind::Point ? glm::vec4(l.position, 0.0f) : glm::vec4(l.to_light, 1.0f));
      lpow.push_back(l.power);
      lshadow.push_back(glm::vec4(float(i < shadow_first.size() ? shadow_first[i] : -1), 0.0f, 0.0f, 0.0f));
    }
    for (const ObjectGpu& og : objects) {
      const render::Object& o = scene.objects[size_t(&og - objects.data())];
      Program& p = *og.program;
      glUseProgram(p.id());
      glUniformMatrix4fv(p.loc("u_clip_from_world"), 1, GL_FALSE, &clip_from_world[0][0]);
      p.set("u_cam_pos", c.position);
      p.set("u_cam_fwd", fwd);
      p.set("u_cam_right", right);
      p.set("u_cam_up", up);
      p.set("u_tan_half", std::tan(glm::radians(c.fov_deg) * 0.5f));
      p.set("u_aspect", float(width) / float(height));
      p.set("u_film", glm::vec2(float(width), float(height)));
      p.set("u_sub", sub);
      p.set("u_far", far);
      p.set("u_alpha", alpha);
      const int shape = o.shape == ShapeKind::Sphere      ? 0
                        : o.shape == ShapeKind::Disc      ? 1
                        : o.shape == ShapeKind::Rectangle ? 2
                                                          : 3;
      p.set("u_shape", shape);
      p.set("u_center", o.center);
      p.set("u_normal", o.normal);
      p.set("u_u_axis", o.u_axis);
      p.set("u_radius", o.radius);
      p.set("u_size", o.size);
      p.set("u_has_normals", int(o.mesh && !o.mesh->normals.empty()));
      p.set("u_has_uvs", int(o.mesh && !o.mesh->uvs.empty()));
      const TangentFieldT<float>& f = og.field;
      p.set("u_tf_kind", int(f.kind));
      p.set("u_tf_direction", f.direction);
      p.set("u_tf_center", f.center);
      p.set("u_tf_axis", f.axis);
      p.set("u_tf_swirl", f.swirl);
      p.set("u_tf_scale", f.scale);
      p.set("u_tf_strength", f.strength);
      p.set("u_tf_angle", f.angle);
      p.set("u_has_map", int(og.map != 0));
      p.set("u_map_size", og.map_size);
      p.set("u_map", 0);
      p.set("u_occluders", 1);
      p.set("u_occluder_count", occluder_count);
      p.set("u_light_count", int(lpos.size()));
      if (!lpos.empty()) {
        glUniform4fv(p.loc("u_light_pos"), GLsizei(lpos.size()), &lpos[0][0]);
        glUniform3fv(p.loc("u_light_power"), GLsizei(lpow.size()), &lpow[0][0]);
        glUniform4fv(p.loc("u_light_shadow"), GLsizei(lshadow.size()), &lshadow[0][0]);
      }
      p.set("u_shadow_atlas", 2);
      p.set("u_shadow_tile", std::max(shadow_tile, 1));
      p.set("u_shadow_cols", shadow_cols);
      p.set("u_shadow_center", shadow_center);
      p.set("u_shadow_radius", shadow_radius);
      set_material_slots(p, og.material);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, og.map ? og.map : dummy);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, occluders);
      glActiveTexture(GL_TEXTURE2);
      glBindTexture(GL_TEXTURE_2D, shadow_atlas ? shadow_atlas : dummy);
      // A sphere's proxy cube seen from outside: its back faces would only shade the same hits
      // again (the depth test then drops them), so they are culled. From inside (or nearly: 1 %
      // margin for the rounding of the comparison) every face is drawn: the far ones find the hits.
      const Vec3 rel = glm::abs(c.position - o.center);
      const bool outside = std::max(rel.x, std::max(rel.y, rel.z)) > 1.01f * kProxyGrowth * o.radius;
      if (o.shape == ShapeKind::Sphere && outside)
        glEnable(GL_CULL_FACE);
      else
        glDisable(GL_CULL_FACE);
      glBindVertexArray(og.vao);
      glDrawArrays(GL_TRIANGLES, 0, og.count);
    }
  }

  // The camera's projection (the CPU's pinhole) shifted so that the rasteriser's sample at a pixel
  // centre is the sub-sample `sub` of that pixel (see scene_raster.h).
  glm::mat4 clip_from_world(const glm::vec2& sub) const {
    const render::Camera& c = scene.camera;
    const Vec3 fwd = glm::normalize(c.look_at - c.position);
    const Vec3 right = glm::normalize(glm::cross(fwd, c.up));
    const Vec3 up = glm::cross(right, fwd);
    glm::mat4 view(1.0f);
    for (int k = 0; k < 3; ++k) {
      view[k][0] = right[k];
      view[k][1] = up[k];
      view[k][2] = -fwd[k];
    }
    view[3][0] = -glm::dot(right, c.position);
    view[3][1] = -glm::dot(up, c.position);
    view[3][2] = glm::dot(fwd, c.position);
    const float tan_half = std::tan(glm::radians(c.fov_deg) * 0.5f), aspect = float(width) / float(height);
    const float far = far_plane(), near = far * 1e-6f;  // depth comes from gl_FragDepth: near only clips
    // Window x of camera pixel px is px + (0.5 - sub.x); window y (up) of py is H - py + (sub.y - 0.5).
    const float jx = 2.0f * (0.5f - sub.x) / float(width), jy = 2.0f * (sub.y - 0.5f) / float(height);
    glm::mat4 proj(0.0f);
    proj[0][0] = 1.0f / (tan_half * aspect);
    proj[1][1] = 1.0f / tan_half;
    proj[2][0] = -jx;  // x_clip += jx * w_clip, w_clip = -z_view
    proj[2][1] = -jy;
    proj[2][2] = -(far + near) / (far - near);
    proj[3][2] = -2.0f * far * near / (far - near);
    proj[2][3] = -1.0f;
    return proj * view;
  }
};

SceneRasterizer::SceneRasterizer(const render::Scene& scene, RasterSettings settings) : impl_(std::make_unique<Impl>()) {
  if (epoxy_gl_version() < 33)
    throw GlUnavailable(fmt::format("OpenGL {} < 3.3 (the GL backend needs 3.3 core)", epoxy_gl_version()));
  const FramebufferRestore restore;
  Impl& m = *impl_;
  m.scene = scene;
  m.settings = settings;
  set_subsamples(settings.subsamples);
  m.width = scene.film.width;
  m.height = scene.film.height;
  set_lights(scene.lights);
  // Materials first: an object without a GLSL twin is an input error before anything is uploaded.
  check_gl_materials(scene);
  std::vector<GlslMaterial> materials;
  for (size_t i = 0; i < scene.objects.size(); ++i) materials.push_back(m.material_glsl(i, *scene.objects[i].material_desc));
  glGenTextures(1, &m.occluders);
  glBindTexture(GL_TEXTURE_2D, m.occluders);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenTextures(1, &m.dummy);
  glBindTexture(GL_TEXTURE_2D, m.dummy);
  const float zero[4] = {0, 0, 0, 0};
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RG32F, 1, 1, 0, GL_RG, GL_FLOAT, zero);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenVertexArrays(1, &m.empty_vao);

  m.objects.resize(scene.objects.size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const render::Object& o = scene.objects[i];
    Impl::ObjectGpu& g = m.objects[i];
    g.material = materials[i];
    g.program = &m.program_for(g.material, fmt::format("{}: objects[{}] (material \"{}\")", scene.source, i, o.material_name));
    g.field = o.tangent.field;
    const std::vector<Vertex> vs = object_vertices(o);
    std::tie(g.bound_center, g.bound_radius) = bounding_sphere(vs);
    g.count = GLsizei(vs.size());
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    glGenBuffers(1, &g.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vs.size() * sizeof(Vertex)), vs.data(), GL_STATIC_DRAW);
    const auto attrib = [](GLuint index, GLint size, size_t offset) {
      glEnableVertexAttribArray(index);
      glVertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offset));
    };
    attrib(0, 3, offsetof(Vertex, p));
    attrib(1, 3, offsetof(Vertex, n));
    attrib(2, 2, offsetof(Vertex, uv));
    attrib(3, 3, offsetof(Vertex, dpdu));
    attrib(4, 3, offsetof(Vertex, ng));
    g.upload_tangent_map(o.tangent.map.get());
    if (o.shape != ShapeKind::Mesh) {
      const float kind = o.shape == ShapeKind::Sphere ? 0.0f : o.shape == ShapeKind::Disc ? 1.0f : 2.0f;
      m.analytic_occluders.push_back(glm::vec4(kind, o.radius, o.size.x, o.size.y));
      m.analytic_occluders.push_back(glm::vec4(o.center, 0.0f));
      m.analytic_occluders.push_back(glm::vec4(o.normal, 0.0f));
      m.analytic_occluders.push_back(glm::vec4(o.u_axis, 0.0f));
    }
  }
  glBindVertexArray(0);
  m.upload_occluders();
  m.accumulate = std::make_unique<Program>(glsl_preamble(GlslDialect::Core330) + kFullscreenVertex,
                                           glsl_preamble(GlslDialect::Core330) + kAccumulateFragment, "GL backend: accumulation");
  m.shadow = std::make_unique<Program>(glsl_preamble(GlslDialect::Core330) + glsl_library_source() + kShadowVertex,
                                       glsl_preamble(GlslDialect::Core330) + kShadowFragment, "GL backend: shadow maps");
  m.tonemap = std::make_unique<Program>(glsl_preamble(GlslDialect::Core330) + kFullscreenVertex,
                                        glsl_preamble(GlslDialect::Core330) + kTonemapFragment, "GL backend: tone mapping");
  m.allocate_targets();
  if (const GLenum err = glGetError(); err != GL_NO_ERROR) throw GlError(fmt::format("GL backend setup: GL error 0x{:x}", err));
}

SceneRasterizer::~SceneRasterizer() {
  Impl& m = *impl_;
  for (Impl::ObjectGpu& g : m.objects) {
    if (g.vbo) glDeleteBuffers(1, &g.vbo);
    if (g.vao) glDeleteVertexArrays(1, &g.vao);
    if (g.map) glDeleteTextures(1, &g.map);
  }
  const GLuint textures[] = {m.occluders, m.dummy, m.scene_color, m.accum_color};
  glDeleteTextures(4, textures);
  if (m.empty_vao) glDeleteVertexArrays(1, &m.empty_vao);
  if (m.scene_depth) glDeleteRenderbuffers(1, &m.scene_depth);
  const GLuint fbos[] = {m.scene_fbo, m.accum_fbo, m.shadow_fbo};
  glDeleteFramebuffers(3, fbos);
  if (m.shadow_atlas) glDeleteTextures(1, &m.shadow_atlas);
}

void SceneRasterizer::set_camera(const render::Camera& camera) { impl_->scene.camera = camera; }

void SceneRasterizer::set_lights(const std::vector<render::Light>& lights) {
  Impl& m = *impl_;
  const std::vector<render::Light> before = m.lights;
  m.scene.lights = lights;
  m.lights.clear();
  for (const render::Light& l : lights)
    if (l.kind != LightKind::Sphere) m.lights.push_back(l);
  if (m.occluders) m.upload_occluders();
  // The shadow maps depend on where the lights are, not on their power.
  bool moved = before.size() != m.lights.size();
  for (size_t i = 0; !moved && i < before.size(); ++i)
    moved = before[i].kind != m.lights[i].kind || before[i].position != m.lights[i].position ||
            before[i].to_light != m.lights[i].to_light;
  m.shadows_dirty = m.shadows_dirty || moved;
}

void SceneRasterizer::set_material(size_t object, const MaterialDesc& material) {
  Impl& m = *impl_;
  if (object >= m.objects.size()) throw std::out_of_range(fmt::format("set_material: no object {}", object));
  GlslMaterial g = m.material_glsl(object, material);
  Impl::ObjectGpu& og = m.objects[object];
  if (g.declarations + g.code != og.material.declarations + og.material.code)
    og.program = &m.program_for(g, fmt::format("{}: objects[{}]", m.scene.source, object));
  og.material = std::move(g);
}

void SceneRasterizer::set_tangent_field(size_t object, const TangentFieldT<float>& field) {
  if (object >= impl_->objects.size()) throw std::out_of_range(fmt::format("set_tangent_field: no object {}", object));
  impl_->objects[object].field = field;
}

void SceneRasterizer::set_tangent(size_t object, const render::TangentSource& tangent) {
  Impl& m = *impl_;
  if (object >= m.objects.size()) throw std::out_of_range(fmt::format("set_tangent: no object {}", object));
  render::Object& o = m.scene.objects[object];
  if (tangent.uv_tangents != o.tangent.uv_tangents)
    throw std::invalid_argument(
        "set_tangent: uv_tangents cannot change on an existing rasteriser (the mesh's tangents are "
        "in its vertex buffer)");
  if (tangent.map && o.shape == ShapeKind::Mesh && o.mesh->uvs.empty())
    throw InputError(
        fmt::format("{}: objects[{}]: a tangent map needs a mesh with UVs; this mesh has none", m.scene.source, object));
  Impl::ObjectGpu& g = m.objects[object];
  g.upload_tangent_map(tangent.map.get());
  g.field = tangent.field;
  o.tangent = tangent;
}

void SceneRasterizer::draw_tonemapped(const render::ToneMapOptions& tm) const {
  const Impl& m = *impl_;
  GLint vp[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, vp);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(m.tonemap->id());
  m.tonemap->set("u_src", 0);
  m.tonemap->set("u_scale", std::exp2(tm.exposure_stops));
  m.tonemap->set("u_aces", int(tm.curve == render::ToneMap::Aces));
  m.tonemap->set("u_viewport_origin", glm::vec2(float(vp[0]), float(vp[1])));
  m.tonemap->set("u_viewport_size", glm::vec2(float(vp[2]), float(vp[3])));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, m.accum_color);
  // Bilinear when the viewport is not the image's size (the explorer's window); texel centres
  // land on pixel centres when it is.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindVertexArray(m.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw GlError(fmt::format("GL backend draw_tonemapped: GL error 0x{:x}", err));
}

void SceneRasterizer::set_size(int width, int height) {
  if (width < 1 || height < 1) throw std::invalid_argument(fmt::format("set_size: {}x{} is not an image size", width, height));
  Impl& m = *impl_;
  if (width == m.width && height == m.height) return;
  m.width = width;
  m.height = height;
  m.scene.film.width = width;
  m.scene.film.height = height;
  const FramebufferRestore restore;
  m.allocate_targets();
}

void SceneRasterizer::set_subsamples(int k) {
  if (k < 1 || k > 16) throw std::invalid_argument(fmt::format("set_subsamples: {} is not in [1, 16]", k));
  impl_->settings.subsamples = k;
}

void SceneRasterizer::render() {
  Impl& m = *impl_;
  const FramebufferRestore restore;
  glDisable(GL_SCISSOR_TEST);
  if (m.shadows_dirty) m.build_shadow_maps();
  glViewport(0, 0, m.width, m.height);
  glDisable(GL_BLEND);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, m.accum_fbo);
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  const int k = m.settings.subsamples;
  const size_t batches = std::max<size_t>(1, (m.lights.size() + kMaxLightsPerPass - 1) / kMaxLightsPerPass);
  const int n = k * k;
  const float weight = 1.0f / float(n);
  for (int s = 0; s < n; ++s) {
    const glm::vec2 sub = subsample_position(s, k);
    const glm::mat4 clip = m.clip_from_world(sub);
    for (size_t b = 0; b < batches; ++b) {
      glBindFramebuffer(GL_FRAMEBUFFER, m.scene_fbo);
      const float far_depth = 1.0f;
      glClearBufferfv(GL_COLOR, 0, zero);
      glClearBufferfv(GL_DEPTH, 0, &far_depth);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      const size_t begin = b * kMaxLightsPerPass, end = std::min(m.lights.size(), begin + kMaxLightsPerPass);
      m.draw_pass(clip, sub, begin, end, b == 0 ? 1.0f : 0.0f);
      glDisable(GL_DEPTH_TEST);
      // accum += weight * scene (additive blending of float targets, GL 3.0 core).
      glBindFramebuffer(GL_FRAMEBUFFER, m.accum_fbo);
      glEnable(GL_BLEND);
      glBlendEquation(GL_FUNC_ADD);
      glBlendFunc(GL_ONE, GL_ONE);
      glUseProgram(m.accumulate->id());
      m.accumulate->set("u_src", 0);
      m.accumulate->set("u_weight", weight);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, m.scene_color);
      glBindVertexArray(m.empty_vao);
      glDrawArrays(GL_TRIANGLES, 0, 3);
      glDisable(GL_BLEND);
    }
  }
  glDisable(GL_CULL_FACE);
  glBindVertexArray(0);
  glUseProgram(0);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR) throw GlError(fmt::format("GL backend render: GL error 0x{:x}", err));
}

unsigned SceneRasterizer::color_texture() const { return impl_->accum_color; }
unsigned SceneRasterizer::framebuffer() const { return impl_->accum_fbo; }
int SceneRasterizer::width() const { return impl_->width; }
int SceneRasterizer::height() const { return impl_->height; }
const render::Scene& SceneRasterizer::scene() const { return impl_->scene; }
size_t SceneRasterizer::program_count() const { return impl_->programs.size(); }

namespace {
std::vector<float> read_rgba(GLuint fbo, int w, int h) {
  GLint old_read = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &old_read);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  std::vector<float> rgba(size_t(w) * size_t(h) * 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(old_read));
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw GlError(fmt::format("GL backend read-back: GL error 0x{:x}", err));
  return rgba;
}
}  // namespace

render::Image SceneRasterizer::read_back() const {
  const int w = impl_->width, h = impl_->height;
  const std::vector<float> rgba = read_rgba(impl_->accum_fbo, w, h);
  render::Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* px = &rgba[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4];  // GL row 0 is the bottom
      img.set(x, y, RGB(px[0], px[1], px[2]));
    }
  return img;
}

std::vector<float> SceneRasterizer::read_coverage() const {
  const int w = impl_->width, h = impl_->height;
  const std::vector<float> rgba = read_rgba(impl_->accum_fbo, w, h);
  std::vector<float> out(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      out[size_t(y) * size_t(w) + size_t(x)] = rgba[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4 + 3];
  return out;
}

}  // namespace aniso::gl
