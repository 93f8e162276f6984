// gl/scene_raster.cpp: the GL backend of the renderer (see scene_raster.h for how it matches the
// CPU renderer). OpenGL 3.3 core only; entry points through libepoxy.
#include "gl/scene_raster.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "gl/gl_objects.h"
#include "gl/raster_geometry.h"
#include "gl/scene_checks.h"
#include "gl/shader_sources.h"
#include "gl/shadow_atlas.h"
#include "gl/tonemap_pass.h"

namespace aniso::gl {
namespace {

using render::LightKind;
using render::ShapeKind;

// Lights per pass: the uniform arrays of the fragment shader. More lights take more passes.
constexpr int kMaxLightsPerPass = 32;

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
RasterShaderSources sources_for(const GlslMaterial& m) {
  std::string scene_part(embedded::gl_shader_raster_frag);
  scene_part.replace(scene_part.find("%MAX_LIGHTS%"), 12, std::to_string(kMaxLightsPerPass));
  return {glsl_preamble(GlslDialect::Core330) + std::string(embedded::gl_shader_raster_vert),
          glsl_preamble(GlslDialect::Core330) + glsl_library_source() + m.declarations + m.code + scene_part};
}
}  // namespace

RasterShaderSources raster_shader_sources(const MaterialDesc& material) {
  return sources_for(glsl_material(material, GlslStorage::Uniform, kMaterialPrefix));
}

int subsamples_for_spp(int spp) { return std::clamp(int(std::lround(std::sqrt(double(std::max(spp, 1))))), 1, 8); }

struct SceneRasterizer::Impl {
  struct ObjectGpu {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    GLuint map = 0;
    glm::ivec2 map_size{0};
    GlslMaterial material;
    Program* program = nullptr;
    std::shared_ptr<TablesTexture> tables;  // a measured material's tables (texture unit 3); else none
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
  // The measured materials' tables textures, one per file (by its data, which the entry keeps).
  std::map<const void*, std::pair<std::shared_ptr<const void>, std::shared_ptr<TablesTexture>>> tables;
  std::unique_ptr<Program> accumulate;
  std::unique_ptr<TonemapPass> tonemap;
  std::vector<ObjectGpu> objects;
  std::vector<render::Light> lights;  // point and directional
  GLuint occluders = 0, dummy = 0, empty_vao = 0;
  int occluder_count = 0;
  std::vector<glm::vec4> analytic_occluders;  // the objects' rows (sphere lights added per set_lights)
  GLuint scene_fbo = 0, scene_color = 0, scene_depth = 0, accum_fbo = 0, accum_color = 0;
  // Mesh shadow maps: redrawn by render() after the lights moved.
  std::unique_ptr<ShadowAtlas> shadow;
  bool shadows_dirty = true;

  // The meshes into the shadow atlas; the directional maps cover every object's bounds.
  void build_shadow_maps() {
    shadows_dirty = false;
    std::vector<ShadowCaster> casters;
    Vec3 lo(INFINITY), hi(-INFINITY);
    for (size_t k = 0; k < objects.size(); ++k) {
      const ObjectGpu& o = objects[k];
      if (scene.objects[k].shape == ShapeKind::Mesh) casters.push_back({o.vao, o.count});
      lo = glm::min(lo, o.bound_center - o.bound_radius), hi = glm::max(hi, o.bound_center + o.bound_radius);
    }
    shadow->build(lights, casters, lo, hi);
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

  // The tables texture of a measured material (made once per file), none for an analytic one.
  std::shared_ptr<TablesTexture> tables_for(const MaterialDesc& desc, const GlslMaterial& g) {
    if (!g.needs_tables) return nullptr;
    const std::shared_ptr<const void> data =
        desc.rgl ? std::shared_ptr<const void>(desc.rgl) : std::shared_ptr<const void>(desc.measured);
    auto& entry = tables[data.get()];
    if (!entry.second) entry = {data, std::make_shared<TablesTexture>(glsl_tables(desc))};
    return entry.second;
  }

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
      lshadow.push_back(glm::vec4(float(shadow->first_tile(i)), 0.0f, 0.0f, 0.0f));
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
      shadow->set_uniforms(p);
      set_material_slots(p, og.material);
      if (og.tables) {
        og.tables->bind(3);
        p.set(kGlslTablesSampler, 3);
      }
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, og.map ? og.map : dummy);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, occluders);
      glActiveTexture(GL_TEXTURE2);
      glBindTexture(GL_TEXTURE_2D, shadow->texture() ? shadow->texture() : dummy);
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
    g.tables = m.tables_for(*o.material_desc, g.material);
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
  m.accumulate = std::make_unique<Program>(glsl_preamble(GlslDialect::Core330) + std::string(embedded::gl_shader_fullscreen_vert),
                                           glsl_preamble(GlslDialect::Core330) + std::string(embedded::gl_shader_accumulate_frag),
                                           "GL backend: accumulation");
  m.shadow = std::make_unique<ShadowAtlas>();
  m.tonemap = std::make_unique<TonemapPass>();
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
  const GLuint fbos[] = {m.scene_fbo, m.accum_fbo};
  glDeleteFramebuffers(2, fbos);
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
  og.tables = m.tables_for(material, g);
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
  impl_->tonemap->draw(impl_->accum_color, glm::ivec2(impl_->width, impl_->height), tm);
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
