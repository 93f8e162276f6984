// apps/aniso/view_app.h: the explorer's window (`aniso view`, docs/explorer.md): GLFW, Dear ImGui
// and OpenGL 3.3 core over the state of src/view (view/explorer.h).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace aniso {

// Every view the explorer has, in the order they are laid out.
inline const std::vector<std::string> kViewNames = {"sphere", "object", "polar", "lobe", "albedo", "compare", "preview"};

struct ViewOptions {
  std::string material = "brushed-gold";  // A
  std::string material_b = "gold";        // B (the A/B comparison)
  std::string scene;                      // --scene: the path-traced preview renders this file
  std::vector<std::string> set, set_b;    // key=value on A, on B
  int width = 1280, height = 720;
  int frames = 0;                  // > 0: render this many frames, then exit (screenshot after the last)
  std::string screenshot;          // PNG written after the last frame
  std::vector<std::string> views;  // empty: all
  double light_theta_deg = 35.0, light_phi_deg = 20.0;
  double tangent_angle_deg = 0.0;
  double camera_yaw_deg = 0.0, camera_pitch_deg = 0.0;  // the orbit camera
  std::string tangent_field;                            // "" = natural
  std::string compare = "split";                        // split | difference
  bool log_scale = false, times_cos = false;
  bool animate = false;  // turn the light 3 degrees a frame (speed measurements: every view redraws)
  int preview_spp = 4;   // scripted runs: the preview's samples per pixel before the last frame
  int subsamples = 1;    // the rasteriser's sub-pixel positions per axis
  // The lit views' resolution while something changes (a slider or the light dragged, --animate),
  // relative to the view's size; full resolution 0.3 s after the last change. 1: always full.
  double interactive_scale = 0.5;
  // Script actions: what the window's buttons do, in this order after --set (errors go to the
  // window and stderr; the run goes on with the last good state).
  std::vector<std::string> load_material, load_material_b, load_obj, load_tangent_map;
  std::string save_material, export_glsl, export_brdf;
};

// No window could be opened (no display, no GL 3.3): the message says why.
class WindowUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs the explorer; returns the exit status. InputError for bad command-line input (--material,
// --set) before any window opens.
int run_view(const ViewOptions& options);

}  // namespace aniso
