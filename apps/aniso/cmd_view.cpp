// apps/aniso/cmd_view.cpp: `aniso view`, the interactive explorer (docs/explorer.md). The window
// is view_app.cpp; this file is its command line.
#include <algorithm>
#include <sstream>

#include "commands.h"
#include "io/text_input.h"
#include "view_app.h"

namespace aniso {

void add_view_command(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  auto size_text = std::make_shared<std::string>("1280x720");
  auto views_text = std::make_shared<std::string>("all");
  CLI::App* cmd = app.add_subcommand("view",
                                     "the interactive explorer: sliders, lit sphere and object, polar and 3D lobe plots, albedo, "
                                     "A/B compare, path-traced preview");
  cmd->add_option("--material,-m", o->material, std::string("material A: ") + kMaterialHelp);
  cmd->add_option("--material-b", o->material_b, "material B of the A/B comparison (same forms)");
  cmd->add_option("--scene", o->scene,
                  "scene file (docs/scenes.md): the path-traced preview renders it, material A on its first object");
  cmd->add_option("--set", o->set,
                  "key=value on material A, keys as in its JSON (alpha_x=0.05, lobe.alpha_y=0.3, lobes[0].n=20); repeatable");
  cmd->add_option("--set-b", o->set_b, "key=value on material B; repeatable");
  cmd->add_option("--size", *size_text, "window size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--views", *views_text,
                  "views to open, comma-separated, from sphere, object, polar, lobe, albedo, compare, preview; or all")
      ->capture_default_str();
  cmd->add_option("--frames", o->frames, "render this many frames and exit (0: run until the window is closed)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--screenshot", o->screenshot, "write the window to this PNG after the last frame (with --frames)");
  cmd->add_option("--light", o->light_theta_deg, "light theta in degrees from the normal")
      ->check(finite_range(0.0, 89.0))
      ->capture_default_str();
  cmd->add_option("--light-phi", o->light_phi_deg, "light phi in degrees from the tangent")
      ->check(finite_range(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--yaw", o->camera_yaw_deg, "orbit camera: degrees about +y (0: looking along -z)")
      ->check(finite_range(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--pitch", o->camera_pitch_deg, "orbit camera: degrees above the horizon")
      ->check(finite_range(-85.0, 85.0))
      ->capture_default_str();
  cmd->add_option("--tangent-angle", o->tangent_angle_deg, "tangent rotation about the normal, degrees")
      ->check(finite_range(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--tangent-field", o->tangent_field, "procedural tangent field")
      ->check(CLI::IsMember({"natural", "projected", "concentric", "radial", "swirl", "noise", "uv"}))
      ->capture_default_str();
  cmd->add_option("--compare", o->compare, "A/B view: split or difference")
      ->check(CLI::IsMember({"split", "difference"}))
      ->capture_default_str();
  cmd->add_flag("--log", o->log_scale, "polar plots on a log scale");
  cmd->add_flag("--times-cos", o->times_cos, "polar and lobe plots of f x cos(theta_o)");
  cmd->add_flag("--animate", o->animate, "turn the light 3 degrees a frame (speed measurement: every view redraws)");
  cmd->add_option("--preview-spp", o->preview_spp, "with --frames: wait for this many path-traced samples before the last frame")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd->add_option("--interactive-scale", o->interactive_scale,
                  "lit views' resolution while something changes, relative to full (full again 0.3 s after the last change)")
      ->check(finite_range(0.1, 1.0))
      ->capture_default_str();
  cmd->add_option("--subsamples", o->subsamples, "rasteriser sub-pixel positions per axis (anti-aliasing)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->add_option("--load-material", o->load_material, "script action: load material A from a file, as the Load button does");
  cmd->add_option("--load-material-b", o->load_material_b, "script action: load material B from a file");
  cmd->add_option("--load-obj", o->load_obj, "script action: load an OBJ into the lit object view");
  cmd->add_option("--load-tangent-map", o->load_tangent_map, "script action: load a tangent map (PNG, EXR, PFM, HDR)");
  cmd->add_option("--save-material", o->save_material, "script action: save material A's JSON");
  cmd->add_option("--export-glsl", o->export_glsl, "script action: export material A as GLSL");
  cmd->add_option("--export-brdf", o->export_brdf, "script action: export material A as a BRDF Explorer .brdf file");
  cmd->callback([o, size_text, views_text] {
    run_command([&] {
      ViewOptions opts = *o;
      int w = 0, h = 0;
      char x = 0;
      std::istringstream in(*size_text);
      if (!(in >> w >> x >> h) || x != 'x' || !in.eof() || w < 320 || h < 240 || w > 8192 || h > 8192)
        throw InputError(fmt::format("--size \"{}\": expected WIDTHxHEIGHT, 320x240 to 8192x8192", *size_text));
      opts.width = w, opts.height = h;
      if (*views_text != "all") {
        std::stringstream ss(*views_text);
        std::string v;
        while (std::getline(ss, v, ',')) {
          if (std::find(kViewNames.begin(), kViewNames.end(), v) == kViewNames.end())
            throw InputError(fmt::format(
                "--views: unknown view \"{}\"; expected sphere, object, polar, lobe, albedo, compare, preview or all", v));
          opts.views.push_back(v);
        }
      }
      if (!opts.screenshot.empty() && opts.frames == 0) throw InputError("--screenshot needs --frames N (the frame to capture)");
      run_view(opts);
    });
  });
}

}  // namespace aniso
