// bench/bench_render.cpp: `aniso_bench_render`, the renderer's benchmark (docs/benchmarks.md,
// "Renderer"). A command, not Google Benchmark: each measurement is a render of seconds.
//
//   1. gallery    the default gallery as `aniso render` renders it: time, paths (samples) and rays
//                 per second, and the CPU time (so that a loaded machine shows: CPU / wall / threads).
//   2. ceiling    the same scenes' rays, recorded from the path tracer (4 samples per pixel of every
//                 gallery cell: camera rays, bounces and shadow rays in the renderer's proportions)
//                 and cast again through Embree alone (rtcIntersect1 / rtcOccluded1, no shading) on
//                 all threads, three times before the gallery and three times after it: the rate a
//                 renderer of these scenes cannot exceed on this machine, over the same stretch of
//                 load as the gallery; the renderer's rays per second as a fraction of it.
//   3. strategies the RMSE of mis, bsdf and light sampling at EQUAL TIME on a brushed-metal scene
//                 (examples/studio-map.json, small: brushed gold, aluminium and copper under an
//                 HDR studio map), against a high-spp MIS reference. "Time" is the process's CPU
//                 time (all threads), so that equal time holds on a loaded machine too.
//   5. lights     light selection, one by power vs every light, at equal CPU time: two gallery
//                 cells (three candidates) and 6, 12 and 24 sphere lights over a brushed disc.
//   6. adaptive   film.noise_threshold against uniform spp at equal RMSE: four gallery cells and
//                 the brushed-metal scene, CPU time.
//   7. fireflies  integrator.clamp and integrator.filter_glossy on the gallery torus: RMSE, bias.
//   4. sampler    the RMSE of Owen-scrambled Sobol' vs independent samples at EQUAL SPP (the
//                 gallery's 48) on the brushed-metal scene and on two gallery cells (a glossy
//                 anisotropic sphere, the concentric disc).
//
// RMSE over all pixels and channels of linear radiance. The reference's own noise is removed from
// the squared error: the reference is the mean of two independent halves a, b, whose own variance
// is E|a - b|^2 / 4 per pixel; MSE = mean |x - ref|^2 - mean |a - b|^2 / 4 (an unbiased estimate
// of the MSE against the true image, since x is independent of the reference).
//
// Options: --quick (smaller everything, for a smoke test: ctest aniso_bench_render_quick),
// --threads N, --only SECTION (1 to 7), --images DIR (write the gallery and the strategy
// comparison renders as PNG), --scene FILE (the scene of sections 3 and 4).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "aniso/image/image_io.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"

using namespace aniso;
using namespace aniso::render;
using nlohmann::json;

namespace {

struct Args {
  bool quick = false;
  int threads = 0;
  int only = 0;  // 0: every section; else just that one (1 and 2 go together)
  std::string images, scene = std::string(ANISO_SOURCE_DIR) + "/examples/studio-map.json";
};

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

int thread_count(const Args& a) { return a.threads > 0 ? a.threads : int(std::max(1u, std::thread::hardware_concurrency())); }

// --- 1 and 2: the gallery, and its rays through Embree alone --------------------------------------

struct Ceiling {
  uint64_t rays = 0, shadow_rays = 0;
  double seconds = 0.0, cpu = 0.0;  // of the all-threads replays; cpu: process CPU seconds
  int rounds = 0;                   // replays of every cell's rays
  uint64_t rays_one_thread = 0;     // the first round's, cast again on one thread
  double seconds_one_thread = 0.0;
};

// One gallery cell's recorded rays, with the geometry they are cast against.
struct CellRays {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<SceneGeometry> geo;
  std::vector<RecordedRay> rays;
  uint64_t shadow_rays = 0;
};

// Records the rays of `spp` samples per pixel of one scene.
CellRays record_scene(Scene scene_in, int spp) {
  CellRays c;
  c.scene = std::make_unique<Scene>(std::move(scene_in));
  const Scene& scene = *c.scene;
  c.geo = std::make_unique<SceneGeometry>(scene);
  PathTracer tracer(scene, *c.geo);
  uint64_t count = 0;
  for (int y = 0; y < scene.film.height; ++y)
    for (int x = 0; x < scene.film.width; ++x) {
      const size_t pix = size_t(y) * size_t(scene.film.width) + size_t(x);
      PixelSeeds pixel_seeds(1, pix, scene.integrator.sampler);
      for (int s = 0; s < spp; ++s) {
        Sampler rng(pixel_seeds, uint64_t(s));
        const Vec2 j = rng.uniform2();
        tracer.li(tracer.camera_ray(float(x) + j.x, float(y) + j.y), rng, &count, &c.rays);
      }
    }
  for (const RecordedRay& r : c.rays) c.shadow_rays += r.shadow ? 1 : 0;
  return c;
}

// Casts every cell's rays again through Embree alone, on all threads (then once on one thread for
// the single-thread column, at the first round only).
void replay_cells(const std::vector<CellRays>& cells, int threads, Ceiling* c) {
  tbb::task_arena arena(threads);
  for (const CellRays& cell : cells) {
    const auto& rays = cell.rays;
    const SceneGeometry& geo = *cell.geo;
    std::atomic<uint64_t> hits{0};  // consumed, so that nothing is optimised away
    const auto cast = [&](size_t b, size_t e) {
      uint64_t h = 0;
      for (size_t i = b; i < e; ++i) {
        const RecordedRay& r = rays[i];
        h += r.shadow ? uint64_t(geo.occluded(r.ray, r.tmax)) : uint64_t(geo.closest_distance(r.ray, r.tmax) < INFINITY);
      }
      hits += h;
    };
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 4096),
                        [&](const tbb::blocked_range<size_t>& r) { cast(r.begin(), r.end()); });
    });
    const auto t1 = std::chrono::steady_clock::now();
    c->cpu += cpu_seconds() - c0;
    c->seconds += std::chrono::duration<double>(t1 - t0).count();
    if (c->rounds == 0) {
      cast(0, rays.size());
      c->seconds_one_thread += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      c->rays_one_thread += rays.size();
    }
    c->rays += rays.size();
    c->shadow_rays += cell.shadow_rays;
    if (hits.load() == uint64_t(-1)) std::puts("");  // never: keeps `hits` alive
  }
  ++c->rounds;
}

void bench_gallery(const Args& a) {
  const int threads = thread_count(a);
  GalleryOptions go;
  go.render.threads = threads;
  if (a.quick) go.width = 256, go.spp = 4;

  // The ceiling's rays first: recorded from every cell (at the gallery's cell size), then cast
  // through Embree alone in rounds before and after the gallery, so that the two rates are
  // measured over the same stretch of the machine's load (on a shared machine the load drifts
  // over seconds, and one short replay after the gallery swung the share by several points).
  const int rec_spp = a.quick ? 1 : 4;
  const int rounds_each_side = a.quick ? 1 : 3;
  fmt::print(stderr, "recording the gallery's rays...\n");
  std::vector<CellRays> cells;
  {
    const GalleryLayout layout = gallery_layout(go);
    for (size_t cell = 0; cell < size_t(layout.cells); ++cell) {
      json sj = gallery_cell_scene(cell);
      sj["film"]["width"] = layout.cell_width;
      sj["film"]["height"] = layout.cell_height;
      cells.push_back(record_scene(parse_scene(sj, fmt::format("gallery cell {}", cell), ""), rec_spp));
    }
  }
  Ceiling c;
  fmt::print(stderr, "replaying them ({} rounds)...\n", rounds_each_side);
  for (int r = 0; r < rounds_each_side; ++r) replay_cells(cells, threads, &c);

  fmt::print(stderr, "gallery ({} threads)...\n", threads);
  const double c0 = cpu_seconds();
  const GalleryResult g = render_gallery(go);
  const double cpu = cpu_seconds() - c0;
  const double wall = g.stats.seconds;
  if (!a.images.empty()) write_png((std::filesystem::path(a.images) / "aniso-gallery.png").string(), g.image);
  const int spp = go.spp > 0 ? go.spp : gallery_document().at("common").at("film").at("spp").get<int>();
  fmt::print("## 1. Default gallery\n\n");
  fmt::print(
      "| figure | cells | cell size | spp | threads | wall time | CPU time | CPU / (wall x threads) | paths/s | rays/s | rays "
      "per path |\n");
  fmt::print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  fmt::print("| {}x{} | {} | {}x{} | {} | {} | {:.1f} s | {:.1f} s | {:.2f} | {:.2f} M | {:.2f} M | {:.2f} |\n\n", g.image.width,
             g.image.height, g.cells, g.cell_width, g.cell_height, spp, threads, wall, cpu, cpu / (wall * threads),
             double(g.stats.paths) / wall * 1e-6, double(g.stats.rays) / wall * 1e-6,
             double(g.stats.rays) / double(g.stats.paths));

  fmt::print(stderr, "replaying them again ({} rounds)...\n", rounds_each_side);
  for (int r = 0; r < rounds_each_side; ++r) replay_cells(cells, threads, &c);
  const double renderer_rate = double(g.stats.rays) / wall, raw = double(c.rays) / c.seconds;
  const double renderer_cpu_rate = double(g.stats.rays) / cpu, raw_cpu = double(c.rays) / c.cpu;
  fmt::print("## 2. Ray-cast ceiling (the gallery's rays through Embree alone)\n\n");
  fmt::print(
      "| rays replayed | shadow rays | Embree, {} threads | Embree, 1 thread | renderer, {} threads | renderer / Embree | per "
      "CPU second: Embree | renderer | renderer / Embree |\n",
      threads, threads);
  fmt::print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  fmt::print(
      "| {:.2f} M ({} spp of every cell, {} times) | {:.0f}% | {:.2f} M rays/s | {:.2f} M rays/s | {:.2f} M rays/s | {:.1f}% | "
      "{:.2f} M | "
      "{:.2f} M | {:.1f}% |\n\n",
      double(c.rays / uint64_t(c.rounds)) * 1e-6, rec_spp, c.rounds, 100.0 * double(c.shadow_rays) / double(c.rays), raw * 1e-6,
      double(c.rays_one_thread) / c.seconds_one_thread * 1e-6, renderer_rate * 1e-6, 100.0 * renderer_rate / raw, raw_cpu * 1e-6,
      renderer_cpu_rate * 1e-6, 100.0 * renderer_cpu_rate / raw_cpu);
  // The figure of record (docs/benchmarks.md): rays per CPU second against rays per CPU second, both
  // measured in this run, so that the machine's load cancels out. The wall-clock share above
  // compares two stretches of wall time under whatever load each saw.
  fmt::print("Renderer / Embree, rays per CPU second: **{:.1f}%** ({:.2f} M of {:.2f} M).\n\n",
             100.0 * renderer_cpu_rate / raw_cpu, renderer_cpu_rate * 1e-6, raw_cpu * 1e-6);
}

// --- 3 and 4: noise ------------------------------------------------------------------------------

struct Rendered {
  Image img;
  double seconds = 0.0;  // wall clock
  double cpu = 0.0;      // CPU seconds of the process (all threads): the "time" of equal-time tables
  int spp = 0;
};

Rendered render_with(Scene scene, Strategy strategy, SamplerKind sampler, int spp, uint64_t seed, int threads,
                     LightSelection selection = LightSelection::Auto) {
  scene.integrator.light_selection = selection;
  scene.integrator.strategy = strategy;
  scene.integrator.sampler = sampler;
  RenderOptions o;
  o.threads = threads;
  o.seed = seed;
  o.spp = spp;
  RenderStats st;
  Rendered r;
  const double c0 = cpu_seconds();
  r.img = aniso::render::render(scene, o, &st);
  r.cpu = cpu_seconds() - c0;
  r.seconds = st.seconds;
  r.spp = spp;
  return r;
}

struct Reference {
  Image mean;
  double noise_mse = 0.0;  // the reference's own squared error per value (estimated)
  double mean_value = 0.0;
  double seconds = 0.0;
  int spp = 0;
};

Reference make_reference(const Scene& scene, int spp, int threads) {
  const Rendered a = render_with(scene, Strategy::Mis, SamplerKind::Sobol, spp / 2, 1001, threads);
  const Rendered b = render_with(scene, Strategy::Mis, SamplerKind::Sobol, spp / 2, 2002, threads);
  Reference r;
  r.mean = a.img;
  double d2 = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.img.rgb.size(); ++i) {
    const double d = double(a.img.rgb[i]) - double(b.img.rgb[i]);
    d2 += d * d;
    r.mean.rgb[i] = 0.5f * (a.img.rgb[i] + b.img.rgb[i]);
    sum += r.mean.rgb[i];
  }
  r.noise_mse = d2 / double(a.img.rgb.size()) / 4.0;
  r.mean_value = sum / double(a.img.rgb.size());
  r.seconds = a.cpu + b.cpu;
  r.spp = a.spp + b.spp;
  return r;
}

double rmse(const Image& x, const Reference& ref) {
  double e = 0.0;
  for (size_t i = 0; i < x.rgb.size(); ++i) {
    const double d = double(x.rgb[i]) - double(ref.mean.rgb[i]);
    e += d * d;
  }
  return std::sqrt(std::max(0.0, e / double(x.rgb.size()) - ref.noise_mse));
}

Scene small_scene(const std::string& path, int width) {
  Scene s = load_scene(path);
  s.source = "examples/" + std::filesystem::path(path).filename().string();
  s.film.height = std::max(1, int(std::lround(double(s.film.height) * width / s.film.width)));
  s.film.width = width;
  return s;
}

const char* name_of(Strategy s) { return s == Strategy::Mis ? "mis" : (s == Strategy::Bsdf ? "bsdf" : "light"); }

void bench_strategies(const Args& a, const Scene& scene, const Reference& ref) {
  const int threads = thread_count(a);
  const double budget = a.quick ? 0.2 : 3.0;  // CPU seconds per strategy
  fmt::print("## 3. MIS vs BSDF vs light sampling at equal time ({}, {}x{}, max_depth {})\n\n", scene.source, scene.film.width,
             scene.film.height, scene.integrator.max_depth);
  fmt::print(
      "Reference: MIS, {} spp ({:.1f} CPU s), its own RMS noise {:.2e} (removed from the figures below); mean pixel value "
      "{:.4f}.\n\n",
      ref.spp, ref.seconds, std::sqrt(ref.noise_mse), ref.mean_value);
  fmt::print(
      "| strategy | spp in {:.1f} CPU s | CPU time | RMSE | relative RMSE | MSE x time (lower is better) | efficiency vs mis |\n",
      budget);
  fmt::print("|---|---:|---:|---:|---:|---:|---:|\n");
  double mis_eff = 0.0;
  for (Strategy s : {Strategy::Mis, Strategy::Bsdf, Strategy::Light}) {
    fmt::print(stderr, "strategy {}...\n", name_of(s));
    const int calib_spp = a.quick ? 2 : 8;
    const Rendered calib = render_with(scene, s, SamplerKind::Sobol, calib_spp, 7, threads);
    const int spp = std::max(1, int(std::lround(calib_spp * budget / std::max(calib.cpu, 1e-6))));
    const Rendered r = render_with(scene, s, SamplerKind::Sobol, spp, 77, threads);
    const double e = rmse(r.img, ref), eff = e * e * r.cpu;
    if (s == Strategy::Mis) mis_eff = eff;
    fmt::print("| {} | {} | {:.2f} s | {:.4f} | {:.1f}% | {:.2e} | {:.2f}x |\n", name_of(s), spp, r.cpu, e,
               100.0 * e / ref.mean_value, eff, mis_eff / eff);
    if (!a.images.empty())
      write_png((std::filesystem::path(a.images) / fmt::format("strategy-{}-{}.png", scene.film.width, name_of(s))).string(),
                tonemap(r.img, ToneMapOptions{}));
  }
  if (!a.images.empty())
    write_png((std::filesystem::path(a.images) / fmt::format("strategy-{}-reference.png", scene.film.width)).string(),
              tonemap(ref.mean, ToneMapOptions{}));
  fmt::print("\n");
}

void bench_samplers(const Args& a, const Scene& brushed, const Reference& brushed_ref) {
  const int threads = thread_count(a);
  const int spp = a.quick ? 8 : 48, ref_spp = a.quick ? 128 : 512, cell_px = a.quick ? 48 : 96;
  fmt::print("## 4. Owen-scrambled Sobol' vs independent samples at equal spp ({} spp, MIS)\n\n", spp);
  fmt::print(
      "| scene | size | RMSE, independent | RMSE, Sobol' | MSE ratio (independent / Sobol') | CPU time, independent | CPU time, "
      "Sobol' |\n");
  fmt::print("|---|---|---:|---:|---:|---:|---:|\n");
  const auto row = [&](const std::string& name, const Scene& scene, const Reference& ref) {
    const Rendered ind = render_with(scene, Strategy::Mis, SamplerKind::Independent, spp, 5, threads);
    const Rendered sob = render_with(scene, Strategy::Mis, SamplerKind::Sobol, spp, 5, threads);
    const double ei = rmse(ind.img, ref), es = rmse(sob.img, ref);
    fmt::print("| {} | {}x{} | {:.4f} | {:.4f} | {:.2f} | {:.2f} s | {:.2f} s |\n", name, scene.film.width, scene.film.height, ei,
               es, (ei * ei) / std::max(es * es, 1e-30), ind.cpu, sob.cpu);
  };
  row(brushed.source, brushed, brushed_ref);
  for (const size_t cell : {size_t(1), size_t(8)}) {  // "Ward, anisotropic" and "Disc, concentric tangents"
    json sj = gallery_cell_scene(cell);
    sj["film"]["width"] = cell_px;
    sj["film"]["height"] = cell_px;
    const Scene sc = parse_scene(sj, "gallery cell", "");
    fmt::print(stderr, "sampler comparison: {}...\n", sj.at("name").get<std::string>());
    const Reference ref = make_reference(sc, ref_spp, threads);
    row("gallery: " + sj.at("name").get<std::string>(), sc, ref);
  }
  fmt::print("\n");
}

// Many lights: a brushed disc and a brushed-gold sphere under a ring of n small sphere lights of
// different colours and powers, and a dim sky.
Scene many_lights_scene(int px, int n) {
  json lights = json::array();
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / n;
    const double r = 2.2 + 0.4 * (i % 3);
    lights.push_back({{"type", "sphere"},
                      {"center", {r * std::cos(a), 0.6 + 0.3 * (i % 4), r * std::sin(a)}},
                      {"radius", 0.08},
                      {"radiance", {40.0 + 30.0 * (i % 5), 40.0 + 20.0 * (i % 3), 60.0}}});
  }
  const json sj = {
      {"camera", {{"position", {0, 3.2, 3.2}}, {"look_at", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_deg", 40}}},
      {"film", {{"width", px}, {"height", px}, {"spp", 16}}},
      {"integrator", {{"max_depth", 4}}},
      {"environment", {{"type", "sky"}, {"zenith", 0.05}, {"horizon", 0.08}, {"ground", 0.02}, {"resolution", 64}}},
      {"lights", lights},
      {"objects", json::array({{{"shape", "disc"},
                                {"center", {0, 0, 0}},
                                {"normal", {0, 1, 0}},
                                {"radius", 2.0},
                                {"tangent", {{"field", "concentric"}}},
                                {"material", "brushed-aluminium"}},
                               {{"shape", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "brushed-gold"}}})}};
  return parse_scene(sj, fmt::format("{} sphere lights over a brushed disc", n), "");
}

void bench_light_selection(const Args& a) {
  const int threads = thread_count(a);
  const int px = a.quick ? 32 : 96, ref_spp = a.quick ? 64 : 512;
  const double budget = a.quick ? 0.1 : 1.5;  // CPU seconds
  fmt::print("## 5. Light selection: one light by power vs every light, at equal time (MIS, Sobol')\n\n");
  fmt::print("| scene | candidates | mode | spp in {:.1f} CPU s | RMSE | MSE x CPU time | efficiency vs all |\n", budget);
  fmt::print("|---|---:|---|---:|---:|---:|---:|\n");
  const auto rows = [&](const std::string& name, const Scene& scene) {
    fmt::print(stderr, "light selection: {}...\n", name);
    const Reference ref = make_reference(scene, ref_spp, threads);
    double eff_all = 0.0;
    for (LightSelection sel : {LightSelection::All, LightSelection::Power}) {
      const Rendered calib = render_with(scene, Strategy::Mis, SamplerKind::Sobol, 4, 7, threads, sel);
      const int spp = std::max(1, int(std::lround(4 * budget / std::max(calib.cpu, 1e-6))));
      const Rendered r = render_with(scene, Strategy::Mis, SamplerKind::Sobol, spp, 77, threads, sel);
      const double e = rmse(r.img, ref), eff = e * e * r.cpu;
      if (sel == LightSelection::All) eff_all = eff;
      fmt::print("| {} | {} | {} | {} | {:.4f} | {:.2e} | {:.2f}x |\n", name,
                 scene.lights.size() + (scene.environment.is_black() ? 0 : 1), sel == LightSelection::All ? "all" : "power", spp,
                 e, eff, eff_all / eff);
    }
  };
  for (const size_t cell : {size_t(1), size_t(8)}) {
    json sj = gallery_cell_scene(cell);
    sj["film"]["width"] = px;
    sj["film"]["height"] = px;
    rows("gallery: " + sj.at("name").get<std::string>(), parse_scene(sj, "gallery cell", ""));
  }
  for (int n : {6, 12, 24}) rows(fmt::format("{} sphere lights, brushed disc", n), many_lights_scene(px, n));
  fmt::print("\n");
}

// Adaptive sampling at equal quality, on 64 x 64 gallery cells and the brushed-metal scene at 96
// pixels wide (a 1024-spp reference each): uniform spp at 4 to 128 (the CPU time uniform sampling
// needs for an RMSE: interpolated in log-log between them), and film.noise_threshold at 0.1, 0.05,
// 0.02 with the spp cap at 512: each adaptive render's CPU time against the uniform time for its
// RMSE.
void bench_adaptive(const Args& a) {
  const int threads = thread_count(a);
  fmt::print("## 6. Adaptive sampling at equal RMSE (MIS, Sobol')\n\n");
  fmt::print("| scene | noise threshold | mean spp | RMSE | CPU time | uniform spp CPU time at that RMSE | gain |\n");
  fmt::print("|---|---:|---:|---:|---:|---:|---:|\n");
  const auto rows = [&](const std::string& name, Scene scene) {
    fmt::print(stderr, "adaptive sampling: {}...\n", name);
    const Reference ref = make_reference(scene, a.quick ? 256 : 1024, threads);
    std::vector<double> log_t, log_e;  // the uniform renders, RMSE decreasing
    for (int spp : a.quick ? std::vector<int>{4, 8} : std::vector<int>{4, 8, 16, 32, 64, 128}) {
      const Rendered r = render_with(scene, Strategy::Mis, SamplerKind::Sobol, spp, 77, threads);
      log_t.push_back(std::log(std::max(r.cpu, 1e-6)));
      log_e.push_back(std::log(std::max(rmse(r.img, ref), 1e-30)));
    }
    // CPU time of uniform sampling at RMSE e: linear in log-log between the two renders around it
    // (the end segments extended).
    const auto uniform_time = [&](double e) {
      const double le = std::log(std::max(e, 1e-30));
      size_t i = 0;
      while (i + 2 < log_e.size() && le < log_e[i + 1]) ++i;
      const double f = (le - log_e[i]) / (log_e[i + 1] - log_e[i]);
      return std::exp(log_t[i] + f * (log_t[i + 1] - log_t[i]));
    };
    for (const float t : a.quick ? std::vector<float>{0.1f} : std::vector<float>{0.1f, 0.05f, 0.02f}) {
      Scene sc = scene;
      sc.film.noise_threshold = t;
      sc.film.spp = a.quick ? 64 : 512;
      RenderOptions o;
      o.threads = threads;
      o.seed = 77;
      RenderStats st;
      const double c0 = cpu_seconds();
      const Image img = aniso::render::render(sc, o, &st);
      const double cpu = cpu_seconds() - c0, e = rmse(img, ref), uniform_t = uniform_time(e);
      fmt::print("| {} | {} | {:.1f} | {:.4f} | {:.2f} s | {:.2f} s | {:.2f}x |\n", name, t, st.mean_spp, e, cpu, uniform_t,
                 uniform_t / cpu);
    }
  };
  const int px = a.quick ? 48 : 64;
  for (const size_t cell : {size_t(1), size_t(5), size_t(8), size_t(11)}) {
    json sj = gallery_cell_scene(cell);
    sj["film"]["width"] = px;
    sj["film"]["height"] = px;
    rows("gallery: " + sj.at("name").get<std::string>(), parse_scene(sj, "gallery cell", ""));
  }
  rows(small_scene(a.scene, a.quick ? 64 : 96).source, small_scene(a.scene, a.quick ? 64 : 96));
  fmt::print("\n");
}

// Fireflies: the gallery torus (brushed copper, the key light reflected through two brushed
// bounces) at 48 spp, 64 x 64, with integrator.clamp and integrator.filter_glossy, against the
// unbiased 1024-spp reference: RMSE, bias of the image mean, and the brightest pixel.
void bench_fireflies(const Args& a) {
  const int threads = thread_count(a);
  json sj = gallery_cell_scene(11);
  sj["film"]["width"] = sj["film"]["height"] = a.quick ? 32 : 64;
  const Scene base = parse_scene(sj, "gallery: Torus", "");
  fmt::print(stderr, "fireflies: reference...\n");
  const Reference ref = make_reference(base, a.quick ? 128 : 1024, threads);
  float ref_max = 0.0f;
  for (float v : ref.mean.rgb) ref_max = std::max(ref_max, v);
  fmt::print("## 7. Fireflies: clamp and glossy filter (gallery torus, {}x{}, 48 spp, MIS, Sobol')\n\n", base.film.width,
             base.film.height);
  fmt::print("Reference: 1024 spp, unbiased, mean {:.4f}, brightest value {:.2f}.\n\n", ref.mean_value, ref_max);
  fmt::print("| setting | RMSE | bias of the mean | brightest value | CPU time |\n|---|---:|---:|---:|---:|\n");
  struct Setting {
    const char* name;
    float clamp, filter;
  };
  for (const Setting& st :
       {Setting{"none (default)", 0.0f, 0.0f}, Setting{"clamp 10", 10.0f, 0.0f}, Setting{"clamp 3", 3.0f, 0.0f},
        Setting{"filter_glossy 1", 0.0f, 1.0f}, Setting{"filter_glossy 0.3", 0.0f, 0.3f}}) {
    Scene sc = base;
    sc.integrator.clamp = st.clamp;
    sc.integrator.filter_glossy = st.filter;
    const Rendered r = render_with(sc, Strategy::Mis, SamplerKind::Sobol, a.quick ? 8 : 48, 77, threads);
    double mean = 0.0;
    float mx = 0.0f;
    for (float v : r.img.rgb) mean += v, mx = std::max(mx, v);
    mean /= double(r.img.rgb.size());
    fmt::print("| {} | {:.4f} | {:+.2f}% | {:.2f} | {:.2f} s |\n", st.name, rmse(r.img, ref),
               100.0 * (mean / ref.mean_value - 1.0), mx, r.cpu);
  }
  fmt::print("\n");
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--quick") {
      a.quick = true;
    } else if (s == "--threads" && i + 1 < argc) {
      a.threads = std::atoi(argv[++i]);
    } else if (s == "--only" && i + 1 < argc) {
      a.only = std::atoi(argv[++i]);
    } else if (s == "--images" && i + 1 < argc) {
      a.images = argv[++i];
    } else if (s == "--scene" && i + 1 < argc) {
      a.scene = argv[++i];
    } else {
      std::fprintf(stderr, "usage: aniso_bench_render [--quick] [--threads N] [--only SECTION] [--images DIR] [--scene FILE]\n");
      return 2;
    }
  }
  try {
    if (!a.images.empty()) std::filesystem::create_directories(a.images);
    const auto t0 = std::chrono::steady_clock::now();
    fmt::print("# aniso_bench_render{}\n\n", a.quick ? " --quick" : "");
    const auto want = [&](int section) { return a.only == 0 || a.only == section || (a.only == 1 && section == 2); };
    if (want(1)) bench_gallery(a);
    if (want(3) || want(4)) {
      const Scene brushed = small_scene(a.scene, a.quick ? 64 : 160);
      fmt::print(stderr, "reference for {}...\n", a.scene);
      const Reference ref = make_reference(brushed, a.quick ? 128 : 512, thread_count(a));
      if (want(3)) {
        bench_strategies(a, brushed, ref);
        // And a gallery cell lit by its two sphere lights and the sky: brushed gold.
        json sj = gallery_cell_scene(5);
        sj["film"]["width"] = sj["film"]["height"] = a.quick ? 48 : 128;
        Scene cell = parse_scene(sj, "gallery cell: Brushed gold", "");
        fmt::print(stderr, "reference for the brushed-gold cell...\n");
        bench_strategies(a, cell, make_reference(cell, a.quick ? 128 : 512, thread_count(a)));
      }
      if (want(4)) bench_samplers(a, brushed, ref);
    }
    if (want(5)) bench_light_selection(a);
    if (want(6)) bench_adaptive(a);
    if (want(7)) bench_fireflies(a);
    fmt::print("(benchmark run took {:.0f} s)\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aniso_bench_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
