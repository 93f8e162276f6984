// aniso/render/scene.h: what `aniso render` renders, as read from a scene file (docs/scenes.md) and
// validated once, on the host. Kernels and the integrator see plain data: a MaterialT<float> and
// a TangentFieldT<float> per object, meshes as arrays.
//
// World space is right-handed and y-up by default (the camera's `up` decides what is up in the
// picture). Lengths have no unit; radiance, intensity and irradiance are linear RGB.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/io/materials.h"
#include "aniso/render/environment.h"
#include "aniso/render/sampler.h"
#include "aniso/tangent/fields.h"

namespace aniso::render {

enum class Strategy { Mis, Bsdf, Light };

struct Camera {
  Vec3 position{0.0f, 0.0f, 5.0f};
  Vec3 look_at{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 40.0f;  // vertical field of view
};

struct Film {
  int width = 640, height = 360, spp = 64;
  float noise_threshold = 0.0f;  // adaptive sampling (render/integrator.h); 0: off
  int min_spp = 0;               // with a noise threshold: samples before a pixel may stop (0: automatic)
  float time_s = 0.0f;           // time budget in seconds (render/integrator.h); 0: none
};

// The film's size from a command line or a keyword (`aniso render --width`, Python render(width=)):
// 0 keeps a side; one side alone keeps the film's aspect ratio (the camera's field of view spans
// the film: changing one side alone would crop or stretch the view), the other clamped to
// [1, 16384].
void resize_film(Film& film, int width, int height);

// Next-event estimation (render/integrator.h): one emitter per vertex chosen by power, every emitter
// at every vertex, or (auto, the default) every emitter when there are at most
// kAutoAllCandidates of them (lights plus the environment), one by power otherwise.
enum class LightSelection { Auto, Power, All };
// Measured at equal time (docs/benchmarks.md, "Light selection"): "all" wins at 3 and 7
// candidates, "power" at 13 and more.
inline constexpr size_t kAutoAllCandidates = 8;

struct IntegratorSettings {
  int max_depth = 8;  // path vertices after the camera (1 = direct lighting only)
  Strategy strategy = Strategy::Mis;
  SamplerKind sampler = SamplerKind::Sobol;  // render/sampler.h
  LightSelection light_selection = LightSelection::Auto;
  float clamp = 0.0f;          // indirect light: cap on R + G + B of each contribution (integrator.h); 0: off
  float filter_glossy = 0.0f;  // roughen after bounces (integrator.h, Cycles' Filter Glossy); 0: off
};

enum class LightKind { Point, Directional, Sphere };

struct Light {
  LightKind kind = LightKind::Point;
  Vec3 position{0.0f};              // Point: where; Sphere: centre
  Vec3 to_light{0.0f, 1.0f, 0.0f};  // Directional: unit direction towards the light
  RGB power{0.0f};                  // Point: intensity I (W/sr); Directional: irradiance E; Sphere: radiance L
  float radius = 0.0f;              // Sphere
};

// A tangent map: doubled-angle direction vectors (TangentMap_ToDoubled) per texel in the shape's
// (dp/du, dp/dv) basis, looked up bilinearly through the shape's UVs (u right, v up: texel row 0
// is v = 1, as OBJ and OpenGL expect), with wrap-around.
struct TangentMap {
  int width = 0, height = 0;
  std::vector<Vec2> doubled;          // width * height
  Vec2 lookup(const Vec2& uv) const;  // unit direction in the (dp/du, dp/dv) basis, or 0
};

struct TangentSource {
  TangentFieldT<float> field;
  std::shared_ptr<const TangentMap> map;  // set: the map replaces the field's direction
  bool uv_tangents = false;               // {"field": "uv"}: a mesh's smooth per-vertex tangents
};

enum class ShapeKind { Sphere, Disc, Rectangle, Mesh };

// A triangle mesh in world space (transform applied). normals, uvs, tangents are per vertex and
// empty when the file has none (tangents: filled when UV tangents are asked for).
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  std::vector<Vec3> tangents;     // smooth per-vertex UV tangents (MikkTSpace-style accumulation)
  std::vector<uint32_t> indices;  // 3 per triangle
};

struct Object {
  ShapeKind shape = ShapeKind::Sphere;
  Vec3 center{0.0f};
  Vec3 normal{0.0f, 1.0f, 0.0f};  // Disc, Rectangle
  Vec3 u_axis{1.0f, 0.0f, 0.0f};  // Rectangle: unit direction of its first side (its dp/du)
  float radius = 1.0f;            // Sphere, Disc
  Vec2 size{1.0f, 1.0f};          // Rectangle: lengths along u_axis and normal x u_axis
  std::shared_ptr<const Mesh> mesh;
  Material material;
  // What `material` was built from (the model's parameters): the GL backend generates its shader
  // from it (gl/glsl_material.h).
  std::shared_ptr<const MaterialDesc> material_desc;
  std::string material_name;  // for messages and labels
  TangentSource tangent;
};

struct Scene {
  std::string source;  // the file name, or "embedded scene NAME"
  Camera camera;
  Film film;
  IntegratorSettings integrator;
  Environment environment;
  std::vector<Light> lights;
  std::vector<Object> objects;
};

// Reads and validates a scene. `source` names it in messages ("scene.json"); relative file names
// inside (meshes, maps, material files) are resolved against `base_dir`. Every problem is an
// InputError "<source>: <json.path>: <what was expected>, got <what>".
Scene parse_scene(const nlohmann::json& doc, const std::string& source, const std::string& base_dir);
Scene load_scene(const std::string& path);

// Material references as everywhere else (a preset name, a JSON file, or an inline object), with
// errors prefixed by `where`. `desc`, when given, receives what the material was built from.
Material resolve_material(const nlohmann::json& m, const std::string& where, const std::string& base_dir,
                          std::string* display_name, std::shared_ptr<const MaterialDesc>* desc = nullptr);

// Procedural meshes for the built-in scenes (also usable as {"shape": "mesh", "generate": ...}).
// A torus about +y, its natural tangent dp/du along the major circle.
std::shared_ptr<Mesh> make_torus(const Vec3& center, float major_radius, float minor_radius, int nu, int nv);

}  // namespace aniso::render
