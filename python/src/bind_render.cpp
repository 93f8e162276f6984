// python/src/bind_render.cpp: aniso.render() and aniso.save_image(): scenes read and rendered by
// src/render as `aniso render` does, images written by its writer (image/image_io.h).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <unistd.h>

#include "aniso/image/image_io.h"
#include "aniso/render/gallery.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "bindings.h"
#include "convert.h"
#include "io/text_escape.h"
#include "io/text_input.h"

namespace aniso::python {

namespace {

std::atomic<bool> g_render_interrupted{false};
extern "C" void on_render_sigint(int) { g_render_interrupted.store(true); }

int int_arg(const std::optional<int>& v, const char* name, int lo, int hi, int fallback) {
  if (!v) return fallback;
  if (*v < lo || *v > hi) throw py::value_error(fmt::format("{}: expected a whole number in [{}, {}], got {}", name, lo, hi, *v));
  return *v;
}

py::array_t<float> render_py(const py::object& scene_in, const py::object& material, std::optional<int> spp,
                             std::optional<int> width, std::optional<int> height, uint64_t seed, int threads,
                             std::optional<int> max_depth, std::optional<std::string> strategy, std::optional<bool> progress) {
  using namespace aniso::render;
  if (!scene_in.is_none() && !material.is_none()) throw py::value_error("give either a scene or material=, not both");
  Scene scene;
  if (!material.is_none()) {
    // The preview scene of `aniso render --material`, with the material as resolved.
    scene = parse_scene(preview_scene(as_material(material).resolved()), "preview scene", "");
  } else if (py::isinstance<py::dict>(scene_in)) {
    scene = parse_scene(from_py(scene_in, "scene dict", ""), "scene dict", "");
  } else if (py::isinstance<py::str>(scene_in) || py::hasattr(scene_in, "__fspath__")) {
    scene = load_scene(py::str(py::module_::import("os").attr("fspath")(scene_in)));
  } else {
    throw py::value_error("render(): expected a scene (a dict or a path to a scene file) or material=");
  }
  scene.film.spp = int_arg(spp, "spp", 1, 1 << 20, scene.film.spp);
  // One of width and height alone keeps the scene's aspect ratio, as `aniso render --width`.
  resize_film(scene.film, int_arg(width, "width", 16, 16384, 0), int_arg(height, "height", 16, 16384, 0));
  scene.integrator.max_depth = int_arg(max_depth, "max_depth", 1, 1024, scene.integrator.max_depth);
  if (strategy) {
    if (*strategy == "mis")
      scene.integrator.strategy = Strategy::Mis;
    else if (*strategy == "bsdf")
      scene.integrator.strategy = Strategy::Bsdf;
    else if (*strategy == "light")
      scene.integrator.strategy = Strategy::Light;
    else
      throw py::value_error(fmt::format("strategy: expected one of \"mis\", \"bsdf\", \"light\", got \"{}\"", *strategy));
  }
  if (threads < 0 || threads > 1024)
    throw py::value_error(fmt::format("threads: expected 0 (all cores) to 1024, got {}", threads));
  RenderOptions ro;
  ro.threads = threads;
  ro.seed = seed;
  // Ctrl-C stops the render at the end of a pass and raises KeyboardInterrupt (Python's own
  // handler cannot run while this thread is in C++); only the main thread may take SIGINT over.
  const bool main_thread =
      py::module_::import("threading").attr("current_thread")().is(py::module_::import("threading").attr("main_thread")());
  // Renders in other threads get a flag of their own that nothing sets (Ctrl-C goes to the main thread).
  std::atomic<bool> never_cancelled{false};
  if (main_thread) g_render_interrupted.store(false);
  ro.cancel = main_thread ? &g_render_interrupted : &never_cancelled;
  const bool show = progress ? *progress : isatty(STDERR_FILENO) != 0;
  const std::string what = scene.source;
  if (show) ro.progress = [&what](double f) { std::fprintf(stderr, "\raniso.render: %s %3.0f%%", what.c_str(), 100.0 * f); };
  struct sigaction old_action {};
  if (main_thread) {
    struct sigaction action {};
    action.sa_handler = on_render_sigint;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_action);
  }
  Image img;
  {
    py::gil_scoped_release release;
    img = aniso::render::render(scene, ro);
  }
  if (main_thread) sigaction(SIGINT, &old_action, nullptr);
  if (show) std::fprintf(stderr, "\r\033[K");
  if (main_thread && g_render_interrupted.load()) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  auto* owned = new std::vector<float>(std::move(img.rgb));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(3)}, owned->data(), free_when_done);
}

// render()'s image (or any (H, W, 3) linear RGB array) to a file, by the CLI's writer
// (image/image_io.h, write_image): .png tone-mapped as `aniso render` does (exposure in stops, the
// aces or clamp curve, sRGB), .exr and .pfm linear as they are; written atomically. exposure and
// tonemap apply to PNG only, as the CLI's --exposure and --tonemap.
void save_image_py(const py::object& img_in, const py::object& path_in, std::optional<double> exposure,
                   std::optional<std::string> tonemap) {
  const py::module_ np = py::module_::import("numpy");
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_in));
  const py::array given = np.attr("asarray")(img_in);
  const char kind = given.dtype().kind();
  if (!((kind == 'f' && given.dtype().itemsize() <= 8) || kind == 'i' || kind == 'u'))
    throw py::value_error(fmt::format("img: expected a (height, width, 3) array of float32 or float64 (linear RGB), got dtype {}",
                                      std::string(py::str(given.dtype()))));
  if (given.ndim() != 3 || given.shape(2) != 3 || given.shape(0) < 1 || given.shape(1) < 1)
    throw py::value_error(fmt::format("img: expected a (height, width, 3) array (linear RGB), got shape {}", shape_text(given)));
  if (given.shape(0) > 65536 || given.shape(1) > 65536)
    throw py::value_error(fmt::format("img: expected at most 65536 x 65536 pixels, got shape {}", shape_text(given)));
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".exr" && ext != ".pfm")
    throw py::value_error(fmt::format("path {}: expected a .png, .exr or .pfm file name", path));
  if ((exposure || tonemap) && ext != ".png")
    throw py::value_error(
        fmt::format("exposure and tonemap apply to PNG output only; {} holds linear radiance, written as given", path));
  render::ToneMapOptions tm;
  if (exposure) {
    if (!(std::isfinite(*exposure) && *exposure >= -30.0 && *exposure <= 30.0))
      throw py::value_error(fmt::format("exposure: expected a finite number of stops in [-30, 30], got {}", *exposure));
    tm.exposure_stops = float(*exposure);
  }
  if (tonemap) {
    if (*tonemap != "aces" && *tonemap != "clamp")
      throw py::value_error(fmt::format("tonemap: expected \"aces\" or \"clamp\", got \"{}\"", *tonemap));
    tm.curve = *tonemap == "clamp" ? render::ToneMap::Clamp : render::ToneMap::Aces;
  }
  const py::array_t<float, py::array::c_style | py::array::forcecast> a = np.attr("ascontiguousarray")(given, "float32");
  render::Image img(int(a.shape(1)), int(a.shape(0)));
  std::copy(a.data(), a.data() + img.rgb.size(), img.rgb.begin());
  for (size_t i = 0; i < img.rgb.size(); ++i)
    if (!std::isfinite(img.rgb[i]))
      throw py::value_error(fmt::format("img[{}, {}, {}]: expected finite radiance, got {}", i / 3 / size_t(img.width),
                                        i / 3 % size_t(img.width), i % 3, img.rgb[i]));
  try {
    py::gil_scoped_release release;
    render::write_image(path, img, tm);
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    PyErr_SetString(PyExc_OSError, terminal_text(e.what()).c_str());
    throw py::error_already_set();
  }
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render", &render_py, py::arg("scene") = py::none(), py::kw_only(), py::arg("material") = py::none(),
        py::arg("spp") = py::none(), py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("seed") = uint64_t(1),
        py::arg("threads") = 0, py::arg("max_depth") = py::none(), py::arg("strategy") = py::none(),
        py::arg("progress") = py::none(),
        "Renders a scene (a dict with the keys of a scene file, or a path: docs/scenes.md) or, with\n"
        "material=, the preview scene of `aniso render --material`. Returns linear RGB radiance,\n"
        "(height, width, 3) float32, row 0 at the top. spp, width, height, max_depth, strategy override\n"
        "the scene's; the same seed gives the same image. Progress on stderr when it is a terminal;\n"
        "Ctrl-C stops it (KeyboardInterrupt).");
  m.def("save_image", &save_image_py, py::arg("img"), py::arg("path"), py::kw_only(), py::arg("exposure") = py::none(),
        py::arg("tonemap") = py::none(),
        "Writes an image such as render()'s ((height, width, 3) linear RGB) as `aniso render -o` does:\n"
        ".png tone-mapped (exposure in stops, tonemap \"aces\" (default) or \"clamp\", sRGB 8-bit), .exr (32-bit\n"
        "float) or .pfm linear as given. Written to a temporary file renamed into place. exposure and\n"
        "tonemap apply to PNG only (ValueError otherwise); a write failure is an OSError.");
}

}  // namespace aniso::python
