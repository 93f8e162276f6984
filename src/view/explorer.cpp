// view/explorer.cpp: the explorer's state (view/explorer.h).
#include "view/explorer.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "aniso/io/presets.h"
#include "io/json_read.h"

namespace aniso::view {

using nlohmann::json;

MaterialSlot slot_from_desc(MaterialDesc desc, const std::string& source) {
  MaterialSlot s;
  s.source = source;
  s.edit = resolved_json(desc);
  s.kernel = build_material<double>(desc);
  s.kernel_f = build_material<float>(desc);
  s.desc = std::move(desc);
  return s;
}

MaterialSlot load_slot(const std::string& spec) { return slot_from_desc(load_material(spec), spec); }

MaterialSlot slot_from_json(const json& material, const std::string& source) {
  return slot_from_desc(parse_material(material, source), source);
}

namespace {

// "lobes[0].cx" or "lobes.0.cx" -> {"lobes", "0", "cx"}.
std::vector<std::string> split_key(std::string_view key) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : key) {
    if (c == '.' || c == '[' || c == ']') {
      if (!cur.empty()) parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) parts.push_back(cur);
  return parts;
}

bool all_digits(const std::string& s) {
  return !s.empty() && s.size() < 4 &&
         std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

// The paths ("lobe.alpha_x", "lobes[1].n") of the objects nested in `j` that hold `key`.
std::vector<std::string> nested_key_paths(const json& j, const std::string& key, const std::string& prefix) {
  std::vector<std::string> out;
  const auto add = [&](const std::vector<std::string>& more) { out.insert(out.end(), more.begin(), more.end()); };
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      const std::string path = prefix.empty() ? k : prefix + "." + k;
      if (v.is_object() && v.contains(key)) out.push_back(path + "." + key);
      add(nested_key_paths(v, key, path));
    }
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) {
      const std::string path = fmt::format("{}[{}]", prefix, i);
      if (j[i].is_object() && j[i].contains(key)) out.push_back(path + "." + key);
      add(nested_key_paths(j[i], key, path));
    }
  }
  return out;
}

}  // namespace

void set_key(MaterialSlot& slot, std::string_view key, const json& value) {
  const std::vector<std::string> parts = split_key(key);
  if (parts.empty()) throw InputError(fmt::format("--set: empty key in \"{}\"", text_escape(key)));
  if (slot.desc.model == "measured")
    throw InputError(fmt::format("{}: a measured material has no parameters to set (key \"{}\")", slot.source, text_escape(key)));
  json edited = slot.edit;
  json* node = &edited;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    if (node->is_array()) {
      if (!all_digits(p) || std::stoul(p) >= node->size())
        throw InputError(fmt::format("{}: key \"{}\": \"{}\" is not an index of the list (it has {} items)", slot.source,
                                     text_escape(key), text_escape(p), node->size()));
      node = &(*node)[std::stoul(p)];
    } else if (node->is_object()) {
      if (!node->contains(p))
        throw InputError(
            fmt::format("{}: key \"{}\": the material has no object \"{}\"", slot.source, text_escape(key), text_escape(p)));
      node = &(*node)[p];
    } else {
      throw InputError(
          fmt::format("{}: key \"{}\": \"{}\" is not an object or a list", slot.source, text_escape(key), text_escape(p)));
    }
  }
  if (!node->is_object())
    throw InputError(fmt::format("{}: key \"{}\": its parent is not an object", slot.source, text_escape(key)));
  const std::string& last = parts.back();
  if (last == "model" && node != &edited) {
    // A lobe's model (metal.lobe): its keys differ per model, so the lobe restarts from the new
    // model's defaults.
    *node = json{{"model", value}};
  } else if (last == "model") {
    throw InputError(fmt::format("{}: the model is chosen by loading a material or a preset, not with --set", slot.source));
  } else {
    (*node)[last] = value;
  }
  // parse_material checks the key (unknown keys are an error naming the key and the table) and
  // the value's type and range.
  std::optional<MaterialSlot> next;
  try {
    next.emplace(slot_from_json(edited, fmt::format("{} (edited)", slot.source)));
  } catch (const InputError& e) {
    // A key of a nested object given at the top level (alpha_x on a metal, whose alpha_x is the
    // lobe's): name the nested keys it could mean.
    const std::vector<std::string> near =
        parts.size() == 1 ? nested_key_paths(slot.edit, parts[0], "") : std::vector<std::string>{};
    if (near.empty()) throw;
    std::string list;
    for (const std::string& n : near) list += fmt::format("{}{}", list.empty() ? "" : " or ", n);
    throw InputError(fmt::format("{}; did you mean {}?", e.what(), list));
  }
  next->source = slot.source;
  next->edited = true;
  slot = std::move(*next);
}

json parse_value_text(std::string_view text) {
  try {
    return parse_json_text(text, "--set value");
  } catch (const InputError&) {
    return json(std::string(text));  // form=angle: a bare word
  }
}

void apply_assignment(MaterialSlot& slot, std::string_view assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0)
    throw InputError(fmt::format("--set \"{}\": expected key=value, e.g. alpha_x=0.05", text_escape(assignment)));
  set_key(slot, assignment.substr(0, eq), parse_value_text(assignment.substr(eq + 1)));
}

namespace {

void add_sliders(const ModelSpec& spec, const json& obj, const std::string& prefix, std::vector<SliderSpec>& out) {
  for (const ParamSpec* p : spec.params()) {
    if (!p->sets[0].empty()) continue;  // shorthands are input only; the two halves have sliders
    const std::string key = prefix + std::string(p->name);
    const auto it = obj.find(std::string(p->name));
    switch (p->kind) {
      case ParamKind::Object: {
        if (it != obj.end() && it->is_object() && p->sub) add_sliders(*p->sub, *it, key + ".", out);
        continue;
      }
      case ParamKind::TaggedObject: {
        if (it == obj.end() || !it->is_object() || !it->contains("model")) continue;
        SliderSpec tag;
        tag.key = key + ".model";
        tag.spec = p;
        tag.kind = ParamKind::Choice;
        for (std::string_view c : p->choices) tag.choices.emplace_back(c);
        tag.value = (*it)["model"];
        tag.doc = std::string(p->doc);
        out.push_back(tag);
        add_sliders(metal_lobe_spec((*it)["model"].get<std::string>()), *it, key + ".", out);
        continue;
      }
      case ParamKind::List: {
        if (it == obj.end() || !it->is_array() || !p->sub) continue;
        for (size_t i = 0; i < it->size(); ++i) add_sliders(*p->sub, (*it)[i], fmt::format("{}[{}].", key, i), out);
        continue;
      }
      default: break;
    }
    if (it == obj.end()) continue;  // optional without default (metal's eta, k when "metal" is given)
    SliderSpec s;
    s.key = key;
    s.spec = p;
    s.kind = p->kind;
    s.value = *it;
    for (std::string_view c : p->choices) s.choices.emplace_back(c);
    s.lo = p->min;
    s.hi = p->max;
    // An open lower end (0, max]: the slider stops at the smallest value the table accepts that a
    // slider can show, 1e-4 of the range or 1e-4, whichever is smaller.
    if (p->min_exclusive) s.lo = p->min + std::min(1e-4, 1e-4 * (p->max - p->min));
    // Exponents (Phong, Ashikhmin-Shirley, Lafortune n) range to kHuge: a logarithmic slider over
    // [max(lo, 1e-3), 1e4] keeps the useful values reachable; typing a value (ctrl-click) reaches the rest.
    if (p->max / std::max(std::abs(p->min), 1e-3) > 1e3 && p->min >= 0.0) {
      s.log_scale = true;
      s.lo = std::max(s.lo, 1e-3);
      s.hi = std::min(s.hi, 1e4);
    }
    s.doc = fmt::format("{} ({})", p->doc, describe_range(*p));
    out.push_back(std::move(s));
  }
}

}  // namespace

std::vector<SliderSpec> slider_specs(const MaterialSlot& slot) {
  std::vector<SliderSpec> out;
  const ModelSpec* spec = find_model_spec(slot.desc.model);
  if (!spec || slot.desc.model == "measured") return out;
  add_sliders(*spec, slot.edit, "", out);
  for (SliderSpec& s : out) {
    const size_t dot = s.key.rfind('.');
    s.group = dot == std::string::npos ? std::string() : s.key.substr(0, dot);
    s.label = dot == std::string::npos ? s.key : s.key.substr(dot + 1);
  }
  return out;
}

std::string ellipsize(const std::string& text, float max_width, const std::function<float(std::string_view)>& width) {
  if (width(text) <= max_width) return text;
  std::string_view kept(text);
  while (!kept.empty()) {
    // Drop one UTF-8 character: its continuation bytes (10xxxxxx) and its lead byte.
    size_t n = kept.size() - 1;
    while (n > 0 && (static_cast<unsigned char>(kept[n]) & 0xC0) == 0x80) --n;
    kept = kept.substr(0, n);
    const std::string shown = std::string(kept) + "...";
    if (width(shown) <= max_width) return shown;
  }
  return width("...") <= max_width ? std::string("...") : std::string();
}

std::vector<std::string> material_choices() {
  std::vector<std::string> out;
  for (const PresetInfo& p : presets()) out.push_back(p.name);
  return out;
}

MaterialSlot default_slot_for_model(const std::string& model) {
  for (const PresetInfo& p : presets())
    if (p.json.value("model", "") == model) return slot_from_json(p.json, p.name);
  return slot_from_json(json{{"model", model}}, fmt::format("model {}", model));
}

Vec3T<double> LightDirection::local() const {
  const double t = glm::radians(theta_deg), p = glm::radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

std::vector<std::string> tangent_field_names() {
  return {"natural", "projected", "concentric", "radial", "swirl", "noise", "uv"};
}

json TangentControls::to_json() const {
  json t = json::object();
  if (angle_deg != 0.0) t["angle_deg"] = angle_deg;
  if (!map_path.empty()) {
    t["map"] = map_path;
    t["encoding"] = map_encoding;
    return t;
  }
  auto vec = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
  if (field == "projected")
    t["field"] = "projected", t["direction"] = vec(direction);
  else if (field == "concentric" || field == "radial")
    t["field"] = field, t["axis"] = vec(axis);
  else if (field == "swirl")
    t["field"] = "swirl", t["axis"] = vec(axis), t["swirl_deg"] = swirl_deg;
  else if (field == "noise")
    t["field"] = "noise", t["scale"] = noise_scale, t["strength"] = noise_strength;
  else if (field == "uv")
    t["field"] = "uv";
  return t;
}

json OrbitCamera::to_json() const {
  const double yaw = glm::radians(yaw_deg), pitch = glm::radians(pitch_deg);
  const json pos = {distance * std::sin(yaw) * std::cos(pitch), distance * std::sin(pitch),
                    distance * std::cos(yaw) * std::cos(pitch)};
  return {{"position", pos}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", fov_deg}};
}

float fitted_fov(float fov_deg, int width, int height) {
  if (height <= width) return fov_deg;
  return glm::degrees(2.0f * std::atan(std::tan(glm::radians(fov_deg) / 2.0f) * float(height) / float(std::max(width, 1))));
}

json Explorer::scene_document(ObjectKind kind, const MaterialSlot& m, int width, int height) const {
  json doc;
  doc["camera"] = camera.to_json();
  doc["film"] = {{"width", width}, {"height", height}, {"spp", 16}};
  // Direct light from the hemisphere widget plus a dim uniform environment, so that the path-traced
  // preview shows the side turned away from the light (the GL views show the direct light only).
  const Vec3T<double> l = light.local();
  doc["lights"] = json::array({{{"type", "directional"}, {"to_light", {l.x, l.y, l.z}}, {"irradiance", light_irradiance}}});
  doc["environment"] = {{"type", "uniform"}, {"radiance", 0.04}};
  json obj;
  if (kind == ObjectKind::Sphere) {
    obj = {{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}};
  } else if (!obj_path.empty()) {
    obj = {{"shape", "mesh"}, {"file", obj_path}};
  } else {
    obj = {{"shape", "torus"}, {"center", {0, 0, 0}}, {"major_radius", 0.95}, {"minor_radius", 0.4}, {"rotate_deg", {60, 0, 0}}};
  }
  // The material is the slot's: a measured one as its file reference (parse_scene would read the
  // file again; view scenes swap the kernel in instead, make_view_scene()).
  obj["material"] = m.desc.model == "measured" ? json{{"model", "lambert"}} : m.edit;
  obj["tangent"] = tangent.to_json();
  if (tangent.field == "uv" && kind == ObjectKind::Sphere) obj["tangent"].erase("field");  // spheres have no UV tangents to read
  doc["objects"] = json::array({obj});
  return doc;
}

json Explorer::preview_document(ObjectKind kind, int width, int height) const {
  if (scene_file.is_null()) return scene_document(kind, a, width, height);
  json doc = scene_file;
  doc["film"]["width"] = width;
  doc["film"]["height"] = height;
  if (doc.contains("objects") && doc["objects"].is_array() && !doc["objects"].empty())
    doc["objects"][0]["material"] = a.desc.model == "measured" ? json{{"model", "lambert"}} : a.edit;
  return doc;
}

render::Scene parse_view_scene(const json& doc, const std::string& what) { return render::parse_scene(doc, what, {}); }

namespace {

// The view's scene with the slot's kernel on its first object, keeping a measured table alive as
// long as the scene (the kernel points into it).
std::shared_ptr<const render::Scene> with_material(render::Scene scene, const MaterialSlot& m) {
  if (!scene.objects.empty()) {
    scene.objects[0].material = m.kernel_f;
    scene.objects[0].material_desc = std::make_shared<const MaterialDesc>(m.desc);  // the GL backend's shader source
    scene.objects[0].material_name = m.source;
  }
  std::shared_ptr<const MeasuredData> keep = m.desc.measured;
  return std::shared_ptr<const render::Scene>(new render::Scene(std::move(scene)), [keep](const render::Scene* s) { delete s; });
}

}  // namespace

std::shared_ptr<const render::Scene> Explorer::preview_scene(ObjectKind kind, int width, int height) const {
  const json doc = preview_document(kind, width, height);
  const std::string what = scene_file.is_null() ? std::string("preview") : scene_path;
  render::Scene s = render::parse_scene(doc, what, scene_file.is_null() ? std::string() : scene_base_dir);
  if (scene_file.is_null()) {
    s.camera = camera_value(kind);
    s.camera.fov_deg = fitted_fov(s.camera.fov_deg, width, height);
  }
  return with_material(std::move(s), a);
}

void Explorer::refresh() {
  // Small films: the lit views set their own size; the scenes carry geometry, light and tangents.
  auto sphere =
      std::make_shared<const render::Scene>(parse_view_scene(scene_document(ObjectKind::Sphere, a, 64, 64), "sphere view"));
  auto object = std::make_shared<const render::Scene>(
      parse_view_scene(scene_document(ObjectKind::Object, a, 64, 64), obj_path.empty() ? std::string("object view") : obj_path));
  // The bounding sphere of a mesh (the box's centre and half diagonal), or of the generated torus.
  Vec3T<double> center(0.0);
  double radius = 1.0;
  if (!object->objects.empty() && object->objects[0].mesh && !object->objects[0].mesh->positions.empty()) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const Vec3& p : object->objects[0].mesh->positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    center = 0.5 * (lo + hi);
    radius = std::max(0.5 * glm::length(hi - lo), 1e-3);
  }
  if (obj_path.empty()) center = Vec3T<double>(0.0), radius = 0.95 + 0.4;  // the torus: major + minor radius
  sphere_base = std::move(sphere), object_base = std::move(object);
  object_center = center, object_radius = radius;
}

render::Camera Explorer::camera_value(ObjectKind kind) const {
  render::Camera c = parse_view_scene({{"camera", camera.to_json()}, {"objects", json::array()}}, "camera").camera;
  if (kind == ObjectKind::Object) {
    // The same orbit about the object's centre, scaled to its size (a mesh rarely fills its bounding
    // sphere: 0.8 of its radius frames the example meshes).
    c.position = Vec3(object_center + (glm::dvec3(c.position) - glm::dvec3(c.look_at)) *
                                          (obj_path.empty() ? object_radius : 0.8 * object_radius));
    c.look_at = Vec3(object_center);
  }
  return c;
}

render::Light Explorer::light_value() const {
  json doc = scene_document(ObjectKind::Sphere, a, 16, 16);
  doc["objects"] = json::array();
  return parse_view_scene(doc, "light").lights.at(0);
}

TangentFieldT<float> Explorer::tangent_field() const {
  json doc = {{"camera", camera.to_json()},
              {"objects", json::array({{{"shape", "sphere"},
                                        {"center", {0, 0, 0}},
                                        {"radius", 1.0},
                                        {"material", {{"model", "lambert"}}},
                                        {"tangent", tangent.to_json()}}})}};
  if (structural_tangent()) doc["objects"][0].erase("tangent");
  return parse_view_scene(doc, "tangent controls").objects.at(0).tangent.field;
}

std::shared_ptr<const render::Scene> Explorer::view_scene(ObjectKind kind, const MaterialSlot& m) const {
  const std::shared_ptr<const render::Scene>& base = kind == ObjectKind::Sphere ? sphere_base : object_base;
  if (!base) throw std::logic_error("Explorer::view_scene before refresh()");
  render::Scene s = *base;
  s.camera = camera_value(kind);
  if (!s.lights.empty()) s.lights[0] = light_value();
  if (!s.objects.empty() && !structural_tangent()) s.objects[0].tangent.field = tangent_field();
  return with_material(std::move(s), m);
}

void Explorer::load_material_a(const std::string& spec) {
  MaterialSlot next = load_slot(spec);
  std::swap(a, next);
  try {
    refresh();
  } catch (...) {
    std::swap(a, next);
    throw;
  }
}

void Explorer::load_material_b(const std::string& spec) {
  MaterialSlot next = load_slot(spec);
  std::swap(b, next);
  try {
    refresh();
  } catch (...) {
    std::swap(b, next);
    throw;
  }
}

void Explorer::load_tangent_map(const std::string& path) {
  const TangentControls saved = tangent;
  tangent.map_path = std::filesystem::absolute(path).string();
  try {
    refresh();  // reads and checks the map (image/image_io.h's reader: corrupt files are InputErrors)
  } catch (...) {
    tangent = saved;
    throw;
  }
}

void Explorer::load_obj(const std::string& path) {
  const std::string saved = obj_path;
  obj_path = std::filesystem::absolute(path).string();
  try {
    refresh();
  } catch (...) {
    obj_path = saved;
    throw;
  }
}

void Explorer::load_scene_file(const std::string& path) {
  json doc = read_json_file(path);
  // Checked as it will be rendered, before anything changes.
  render::parse_scene(doc, path, std::filesystem::path(path).parent_path().string());
  // Relative file names inside resolve against the scene's folder; the preview parses the document
  // with that folder as its base (Explorer::scene_base_dir).
  scene_file = std::move(doc);
  scene_path = path;
  scene_base_dir = std::filesystem::path(path).parent_path().string();
  if (scene_file.contains("camera") && scene_file["camera"].contains("fov_deg"))
    camera.fov_deg = scene_file["camera"]["fov_deg"].get<double>();
}

}  // namespace aniso::view
