// apps/aniso/cmd_render.cpp: `aniso render`, a scene file (docs/scenes.md), the preview scene of a
// material (--material) or, with neither, the built-in gallery; on the CPU path tracer or, with
// --backend gl, headless OpenGL. Ctrl-C ends a render after its current pass: what it has is
// written and the exit status is 130.
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "aniso/gl/gl_context.h"
#include "aniso/image/image_io.h"
#include "aniso/io/presets.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "commands.h"
#include "gl/scene_raster.h"
#include "io/json_read.h"
#include "io/text_input.h"

namespace aniso {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the program at once
}

// A progress bar with the time left, on stderr, only when stderr is a terminal; at most 10 updates
// a second.
class ProgressBar {
 public:
  explicit ProgressBar(std::string what) : what_(what), base_(std::move(what)), enabled_(isatty(STDERR_FILENO) != 0) {}
  void update(double f) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (f < 1.0 && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const int width = 30, filled = int(f * width + 0.5);
    std::string bar(size_t(filled), '#');
    bar.resize(size_t(width), '-');
    const std::string left = f > 0.02 ? fmt::format("~{:.0f} s left", elapsed * (1.0 - f) / f) : "estimating";
    fmt::print(stderr, "\r{} [{}] {:3.0f}%  {:.1f} s, {}   ", what_, bar, 100.0 * f, elapsed, left);
    std::fflush(stderr);
    drawn_ = true;
  }
  void finish() {
    if (drawn_) fmt::print(stderr, "\r\033[K");
  }
  // The renderer's passes: samples per pixel so far and, with adaptive sampling, the pixels left.
  void pass(const aniso::render::PassReport& p) {
    what_ = fmt::format("{} ({} spp{})", base_, p.spp,
                        p.active_fraction < 1.0 ? fmt::format(", {:.0f}% of pixels active", 100.0 * p.active_fraction) : "");
  }

 private:
  std::string what_, base_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

struct RenderArgs {
  std::string scene, output, material, strategy, sampler, tonemap = "aces", backend = "cpu";
  int spp = 0, width = 0, height = 0, threads = 0, max_depth = 0, min_spp = 0;
  uint64_t seed = 1;
  double exposure = 0.0, noise_threshold = -1.0, time_s = 0.0;
  bool print_scene = false;
  bool tone_given = false;  // --exposure or --tonemap given
};

// The scene document with every file it names (environment and tangent maps, meshes, material
// files) made absolute, so that the printed scene reads the same files wherever it is saved.
// Which keys are files: docs/scenes.md (render/scene.cpp resolves them against the scene's folder).
void resolve_scene_paths(nlohmann::json& doc, const std::string& base_dir) {
  namespace fs = std::filesystem;
  const auto resolve = [&](nlohmann::json& v) {
    if (!v.is_string()) return;
    const fs::path p = v.get<std::string>();
    std::error_code ec;
    const fs::path full = fs::absolute(p.is_absolute() ? p : fs::path(base_dir) / p, ec);
    if (!ec) v = full.lexically_normal().string();
  };
  const auto material = [&](nlohmann::json& m) {
    if (m.is_string() && !find_preset(m.get<std::string>()))
      resolve(m);
    else if (m.is_object() && m.contains("file"))
      resolve(m["file"]);  // {"model": "measured", "file": ...}
  };
  if (!doc.is_object()) return;
  if (doc.contains("environment") && doc["environment"].is_object() && doc["environment"].contains("file"))
    resolve(doc["environment"]["file"]);
  if (!doc.contains("objects") || !doc["objects"].is_array()) return;
  for (nlohmann::json& o : doc["objects"]) {
    if (!o.is_object()) continue;
    if (o.contains("file")) resolve(o["file"]);
    if (o.contains("material")) material(o["material"]);
    if (o.contains("tangent") && o["tangent"].is_object() && o["tangent"].contains("map")) resolve(o["tangent"]["map"]);
  }
}

// `--backend gl`: the scene's direct light from point and directional lights, rasterised through
// OpenGL (gl/scene_raster.h), headless (EGL). What it leaves out is said on stderr; a material
// without a GLSL twin, a scene with nothing it can light, or no GL at all exit 2.
int render_gl(const aniso::render::Scene& scene, const RenderArgs& a, const aniso::render::ToneMapOptions& tm) {
  using namespace aniso::render;
  gl::check_gl_materials(scene);
  if (!gl::gl_has_lights(scene))
    throw InputError(
        fmt::format("{}: --backend gl: the scene has no point or directional light with power, the only lights the "
                    "GL backend draws (it renders no sphere lights and no environment): the image would be black",
                    scene.source));
  for (const std::string& w : gl::gl_unsupported(scene)) fmt::print(stderr, "aniso render: warning: --backend gl: {}\n", w);
  try {
    gl::GlContext::get();
  } catch (const gl::GlUnavailable& e) {
    throw InputError(fmt::format("--backend gl: no OpenGL context could be made ({}); render with --backend cpu", e.what()));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int k = gl::subsamples_for_spp(scene.film.spp);
  gl::SceneRasterizer raster(scene, gl::RasterSettings{k});
  raster.render();
  gl::GlContext::get().finish();
  const Image img = raster.read_back();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_image(a.output, img, tm);
  fmt::print("wrote {} ({}x{}, {} sub-samples per pixel, GL: {}) in {:.2f} s\n", a.output, img.width, img.height, k * k,
             gl::GlContext::get().renderer(), seconds);
  return 0;
}

// Ctrl-C before every pixel had one sample: the picture would have holes, so the output (an older
// picture, perhaps) is left as it was.
int interrupted_before_first_pass(const std::string& output) {
  fmt::print(stderr, "aniso render: interrupted before the first pass was complete: nothing written ({} left as it was)\n",
             output);
  return 130;
}

int cmd_render(RenderArgs a) {
  using namespace aniso::render;
  if (!a.scene.empty() && !a.material.empty())
    throw InputError("give either a scene file or --material (the preview scene), not both");
  const std::string ext_out = a.output.empty() ? ".png" : lower_extension(a.output);
  if (ext_out != ".png" && ext_out != ".exr" && ext_out != ".pfm")
    throw InputError(fmt::format("-o {}: expected a .png, .exr or .pfm file name", a.output));
  if (a.tone_given && ext_out != ".png")
    throw InputError(
        fmt::format("--exposure and --tonemap apply to PNG output only; -o {} holds linear radiance, "
                    "written as rendered",
                    a.output));
  ToneMapOptions tm;
  tm.exposure_stops = float(a.exposure);
  tm.curve = a.tonemap == "clamp" ? ToneMap::Clamp : ToneMap::Aces;
  RenderOptions ro;
  ro.threads = a.threads;
  ro.seed = a.seed;
  ro.cancel = &g_interrupted;

  if (a.scene.empty() && a.material.empty()) {
    if (a.print_scene) {
      write_stdout(fmt::format("{}\n", gallery_document().dump(2)));
      return 0;
    }
    if (a.backend == "gl")
      throw InputError(
          "--backend gl: the gallery is lit by sphere lights and a sky, which the GL backend does not render; "
          "give a scene file with point or directional lights");
    if (a.output.empty()) a.output = "aniso-gallery.png";
    if (ext_out != ".png") throw InputError(fmt::format("-o {}: the gallery is a labelled figure: PNG only", a.output));
    if (!a.strategy.empty() || a.max_depth > 0 || a.noise_threshold >= 0.0 || a.min_spp > 0 || a.time_s > 0.0)
      throw InputError(
          "--strategy, --max-depth, --noise-threshold, --min-spp and --time apply to scene files, not to the gallery");
    GalleryOptions go;
    go.width = a.width > 0 ? a.width : 1024;
    go.height = a.height;
    go.spp = a.spp;
    go.sampler = a.sampler;
    go.tonemap = tm;
    ProgressBar bar("aniso render: gallery");
    go.render = ro;
    go.render.progress = [&](double f) { bar.update(f); };
    std::signal(SIGINT, on_sigint);
    const GalleryResult r = render_gallery(go);
    bar.finish();
    if (r.stats.spp_done == 0) return interrupted_before_first_pass(a.output);
    write_png(a.output, r.image);
    fmt::print("{}wrote {} ({}x{}, {} cells, {} spp) in {:.1f} s: {:.2f} M paths/s, {:.2f} M rays/s\n",
               r.stats.cancelled ? "interrupted: " : "", a.output, r.image.width, r.image.height, r.cells, r.stats.spp_done,
               r.stats.seconds, double(r.stats.paths) / r.stats.seconds * 1e-6, double(r.stats.rays) / r.stats.seconds * 1e-6);
    return r.stats.cancelled ? 130 : 0;
  }

  nlohmann::json doc;
  std::string source, base_dir;
  if (!a.material.empty()) {
    // A material argument is a preset name, a JSON file, or an inline JSON object.
    nlohmann::json m = a.material;
    const size_t first = a.material.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && a.material[first] == '{') m = parse_json_text(a.material, "inline material");
    doc = preview_scene(m);
    source = "preview scene";
    if (a.output.empty()) a.output = "aniso-preview.png";
  } else {
    doc = parse_json_text(read_text_file(a.scene, "a scene file"), a.scene);
    source = a.scene;
    base_dir = std::filesystem::path(a.scene).parent_path().string();
    if (a.output.empty()) a.output = std::filesystem::path(a.scene).stem().string() + ".png";
  }
  if (a.print_scene) {
    resolve_scene_paths(doc, base_dir);
    write_stdout(fmt::format("{}\n", doc.dump(2)));
    return 0;
  }
  Scene scene = parse_scene(doc, source, base_dir);
  resize_film(scene.film, a.width, a.height);  // one side alone keeps the scene's aspect ratio
  if (a.spp > 0) scene.film.spp = a.spp;
  if (a.max_depth > 0) scene.integrator.max_depth = a.max_depth;
  if (a.noise_threshold >= 0.0) scene.film.noise_threshold = float(a.noise_threshold);
  if (a.min_spp > 0) scene.film.min_spp = a.min_spp;
  if (a.time_s > 0.0) {
    scene.film.time_s = float(a.time_s);
    if (a.spp == 0) scene.film.spp = 1 << 20;  // --time alone: the budget decides
  }
  if (!a.sampler.empty()) scene.integrator.sampler = a.sampler == "independent" ? SamplerKind::Independent : SamplerKind::Sobol;
  if (!a.strategy.empty())
    scene.integrator.strategy = a.strategy == "bsdf" ? Strategy::Bsdf : (a.strategy == "light" ? Strategy::Light : Strategy::Mis);
  if (a.backend == "gl") return render_gl(scene, a, tm);
  bool lit = !scene.environment.is_black();
  for (const Light& l : scene.lights) lit = lit || l.power.x > 0.0f || l.power.y > 0.0f || l.power.z > 0.0f;
  if (!lit)
    fmt::print(stderr, "aniso render: warning: {}: no light with power and no environment: the image will be black\n", source);
  ProgressBar bar(fmt::format("aniso render: {}", source));
  ro.progress = [&](double f) { bar.update(f); };
  std::signal(SIGINT, on_sigint);
  ro.on_pass = [&](const PassReport& p) { bar.pass(p); };
  RenderStats st;
  const Image img = aniso::render::render(scene, ro, &st);
  bar.finish();
  if (st.spp_done == 0) return interrupted_before_first_pass(a.output);
  write_image(a.output, img, tm);
  const std::string spp_text = scene.film.noise_threshold > 0.0f ? fmt::format("{} spp, {:.1f} on average{}", st.spp_done,
                                                                               st.mean_spp, st.converged ? ", converged" : "")
                                                                 : fmt::format("{} spp", st.spp_done);
  fmt::print("{}wrote {} ({}x{}, {}{}) in {:.1f} s: {:.2f} M paths/s, {:.2f} M rays/s\n", st.cancelled ? "interrupted: " : "",
             a.output, img.width, img.height, spp_text, st.out_of_time ? ", time budget reached" : "", st.seconds,
             double(st.paths) / st.seconds * 1e-6, double(st.rays) / st.seconds * 1e-6);
  if (st.nonfinite > 0) fmt::print(stderr, "aniso render: warning: {} samples were NaN or Inf and were dropped\n", st.nonfinite);
  return st.cancelled ? 130 : 0;
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto ra = std::make_shared<RenderArgs>();
  auto* render_cmd = app.add_subcommand(
      "render", "render a scene file, the preview scene of a material (--material), or with neither the built-in gallery");
  render_cmd->add_option("scene", ra->scene, "scene file (docs/scenes.md); none: the gallery or the material preview");
  render_cmd->add_option("-o,--output", ra->output,
                         "output image: .png (tone-mapped sRGB), .exr or .pfm (linear radiance); default aniso-gallery.png, "
                         "aniso-preview.png or <scene>.png");
  render_cmd->add_option("--material,-m", ra->material,
                         std::string("render the preview scene with this material: ") + kMaterialHelp);
  render_cmd->add_option("--spp", ra->spp, "samples per pixel (default: the scene's; the gallery's 64)")
      ->transform(whole_range(1, 1 << 20));
  render_cmd
      ->add_option("--width", ra->width,
                   "image width in pixels (default: the scene's; alone, the height follows the scene's aspect ratio)")
      ->transform(whole_range(16, 16384));
  render_cmd->add_option("--height", ra->height, "image height in pixels (default: the scene's; alone, the width follows)")
      ->transform(whole_range(16, 16384));
  render_cmd->add_option("--threads", ra->threads, "worker threads (default: all cores)")->transform(whole_range(1, 1024));
  render_cmd->add_option("--seed", ra->seed, "random seed (same seed, same image, whatever the thread count)")
      ->transform(seed_value())
      ->capture_default_str();
  render_cmd->add_option("--strategy", ra->strategy, "mis (default), bsdf or light")
      ->check(CLI::IsMember({"mis", "bsdf", "light"}));
  render_cmd->add_option("--sampler", ra->sampler, "sobol (default: Owen-scrambled Sobol') or independent (PCG32)")
      ->check(CLI::IsMember({"sobol", "independent"}));
  render_cmd
      ->add_option("--noise-threshold", ra->noise_threshold,
                   "adaptive sampling: stop pixels whose estimated error is below this (docs/scenes.md; default: the scene's "
                   "film.noise_threshold, 0 = off)")
      ->check(finite_range(0.0, 1.0));
  render_cmd->add_option("--min-spp", ra->min_spp, "adaptive sampling: samples before a pixel may stop (default: automatic)")
      ->transform(whole_range(1, 1 << 20));
  render_cmd->add_option("--time", ra->time_s, "time budget in seconds: passes until it ends (with --spp as a cap)")
      ->check(finite_range(0.001, 1e6));
  render_cmd->add_option("--max-depth", ra->max_depth, "path length limit (default: the scene's)")
      ->transform(whole_range(1, 1024));
  auto* exposure_opt = render_cmd->add_option("--exposure", ra->exposure, "exposure in stops (PNG output only)")
                           ->check(finite_range(-30.0, 30.0))
                           ->capture_default_str();
  auto* tonemap_opt =
      render_cmd->add_option("--tonemap", ra->tonemap, "PNG tone curve: aces (default) or clamp (PNG output only)")
          ->check(CLI::IsMember({"aces", "clamp"}));
  render_cmd
      ->add_option("--backend", ra->backend,
                   "cpu (default: the path tracer) or gl (direct light of point and directional lights through OpenGL, "
                   "headless; docs/scenes.md, \"GL backend\")")
      ->check(CLI::IsMember({"cpu", "gl"}));
  render_cmd->add_flag("--print-scene", ra->print_scene, "print the scene document that would be rendered, and exit");
  render_cmd->callback([ra, exposure_opt, tonemap_opt] {
    ra->tone_given = exposure_opt->count() > 0 || tonemap_opt->count() > 0;
    run_command([&] { return cmd_render(*ra); });
  });
}

}  // namespace aniso
