// The scene pass's fragment shader (gl/scene_raster.cpp, scene_raster.h says how it matches the CPU
// renderer): the exact ray hit of the fragment's primary ray, its shading frame and the direct light
// of this pass's lights, with shadows. The program is the preamble, the GLSL library, the
// material's declarations and code, then this file (kMaxLights set by gl/scene_raster.cpp).

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
// two axes in order. The shadow pass (shadow_map.vert.glsl) projects with the same rule.
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
