// apps/aniso/view_app.cpp: the explorer's window (view_app.h). Thin over src/view: every change
// goes through view::Explorer, every plot draws the numbers of view/plots.h, the lit views are
// rasterised by gl/scene_raster.h, the preview is the CPU renderer (view/preview.h).
#include "view_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "aniso/gl/glsl_export.h"
#include "aniso/image/canvas.h"
#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/params.h"
#include "commands.h"
#include "view/explorer.h"
#include "view/frame_times.h"
#include "view/plots.h"
#include "view/preview.h"
#include "view_gl.h"

#if __has_include("gl/scene_raster.h")
#include "gl/scene_raster.h"
#define ANISO_VIEW_HAVE_RASTER 1
#else
#define ANISO_VIEW_HAVE_RASTER 0
#endif

namespace aniso {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

constexpr float kPanelWidth = 340.0f;
const glm::vec3 kBackground(0.12f, 0.12f, 0.13f);
const ImU32 kColA = IM_COL32(255, 170, 60, 255), kColB = IM_COL32(110, 190, 255, 255);
const ImU32 kColLight = IM_COL32(255, 230, 80, 255), kColGrid = IM_COL32(90, 90, 100, 255);

ImTextureID tex_id(unsigned tex) { return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)); }

// A rasterised view of a scene: the GL backend's image, tone-mapped into a display target.
struct LitView {
#if ANISO_VIEW_HAVE_RASTER
  std::unique_ptr<gl::SceneRasterizer> raster;
#endif
  const render::Scene* base = nullptr;  // the parsed scene the rasteriser was built from
  std::string key;                      // what was last drawn (material, light, camera, size)
  viewgl::RenderTarget display;
  std::string error;    // shown in the view instead of the picture
  bool scaled = false;  // drawn at the interactive scale (below the view's size)
};

class App {
 public:
  App(const ViewOptions& o, GLFWwindow* w) : opt_(o), window_(w) {}
  int run();
  view::Explorer ex;
  std::map<std::string, bool> open;

 private:
  void report(const std::string& action, const std::exception& e);
  void frame(bool last);
  void panel_controls(float height);
  void material_controls(view::MaterialSlot& slot, const char* id, bool is_a);
  void light_widget();
  void tangent_controls();
  void views_grid(float x0, float width, float height);
  void view_lit(LitView& v, view::ObjectKind kind, const view::MaterialSlot& slot, int w, int h);
  void draw_sphere(float w, float h, LitView& v, view::ObjectKind kind);
  void draw_polar(float w, float h);
  void draw_lobe(float w, float h);
  void draw_albedo(float w, float h);
  void draw_compare(float w, float h);
  void draw_preview(float w, float h);
  void drag_camera(bool active);
  void save_screenshot(const std::string& path);
  void after_change() { changed_ = Clock::now(); }

  ViewOptions opt_;
  GLFWwindow* window_;
  LitView sphere_, object_, cmp_a_, cmp_b_;
  viewgl::RenderTarget cmp_display_, lobe_target_;
  std::unique_ptr<viewgl::DisplayPass> display_;
  std::unique_ptr<viewgl::LobeRenderer> lobe_;
  std::string lobe_key_, albedo_key_, preview_key_;
  std::vector<view::AlbedoPoint> albedo_a_, albedo_b_;
  float lobe_yaw_ = 30.0f, lobe_pitch_ = 25.0f;
  view::ProgressivePreview preview_{0, 1024};
  viewgl::ImageTexture preview_tex_;
  render::Image preview_img_;
  float preview_exposure_ = 0.0f;
  uint64_t preview_gen_ = 0;
  int preview_spp_ = 0;
  bool difference_ = false;
  float diff_gain_ = 4.0f, exposure_ = 0.0f;
  bool log_scale_ = false, times_cos_ = false;
  Clock::time_point camera_moved_{}, changed_ = Clock::now() - std::chrono::seconds(1);
  std::string path_a_, path_b_, path_map_, path_obj_, path_save_ = "material.json", path_glsl_ = "material.glsl",
                                                      path_brdf_ = "material.brdf", path_shot_ = "aniso-view.png";
  view::FrameTimes frame_times_;
  std::string pending_screenshot_;
};

// Errors of a button or a script action: in the window (until the next success) and on stderr.
void App::report(const std::string& action, const std::exception& e) {
  ex.last_error = fmt::format("{}: {}", action, e.what());
  fmt::print(stderr, "aniso view: error: {}\n", ex.last_error);
}

// A save or export of the window's buttons and of the script actions: the file written atomically
// (cmd_export.cpp) and one line saying what went where, on stdout as `aniso render` and `aniso
// export` say it (docs/cli.md, "Output streams"); on stderr when the file itself went to stdout ("-").
void write_reported(const std::string& path, const std::string& text, const std::string& what) {
  write_atomically(path, text);
  const bool to_stdout = path.empty() || path == "-";
  // Not flushed here: a terminal's stdout is line-buffered, and a failing stdout is found, with its
  // reason, by the command's final check (main.cpp, stdout_error: exit 1).
  fmt::print(to_stdout ? stderr : stdout, "wrote {} ({})\n", to_stdout ? "stdout" : path, what);
}

// Material A as GLSL; a measured material's tables beside it, in FILE.tables (docs/glsl.md
// "Measured materials"), as `aniso export-glsl -o FILE` writes them.
void write_glsl_reported(const std::string& path, const MaterialDesc& desc, const std::string& source) {
  const std::string tables = gl::export_glsl_tables(desc);
  if (!tables.empty()) {
    if (path.empty() || path == "-") throw InputError("a measured material's GLSL needs a file name (its tables go beside it)");
    write_reported(path + ".tables", tables, "material A's tables for its GLSL");
  }
  write_reported(path, gl::export_glsl(desc, source, false, tables.empty() ? std::string() : path + ".tables"),
                 "material A as GLSL");
}

bool input_path(const char* label, std::string& s) {
  char buf[1024];
  const size_t n = std::min(s.size(), sizeof buf - 1);
  std::copy_n(s.data(), n, buf);
  buf[n] = 0;
  const bool changed = ImGui::InputText(label, buf, sizeof buf);
  if (changed) s = buf;
  return changed;
}

void App::material_controls(view::MaterialSlot& slot, const char* id, bool is_a) {
  ImGui::PushID(id);
  // Presets (fitted materials and metals among them) and each model's defaults.
  static const std::vector<std::string> choices = view::material_choices();
  if (ImGui::BeginCombo("preset", slot.label().c_str())) {
    for (const ModelSpec* m : model_specs()) {
      if (m->name == "measured") continue;  // a file: load it by path
      const std::string label = fmt::format("model: {}", m->name);
      if (ImGui::Selectable(label.c_str())) {
        try {
          slot = view::default_slot_for_model(std::string(m->name));
          ex.last_error.clear();
          after_change();
        } catch (const std::exception& e) {
          report(label, e);
        }
      }
    }
    for (const std::string& c : choices)
      if (ImGui::Selectable(c.c_str(), c == slot.source)) {
        try {
          if (is_a)
            ex.load_material_a(c);
          else
            ex.load_material_b(c);
          ex.last_error.clear();
          after_change();
        } catch (const std::exception& e) {
          report("preset " + c, e);
        }
      }
    ImGui::EndCombo();
  }
  ImGui::TextDisabled("model %s", slot.desc.model.c_str());
  // One tree node per nested object (lobe, directional_diffuse, lobes[0], ...), each slider labelled
  // by its name there; the label column as wide as the widest label, so that none is cut. The
  // widget's id is the full key (labels repeat across lobes).
  const std::vector<view::SliderSpec> specs = view::slider_specs(slot);
  float label_w = 0.0f;
  for (const view::SliderSpec& s : specs) label_w = std::max(label_w, ImGui::CalcTextSize(s.label.c_str()).x);
  ImGui::PushItemWidth(-std::max(110.0f, label_w + ImGui::GetStyle().ItemInnerSpacing.x + 4.0f));
  std::string group;
  bool group_open = true;
  for (const view::SliderSpec& s : specs) {
    if (s.group != group) {
      if (!group.empty() && group_open) ImGui::TreePop();
      group = s.group;
      group_open = group.empty() || ImGui::TreeNodeEx(group.c_str(), ImGuiTreeNodeFlags_DefaultOpen);
    }
    if (!group_open) continue;
    std::optional<json> next;
    const std::string label_id = s.label + "##" + s.key;
    const char* label = label_id.c_str();
    switch (s.kind) {
      case ParamKind::Scalar: {
        float v = s.value.is_number() ? s.value.get<float>() : 0.0f;
        if (ImGui::SliderFloat(label, &v, float(s.lo), float(s.hi), "%.4g", s.log_scale ? ImGuiSliderFlags_Logarithmic : 0))
          next = double(v);
        break;
      }
      case ParamKind::Color: {
        float c[3];
        for (int i = 0; i < 3; ++i) c[i] = s.value.is_array() ? s.value[size_t(i)].get<float>() : s.value.get<float>();
        bool changed = false;
        if (s.lo >= 0.0 && s.hi <= 1.0)
          changed = ImGui::ColorEdit3(label, c, ImGuiColorEditFlags_Float);
        else
          changed =
              ImGui::SliderFloat3(label, c, float(s.lo), float(s.hi), "%.3g", s.log_scale ? ImGuiSliderFlags_Logarithmic : 0);
        if (changed) next = json::array({double(c[0]), double(c[1]), double(c[2])});
        break;
      }
      case ParamKind::Bool: {
        bool b = s.value.get<bool>();
        if (ImGui::Checkbox(label, &b)) next = b;
        break;
      }
      case ParamKind::Choice: {
        const std::string cur = s.value.get<std::string>();
        if (ImGui::BeginCombo(label, cur.c_str())) {
          for (const std::string& c : s.choices)
            if (ImGui::Selectable(c.c_str(), c == cur)) next = c;
          ImGui::EndCombo();
        }
        break;
      }
      case ParamKind::String: {
        const std::string cur = s.value.get<std::string>();
        if (s.key == "metal" && ImGui::BeginCombo(label, cur.c_str())) {
          for (const MetalData& m : metal_table())
            if (ImGui::Selectable(std::string(m.name).c_str(), m.name == cur)) next = std::string(m.name);
          ImGui::EndCombo();
        } else if (s.key != "metal") {
          ImGui::TextDisabled("%s: %s", s.label.c_str(), cur.c_str());
        }
        break;
      }
      default: break;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: %s", s.key.c_str(), s.doc.c_str());
    if (next) {
      try {
        view::set_key(slot, s.key, *next);
        ex.last_error.clear();
        after_change();
      } catch (const std::exception& e) {
        report(s.key, e);
      }
    }
  }
  if (!group.empty() && group_open) ImGui::TreePop();
  ImGui::PopItemWidth();
  // Lafortune's lobes: one more (a forward-scattering cosine lobe, the table's defaults for C and
  // n = 10) or one fewer, within the table's 1 to 8.
  if (slot.edit.contains("lobes") && slot.edit["lobes"].is_array()) {
    json lobes = slot.edit["lobes"];
    bool changed = false;
    if (ImGui::SmallButton("+ lobe") && lobes.size() < 8)
      lobes.push_back({{"cx", -1.0}, {"cy", -1.0}, {"cz", 1.0}, {"n", 10.0}}), changed = true;
    ImGui::SameLine();
    if (ImGui::SmallButton("- lobe") && lobes.size() > 1) lobes.erase(lobes.size() - 1), changed = true;
    if (changed) {
      try {
        view::set_key(slot, "lobes", lobes);
        ex.last_error.clear();
        after_change();
      } catch (const std::exception& e) {
        report("lobes", e);
      }
    }
  }
  // Files, as the script actions do them.
  std::string& path = is_a ? path_a_ : path_b_;
  input_path("file", path);
  if (ImGui::Button("Load")) {
    try {
      if (is_a)
        ex.load_material_a(path);
      else
        ex.load_material_b(path);
      ex.last_error.clear();
      after_change();
    } catch (const std::exception& e) {
      report("load " + path, e);
    }
  }
  if (is_a) {
    ImGui::SameLine();
    if (ImGui::Button("Save JSON")) {
      try {
        write_reported(path_save_, slot.edit.dump(2) + "\n", "material A as JSON");
      } catch (const std::exception& e) {
        report("save " + path_save_, e);
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("GLSL")) {
      try {
        write_glsl_reported(path_glsl_, slot.desc, slot.source);
      } catch (const std::exception& e) {
        report("export " + path_glsl_, e);
      }
    }
    ImGui::SameLine();
    if (ImGui::Button(".brdf")) {
      try {
        write_reported(path_brdf_, gl::export_brdf(slot.desc, slot.source), "material A as a BRDF Explorer .brdf file");
      } catch (const std::exception& e) {
        report("export " + path_brdf_, e);
      }
    }
    input_path("save as", path_save_);
    input_path("GLSL as", path_glsl_);
    input_path(".brdf as", path_brdf_);
  }
  ImGui::PopID();
}

// The light by dragging on the hemisphere seen from above: the centre is the normal, the rim the
// horizon, right the tangent t, up the bitangent b; a point at distance r from the centre is
// theta = asin(r) (orthographic projection).
void App::light_widget() {
  const float size = 150.0f;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("hemisphere", ImVec2(size, size));
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 c(p0.x + size / 2, p0.y + size / 2);
  const float r = size / 2 - 4;
  dl->AddCircleFilled(c, r, IM_COL32(40, 40, 48, 255), 64);
  dl->AddCircle(c, r, kColGrid, 64);
  dl->AddCircle(c, r * std::sin(glm::radians(30.0f)), kColGrid, 48);
  dl->AddCircle(c, r * std::sin(glm::radians(60.0f)), kColGrid, 48);
  dl->AddLine(ImVec2(c.x - r, c.y), ImVec2(c.x + r, c.y), kColGrid);
  dl->AddLine(ImVec2(c.x, c.y - r), ImVec2(c.x, c.y + r), kColGrid);
  dl->AddText(ImVec2(c.x + r - 8, c.y - 16), IM_COL32(230, 90, 90, 255), "t");
  dl->AddText(ImVec2(c.x + 4, c.y - r), IM_COL32(120, 220, 120, 255), "b");
  if (ImGui::IsItemActive()) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    double x = (m.x - c.x) / r, y = -(m.y - c.y) / r;
    const double len = std::hypot(x, y);
    // The rim is 90 degrees; the widget stops at 89 (a light on the horizon lights nothing).
    const double max_len = std::sin(glm::radians(89.0));
    if (len > max_len) x *= max_len / len, y *= max_len / len;
    ex.light.theta_deg = glm::degrees(std::asin(std::min(std::hypot(x, y), 1.0)));
    if (len > 1e-6) ex.light.phi_deg = glm::degrees(std::atan2(y, x));
    after_change();
  }
  const Vec3T<double> l = ex.light.local();
  dl->AddCircleFilled(ImVec2(c.x + float(l.x) * r, c.y - float(l.y) * r), 5.0f, kColLight);
  float theta = float(ex.light.theta_deg), phi = float(ex.light.phi_deg);
  if (ImGui::SliderFloat("theta", &theta, 0.0f, 89.0f, "%.1f deg")) ex.light.theta_deg = theta, after_change();
  if (ImGui::SliderFloat("phi", &phi, -180.0f, 180.0f, "%.1f deg")) ex.light.phi_deg = phi, after_change();
  float e = float(ex.light_irradiance);
  if (ImGui::SliderFloat("irradiance", &e, 0.1f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
    ex.light_irradiance = e, after_change();
  ImGui::SliderFloat("exposure", &exposure_, -6.0f, 6.0f, "%.1f stops");
}

void App::tangent_controls() {
  view::TangentControls t = ex.tangent;
  bool changed = false;
  float angle = float(t.angle_deg);
  if (ImGui::SliderFloat("angle", &angle, -180.0f, 180.0f, "%.1f deg")) t.angle_deg = angle, changed = true;
  if (ImGui::BeginCombo("field", t.field.c_str())) {
    for (const std::string& f : view::tangent_field_names())
      if (ImGui::Selectable(f.c_str(), f == t.field)) t.field = f, changed = true;
    ImGui::EndCombo();
  }
  auto vec3 = [&](const char* label, glm::dvec3& v) {
    float f[3] = {float(v.x), float(v.y), float(v.z)};
    if (ImGui::SliderFloat3(label, f, -1.0f, 1.0f, "%.2f")) v = glm::dvec3(f[0], f[1], f[2]), changed = true;
  };
  if (t.field == "projected") vec3("direction", t.direction);
  if (t.field == "concentric" || t.field == "radial" || t.field == "swirl") vec3("axis", t.axis);
  if (t.field == "swirl") {
    float s = float(t.swirl_deg);
    if (ImGui::SliderFloat("swirl", &s, -90.0f, 90.0f, "%.1f deg")) t.swirl_deg = s, changed = true;
  }
  if (t.field == "noise") {
    float sc = float(t.noise_scale), st = float(t.noise_strength);
    if (ImGui::SliderFloat("scale", &sc, 0.1f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) t.noise_scale = sc, changed = true;
    if (ImGui::SliderFloat("strength", &st, 0.0f, 1.0f, "%.2f")) t.noise_strength = st, changed = true;
  }
  input_path("map", path_map_);
  if (ImGui::BeginCombo("encoding", t.map_encoding.c_str())) {
    for (const char* e : {"angle", "xy"})
      if (ImGui::Selectable(e, t.map_encoding == e)) t.map_encoding = e, changed = true;
    ImGui::EndCombo();
  }
  if (ImGui::Button("Load map")) {
    try {
      ex.tangent.map_encoding = t.map_encoding;
      ex.load_tangent_map(path_map_);
      ex.last_error.clear();
      after_change();
    } catch (const std::exception& e) {
      report("tangent map " + path_map_, e);
    }
    return;
  }
  ImGui::SameLine();
  if (ImGui::Button("Clear map")) t.map_path.clear(), changed = true;
  if (!ex.tangent.map_path.empty()) ImGui::TextDisabled("map: %s", std::filesystem::path(ex.tangent.map_path).filename().c_str());
  if (!changed) return;
  const view::TangentControls saved = ex.tangent;
  // A tangent map or mesh UV tangents live in the parsed scene (view_scene() does not patch them):
  // any change while one is in use, or to or from one, parses the scenes again.
  const bool structural = !saved.map_path.empty() || !t.map_path.empty() || saved.field == "uv" || t.field == "uv";
  ex.tangent = t;
  try {
    if (structural)
      ex.refresh();
    else
      (void)ex.tangent_field();  // validates
    ex.last_error.clear();
    after_change();
  } catch (const std::exception& e) {
    ex.tangent = saved;
    report("tangent", e);
  }
}

void App::panel_controls(float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, height));
  ImGui::Begin("aniso view", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(-110.0f);
  ImGui::TextUnformatted(frame_times_.text().c_str());  // the figure a scripted run prints on stderr
  if (!ex.last_error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 110, 110, 255));
    ImGui::TextWrapped("error: %s", ex.last_error.c_str());
    ImGui::PopStyleColor();
    if (ImGui::SmallButton("dismiss")) ex.last_error.clear();
  }
  if (ImGui::CollapsingHeader("Material A", ImGuiTreeNodeFlags_DefaultOpen)) material_controls(ex.a, "A", true);
  if (ImGui::CollapsingHeader("Material B (compare)")) material_controls(ex.b, "B", false);
  if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) light_widget();
  if (ImGui::CollapsingHeader("Tangent", ImGuiTreeNodeFlags_DefaultOpen)) tangent_controls();
  if (ImGui::CollapsingHeader("Object")) {
    input_path("OBJ", path_obj_);
    if (ImGui::Button("Load OBJ")) {
      try {
        ex.load_obj(path_obj_);
        ex.last_error.clear();
        after_change();
      } catch (const std::exception& e) {
        report("OBJ " + path_obj_, e);
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("Torus")) {
      const std::string saved = ex.obj_path;
      ex.obj_path.clear();
      try {
        ex.refresh();
      } catch (const std::exception& e) {
        ex.obj_path = saved;
        report("torus", e);
      }
    }
  }
  if (ImGui::CollapsingHeader("Plots and views")) {
    ImGui::Checkbox("log scale", &log_scale_);
    ImGui::SameLine();
    ImGui::Checkbox("x cos", &times_cos_);
    ImGui::Checkbox("difference image", &difference_);
    ImGui::SliderFloat("gain", &diff_gain_, 1.0f, 64.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
    for (const std::string& v : kViewNames) ImGui::Checkbox(v.c_str(), &open[v]);
    input_path("screenshot", path_shot_);
    if (ImGui::Button("Save screenshot")) pending_screenshot_ = path_shot_;
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

// Orbit: dragging in a lit view turns the camera (yaw, pitch), the wheel zooms; the path-traced
// preview restarts when the camera has stopped.
void App::drag_camera(bool active) {
  // The mouse wheel over a lit view moves the camera closer or further (10 % a notch).
  if (ImGui::IsItemHovered() && ImGui::GetIO().MouseWheel != 0.0f) {
    ex.camera.distance = std::clamp(ex.camera.distance * std::pow(0.9, double(ImGui::GetIO().MouseWheel)), 1.5, 40.0);
    camera_moved_ = Clock::now();
    after_change();
  }
  if (!active) return;
  const ImVec2 d = ImGui::GetIO().MouseDelta;
  if (d.x == 0.0f && d.y == 0.0f) return;
  ex.camera.yaw_deg -= 0.4 * d.x;
  ex.camera.pitch_deg = std::clamp(ex.camera.pitch_deg + 0.4 * d.y, -85.0, 85.0);
  camera_moved_ = Clock::now();
  after_change();
}

void App::view_lit(LitView& v, view::ObjectKind kind, const view::MaterialSlot& slot, int display_w, int display_h) {
  v.display.resize(display_w, display_h);
  // Fewer pixels while the user drags (the display pass scales the picture up), all of them once
  // the state has been still for 0.3 s.
  const bool changing = Clock::now() - changed_ < std::chrono::milliseconds(300);
  const double scale = changing ? opt_.interactive_scale : 1.0;
  const int w = std::max(8, int(std::lround(display_w * scale))), h = std::max(8, int(std::lround(display_h * scale)));
#if ANISO_VIEW_HAVE_RASTER
  const std::shared_ptr<const render::Scene>& base = kind == view::ObjectKind::Sphere ? ex.sphere_base : ex.object_base;
  const std::string key =
      fmt::format("{} {} {} {} {} {} {} {} {} {} {}", slot.edit.dump(), ex.light.theta_deg, ex.light.phi_deg, ex.light_irradiance,
                  ex.tangent.to_json().dump(), ex.camera.yaw_deg, ex.camera.pitch_deg, ex.camera.distance, w, h, exposure_);
  if (key == v.key && base.get() == v.base) return;
  v.key = key;
  try {
    const std::shared_ptr<const render::Scene> scene = ex.view_scene(kind, slot);
    if (!v.raster || base.get() != v.base) {
      v.raster.reset();
      v.raster = std::make_unique<gl::SceneRasterizer>(*scene, gl::RasterSettings{opt_.subsamples});
      v.base = base.get();
    }
    render::Camera cam = scene->camera;
    cam.fov_deg = view::fitted_fov(cam.fov_deg, w, h);
    v.raster->set_camera(cam);
    v.raster->set_lights(scene->lights);
    v.raster->set_material(0, slot.desc);
    if (!ex.structural_tangent()) v.raster->set_tangent_field(0, scene->objects[0].tangent.field);
    v.raster->set_size(w, h);
    v.raster->render();
    v.error.clear();
    v.display.bind();
    display_->draw(v.raster->color_texture(), 0, false, exposure_, 1.0f, kBackground);
    v.scaled = w != display_w;
  } catch (const std::exception& e) {
    v.error = e.what();
    v.display.bind();
    glClearColor(kBackground.x, kBackground.y, kBackground.z, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
#else
  (void)kind, (void)slot;
  v.error = "the GL rasteriser (gl/scene_raster.h) is not in this build";
#endif
}

void App::draw_sphere(float w, float h, LitView& v, view::ObjectKind kind) {
  view_lit(v, kind, ex.a, int(w), int(h));
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("lit", ImVec2(w, h));
  drag_camera(ImGui::IsItemActive());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddImage(tex_id(v.display.texture()), p, ImVec2(p.x + w, p.y + h), ImVec2(0, 1), ImVec2(1, 0));
  if (!v.error.empty())
    dl->AddText(nullptr, 0.0f, ImVec2(p.x + 6, p.y + 6), IM_COL32(255, 110, 110, 255), v.error.c_str(), nullptr, w - 12);
}

// Two polar plots of material A (orange) and B (blue): the plane of incidence (phi = phi_light)
// and the slice at phi_light + 90 degrees; the light and its mirror direction marked.
void App::draw_polar(float w, float h) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::Dummy(ImVec2(w, h));
  const Vec3T<double> wi = ex.light.local();
  const float half = (h - 8.0f) / 2.0f;
  for (int k = 0; k < 2; ++k) {
    const double plane = ex.light.phi_deg + (k == 0 ? 0.0 : 90.0);
    const auto sa = view::polar_slice(ex.a.kernel, wi, plane, 181, times_cos_);
    const auto sb = view::polar_slice(ex.b.kernel, wi, plane, 181, times_cos_);
    double vmax = 0.0;
    for (const auto& s : sa) vmax = std::max(vmax, s.value);
    for (const auto& s : sb) vmax = std::max(vmax, s.value);
    const float R = std::min(w / 2.0f - 6.0f, half - 20.0f);
    const ImVec2 c(p.x + w / 2.0f, p.y + half * float(k) + half - 4.0f + 4.0f * float(k));
    for (float f : {0.25f, 0.5f, 0.75f, 1.0f}) {
      // Upper half circles (the hemisphere above the surface).
      dl->PathArcTo(c, R * f, float(kPi<double>), float(2.0 * kPi<double>), 48);
      dl->PathStroke(kColGrid, 0, 1.0f);
    }
    dl->AddLine(ImVec2(c.x - R, c.y), ImVec2(c.x + R, c.y), kColGrid);
    auto curve = [&](const std::vector<view::PolarSample>& s, ImU32 col, float thick) {
      for (const auto& q : s) {
        const float r = R * float(view::plot_radius(q.value, vmax, log_scale_));
        const float t = float(glm::radians(q.theta_deg));
        dl->PathLineTo(ImVec2(c.x + r * std::sin(t), c.y - r * std::cos(t)));
      }
      dl->PathStroke(col, 0, thick);
    };
    curve(sb, kColB, 1.5f);
    curve(sa, kColA, 2.0f);
    if (k == 0) {
      // The light lies at +theta_i in its own plane; the mirror direction at -theta_i.
      const float t = float(glm::radians(ex.light.theta_deg));
      dl->AddLine(c, ImVec2(c.x + R * std::sin(t), c.y - R * std::cos(t)), kColLight, 1.5f);
      dl->AddLine(c, ImVec2(c.x - R * std::sin(t), c.y - R * std::cos(t)), IM_COL32(255, 230, 80, 90), 1.0f);
    }
    const std::string label = fmt::format("{}, phi {:.0f}{}{}", k == 0 ? "incidence" : "perpendicular", plane,
                                          log_scale_ ? ", log" : "", times_cos_ ? ", x cos" : "");
    dl->AddText(ImVec2(p.x + 4, c.y - R - 16.0f), IM_COL32(200, 200, 200, 255), label.c_str());
  }
}

void App::draw_lobe(float w, float h) {
  const Vec3T<double> wi = ex.light.local();
  const std::string key = fmt::format("{} {} {} {}", ex.a.edit.dump(), ex.light.theta_deg, ex.light.phi_deg, times_cos_);
  if (key != lobe_key_) {
    lobe_->upload(view::lobe_mesh(ex.a.kernel, wi, 90, 360, times_cos_),
                  glm::vec3(wi));  // 1-degree steps: sharp lobes stay smooth
    lobe_key_ = key;
  }
  lobe_target_.resize(int(w), int(h));
  lobe_target_.bind();
  lobe_->draw(int(w), int(h), lobe_yaw_, lobe_pitch_);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("lobe", ImVec2(w, h));
  if (ImGui::IsItemActive()) {
    lobe_yaw_ -= 0.4f * ImGui::GetIO().MouseDelta.x;
    lobe_pitch_ = std::clamp(lobe_pitch_ + 0.4f * ImGui::GetIO().MouseDelta.y, -10.0f, 89.0f);
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddImage(tex_id(lobe_target_.texture()), p, ImVec2(p.x + w, p.y + h), ImVec2(0, 1), ImVec2(1, 0));
  dl->AddText(ImVec2(p.x + 4, p.y + 4), IM_COL32(200, 200, 200, 255), "A: r = f / max; n t light");
}

// Directional albedo of A (R, G, B) and B (luminance, blue) against theta, at the light's azimuth.
void App::draw_albedo(float w, float h) {
  const std::string key = fmt::format("{} {} {}", ex.a.edit.dump(), ex.b.edit.dump(), ex.light.phi_deg);
  if (key != albedo_key_) {
    albedo_a_ = view::albedo_curve(ex.a.kernel, ex.light.phi_deg, 46, 1024);
    albedo_b_ = view::albedo_curve(ex.b.kernel, ex.light.phi_deg, 46, 1024);
    albedo_key_ = key;
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::Dummy(ImVec2(w, h));
  const float x0 = p.x + 34, y0 = p.y + h - 20, pw = w - 44, ph = h - 34;
  double ymax = 1.0;
  for (const auto& q : albedo_a_) ymax = std::max({ymax, q.albedo.x, q.albedo.y, q.albedo.z});
  for (const auto& q : albedo_b_) ymax = std::max(ymax, view::luminance(q.albedo));
  for (int i = 0; i <= 4; ++i) {
    const float y = y0 - ph * float(i) / 4.0f;
    dl->AddLine(ImVec2(x0, y), ImVec2(x0 + pw, y), kColGrid);
    dl->AddText(ImVec2(p.x + 2, y - 7), IM_COL32(180, 180, 180, 255), fmt::format("{:.2g}", ymax * i / 4.0).c_str());
  }
  for (int d = 0; d <= 90; d += 30) {
    const float x = x0 + pw * float(d) / 90.0f;
    dl->AddLine(ImVec2(x, y0), ImVec2(x, y0 - ph), kColGrid);
    dl->AddText(ImVec2(x - 8, y0 + 3), IM_COL32(180, 180, 180, 255), fmt::format("{}", d).c_str());
  }
  auto line = [&](const std::vector<view::AlbedoPoint>& c, int channel, ImU32 col) {
    for (const auto& q : c) {
      const double v = channel < 0 ? view::luminance(q.albedo) : q.albedo[channel];
      dl->PathLineTo(ImVec2(x0 + pw * float(q.theta_deg / 90.0), y0 - ph * float(v / ymax)));
    }
    dl->PathStroke(col, 0, 1.8f);
  };
  line(albedo_b_, -1, IM_COL32(200, 200, 200, 255));
  line(albedo_a_, 0, IM_COL32(240, 80, 80, 255));
  line(albedo_a_, 1, IM_COL32(80, 220, 80, 255));
  line(albedo_a_, 2, IM_COL32(90, 120, 255, 255));
  const float xl = x0 + pw * float(ex.light.theta_deg / 90.0);
  dl->AddLine(ImVec2(xl, y0), ImVec2(xl, y0 - ph), kColLight);
  dl->AddText(ImVec2(x0 + 4, p.y + 2), IM_COL32(200, 200, 200, 255), "A: r g b; B: grey");
}

void App::draw_compare(float w, float h) {
  view_lit(cmp_a_, view::ObjectKind::Sphere, ex.a, int(w), int(h));
  view_lit(cmp_b_, view::ObjectKind::Sphere, ex.b, int(w), int(h));
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("cmp", ImVec2(w, h));
  drag_camera(ImGui::IsItemActive());
  ImDrawList* dl = ImGui::GetWindowDrawList();
#if ANISO_VIEW_HAVE_RASTER
  if (difference_ && cmp_a_.raster && cmp_b_.raster && cmp_a_.error.empty() && cmp_b_.error.empty()) {
    cmp_display_.resize(int(w), int(h));
    cmp_display_.bind();
    display_->draw(cmp_a_.raster->color_texture(), cmp_b_.raster->color_texture(), true, exposure_, diff_gain_, kBackground);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    dl->AddImage(tex_id(cmp_display_.texture()), p, ImVec2(p.x + w, p.y + h), ImVec2(0, 1), ImVec2(1, 0));
    dl->AddText(ImVec2(p.x + 4, p.y + 4), IM_COL32(220, 220, 220, 255), fmt::format("|A - B| x {:.0f}", diff_gain_).c_str());
    return;
  }
#endif
  // Split: A's left half beside B's right half of the same sphere.
  dl->AddImage(tex_id(cmp_a_.display.texture()), p, ImVec2(p.x + w / 2, p.y + h), ImVec2(0, 1), ImVec2(0.5f, 0));
  dl->AddImage(tex_id(cmp_b_.display.texture()), ImVec2(p.x + w / 2, p.y), ImVec2(p.x + w, p.y + h), ImVec2(0.5f, 1),
               ImVec2(1, 0));
  dl->AddLine(ImVec2(p.x + w / 2, p.y), ImVec2(p.x + w / 2, p.y + h), IM_COL32(255, 255, 255, 160));
  // Each caption within its own half (4 pixels from each side), shortened with "..." when the
  // material's name is wider than that: they never run into each other.
  const auto text_width = [](std::string_view t) { return ImGui::CalcTextSize(t.data(), t.data() + t.size()).x; };
  const float half = w / 2 - 8.0f;
  dl->AddText(ImVec2(p.x + 4, p.y + 4), kColA, view::ellipsize("A " + ex.a.label(), half, text_width).c_str());
  dl->AddText(ImVec2(p.x + w / 2 + 4, p.y + 4), kColB, view::ellipsize("B " + ex.b.label(), half, text_width).c_str());
  for (const LitView* v : {&cmp_a_, &cmp_b_})
    if (!v->error.empty())
      dl->AddText(nullptr, 0.0f, ImVec2(p.x + 6, p.y + 24), IM_COL32(255, 110, 110, 255), v->error.c_str(), nullptr, w - 12);
}

// The path-traced preview of the lit object's scene (or the --scene file).
void App::draw_preview(float w, float h) {
  const int pw = std::max(16, int(w)), ph = std::max(16, int(h));
  const std::string key =
      fmt::format("{} {} {} {} {} {} {} {} {} {} {} {}", ex.a.edit.dump(), ex.light.theta_deg, ex.light.phi_deg,
                  ex.light_irradiance, ex.tangent.to_json().dump(), ex.camera.yaw_deg, ex.camera.pitch_deg, ex.camera.distance,
                  static_cast<const void*>(ex.object_base.get()), pw, ph, ex.scene_path);
  // Restarted once the camera (and everything else) has been still for 0.3 s: while a slider or
  // the light is dragged the path tracer does not compete with the window for the cores.
  const bool moving = Clock::now() - camera_moved_ < std::chrono::milliseconds(300);
  const bool still = Clock::now() - changed_ >= std::chrono::milliseconds(300);
  if (key != preview_key_ && still) {
    try {
      preview_.restart(ex.preview_scene(view::ObjectKind::Object, pw, ph));
      preview_key_ = key;
    } catch (const std::exception& e) {
      report("preview", e);
      preview_key_ = key;
    }
  }
  // A new average, or the exposure changed: tone-map again (the exposure does not restart the path tracer).
  const bool fresh = preview_.snapshot(&preview_img_, &preview_spp_, &preview_gen_);
  if ((fresh || exposure_ != preview_exposure_) && preview_img_.width > 0) {
    render::ToneMapOptions tm;
    tm.exposure_stops = exposure_;
    preview_tex_.upload(render::tonemap(preview_img_, tm));
    preview_exposure_ = exposure_;
  }
  const ImVec2 p = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("pt", ImVec2(w, h));
  drag_camera(ImGui::IsItemActive());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (preview_tex_.texture()) dl->AddImage(tex_id(preview_tex_.texture()), p, ImVec2(p.x + w, p.y + h));
  const std::string label = moving ? std::string("camera moving")
                                   : (key != preview_key_ ? std::string("waiting for the changes to stop")
                                                          : fmt::format("path traced: {} spp", preview_spp_));
  dl->AddText(ImVec2(p.x + 4, p.y + 4), IM_COL32(230, 230, 230, 255), label.c_str());
}

void App::views_grid(float x0, float width, float height) {
  std::vector<std::string> shown;
  for (const std::string& v : kViewNames)
    if (open[v]) shown.push_back(v);
  if (shown.empty()) return;
  const int n = int(shown.size());
  const int cols = n <= 2 ? n : (n <= 4 ? 2 : (n <= 6 ? 3 : 4));
  const int rows = (n + cols - 1) / cols;
  const float cw = width / float(cols), rh = height / float(rows);
  static const std::map<std::string, std::string> titles = {
      {"sphere", "Lit sphere (GL)"},    {"object", "Lit object (GL)"}, {"polar", "Polar plot"},         {"lobe", "3D lobe"},
      {"albedo", "Directional albedo"}, {"compare", "A/B compare"},    {"preview", "Path traced (CPU)"}};
  for (int i = 0; i < n; ++i) {
    const std::string& v = shown[size_t(i)];
    ImGui::SetNextWindowPos(ImVec2(x0 + cw * float(i % cols), rh * float(i / cols)));
    ImGui::SetNextWindowSize(ImVec2(cw, rh));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(2, 2));
    ImGui::Begin(titles.at(v).c_str(), nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const float w = std::max(avail.x, 16.0f), h = std::max(avail.y, 16.0f);
    if (v == "sphere")
      draw_sphere(w, h, sphere_, view::ObjectKind::Sphere);
    else if (v == "object")
      draw_sphere(w, h, object_, view::ObjectKind::Object);
    else if (v == "polar")
      draw_polar(w, h);
    else if (v == "lobe")
      draw_lobe(w, h);
    else if (v == "albedo")
      draw_albedo(w, h);
    else if (v == "compare")
      draw_compare(w, h);
    else if (v == "preview")
      draw_preview(w, h);
    ImGui::End();
    ImGui::PopStyleVar();
  }
}

void App::save_screenshot(const std::string& path) {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  try {
    render::write_png(path, viewgl::read_window(w, h));       // temp file + rename (image/image_io.h)
    fmt::print("wrote {} ({}x{} screenshot)\n", path, w, h);  // as write_reported()
  } catch (const std::exception& e) {
    report("screenshot " + path, e);
  }
}

void App::frame(bool last) {
  glfwPollEvents();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(window_, &fw, &fh);
  panel_controls(float(fh));
  views_grid(kPanelWidth, float(fw) - kPanelWidth, float(fh));
  ImGui::Render();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fw, fh);
  glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (last && !opt_.screenshot.empty()) pending_screenshot_ = opt_.screenshot;
  if (!pending_screenshot_.empty()) {
    save_screenshot(pending_screenshot_);
    pending_screenshot_.clear();
  }
}

int App::run() {
  for (const std::string& v : kViewNames)
    open[v] = opt_.views.empty() || std::find(opt_.views.begin(), opt_.views.end(), v) != opt_.views.end();
  display_ = std::make_unique<viewgl::DisplayPass>();
  lobe_ = std::make_unique<viewgl::LobeRenderer>();
  difference_ = opt_.compare == "difference";
  log_scale_ = opt_.log_scale;
  times_cos_ = opt_.times_cos;
  camera_moved_ = Clock::now() - std::chrono::seconds(1);
  const bool scripted = opt_.frames > 0;
  // A scripted run's figure is the mean of every frame after the first two; an interactive one
  // follows the last 30.
  frame_times_ = view::FrameTimes(2, scripted ? 0 : 30);
  for (int i = 0; scripted ? i < opt_.frames : !glfwWindowShouldClose(window_); ++i) {
    const bool last = scripted && i == opt_.frames - 1;
    if (opt_.animate) {
      ex.light.phi_deg = std::fmod(ex.light.phi_deg + 3.0 + 180.0, 360.0) - 180.0;
      after_change();
    }
    if (last && open["preview"] && opt_.preview_spp > 0) {
      // A scripted screenshot shows the preview with a known number of samples: one frame to start
      // it (the camera does not move in a script), then wait for the samples.
      frame(false);
      glfwSwapBuffers(window_);
      preview_.wait_for(opt_.preview_spp);
    }
    const auto t0 = Clock::now();
    frame(last);
    glFinish();  // wall time of the frame's GL work too (GL timer queries are unreliable on llvmpipe)
    // A scripted run's last frame is left out: it writes the screenshot (PNG encoding and fsync
    // inside the timed frame), and the figure it shows is the one printed below.
    if (!last) frame_times_.add(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    glfwSwapBuffers(window_);
  }
  preview_.pause();
  if (scripted && frame_times_.frames() > 0) {
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_, &fw, &fh);
    fmt::print(stderr, "aniso view: {}x{} ({}): {} ({}; as the window shows it)\n", fw, fh,
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)), frame_times_.text(),
               opt_.animate ? "light turning: every view redrawn each frame" : "static: views redrawn only on change");
  }
  return 0;
}

struct GlfwSession {
  GLFWwindow* window = nullptr;
  ~GlfwSession() {
    if (window) glfwDestroyWindow(window);
    glfwTerminate();
  }
};

std::string g_glfw_error;
void on_glfw_error(int code, const char* what) { g_glfw_error = fmt::format("GLFW error {}: {}", code, what); }

}  // namespace

int run_view(const ViewOptions& o) {
  // Command-line input first: a bad --material or --set is exit 2 before any window opens.
  auto app_state = std::make_unique<view::Explorer>();
  view::Explorer& ex = *app_state;
  ex.a = view::load_slot(o.material);
  ex.b = view::load_slot(o.material_b);
  for (const std::string& s : o.set) view::apply_assignment(ex.a, s);
  for (const std::string& s : o.set_b) view::apply_assignment(ex.b, s);
  ex.light.theta_deg = o.light_theta_deg;
  ex.light.phi_deg = o.light_phi_deg;
  ex.tangent.angle_deg = o.tangent_angle_deg;
  ex.camera.yaw_deg = o.camera_yaw_deg;
  ex.camera.pitch_deg = o.camera_pitch_deg;
  if (!o.tangent_field.empty()) ex.tangent.field = o.tangent_field;
  if (!o.scene.empty()) ex.load_scene_file(o.scene);
  ex.refresh();

  glfwSetErrorCallback(on_glfw_error);
  GlfwSession session;
  if (!glfwInit())
    throw WindowUnavailable(fmt::format("cannot open a window: {} (no display? run under xvfb-run)", g_glfw_error));
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
  session.window = glfwCreateWindow(o.width, o.height, "aniso view", nullptr, nullptr);
  if (!session.window) throw WindowUnavailable(fmt::format("cannot open a window with OpenGL 3.3 core: {}", g_glfw_error));
  glfwMakeContextCurrent(session.window);
  glfwSwapInterval(o.frames > 0 ? 0 : 1);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(session.window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  int rc = 0;
  {
    App app(o, session.window);
    app.ex = std::move(ex);
    // Script actions: as the window's buttons, errors shown in the window and on stderr.
    auto act = [&](const std::string& what, auto&& fn) {
      try {
        fn();
      } catch (const std::exception& e) {
        app.ex.last_error = fmt::format("{}: {}", what, e.what());
        fmt::print(stderr, "aniso view: error: {}\n", app.ex.last_error);
      }
    };
    for (const std::string& f : o.load_material) act("load material " + f, [&] { app.ex.load_material_a(f); });
    for (const std::string& f : o.load_material_b) act("load material B " + f, [&] { app.ex.load_material_b(f); });
    for (const std::string& f : o.load_obj) act("load OBJ " + f, [&] { app.ex.load_obj(f); });
    for (const std::string& f : o.load_tangent_map) act("load tangent map " + f, [&] { app.ex.load_tangent_map(f); });
    const view::MaterialSlot& a = app.ex.a;
    if (!o.save_material.empty())
      act("save " + o.save_material, [&] { write_reported(o.save_material, a.edit.dump(2) + "\n", "material A as JSON"); });
    if (!o.export_glsl.empty()) act("export " + o.export_glsl, [&] { write_glsl_reported(o.export_glsl, a.desc, a.source); });
    if (!o.export_brdf.empty())
      act("export " + o.export_brdf,
          [&] { write_reported(o.export_brdf, gl::export_brdf(a.desc, a.source), "material A as a BRDF Explorer .brdf file"); });
    rc = app.run();
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  return rc;
}

}  // namespace aniso
