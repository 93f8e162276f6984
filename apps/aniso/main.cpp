// aniso: the command-line tool. Scripting commands (exact formats; other tools and tests depend on
// them, docs/cli.md): eval, sample, albedo, fresnel; and presets, models for discovery.
// Numbers are computed in double precision and printed with 9 significant digits.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "commands.h"
#include "data/metals.h"
#include "io/materials.h"
#include "io/presets.h"
#include "render/gallery.h"
#include "render/integrator.h"
#include "stats/albedo.h"
#include "stats/rng.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

Vec3d normalized_or_throw(const Vec3d& v, const std::string& what) {
  const double len = glm::length(v);
  if (!std::isfinite(len) || !(len > 0.0))
    throw InputError(fmt::format("{}: expected a non-zero, finite direction, got ({}, {}, {})", what, v.x, v.y, v.z));
  return v / len;
}

std::string num(double x) { return fmt::format("{:.9g}", x); }

// Reads "wi.x wi.y wi.z wo.x wo.y wo.z" lines; all lines are checked before anything is printed,
// so a bad line leaves no half-written output.
int cmd_eval(const std::string& material) {
  const Mat m = build_material<double>(load_material(material));
  std::string out, line;
  size_t line_no = 0;
  while (std::getline(std::cin, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;  // blank lines and comments
    std::istringstream in(line);
    double v[6];
    for (int i = 0; i < 6; ++i) {
      std::string tok;
      if (!(in >> tok))
        throw InputError(fmt::format("stdin line {}: expected 6 numbers (wi.x wi.y wi.z wo.x wo.y wo.z), got {}",
                                     line_no, i));
      try {
        size_t used = 0;
        v[i] = std::stod(tok, &used);
        if (used != tok.size() || !std::isfinite(v[i])) throw std::invalid_argument(tok);
      } catch (const std::exception&) {
        throw InputError(fmt::format("stdin line {}: field {}: expected a finite number, got \"{}\"", line_no, i + 1, tok));
      }
    }
    std::string extra;
    if (in >> extra) throw InputError(fmt::format("stdin line {}: expected 6 numbers, got more (\"{}\")", line_no, extra));
    const Vec3d wi = normalized_or_throw(Vec3d(v[0], v[1], v[2]), fmt::format("stdin line {}: wi", line_no));
    const Vec3d wo = normalized_or_throw(Vec3d(v[3], v[4], v[5]), fmt::format("stdin line {}: wo", line_no));
    const RGBT<double> f = m.f(wi, wo);
    out += fmt::format("{} {} {} {}\n", num(f.x), num(f.y), num(f.z), num(m.pdf(wi, wo)));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

int cmd_sample(const std::string& material, const std::vector<double>& wo_in, int64_t count, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const Vec3d wo = normalized_or_throw(Vec3d(wo_in[0], wo_in[1], wo_in[2]), "--wo");
  Rng rng(seed);
  std::string out;
  for (int64_t i = 0; i < count; ++i) {
    const double uc = rng.uniform();
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    const BSDFSampleT<double> s = m.sample(wo, uc, u);
    if (!s.valid) {
      out += "0 0 0 0 0 0 0\n";
      continue;
    }
    out += fmt::format("{} {} {} {} {} {} {}\n", num(s.wi.x), num(s.wi.y), num(s.wi.z), num(s.weight.x),
                       num(s.weight.y), num(s.weight.z), num(s.pdf));
    if (out.size() > (1u << 20)) {
      std::fwrite(out.data(), 1, out.size(), stdout);
      out.clear();
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

Vec3d direction_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

int cmd_albedo(const std::string& material, double theta, double phi, int64_t samples, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const AlbedoEstimate a = albedo_importance(m, direction_deg(theta, phi), samples, seed);
  fmt::print("{} {} {}\n", num(a.mean.x), num(a.mean.y), num(a.mean.z));
  return 0;
}

int cmd_fresnel(const std::string& metal, double theta, bool schlick) {
  const MetalData* md = find_metal(metal);
  if (!md) throw InputError(fmt::format("--metal: unknown metal \"{}\"; expected one of {}", metal, metal_names()));
  const double c = std::cos(theta * M_PI / 180.0);
  const RGBT<double> eta(md->eta), k(md->k);
  // --schlick: Schlick's approximation with the exact F0 of the same metal, for comparison.
  const RGBT<double> F = schlick ? F_Schlick(F_Conductor(1.0, eta, k), c) : F_Conductor(c, eta, k);
  fmt::print("{} {} {}\n", num(F.x), num(F.y), num(F.z));
  return 0;
}

int cmd_presets(const std::string& show) {
  if (!show.empty()) {
    const auto p = find_preset(show);
    if (!p) throw InputError(fmt::format("--show: unknown preset \"{}\" (run `aniso presets` for the list)", show));
    fmt::print("{}\n", p->dump(2));
    return 0;
  }
  for (const PresetInfo& p : presets()) fmt::print("{:<40} {}\n", p.name, p.source);
  return 0;
}

int cmd_models(bool markdown, const std::string& only) {
  if (!only.empty() && !find_model_spec(only)) {
    std::string names;
    for (const ModelSpec* m : model_specs()) names += fmt::format(" {}", m->name);
    throw InputError(fmt::format("--model: unknown model \"{}\"; expected one of{}", only, names));
  }
  if (markdown) {
    for (const ModelSpec* m : model_specs())
      if (only.empty() || m->name == only) fmt::print("{}\n", markdown_table(*m));
    return 0;
  }
  for (const ModelSpec* m : model_specs()) {
    if (!only.empty() && m->name != only) continue;
    fmt::print("{} ({}) -- {}\n", m->name, m->title, m->citation);
    for (const ParamSpec* p : m->params()) {
      fmt::print("  {:<20} {:<55} {}{}\n", p->name, describe_range(*p), p->doc, p->required ? " [required]" : "");
    }
  }
  return 0;
}

// --- render ------------------------------------------------------------------------------

std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the program at once
}

// A progress bar with the time left, on stderr, only when stderr is a terminal; at most 10 updates
// a second.
class ProgressBar {
 public:
  explicit ProgressBar(std::string what) : what_(std::move(what)), enabled_(isatty(STDERR_FILENO) != 0) {}
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

 private:
  std::string what_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

struct RenderArgs {
  std::string scene, output, material, strategy, tonemap = "aces";
  int spp = 0, width = 0, height = 0, threads = 0, max_depth = 0;
  uint64_t seed = 1;
  double exposure = 0.0;
  bool print_scene = false;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

int cmd_render(RenderArgs a) {
  using namespace aniso::render;
  if (!a.scene.empty() && !a.material.empty())
    throw InputError("give either a scene file or --material (the preview scene), not both");
  const std::string ext_out = a.output.empty() ? ".png" : lower_extension(a.output);
  if (ext_out != ".png" && ext_out != ".exr" && ext_out != ".pfm")
    throw InputError(fmt::format("-o {}: expected a .png, .exr or .pfm file name", a.output));
  ToneMapOptions tm;
  tm.exposure_stops = float(a.exposure);
  tm.curve = a.tonemap == "clamp" ? ToneMap::Clamp : ToneMap::Aces;
  RenderOptions ro;
  ro.threads = a.threads;
  ro.seed = a.seed;
  ro.cancel = &g_interrupted;

  if (a.scene.empty() && a.material.empty()) {
    if (a.print_scene) {
      fmt::print("{}\n", gallery_document().dump(2));
      return 0;
    }
    if (a.output.empty()) a.output = "aniso-gallery.png";
    if (ext_out != ".png") throw InputError(fmt::format("-o {}: the gallery is a labelled figure: PNG only", a.output));
    if (!a.strategy.empty() || a.max_depth > 0) throw InputError("--strategy and --max-depth apply to scene files, not to the gallery");
    GalleryOptions go;
    go.width = a.width > 0 ? a.width : 1024;
    go.height = a.height;
    go.spp = a.spp;
    go.tonemap = tm;
    ProgressBar bar("aniso render: gallery");
    go.render = ro;
    go.render.progress = [&](double f) { bar.update(f); };
    std::signal(SIGINT, on_sigint);
    const GalleryResult r = render_gallery(go);
    bar.finish();
    write_png(a.output, r.image);
    fmt::print("{}wrote {} ({}x{}, {} cells, {} spp) in {:.1f} s: {:.2f} M paths/s, {:.2f} M rays/s\n",
               r.stats.cancelled ? "interrupted: " : "", a.output, r.image.width, r.image.height, r.cells,
               r.stats.spp_done, r.stats.seconds, double(r.stats.paths) / r.stats.seconds * 1e-6,
               double(r.stats.rays) / r.stats.seconds * 1e-6);
    return r.stats.cancelled ? 130 : 0;
  }

  nlohmann::json doc;
  std::string source, base_dir;
  if (!a.material.empty()) {
    // A material argument is a preset name, a JSON file, or an inline JSON object.
    nlohmann::json m = a.material;
    if (!a.material.empty() && a.material.front() == '{') {
      try {
        m = nlohmann::json::parse(a.material);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(fmt::format("--material: invalid inline JSON: {}", e.what()));
      }
    }
    doc = preview_scene(m);
    source = "preview scene";
    if (a.output.empty()) a.output = "aniso-preview.png";
  } else {
    std::error_code ec;
    if (!std::filesystem::exists(a.scene, ec)) throw InputError(fmt::format("{}: no such file", a.scene));
    if (std::filesystem::is_directory(a.scene, ec)) throw InputError(fmt::format("{}: is a directory, expected a scene file", a.scene));
    std::ifstream in(a.scene);
    if (!in) throw InputError(fmt::format("{}: cannot open for reading", a.scene));
    try {
      doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("{}: invalid JSON: {}", a.scene, e.what()));
    }
    source = a.scene;
    base_dir = std::filesystem::path(a.scene).parent_path().string();
    if (a.output.empty()) a.output = std::filesystem::path(a.scene).stem().string() + ".png";
  }
  if (a.print_scene) {
    fmt::print("{}\n", doc.dump(2));
    return 0;
  }
  Scene scene = parse_scene(doc, source, base_dir);
  if (a.width > 0) scene.film.width = a.width;
  if (a.height > 0) scene.film.height = a.height;
  if (a.spp > 0) scene.film.spp = a.spp;
  if (a.max_depth > 0) scene.integrator.max_depth = a.max_depth;
  if (!a.strategy.empty())
    scene.integrator.strategy = a.strategy == "bsdf" ? Strategy::Bsdf : (a.strategy == "light" ? Strategy::Light : Strategy::Mis);
  ProgressBar bar(fmt::format("aniso render: {}", source));
  ro.progress = [&](double f) { bar.update(f); };
  std::signal(SIGINT, on_sigint);
  RenderStats st;
  const Image img = aniso::render::render(scene, ro, &st);
  bar.finish();
  write_image(a.output, img, tm);
  fmt::print("{}wrote {} ({}x{}, {} spp) in {:.1f} s: {:.2f} M paths/s, {:.2f} M rays/s\n", st.cancelled ? "interrupted: " : "",
             a.output, img.width, img.height, st.spp_done, st.seconds, double(st.paths) / st.seconds * 1e-6,
             double(st.rays) / st.seconds * 1e-6);
  if (st.nonfinite > 0) fmt::print(stderr, "aniso render: warning: {} samples were NaN or Inf and were dropped\n", st.nonfinite);
  return st.cancelled ? 130 : 0;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) {
  using namespace aniso;
  CLI::App app{"aniso: anisotropic and measured reflectance (models, sampling, metals)"};
  app.require_subcommand(1);

  std::string material;
  auto* eval = app.add_subcommand("eval", "read 'wi.x wi.y wi.z wo.x wo.y wo.z' lines on stdin, write 'f_r f_g f_b pdf'");
  eval->add_option("--material,-m", material, "preset name or JSON file")->required();

  std::vector<double> wo;
  int64_t count = 1;
  uint64_t seed = 1;
  auto* sample = app.add_subcommand("sample", "write N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf'");
  sample->add_option("--material,-m", material, "preset name or JSON file")->required();
  sample->add_option("--wo", wo, "viewing direction x y z (local frame)")->required()->expected(3);
  sample->add_option("--count,-n", count, "number of samples")->check(CLI::Range(int64_t(0), int64_t(1) << 40));
  sample->add_option("--seed", seed, "random seed");

  double theta = 0.0, phi = 0.0;
  int64_t samples = 1 << 20;
  auto* albedo = app.add_subcommand("albedo", "directional albedo 'r g b' for the viewing direction (theta, phi)");
  albedo->add_option("--material,-m", material, "preset name or JSON file")->required();
  albedo->add_option("--theta-deg", theta, "viewing angle from the normal")->required()->check(CLI::Range(0.0, 90.0));
  albedo->add_option("--phi-deg", phi, "azimuth from the tangent")->check(CLI::Range(-360.0, 360.0));
  albedo->add_option("--samples", samples, "importance samples")->check(CLI::Range(int64_t(1), int64_t(1) << 34));
  albedo->add_option("--seed", seed, "random seed");

  std::string metal;
  auto* fresnel = app.add_subcommand("fresnel", "conductor Fresnel reflectance 'r g b' of a measured metal");
  fresnel->add_option("--metal", metal, "metal name (aniso presets lists them)")->required();
  fresnel->add_option("--theta-deg", theta, "angle of incidence")->check(CLI::Range(0.0, 90.0));
  bool schlick = false;
  fresnel->add_flag("--schlick", schlick, "Schlick's approximation from the metal's F0 instead of the exact equations");

  std::string show;
  auto* presets_cmd = app.add_subcommand("presets", "list the named materials");
  presets_cmd->add_option("--show", show, "print one preset's JSON");

  auto* models = app.add_subcommand("models", "list the models and their parameter tables");
  bool markdown = false;
  std::string only_model;
  models->add_flag("--markdown", markdown, "print the tables as markdown (as docs/models/*.md quote them)");
  models->add_option("--model", only_model, "only this model");

  RenderArgs ra;
  auto* render_cmd = app.add_subcommand(
      "render", "render a scene file, the preview scene of a material (--material), or with neither the built-in gallery");
  render_cmd->add_option("scene", ra.scene, "scene file (docs/scenes.md); none: the gallery or the material preview");
  render_cmd->add_option("-o,--output", ra.output,
                         "output image: .png (tone-mapped sRGB), .exr or .pfm (linear radiance); default aniso-gallery.png, "
                         "aniso-preview.png or <scene>.png");
  render_cmd->add_option("--material,-m", ra.material, "render the preview scene with this material (preset, JSON file or inline JSON)");
  render_cmd->add_option("--spp", ra.spp, "samples per pixel (default: the scene's)")->check(CLI::Range(1, 1 << 20));
  render_cmd->add_option("--width", ra.width, "image width in pixels")->check(CLI::Range(16, 16384));
  render_cmd->add_option("--height", ra.height, "image height in pixels")->check(CLI::Range(16, 16384));
  render_cmd->add_option("--threads", ra.threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  render_cmd->add_option("--seed", ra.seed, "random seed (same seed, same image, whatever the thread count)");
  render_cmd->add_option("--strategy", ra.strategy, "mis (default), bsdf or light")->check(CLI::IsMember({"mis", "bsdf", "light"}));
  render_cmd->add_option("--max-depth", ra.max_depth, "path length limit (default: the scene's)")->check(CLI::Range(1, 1024));
  render_cmd->add_option("--exposure", ra.exposure, "exposure in stops for PNG output")->check(CLI::Range(-30.0, 30.0));
  render_cmd->add_option("--tonemap", ra.tonemap, "PNG tone curve: aces (default) or clamp")->check(CLI::IsMember({"aces", "clamp"}));
  render_cmd->add_flag("--print-scene", ra.print_scene, "print the scene document that would be rendered, and exit");

  add_export_commands(app);

  // An unknown command would otherwise be reported by CLI11 as "A subcommand is required".
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names += fmt::format(" {}", sub->get_name());
      known = known || sub->check_name(argv[1]);
    }
    if (!known) {
      fmt::print(stderr, "aniso: error: unknown command \"{}\"; expected one of{}\n", argv[1], names);
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help); every command-line error exits 2, like input errors.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (eval->parsed()) return cmd_eval(material);
    if (sample->parsed()) return cmd_sample(material, wo, count, seed);
    if (albedo->parsed()) return cmd_albedo(material, theta, phi, samples, seed);
    if (fresnel->parsed()) return cmd_fresnel(metal, theta, schlick);
    if (presets_cmd->parsed()) return cmd_presets(show);
    if (models->parsed()) return cmd_models(markdown, only_model);
    if (render_cmd->parsed()) return cmd_render(ra);
  } catch (const InputError& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    return 1;
  }
  return 1;
}
