// gl/scene_checks.cpp: what the GL backend can render of a scene, decided without a GL context
// (the CLI checks before it opens one): check_gl_materials, gl_has_lights, gl_unsupported
// (declared in scene_raster.h), and the GLSL of an object's material.
#include "gl/scene_checks.h"

#include <fmt/format.h>

#include "gl/scene_raster.h"

namespace aniso::gl {

using render::LightKind;
using render::ShapeKind;

GlslMaterial object_glsl(const render::Scene& scene, size_t i, const MaterialDesc& desc) {
  const render::Object& o = scene.objects[i];
  try {
    return glsl_material(desc, GlslStorage::Uniform, kMaterialPrefix);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: objects[{}] (material \"{}\"): the GL backend cannot shade it: {}", scene.source, i,
                                 o.material_name, e.what()));
  }
}

void check_gl_materials(const render::Scene& scene) {
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].material_desc)
      throw InputError(fmt::format("{}: objects[{}]: no material description (render::Object::material_desc)", scene.source, i));
    object_glsl(scene, i, *scene.objects[i].material_desc);
  }
}

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

}  // namespace aniso::gl
