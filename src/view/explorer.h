// view/explorer.h: the state of `aniso view` (the explorer, docs/explorer.md) without a window:
// the two materials of the A/B comparison, the light, the tangent controls, the object and the
// camera, and the scene document they make. The window code (apps/aniso/view_*.cpp) draws this
// state and changes it only through the functions here, so that the tests can drive the same
// changes without a window.
//
// Every change that reads user input (a slider, --set, a file loaded by a button) either succeeds
// or throws InputError and leaves the state as it was: the last good state is kept.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/brdf/material.h"
#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "aniso/render/scene.h"

namespace aniso::view {

// A material being edited: as loaded (desc) and as the JSON the sliders edit (every key of its
// table, shorthands expanded: resolved_json), with its double-precision kernel for the plots.
struct MaterialSlot {
  std::string source;   // what it was loaded from: a preset name, a file, "inline material"
  bool edited = false;  // changed since (set_key: a slider, --set)
  std::string label() const { return edited ? source + " (edited)" : source; }
  MaterialDesc desc;
  nlohmann::json edit;
  MaterialT<double> kernel;
  MaterialT<float> kernel_f;
};

// load_material(spec) (a preset name, a JSON file, a .binary file or inline JSON), resolved.
MaterialSlot load_slot(const std::string& spec);
// The slot of an already parsed material JSON object (model switch, sliders).
MaterialSlot slot_from_json(const nlohmann::json& material, const std::string& source);

// A key of the material, as in its JSON: "alpha_x", "lobe.alpha_x", "directional_diffuse.n",
// "lobes[0].cx" (or "lobes.0.cx"). Setting it re-validates the whole material against its table
// (InputError naming the key otherwise; the slot is unchanged then).
void set_key(MaterialSlot& slot, std::string_view key, const nlohmann::json& value);
// "--set key=value": the value is JSON (0.05, [0.5, 0.4, 0.3], true, "angle") or, when it does
// not parse as JSON, a bare string (form=angle).
void apply_assignment(MaterialSlot& slot, std::string_view assignment);
nlohmann::json parse_value_text(std::string_view text);

// One slider of the material's table: what the window draws, generated from the parameter table
// (io/params.h: its range, default and doc), at a key of set_key().
struct SliderSpec {
  std::string key;  // "lobe.alpha_x"
  // The key split at its last '.': the nested object it belongs to ("" at the top level, "lobe",
  // "directional_diffuse", "lobes[0]") and its name there ("alpha_x"). The window draws one tree
  // node per group and labels each slider by its name, so that the five keys of a metal's
  // directional_diffuse object are five different labels (the full keys, cut by the label column,
  // would all read "directional_diff").
  std::string group, label;
  const ParamSpec* spec = nullptr;
  ParamKind kind = ParamKind::Scalar;  // Scalar, Color, Bool, Choice, String (ParamKind::Choice also for a lobe's "model")
  std::vector<std::string> choices;    // Choice
  nlohmann::json value;                // current value (a number, [r, g, b], bool, string)
  bool log_scale = false;              // range wider than 3 decades above a positive minimum
  double lo = 0.0, hi = 1.0;           // the slider's range: the table's, with the open end nudged in
  std::string doc;                     // tooltip: the table's doc and its range
};
std::vector<SliderSpec> slider_specs(const MaterialSlot& slot);

// `text` shortened to at most `max_width` as measured by `width` (the window's font: ImGui's
// CalcTextSize): whole UTF-8 characters dropped from the end and "..." appended; "" when not even
// "..." fits. The A/B compare view's captions, each within its half of the picture.
std::string ellipsize(const std::string& text, float max_width, const std::function<float(std::string_view)>& width);

// Models and presets to pick from: every preset name (io/presets.h), then every model's name.
std::vector<std::string> material_choices();
// A model by name: the first preset of that model, or {"model": name} with the table's defaults.
MaterialSlot default_slot_for_model(const std::string& model);

// Light direction from the hemisphere widget: theta from the normal, phi from the tangent, in the
// local shading frame (docs/conventions.md). In the sphere views the frame at the point of the
// sphere facing the camera is world (x, y, z) with the camera on +z, so the same vector is the
// directional light's to_light in world space: the plots and the lit views share one light.
struct LightDirection {
  double theta_deg = 35.0;
  double phi_deg = 20.0;
  Vec3T<double> local() const;
};

// The tangent controls: an angle, a procedural field with its parameters, or a tangent map.
struct TangentControls {
  double angle_deg = 0.0;
  std::string field = "natural";        // natural | projected | concentric | radial | swirl | noise | uv
  glm::dvec3 direction{1.0, 0.0, 0.0};  // projected
  glm::dvec3 axis{0.0, 1.0, 0.0};       // concentric, radial, swirl (through the object's centre)
  double swirl_deg = 45.0;
  double noise_scale = 1.0, noise_strength = 0.5;
  std::string map_path;                // set: a tangent map replaces the field
  std::string map_encoding = "angle";  // angle | xy
  nlohmann::json to_json() const;      // the scene's "tangent" object (docs/scenes.md)
};
std::vector<std::string> tangent_field_names();

// The orbit camera of the lit views (yaw about +y, pitch up, looking at the origin).
struct OrbitCamera {
  double yaw_deg = 0.0, pitch_deg = 0.0, distance = 4.2, fov_deg = 30.0;
  nlohmann::json to_json() const;
  bool operator==(const OrbitCamera&) const = default;
};

enum class ObjectKind { Sphere, Object };

// The orbit camera's field of view is the vertical one for a landscape view; a portrait view
// widens it so that the same horizontal extent stays in the picture (the sphere fits either way).
float fitted_fov(float fov_deg, int width, int height);

// Everything the lit views and the path-traced preview show.
struct Explorer {
  MaterialSlot a, b;
  LightDirection light;
  double light_irradiance = 3.0;
  TangentControls tangent;
  OrbitCamera camera;
  std::string obj_path;  // empty: the lit object view shows a generated torus
  // The scene file given with --scene: the preview path-traces it (its first object gets material
  // A), and its camera starts the orbit.
  nlohmann::json scene_file;
  std::string scene_path, scene_base_dir;
  std::string last_error;  // shown in the window until the next successful action
  // The views' scenes as parsed (geometry, tangent map, UV tangents), rebuilt by refresh() after
  // a structural change (an OBJ, a tangent map, the uv field); view_scene() patches the rest.
  std::shared_ptr<const render::Scene> sphere_base, object_base;
  // The object's bounding sphere (refresh()): the orbit camera of the object views frames it.
  Vec3T<double> object_center{0.0};
  double object_radius = 1.0;

  // The scene document of a view: the sphere (or the object) with the material, the light as a
  // directional light, a dim uniform environment, the orbit camera, the film size given.
  nlohmann::json scene_document(ObjectKind kind, const MaterialSlot& m, int width, int height) const;
  // The path-traced preview's document: scene_document(Object or Sphere), or the --scene file.
  nlohmann::json preview_document(ObjectKind kind, int width, int height) const;
  // The preview's parsed scene (material A's kernel on the first object), for the path tracer.
  std::shared_ptr<const render::Scene> preview_scene(ObjectKind kind, int width, int height) const;

  // Rebuilds the parsed scenes (parse_scene: reads the OBJ and the tangent map). InputError on bad
  // input, with the scenes unchanged.
  void refresh();
  // A view's scene now: the parsed base with the orbit camera, the light, the tangent field of the
  // controls and the slot's material on its object (cheap: no file is read). refresh() first.
  std::shared_ptr<const render::Scene> view_scene(ObjectKind kind, const MaterialSlot& m) const;
  render::Camera camera_value(ObjectKind kind = ObjectKind::Sphere) const;
  render::Light light_value() const;
  // The procedural field of the controls as the scene reader makes it (InputError when invalid).
  TangentFieldT<float> tangent_field() const;
  // A tangent map, or mesh UV tangents: what only refresh() can change.
  bool structural_tangent() const { return !tangent.map_path.empty() || tangent.field == "uv"; }

  // Script actions and buttons: each either succeeds or throws InputError with the state unchanged.
  void load_material_a(const std::string& spec);
  void load_material_b(const std::string& spec);
  void load_tangent_map(const std::string& path);
  void load_obj(const std::string& path);
  void load_scene_file(const std::string& path);
};

render::Scene parse_view_scene(const nlohmann::json& doc, const std::string& what);

}  // namespace aniso::view
