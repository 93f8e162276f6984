// gl/scene_raster.h: the GL backend of the renderer. Rasterises a scene (render/scene.h) with
// OpenGL 3.3 core and shades it through the GLSL library: the direct light of the scene's point
// and directional lights, the same quantity the CPU path tracer (render/integrator.h) gives with
// integrator.max_depth 1 and only those lights (docs/scenes.md, "GL backend").
//
// How it matches the CPU renderer:
// - Camera: every fragment builds its primary ray from gl_FragCoord with the CPU's formula
//   (PathTracer::camera_ray), and the rasteriser's projection is that pinhole, shifted by the
//   sub-pixel offset of the pass, so the rasterised sample and the fragment's ray are one ray.
// - Pixels: the CPU averages radiance over each pixel's square (box filter). Here each pixel gets
//   k^2 sub-samples at the centres of a k x k grid over its square (subsample_position()),
//   one render pass each, averaged in a float accumulation target (RasterSettings::subsamples).
// - Analytic shapes (sphere, disc, rectangle): a slightly larger convex proxy (a cube about the
//   sphere, a square about the disc, the rectangle grown by 1 %) is rasterised only to find the
//   pixels; the fragment intersects its ray with the exact shape, discards a miss, and writes
//   gl_FragDepth. Silhouettes, points, normals and UVs are the CPU's (SceneGeometry::shade).
// - Meshes (OBJ, torus): triangles rasterised as they are; perspective-correct interpolation is
//   Embree's barycentric interpolation of the same vertex normals, UVs and tangents (the mesh's
//   own tangents: the torus's, or the UV tangents the scene reader computed for {"field": "uv"};
//   otherwise each triangle's dp/du from its UVs, computed on the host as shade() does).
// - Tangent frames: the GLSL twin of aniso/tangent/fields.h (tangent_frame); tangent maps are
//   the scene reader's doubled-angle texels in a float texture, filtered in the shader with the
//   arithmetic of TangentMap::lookup (texelFetch, no hardware filtering).
// - Shadows: shadow rays are intersected exactly, per fragment, with every analytic shape (and
//   with the scene's sphere lights, which block light in the CPU's BVH too), from the CPU's
//   offset origin (SceneGeometry::offset_origin). Meshes cast theirs through shadow maps (an R32F
//   atlas: 6 cube faces per point light, one orthographic tile per directional light), redrawn by
//   render() after set_lights(); their edges are placed to about a texel.
// - Not rendered: sphere (area) lights and environments (gl_unsupported() lists them), indirect
//   light. A material without a GLSL twin (measured MERL tables) is an InputError naming the object.
//
// Depth: every fragment writes gl_FragDepth = (distance along its unit ray) / far into a 32-bit
// float depth buffer, analytic or mesh alike, so the two kinds of geometry are depth-tested on one
// scale.
//
// Context: the caller's OpenGL >= 3.3 core context must be current on the calling thread for the
// whole life of the object (gl::GlContext::get() for headless use, a GLFW window's context in the
// explorer). Only GL 3.3 core entry points are used (no DSA, no compute). Every call puts back the
// draw and read framebuffers and the viewport it found; it changes the bound program, vertex array,
// active texture unit and the textures on units 0 to 2, and leaves GL_DEPTH_TEST, GL_BLEND,
// GL_CULL_FACE and GL_SCISSOR_TEST disabled.
//
// Use from a window (the explorer's lit sphere):
//   render::Scene s = render::parse_scene(doc, "lit sphere", "");  // camera, a sphere, a directional light
//   gl::SceneRasterizer r(s, gl::RasterSettings{2});
//   per frame: r.set_material(0, desc); r.set_lights(lights); r.set_size(w, h); r.render();
//              bind the window's framebuffer, glViewport(...), r.draw_tonemapped({exposure, curve});
//   screenshot / tests: r.read_back() (linear RGB) or render::tonemap(r.read_back(), tm).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "aniso/image/tonemap.h"
#include "aniso/io/materials.h"
#include "aniso/render/scene.h"

namespace aniso::gl {

struct RasterSettings {
  int subsamples = 4;  // k: k^2 sub-pixel positions per pixel (one pass each), k in [1, 16]
};

// Sub-sample s in [0, k^2) within a pixel's square, (0, 0) its top-left corner: the centre
// ((i + 0.5) / k, (j + 0.5) / k) of cell (i, j) = (s mod k, s / k) of the k x k grid.
glm::vec2 subsample_position(int s, int k);

// The sub-sample count per axis the CLI uses for a scene with `spp` samples per pixel:
// round(sqrt(spp)) clamped to [1, 8] (k^2 sub-samples per pixel).
int subsamples_for_spp(int spp);

// What the GL backend leaves out of `scene`, one sentence each (sphere lights, the environment,
// indirect light when max_depth > 1, mesh shadows of lights beyond the shadow maps' 256 tiles):
// `aniso render --backend gl` prints them as warnings.
std::vector<std::string> gl_unsupported(const render::Scene& scene);
// Throws the InputError SceneRasterizer's constructor would for a material without a GLSL twin,
// without needing a GL context (the CLI checks before it opens one).
void check_gl_materials(const render::Scene& scene);
// Whether the scene has a point or directional light with non-zero power (else the GL render is black).
bool gl_has_lights(const render::Scene& scene);

// The vertex and fragment shader (complete, #version 330 core) the rasteriser compiles for a
// material: what the tests hand to glslangValidator as GLSL 3.30.
struct RasterShaderSources {
  std::string vertex, fragment;
};
RasterShaderSources raster_shader_sources(const MaterialDesc& material);

class SceneRasterizer {
 public:
  // Uploads the scene's geometry, tangent maps and occluders and compiles one program per material
  // structure. Each object's material is scene.objects[i].material_desc (set by the scene reader).
  // A measured material's tables go to a texture (one per file, glsl_tables()). Throws InputError
  // for an object whose material has no GLSL twin ("objects[2] (material x): ..."), GlError for a
  // GL failure (a shader that does not compile carries the log). The scene is copied: the
  // caller's Scene may go away.
  explicit SceneRasterizer(const render::Scene& scene, RasterSettings settings = {});
  ~SceneRasterizer();
  SceneRasterizer(const SceneRasterizer&) = delete;
  SceneRasterizer& operator=(const SceneRasterizer&) = delete;

  // --- per-frame changes: uniforms, except where said ---
  void set_camera(const render::Camera& camera);
  // Point and directional lights are drawn; sphere lights are kept as occluders only. When the scene
  // has meshes, the next render() redraws their shadow maps (the meshes once per cube face or tile).
  void set_lights(const std::vector<render::Light>& lights);
  // A material for object `object` (e.g. a slider moved). Same structure as before (the same model,
  // Ward form / normalisation choices are uniforms too, the same Lafortune lobe count, the same metal
  // lobe model and directional_diffuse presence): uniforms only. Another structure: a cached program,
  // compiled on first use. InputError for a material without a GLSL twin.
  void set_material(size_t object, const MaterialDesc& material);
  // The object's tangent field (kind, angle, centre, axis, swirl, noise): uniforms only. A tangent map
  // or mesh UV tangents stay as the scene gave them.
  void set_tangent_field(size_t object, const TangentFieldT<float>& field);
  // The object's whole tangent source: the field, and a tangent map (uploaded; null removes it).
  // uv_tangents cannot be switched here: a mesh's tangents are in its vertex buffer (build a new
  // rasteriser from a scene read with {"field": "uv"}); asking for a change is std::invalid_argument.
  void set_tangent(size_t object, const render::TangentSource& tangent);
  // Image size in pixels (reallocates the targets when it changes) and sub-samples per axis.
  void set_size(int width, int height);
  void set_subsamples(int k);

  // Renders the image into color_texture().
  void render();
  // The result of the last render(): a width x height GL_RGBA32F texture, RGB the linear radiance,
  // alpha the fraction of the pixel's sub-samples that hit a surface (its coverage). GL's
  // convention: row 0 at the BOTTOM.
  unsigned color_texture() const;
  // The framebuffer object holding color_texture() (for glBlitFramebuffer to a window).
  unsigned framebuffer() const;
  // Draws the last render() into the caller's bound draw framebuffer and viewport, tone-mapped
  // as the CPU's PNG writer does (render::tonemap: 2^exposure, the ACES curve or a clamp, the sRGB
  // transfer function; written as is, so GL_FRAMEBUFFER_SRGB must be off). Covers the viewport
  // (the caller picks its aspect); depth test and blending off; restores nothing else.
  void draw_tonemapped(const render::ToneMapOptions& tm = {}) const;
  // Linear RGB of the last render(), row 0 at the top (render::Image, what write_image takes).
  render::Image read_back() const;
  // Coverage (alpha) of the last render(), row 0 at the top, width * height values in [0, 1].
  std::vector<float> read_coverage() const;

  int width() const;
  int height() const;
  const render::Scene& scene() const;
  size_t program_count() const;  // compiled material programs (the structure cache), for tests

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aniso::gl
