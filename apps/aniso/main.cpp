// aniso: the command-line tool. Scripting commands (exact formats; other tools and tests depend on
// them, docs/cli.md): eval, sample, albedo, fresnel; and presets, models for discovery.
// Numbers are computed in double precision and printed with 9 significant digits.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>

#include <fcntl.h>
#include <unistd.h>

#include "aniso/batch/batch.h"
#include "aniso/data/metals.h"
#include "aniso/gl/gl_context.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "aniso/measured/measured.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/stats/albedo.h"
#include "aniso/version.h"
#include "commands.h"
#include "gl/scene_raster.h"
#include "io/json_read.h"
#include "io/names.h"
#include "io/text_input.h"
#include "stats/rng.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

std::string num(double x) { return fmt::format("{:.9g}", x + 0.0); }  // + 0.0: never print "-0"

// Every write to stdout goes through here: a short write (a full disk, a closed pipe) is an error
// with a message and exit 1, never a silent exit 0 (docs/cli.md, "Exit codes").
void write_stdout(std::string_view text) {
  if (text.empty()) return;
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size())
    throw std::runtime_error(fmt::format("stdout: write error: {}", std::strerror(errno)));
}
void flush_stdout() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw std::runtime_error(fmt::format("stdout: write error: {}", std::strerror(errno)));
}

// One line of stdin without its newline; false at the end of input. A read error (a directory as
// stdin, a closed descriptor) is an error, not the end of input; lines are capped at 1 MiB (a
// direction pair needs under 200 bytes) so that a line without newline cannot exhaust memory.
// Byte by byte (getc_unlocked, no lock per byte): fgets cannot tell a NUL byte from the end of what
// it read, so a line with a NUL lost its rest and was joined to the next one.
bool read_stdin_line(std::string& line, size_t line_no) {
  constexpr size_t kMaxLine = size_t(1) << 20;
  line.clear();
  int c;
  while ((c = getc_unlocked(stdin)) != EOF) {
    if (c == '\n') return true;
    line.push_back(char(c));
    if (line.size() > kMaxLine) throw InputError(fmt::format("stdin line {}: longer than 1 MiB", line_no));
  }
  if (std::ferror(stdin)) throw InputError(fmt::format("stdin: read error after line {}: {}", line_no - 1, std::strerror(errno)));
  return !line.empty();  // a last line without newline
}

// Reads direction-pair lines (io/text_input.h) and writes 'f_r f_g f_b pdf' per line.
// Piped input: every line is checked before anything is printed, so a bad line leaves no
// half-written output. On a terminal each result is printed as its line is entered (a bad line
// still ends the command with exit 2).
// Piped input is evaluated in blocks of kEvalBlock pairs; a block of kEvalBatchThreshold pairs or
// more goes through the batch path on all cores, with the scalar kernels (batch::Kernels::Scalar),
// so that a line's output never depends on how many lines came with it: the SIMD twins agree to
// ~1e-14 relative in double, which still flips a 9th printed digit now and then (within the first
// 2000 numbers of tests/test_batch.cpp's input). Below it, the plain loop.
// Memory stays bounded whatever the input's length: the output waits in memory up to
// kEvalMemory bytes, beyond that in an unnamed temporary file (EvalSpool), until the input ends.
constexpr size_t kEvalBatchThreshold = 1024, kEvalBlock = size_t(1) << 16, kEvalMemory = size_t(16) << 20;

// The output of piped `aniso eval` while the input is still being checked: in memory, then, past
// kEvalMemory bytes, in a temporary file in $TMPDIR (or /tmp), unlinked at once so that nothing is
// left behind whatever ends the program. A temporary file rather than streaming: a bad line must
// leave stdout empty (docs/cli.md, "Output streams").
class EvalSpool {
 public:
  ~EvalSpool() {
    if (file_) std::fclose(file_);
  }
  void add(std::string& text) {
    if (!file_ && text.size() <= kEvalMemory) return;
    if (!file_) open();
    if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
      throw std::runtime_error(fmt::format("eval: temporary file in {}: write error: {}", dir_, std::strerror(errno)));
    text.clear();
  }
  // Everything to stdout: the temporary file's contents, then `rest`.
  void finish(const std::string& rest) {
    if (file_) {
      if (std::fflush(file_) != 0 || std::fseek(file_, 0, SEEK_SET) != 0)
        throw std::runtime_error(fmt::format("eval: temporary file in {}: write error: {}", dir_, std::strerror(errno)));
      std::vector<char> buf(size_t(1) << 20);
      size_t n;
      while ((n = std::fread(buf.data(), 1, buf.size(), file_)) > 0) write_stdout(std::string_view(buf.data(), n));
      if (std::ferror(file_))
        throw std::runtime_error(fmt::format("eval: temporary file in {}: read error: {}", dir_, std::strerror(errno)));
    }
    write_stdout(rest);
  }

 private:
  void open() {
    std::error_code ec;
    dir_ = std::filesystem::temp_directory_path(ec).string();
    if (ec) dir_ = "/tmp";
    std::string name = (std::filesystem::path(dir_) / "aniso-eval-XXXXXX").string();
    const int fd = mkstemp(name.data());
    if (fd < 0)
      throw std::runtime_error(fmt::format("eval: cannot create a temporary file in {}: {}", dir_, std::strerror(errno)));
    unlink(name.c_str());
    file_ = fdopen(fd, "w+b");
    if (!file_) {
      close(fd);
      throw std::runtime_error(fmt::format("eval: cannot open a temporary file in {}: {}", dir_, std::strerror(errno)));
    }
  }
  std::FILE* file_ = nullptr;
  std::string dir_;
};

// Appends the results of one block of piped pairs to `out`.
void eval_block(const Mat& m, const std::vector<Vec3d>& wis, const std::vector<Vec3d>& wos, std::string& out) {
  const size_t n = wis.size();
  std::vector<RGBT<double>> f(n);
  std::vector<double> pdf(n);
  if (n >= kEvalBatchThreshold) {
    batch::DirectionArray<double> bwi(n), bwo(n);
    for (size_t i = 0; i < n; ++i) bwi.set(i, wis[i]), bwo.set(i, wos[i]);
    batch::ColorArray<double> bf(n);
    batch::evaluate(m, bwi.view(), bwo.view(), n, bf.view(), batch::Threads::All, batch::Kernels::Scalar);
    batch::pdf(m, bwi.view(), bwo.view(), n, pdf.data(), batch::Threads::All, batch::Kernels::Scalar);
    for (size_t i = 0; i < n; ++i) f[i] = bf.get(i);
  } else {
    for (size_t i = 0; i < n; ++i) f[i] = m.f(wis[i], wos[i]), pdf[i] = m.pdf(wis[i], wos[i]);
  }
  for (size_t i = 0; i < n; ++i) out += fmt::format("{} {} {} {}\n", num(f[i].x), num(f[i].y), num(f[i].z), num(pdf[i]));
}

int cmd_eval(const std::string& material, bool angles) {
  const Mat m = build_material<double>(load_material(material));
  const bool interactive = isatty(STDIN_FILENO) != 0;
  std::string out, line;
  size_t line_no = 0;
  std::vector<Vec3d> wis, wos;
  EvalSpool spool;
  while (read_stdin_line(line, ++line_no)) {
    if (is_blank_or_comment(line)) continue;
    const DirectionPair d = parse_direction_line(line, line_no, angles);
    if (!interactive) {  // evaluated by blocks, printed at the end
      wis.push_back(d.wi);
      wos.push_back(d.wo);
      if (wis.size() == kEvalBlock) {
        eval_block(m, wis, wos, out);
        spool.add(out);
        wis.clear();
        wos.clear();
      }
      continue;
    }
    const RGBT<double> f = m.f(d.wi, d.wo);
    out += fmt::format("{} {} {} {}\n", num(f.x), num(f.y), num(f.z), num(m.pdf(d.wi, d.wo)));
    write_stdout(out);
    flush_stdout();
    out.clear();
  }
  eval_block(m, wis, wos, out);
  spool.finish(out);
  return 0;
}

// Streams N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf' in 1 MiB blocks (bounded memory).
int cmd_sample(const std::string& material, const std::vector<double>& wo_in, uint64_t count, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  const auto wo = normalized_direction(Vec3d(wo_in[0], wo_in[1], wo_in[2]));
  if (!wo) throw InputError("--wo: expected a non-zero direction, got (0, 0, 0)");
  Rng rng(seed);
  std::string out;
  for (uint64_t i = 0; i < count; ++i) {
    const double uc = rng.uniform();
    const Vec2T<double> u(rng.uniform(), rng.uniform());
    const BSDFSampleT<double> s = m.sample(*wo, uc, u);
    if (!s.valid) {
      out += "0 0 0 0 0 0 0\n";
    } else {
      out += fmt::format("{} {} {} {} {} {} {}\n", num(s.wi.x), num(s.wi.y), num(s.wi.z), num(s.weight.x), num(s.weight.y),
                         num(s.weight.z), num(s.pdf));
    }
    if (out.size() > (size_t(1) << 20)) {
      write_stdout(out);
      out.clear();
    }
  }
  write_stdout(out);
  return 0;
}

int cmd_albedo(const std::string& material, double theta, double phi, uint64_t samples, uint64_t seed) {
  const Mat m = build_material<double>(load_material(material));
  // theta = 90 is on the horizon (cos rounds to 6e-17 < the double horizon cosine 1e-12): albedo 0
  // (docs/conventions.md, "The horizon").
  const AlbedoEstimate a = albedo_importance(m, direction_from_degrees(theta, phi), int64_t(samples), seed);
  write_stdout(fmt::format("{} {} {}\n", num(a.mean.x), num(a.mean.y), num(a.mean.z)));
  return 0;
}

struct FresnelArgs {
  std::string metal;
  std::vector<double> eta, k;
  double theta = 0.0;
  bool schlick = false;
};

int cmd_fresnel(const FresnelArgs& a) {
  RGBT<double> eta, k;
  if (!a.metal.empty()) {
    if (!a.eta.empty() || !a.k.empty()) throw InputError("give either --metal or --eta and --k, not both");
    const MetalData* md = find_metal(a.metal);
    if (!md) throw InputError(fmt::format("--metal: {}", unknown_metal_message(a.metal)));
    eta = md->eta;
    k = md->k;
  } else {
    if (a.eta.empty() || a.k.empty())
      throw InputError(fmt::format("give --metal NAME (one of {}) or both --eta R G B and --k R G B", metal_names()));
    for (int c = 0; c < 3; ++c) {
      if (!(a.eta[c] > 0.0 && a.eta[c] <= 100.0))
        throw InputError(fmt::format("--eta: channel {}: expected a number in (0, 100], got {}", c, a.eta[c]));
      if (!(a.k[c] >= 0.0 && a.k[c] <= 100.0))
        throw InputError(fmt::format("--k: channel {}: expected a number in [0, 100], got {}", c, a.k[c]));
      eta[c] = a.eta[c];
      k[c] = a.k[c];
    }
  }
  const double c = std::cos(a.theta * M_PI / 180.0);
  // --schlick: Schlick's approximation with the exact F0 of the same metal, for comparison.
  const RGBT<double> F = a.schlick ? F_Schlick(F_Conductor(1.0, eta, k), c) : F_Conductor(c, eta, k);
  write_stdout(fmt::format("{} {} {}\n", num(F.x), num(F.y), num(F.z)));
  return 0;
}

int cmd_metals() {
  std::string out =
      fmt::format("{:<10} {:<4} {:<32} {:<32} {:<32} {}\n", "# name", "sym", "eta (r g b)", "k (r g b)", "F0 (r g b)", "source");
  for (const MetalData& md : metal_table()) {
    const RGBT<double> f0 = F_Conductor(1.0, RGBT<double>(md.eta), RGBT<double>(md.k));
    const auto rgb = [](const glm::dvec3& v) { return fmt::format("{:.4f} {:.4f} {:.4f}", v.x, v.y, v.z); };
    out += fmt::format("{:<10} {:<4} {:<32} {:<32} {:<32} {}\n", md.name, md.symbol, rgb(md.eta), rgb(md.k), rgb(f0), md.source);
  }
  write_stdout(out);
  return 0;
}

int cmd_presets(const std::string& show, bool show_given) {
  if (show_given) {
    if (show.empty()) throw InputError("--show: expected a preset name, got an empty string (run `aniso presets` for the list)");
    if (is_measured_file_name(show)) {
      // A MERL file: the material it stands for on stdout, what it is on stderr (recognised by its
      // sha256 among the MERL database's files, docs/measured.md).
      const MaterialDesc d = load_material(show);
      fmt::print(stderr, "aniso: {}\n", describe_measured(*d.measured));
      write_stdout(fmt::format("{}\n", resolved_json(d).dump(2)));
      return 0;
    }
    if (rgl::is_rgl_file_name(show)) {
      // An RGL tensor file: its fields, grids, isotropy and description (docs/rgl.md).
      write_stdout(rgl::describe_rgl(*rgl::load_rgl(show)));
      return 0;
    }
    if (!find_preset(show)) {
      const std::string near = nearest_preset_names(show);
      throw InputError(fmt::format("--show: unknown preset \"{}\"{} (run `aniso presets` for the list)", text_escape(show),
                                   near.empty() ? "" : fmt::format("; did you mean {}?", near)));
    }
    // The material as resolved: every key, defaults filled in; valid input as it stands.
    write_stdout(fmt::format("{}\n", resolved_json(load_material(show)).dump(2)));
    return 0;
  }
  std::string out;
  for (const PresetInfo& p : presets()) out += fmt::format("{:<40} {}\n", p.name, p.source);
  write_stdout(out);
  return 0;
}

int cmd_models(bool markdown, const std::string& only, bool only_given) {
  if (only_given && !find_model_spec(only)) {
    std::string names;
    std::vector<std::string> all;
    for (const ModelSpec* m : model_specs()) {
      names += fmt::format(" {}", m->name);
      all.emplace_back(m->name);
    }
    const std::string near = nearest_names(only, all);
    throw InputError(fmt::format("--model: unknown model \"{}\"{}; expected one of{}", text_escape(only),
                                 near.empty() ? "" : fmt::format(" (did you mean {}?)", near), names));
  }
  std::string out;
  if (markdown) {
    for (const ModelSpec* m : model_specs())
      if (!only_given || m->name == only) out += fmt::format("{}\n", markdown_table(*m));
    write_stdout(out);
    return 0;
  }
  // Nested tables (Lafortune lobes, metal lobes, the directional-diffuse lobe) follow their key,
  // indented, as in the markdown tables.
  const auto key = [&out](const ParamSpec& p, int depth) {
    out +=
        fmt::format("{:{}}  {:<20} {:<45} default {:<12} {}\n", "", 4 * depth, p.name, describe_range(p), default_text(p), p.doc);
  };
  const auto nested = [&out](const ParamSpec& p, const ModelSpec& sub, int depth) {
    out += fmt::format("{:{}}    keys of {} ({}):\n", "", 4 * depth,
                       p.kind == ParamKind::TaggedObject ? fmt::format("\"{}\": {{\"model\": \"{}\"}}", p.name, sub.name)
                                                         : fmt::format("\"{}\"", p.name),
                       sub.title);
  };
  for (const ModelSpec* m : model_specs()) {
    if (only_given && m->name != only) continue;
    out += fmt::format("{} ({}) -- {}\n", m->name, m->title, m->citation);
    walk_params(*m, key, nested);
  }
  write_stdout(out);
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
}  // namespace aniso

// A numeric option's range check that also rejects NaN (CLI11's Range lets NaN through: every
// comparison with NaN is false) and says what the option means by its range.
CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        std::string why;
        const auto v = aniso::parse_decimal(text, &why);
        if (!v) return fmt::format("expected a finite decimal number in [{}, {}], got \"{}\" ({})", lo, hi, text, why);
        if (*v < lo || *v > hi) return fmt::format("{} is not in [{}, {}]", text, lo, hi);
        return {};
      },
      fmt::format("FLOAT in [{}, {}]", lo, hi));
}

// A whole-number option, decimal only (CLI11 would read "010" as octal 8, and wrap "-1" for an
// unsigned seed): checked by io/text_input.h's rule, then handed to CLI11 in canonical form.
CLI::Validator whole_range(int64_t lo, int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        try {
          text = std::to_string(aniso::parse_integer(text, lo, hi, "value"));
        } catch (const aniso::InputError& e) {
          return std::string(e.what()).substr(7);  // drop "value: "
        }
        return {};
      },
      fmt::format("INT in [{}, {}]", lo, hi));
}
// A number option's value, decimal only (CLI11 itself would read "0x1", "nan" and "inf"), range
// checked by the command.
CLI::Validator decimal_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string why;
        if (!aniso::parse_decimal(text, &why)) return fmt::format("expected a finite decimal number, got \"{}\" ({})", text, why);
        return {};
      },
      "FLOAT");
}
CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          text = std::to_string(aniso::parse_unsigned(text, UINT64_MAX, "value"));
        } catch (const aniso::InputError& e) {
          return std::string(e.what()).substr(7);
        }
        return {};
      },
      "UINT64");
}

namespace aniso {
namespace {

// Whether everything written to stdout reached it (closed stdout, a full disk, a closed pipe):
// "" or the message. Help and version text goes through CLI11's std::cout, which shares stdio's
// buffer (sync_with_stdio), so one flush checks both.
std::string stdout_error() {
  errno = 0;
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.good();
  if (!failed) return {};
  // A write that failed before (std::endl's flush of a closed stdout) left no errno: ask the
  // descriptor itself (fcntl sets EBADF for a closed one).
  if (errno == 0) (void)fcntl(STDOUT_FILENO, F_GETFD);
  return fmt::format("stdout: write error: {}", errno ? std::strerror(errno) : "output failed");
}

// The names a command's options are typed with ("--material", "-m").
std::vector<std::string> option_names(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::Option* o : cmd.get_options()) {
    for (const std::string& l : o->get_lnames()) out.push_back("--" + l);
    for (const std::string& c : o->get_snames()) out.push_back("-" + c);
  }
  return out;
}

// A mistyped option would otherwise be reported by CLI11 as a missing required one ("--material is
// required" for --materail) or as an unexpected argument. The first argument from argv[first] on
// that looks like an option ("--word", "-x") and that `cmd` does not know, named with the nearest
// spellings; "" when there is none. Values such as "-1" or "-0.5" are not options.
std::string unknown_option_message(const CLI::App& cmd, const std::string& command, int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    const std::string_view t = argv[i];
    if (t == "--") break;
    const bool long_form = t.size() > 2 && t.substr(0, 2) == "--";
    const bool short_form = t.size() == 2 && t[0] == '-' && std::isalpha(static_cast<unsigned char>(t[1]));
    if (!long_form && !short_form) continue;
    const std::string name(t.substr(0, t.find('=')));
    if (cmd.get_option_no_throw(name)) continue;
    std::string near = nearest_names(name, option_names(cmd));
    near.erase(std::remove(near.begin(), near.end(), '"'), near.end());
    return fmt::format("unknown option {}{}{} (`{} --help` lists the options)", text_escape(name),
                       command.empty() ? "" : " for " + command, near.empty() ? "" : fmt::format("; did you mean {}?", near),
                       command.empty() ? "aniso" : command);
  }
  return {};
}

// The commands and what they do, for `aniso` alone and an unknown command.
std::string command_list(const CLI::App& app) {
  std::string out = "usage: aniso COMMAND [OPTIONS] (aniso COMMAND --help for its options)\ncommands:\n";
  for (const CLI::App* sub : app.get_subcommands({}))
    out += fmt::format("  {:<13} {}\n", sub->get_name(), sub->get_description());
  return out;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) {
  using namespace aniso;
  // A closed pipe (`aniso sample ... | head`) is a write error with a message and exit 1
  // (docs/cli.md, "Exit status"), not death by SIGPIPE: every write to stdout is checked.
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App app{"aniso: anisotropic and measured reflectance (models, sampling, metals, rendering)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("aniso ") + ANISO_VERSION);
  // --help shows the defaults that are values (capture_default_str); the others ("the scene's",
  // "all cores") are said in the option's text.

  // Largest counts: 1e9 sample lines is ~60 GB of text (minutes); 1e9 albedo samples ~1 minute.
  constexpr uint64_t kMaxCount = 1'000'000'000, kMaxSamples = 1'000'000'000;

  std::string material;
  bool angles = false;
  auto* eval = app.add_subcommand("eval", "read 'wi.x wi.y wi.z wo.x wo.y wo.z' lines on stdin, write 'f_r f_g f_b pdf'");
  eval->add_option("--material,-m", material, "preset name, JSON file, MERL .binary file or inline JSON object")->required();
  eval->add_flag("--angles", angles,
                 "input lines are 'theta_i phi_i theta_o phi_o' in degrees (theta from the normal, phi from the tangent)");

  std::vector<double> wo;
  std::string count_text = "1", seed_text = "1", samples_text = "1048576";
  auto* sample = app.add_subcommand("sample", "write N lines 'wi.x wi.y wi.z weight_r weight_g weight_b pdf'");
  sample->add_option("--material,-m", material, "preset name, JSON file, MERL .binary file or inline JSON object")->required();
  sample->add_option("--wo", wo, "viewing direction x y z (local frame; normalised)")
      ->required()
      ->expected(3)
      ->check(decimal_value());
  // --samples counts the same thing as albedo's --samples (draws of sample()); --count is kept.
  sample
      ->add_option("--count,-n,--samples", count_text,
                   fmt::format("number of samples (draws of sample(): output lines), 0 to {}", kMaxCount))
      ->type_name("INT")
      ->capture_default_str();
  sample->add_option("--seed", seed_text, "random seed, 0 to 2^64-1")->type_name("UINT64")->capture_default_str();

  double theta = 0.0, phi = 0.0;
  auto* albedo = app.add_subcommand("albedo", "directional albedo 'r g b' for the viewing direction (theta, phi)");
  albedo->add_option("--material,-m", material, "preset name, JSON file, MERL .binary file or inline JSON object")->required();
  albedo->add_option("--theta-deg", theta, "viewing angle from the normal; 90 is the horizon (albedo 0)")
      ->required()
      ->check(finite_range(0.0, 90.0));
  albedo->add_option("--phi-deg", phi, "azimuth from the tangent")->check(finite_range(-360.0, 360.0))->capture_default_str();
  albedo->add_option("--samples", samples_text, fmt::format("importance samples, 1 to {}", kMaxSamples))
      ->type_name("INT")
      ->capture_default_str();
  albedo->add_option("--seed", seed_text, "random seed, 0 to 2^64-1")->type_name("UINT64")->capture_default_str();

  FresnelArgs fa;
  auto* fresnel = app.add_subcommand("fresnel", "conductor Fresnel reflectance 'r g b' of a measured metal or of a given eta, k");
  fresnel->add_option("--metal", fa.metal, "metal name (`aniso metals` lists them)");
  fresnel->add_option("--eta", fa.eta, "real part of the complex index, R G B, each in (0, 100]")
      ->expected(3)
      ->check(decimal_value());
  fresnel->add_option("--k", fa.k, "extinction coefficient, R G B, each in [0, 100]")->expected(3)->check(decimal_value());
  fresnel->add_option("--theta-deg", fa.theta, "angle of incidence")->check(finite_range(0.0, 90.0))->capture_default_str();
  fresnel->add_flag("--schlick", fa.schlick, "Schlick's approximation from the metal's F0 instead of the exact equations");

  auto* metals_cmd = app.add_subcommand("metals", "list the measured metals: RGB eta, k, F0 and the data source");

  std::string show;
  auto* presets_cmd = app.add_subcommand("presets", "list the named materials");
  auto* show_opt = presets_cmd->add_option(
      "--show", show,
      "print one preset as resolved (every key, defaults filled in); for a .binary file, also name the MERL material it is");

  auto* models = app.add_subcommand("models", "list the models and their parameter tables");
  bool markdown = false;
  std::string only_model;
  models->add_flag("--markdown", markdown, "print the tables as markdown (as docs/models/*.md quote them)");
  auto* model_opt = models->add_option("--model", only_model, "only this model");

  RenderArgs ra;
  auto* render_cmd = app.add_subcommand(
      "render", "render a scene file, the preview scene of a material (--material), or with neither the built-in gallery");
  render_cmd->add_option("scene", ra.scene, "scene file (docs/scenes.md); none: the gallery or the material preview");
  render_cmd->add_option("-o,--output", ra.output,
                         "output image: .png (tone-mapped sRGB), .exr or .pfm (linear radiance); default aniso-gallery.png, "
                         "aniso-preview.png or <scene>.png");
  render_cmd->add_option("--material,-m", ra.material,
                         "render the preview scene with this material (preset, JSON file or inline JSON)");
  render_cmd->add_option("--spp", ra.spp, "samples per pixel (default: the scene's; the gallery's 64)")
      ->transform(whole_range(1, 1 << 20));
  render_cmd
      ->add_option("--width", ra.width,
                   "image width in pixels (default: the scene's; alone, the height follows the scene's aspect ratio)")
      ->transform(whole_range(16, 16384));
  render_cmd->add_option("--height", ra.height, "image height in pixels (default: the scene's; alone, the width follows)")
      ->transform(whole_range(16, 16384));
  render_cmd->add_option("--threads", ra.threads, "worker threads (default: all cores)")->transform(whole_range(1, 1024));
  render_cmd->add_option("--seed", ra.seed, "random seed (same seed, same image, whatever the thread count)")
      ->transform(seed_value())
      ->capture_default_str();
  render_cmd->add_option("--strategy", ra.strategy, "mis (default), bsdf or light")
      ->check(CLI::IsMember({"mis", "bsdf", "light"}));
  render_cmd->add_option("--sampler", ra.sampler, "sobol (default: Owen-scrambled Sobol') or independent (PCG32)")
      ->check(CLI::IsMember({"sobol", "independent"}));
  render_cmd
      ->add_option("--noise-threshold", ra.noise_threshold,
                   "adaptive sampling: stop pixels whose estimated error is below this (docs/scenes.md; default: the scene's "
                   "film.noise_threshold, 0 = off)")
      ->check(finite_range(0.0, 1.0));
  render_cmd->add_option("--min-spp", ra.min_spp, "adaptive sampling: samples before a pixel may stop (default: automatic)")
      ->transform(whole_range(1, 1 << 20));
  render_cmd->add_option("--time", ra.time_s, "time budget in seconds: passes until it ends (with --spp as a cap)")
      ->check(finite_range(0.001, 1e6));
  render_cmd->add_option("--max-depth", ra.max_depth, "path length limit (default: the scene's)")
      ->transform(whole_range(1, 1024));
  auto* exposure_opt = render_cmd->add_option("--exposure", ra.exposure, "exposure in stops (PNG output only)")
                           ->check(finite_range(-30.0, 30.0))
                           ->capture_default_str();
  auto* tonemap_opt = render_cmd->add_option("--tonemap", ra.tonemap, "PNG tone curve: aces (default) or clamp (PNG output only)")
                          ->check(CLI::IsMember({"aces", "clamp"}));
  render_cmd
      ->add_option("--backend", ra.backend,
                   "cpu (default: the path tracer) or gl (direct light of point and directional lights through OpenGL, "
                   "headless; docs/scenes.md, \"GL backend\")")
      ->check(CLI::IsMember({"cpu", "gl"}));
  render_cmd->add_flag("--print-scene", ra.print_scene, "print the scene document that would be rendered, and exit");

  add_export_commands(app);
  add_export_target_command(app);
  add_rgl_command(app);
  add_fit_command(app);
  add_fit_db_command(app);
  add_view_command(app);
  add_web_commands(app);

  // `aniso` alone: the commands. An unknown command would otherwise be reported by CLI11 as "A
  // subcommand is required", an unknown option as a missing one.
  if (argc == 1) {
    fmt::print(stderr, "aniso: error: no command given\n{}", command_list(app));
    return 2;
  }
  if (std::string_view(argv[1]) == "fit-db") return run_fit_db(argc, argv);
  if (argv[1][0] != '-') {
    std::vector<std::string> names;
    const CLI::App* cmd = nullptr;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names.push_back(sub->get_name());
      if (sub->check_name(argv[1])) cmd = sub;
    }
    if (!cmd) {
      std::string near = nearest_names(argv[1], names);
      near.erase(std::remove(near.begin(), near.end(), '"'), near.end());
      fmt::print(stderr, "aniso: error: unknown command \"{}\"{}\n{}", text_escape(argv[1]),
                 near.empty() ? "" : fmt::format("; did you mean {}?", near), command_list(app));
      return 2;
    }
    // A command that takes any arguments (the render-only build's fit and export: cmd_render_only.cpp)
    // answers for itself.
    if (const std::string msg = cmd->get_allow_extras()
                                    ? std::string()
                                    : unknown_option_message(*cmd, fmt::format("aniso {}", cmd->get_name()), argc, argv, 2);
        !msg.empty()) {
      fmt::print(stderr, "aniso: error: {}\n", msg);
      return 2;
    }
  } else if (const std::string msg = unknown_option_message(app, "", argc, argv, 1); !msg.empty()) {
    fmt::print(stderr, "aniso: error: {}\n", msg);
    return 2;
  }
  // The exit status once stdout is known to hold everything written to it (exit 1 otherwise,
  // unless the command already failed with 2).
  const auto finish = [](int rc) {
    const std::string err = stdout_error();
    if (err.empty()) return rc;
    fmt::print(stderr, "aniso: error: {}\n", err);
    return rc == 0 ? 1 : rc;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    // A command run inside CLI11's callback (export-glsl, export-brdf: cmd_export.cpp) has printed
    // its message and chosen the exit status itself: 2 for bad input, 1 for a write error. A failed
    // one is not checked again: its own message may already be stdout's write error (export-glsl
    // without -o > /dev/full), and one error is one line (docs/cli.md, "Exit status").
    return e.get_exit_code() == 0 ? finish(0) : e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help); every command-line error exits 2, like input errors.
    const int code = app.exit(e);
    return finish(code == 0 ? 0 : 2);
  }
  ra.tone_given = exposure_opt->count() > 0 || tonemap_opt->count() > 0;
  try {
    int rc = 1;
    if (eval->parsed())
      rc = cmd_eval(material, angles);
    else if (sample->parsed())
      rc = cmd_sample(material, wo, parse_unsigned(count_text, kMaxCount, "--count"),
                      parse_unsigned(seed_text, UINT64_MAX, "--seed"));
    else if (albedo->parsed()) {
      const uint64_t n = parse_unsigned(samples_text, kMaxSamples, "--samples");
      if (n == 0) throw InputError(fmt::format("--samples: expected a whole number in [1, {}], got 0", kMaxSamples));
      rc = cmd_albedo(material, theta, phi, n, parse_unsigned(seed_text, UINT64_MAX, "--seed"));
    } else if (fresnel->parsed())
      rc = cmd_fresnel(fa);
    else if (metals_cmd->parsed())
      rc = cmd_metals();
    else if (presets_cmd->parsed())
      rc = cmd_presets(show, show_opt->count() > 0);
    else if (models->parsed())
      rc = cmd_models(markdown, only_model, model_opt->count() > 0);
    else if (render_cmd->parsed())
      rc = cmd_render(ra);
    flush_stdout();
    return finish(rc);
  } catch (const InputError& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "aniso: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    return 1;
  }
}
