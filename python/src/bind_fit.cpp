// python/src/bind_fit.cpp: aniso.fit(), aniso.FitResult and aniso.read_measured(): fits run by
// src/fit as `aniso fit` runs them, on a data file or the caller's arrays.
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <unistd.h>

#include "aniso/fit/fit.h"
#include "aniso/measured/samples.h"
#include "bindings.h"
#include "convert.h"
#include "io/enum_names.h"
#include "io/text_input.h"

namespace aniso::python {

namespace {

// Samples from the caller's arrays: wi, wo (N, 3) unit directions above the horizon (one of them
// may be (3,), used for every row), value (N, 3) the BRDF in 1/sr, weight (N,) or None. Checked as
// the CSV reader checks its rows (measured/samples.cpp), each message naming the argument and row.
SampleSet samples_from_arrays(const py::object& wi_in, const py::object& wo_in, const py::object& value_in,
                              const py::object& weight_in) {
  if (wi_in.is_none() || wo_in.is_none() || value_in.is_none())
    throw py::value_error(
        "fit(): expected data (a path to a .binary, .brdf, .bsdf or .csv file) or all of the arrays wi=, wo= "
        "and value= (and optionally weight=)");
  const RowsView wi = rows_view(wi_in, "wi"), wo = rows_view(wo_in, "wo"), value = rows_view(value_in, "value");
  const size_t n = common_rows({{"wi", &wi}, {"wo", &wo}, {"value", &value}});
  std::vector<double> weight;
  if (!weight_in.is_none()) {
    const py::module_ np = py::module_::import("numpy");
    py::array_t<double, py::array::c_style | py::array::forcecast> w;
    try {
      w = np.attr("asarray")(weight_in, "float64");
    } catch (py::error_already_set& e) {
      throw py::value_error(fmt::format("weight: expected an array of shape (N,) of numbers > 0 ({})", e.what()));
    }
    if (w.ndim() != 1 || size_t(w.shape(0)) != n)
      throw py::value_error(
          fmt::format("weight: expected an array of shape ({},) (the rows of wi, wo and value), got shape {}", n, shape_text(w)));
    weight.assign(w.data(), w.data() + n);
  }
  SampleSet set;
  set.source = "arrays";
  set.format = "arrays";
  set.samples.resize(n);
  // A unit direction: length 1 within 1e-5 (a float32 unit vector is within 1e-7; the fit takes z as
  // cos(theta) and does not normalise), strictly above the horizon (z > 0) as the CSV's theta < 90 deg.
  const auto direction = [](const RowsView& v, const char* name, size_t i) {
    const Vec3d w(v.at<double>(i, 0), v.at<double>(i, 1), v.at<double>(i, 2));
    if (!(std::abs(glm::length(w) - 1.0) <= 1e-5 && w.z > 0.0))
      throw py::value_error(
          fmt::format("{}: row {}: expected a unit direction above the horizon (length 1 within 1e-5, z > 0), "
                      "got ({}, {}, {})",
                      name, v.single ? 0 : i, w.x, w.y, w.z));
    return w;
  };
  for (size_t i = 0; i < n; ++i) {
    MeasuredSample& s = set.samples[i];
    s.wi = direction(wi, "wi", i);
    s.wo = direction(wo, "wo", i);
    for (int c = 0; c < 3; ++c) s.value[c] = value.at<double>(i, c);
    if (!(std::isfinite(s.value.x) && std::isfinite(s.value.y) && std::isfinite(s.value.z)) ||
        !(s.value.x >= 0.0 && s.value.y >= 0.0 && s.value.z >= 0.0))
      throw py::value_error(fmt::format("value: row {}: expected finite BRDF values >= 0 (1/sr), got ({}, {}, {})",
                                        value.single ? 0 : i, s.value.x, s.value.y, s.value.z));
    s.value += 0.0;  // -0 as 0, as the CSV reader
    if (!weight.empty()) {
      s.weight = weight[i];
      if (!(std::isfinite(s.weight) && s.weight > 0.0))
        throw py::value_error(fmt::format("weight: row {}: expected a finite number > 0, got {}", i, s.weight));
    }
  }
  return set;
}

// A measured data file as arrays (aniso.read_measured): what `aniso fit DATA` fits.
// grid= as `aniso fit --grid`: None, or an even number in [4, 256] for a .bsdf file (check_rgl_fit_grid).
int rgl_grid_of(const py::object& grid, const std::string& path) {
  if (grid.is_none()) return 0;
  if (py::isinstance<py::bool_>(grid) || !py::isinstance<py::int_>(grid))
    throw py::value_error(
        fmt::format("grid: expected an integer or None, got {}", std::string(py::str(py::type::of(grid).attr("__name__")))));
  const std::string text = py::str(grid);
  return check_rgl_fit_grid(path, parse_integer(text, INT64_MIN, INT64_MAX, "grid"), "grid");
}

py::dict read_measured_py(const py::object& path_in, const py::object& grid) {
  if (!(py::isinstance<py::str>(path_in) || py::hasattr(path_in, "__fspath__")))
    throw py::value_error(
        fmt::format("path: expected a path to a .binary (MERL), .brdf (Cornell), .bsdf (RGL) or .csv file, got {}",
                    std::string(py::str(py::type::of(path_in).attr("__name__")))));
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_in));
  const int rgl_grid = rgl_grid_of(grid, path);
  SampleSet set;
  {
    py::gil_scoped_release release;
    set = read_measured(path, rgl_grid);
  }
  const size_t n = set.samples.size();
  py::array_t<double> wi = rows_out<double>(n, false, 3), wo = rows_out<double>(n, false, 3),
                      value = rows_out<double>(n, false, 3);
  py::array_t<double> weight(std::vector<py::ssize_t>{py::ssize_t(n)});
  double *pi = wi.mutable_data(), *po = wo.mutable_data(), *pv = value.mutable_data(), *pw = weight.mutable_data();
  for (size_t i = 0; i < n; ++i) {
    const MeasuredSample& s = set.samples[i];
    for (int c = 0; c < 3; ++c) pi[3 * i + c] = s.wi[c], po[3 * i + c] = s.wo[c], pv[3 * i + c] = s.value[c];
    pw[i] = s.weight;
  }
  py::dict d;
  d["wi"] = wi, d["wo"] = wo, d["value"] = value, d["weight"] = weight;
  d["source"] = set.source, d["format"] = set.format, d["description"] = set.description, d["warnings"] = set.warnings;
  return d;
}

// What aniso.fit returns: the fitted material, its error figures and the fit's record (the "fit"
// object of the CLI's fitted.json).
struct PyFitResult {
  PyMaterial material;
  json material_json;  // as fit_samples returned it (fitted.json without "fit")
  json provenance;     // fit_provenance: fitted.json's "fit"
  FitResult result;
};

std::atomic<bool> g_fit_interrupted{false};
extern "C" void on_fit_sigint(int) { g_fit_interrupted.store(true); }

// Python's numbers as the CLI's option text: the same parser, so the same checks and messages.
std::string option_text(const py::object& v, const char* name) {
  if (py::isinstance<py::bool_>(v) ||
      !(py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v) || py::isinstance<py::str>(v)))
    throw py::value_error(
        fmt::format("{}: expected a number, got {}", name, std::string(py::str(py::type::of(v).attr("__name__")))));
  return py::str(v);
}

PyFitResult fit_py(const py::object& data_in, const py::object& wi, const py::object& wo, const py::object& value,
                   const py::object& weight, const std::string& model, const py::object& lobes, const py::object& anisotropic,
                   bool allow_energy_gain, bool shared_exponents, const std::string& normalization, const py::object& metal,
                   const std::string& metal_lobe, const std::string& fresnel, const std::string& metric, const std::string& loss,
                   const py::object& loss_scale, const py::object& starts, const py::object& seed, const py::object& threads,
                   const py::object& max_iterations, const py::object& max_theta_deg, const py::object& progress,
                   const py::object& grid) {
  FitOptionText t;
  t.model = model;
  t.lobes = option_text(lobes, "lobes");
  // anisotropic: "auto" | "yes" | "no" as the CLI's --anisotropic, or True / False for yes / no.
  if (py::isinstance<py::bool_>(anisotropic))
    t.anisotropic = anisotropic.cast<bool>() ? "yes" : "no";
  else if (py::isinstance<py::str>(anisotropic))
    t.anisotropic = anisotropic.cast<std::string>();
  else
    throw py::value_error(fmt::format("anisotropic: expected \"auto\", \"yes\", \"no\", True or False, got {}",
                                      std::string(py::str(py::type::of(anisotropic).attr("__name__")))));
  t.allow_energy_gain = allow_energy_gain;
  t.shared_exponents = shared_exponents;
  t.normalization = normalization;
  t.metal = metal.is_none() ? "" : std::string(py::str(metal));
  t.metal_lobe = metal_lobe;
  t.fresnel = fresnel;
  t.metric = metric;
  t.loss = loss;
  t.loss_scale = option_text(loss_scale, "loss_scale");
  t.starts = option_text(starts, "starts");
  t.seed = option_text(seed, "seed");
  t.threads = option_text(threads, "threads");
  t.max_iterations = option_text(max_iterations, "max_iterations");
  t.max_theta = option_text(max_theta_deg, "max_theta_deg");
  FitOptions o = parse_fit_options(t);

  SampleSet data;
  if (!data_in.is_none()) {
    if (!wi.is_none() || !wo.is_none() || !value.is_none() || !weight.is_none())
      throw py::value_error("fit(): give either data (a file) or the arrays wi=, wo=, value=, not both");
    if (!(py::isinstance<py::str>(data_in) || py::hasattr(data_in, "__fspath__")))
      throw py::value_error(
          fmt::format("data: expected a path to a .binary (MERL), .brdf (Cornell), .bsdf (RGL) or .csv file, got {}",
                      std::string(py::str(py::type::of(data_in).attr("__name__")))));
    const std::string path = py::str(py::module_::import("os").attr("fspath")(data_in));
    const int rgl_grid = rgl_grid_of(grid, path);
    py::gil_scoped_release release;
    data = read_measured(path, rgl_grid);
  } else {
    if (!grid.is_none())
      throw py::value_error("grid: applies to an RGL tensor file (.bsdf) given as data, not to the arrays wi=, wo=, value=");
    data = samples_from_arrays(wi, wo, value, weight);
  }
  for (const std::string& w : data.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();

  // Progress: None shows a line on stderr as `aniso fit` does (when stderr is a terminal, once the fit
  // has run a second), True always, False never; a callable gets a dict per solver iteration.
  const bool call = !progress.is_none() && PyCallable_Check(progress.ptr()) && !py::isinstance<py::bool_>(progress);
  if (!progress.is_none() && !call && !py::isinstance<py::bool_>(progress))
    throw py::value_error(fmt::format("progress: expected None, True, False or a callable, got {}",
                                      std::string(py::str(py::type::of(progress).attr("__name__")))));
  const bool print = !call && (progress.is_none() ? isatty(STDERR_FILENO) != 0 : progress.cast<bool>());
  const double print_after = progress.is_none() ? 1.0 : 0.0;
  std::optional<py::error_already_set> callback_error;
  double last_print = -1.0;
  bool printed = false;
  // Ctrl-C (SIGINT, in the main thread) stops the fit at the solver's next iteration and raises
  // KeyboardInterrupt, as render does; a progress callback that raises stops it too.
  std::atomic<bool> stop{false};
  const py::module_ threading = py::module_::import("threading");
  const bool main_thread = threading.attr("current_thread")().is(threading.attr("main_thread")());
  struct SigintScope {
    bool active;
    struct sigaction old {};
    explicit SigintScope(bool on) : active(on) {
      if (!active) return;
      g_fit_interrupted.store(false);
      struct sigaction action {};
      action.sa_handler = on_fit_sigint;
      sigemptyset(&action.sa_mask);
      sigaction(SIGINT, &action, &old);
    }
    ~SigintScope() {
      if (active) sigaction(SIGINT, &old, nullptr);
    }
  };
  o.cancel = &stop;
  o.progress = [&](const FitProgress& p) {
    if (main_thread && g_fit_interrupted.load()) stop.store(true);
    if (call) {
      py::gil_scoped_acquire gil;
      try {
        py::dict d;
        d["stage"] = p.stage;
        d["iteration"] = p.iteration;
        d["cost"] = p.cost;
        d["elapsed_s"] = p.elapsed_s;
        d["remaining_s"] = p.remaining_s;
        progress(d);
      } catch (py::error_already_set& e) {
        if (!callback_error) callback_error.emplace(std::move(e));
        stop.store(true);
      }
    } else if (print && p.elapsed_s >= print_after && p.elapsed_s - last_print >= 0.1) {
      last_print = p.elapsed_s;
      std::fprintf(stderr, "\raniso.fit: %-90s",
                   fmt::format("{} iteration {} cost {:.4g}  {:.1f} s, about {:.0f} s left", p.stage, p.iteration, p.cost,
                               p.elapsed_s, p.remaining_s)
                       .c_str());
      printed = true;
    }
  };
  std::optional<FitResult> r;
  bool cancelled = false;
  {
    const SigintScope sigint(main_thread);
    py::gil_scoped_release release;
    try {
      r = fit_samples(data, o);
    } catch (const FitCancelled&) {
      cancelled = true;
    }
  }
  if (printed) std::fprintf(stderr, "\r\033[K");
  if (callback_error) throw std::move(*callback_error);
  if (cancelled) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  json provenance = fit_provenance(*r, data, o);
  PyMaterial mat(parse_material(r->material, "fitted material"), "fitted material");
  return PyFitResult{std::move(mat), r->material, std::move(provenance), std::move(*r)};
}

// aniso.fit's docstring. Its lists of choices come from where the fitter reads them: the models
// from kFittable (fittable_models()), the Ward normalizations and the metal's lobes from
// io/enum_names.h.
const std::string& fit_doc() {
  static const std::string doc = [] {
    std::string models;
    for (const std::string_view m : fittable_models()) (models += models.empty() ? "" : " | ") += m;
    return fmt::format(
        "Fits a model to measured data, as `aniso fit` (docs/fitting.md): the same solver, options, starts\n"
        "and error figures; the same data, options and seed give the same material.\n\n"
        "data: a path to a MERL .binary, Cornell .brdf, RGL tensor .bsdf or CSV file of samples (what `aniso fit\n"
        "DATA` reads);\n"
        "or instead wi, wo: (N, 3) unit directions above the horizon (one of them may be (3,)), value: (N, 3)\n"
        "f(wi, wo) in 1/sr (no cosine), weight: (N,) or None. The keywords are `aniso fit`'s options:\n"
        "model ({}), lobes (Lafortune, 1 to 8),\n"
        "anisotropic (\"auto\": when the data show it, \"yes\" / True, \"no\" / False; an anisotropic fit fits\n"
        "rotation_deg too), allow_energy_gain (else every directional albedo stays <= 1), shared_exponents, normalization (Ward: "
        "{}), metal (a named metal; None fits eta\n"
        "and k), metal_lobe ({}), fresnel (ggx: \"schlick\", f90 = 1, or \"free-f90\", f90 fitted per channel),\n"
        "metric (l2cos | log), loss (none | huber |\n"
        "cauchy | soft_l1), loss_scale, starts, seed, threads (0: all cores), max_iterations, max_theta_deg\n"
        "(samples with a direction farther from the normal are left out: Ngan 2005's 80 degrees), grid (an RGL\n"
        ".bsdf file's sampling: N theta_h x N/2 theta_d x N phi_d, N even in [4, 256]; None: 64 isotropic, 32\n"
        "anisotropic).\n"
        "progress: None (a line on stderr when it is a terminal, as the CLI), True, False, or a callable\n"
        "given {{stage, iteration, cost, elapsed_s, remaining_s}} each iteration. The GIL is released while\n"
        "fitting; Ctrl-C stops the fit (KeyboardInterrupt). Returns a FitResult: `m, errors = aniso.fit(...)`.\n"
        "Bad data or options raise ValueError with the CLI's message.",
        models, enum_names_text<WardNormalization>(), enum_names_text<SpecularLobeKind>());
  }();
  return doc;
}

}  // namespace

void bind_fit(py::module_& m) {
  py::class_<PyFitResult>(m, "FitResult",
                          "What aniso.fit returns: the fitted Material and its error figures (iterable as\n"
                          "material, errors), the fitted parameters and the record `aniso fit` stores in fitted.json.")
      .def_property_readonly(
          "material", [](const PyFitResult& r) { return r.material; }, "the fitted Material")
      .def_property_readonly(
          "errors", [](const PyFitResult& r) { return to_py(r.provenance["error"]); },
          "{l2cos, l2cos_rgb, log, log_rgb, relative_l2cos} over every sample (docs/fitting.md, \"Metrics\"),\n"
          "as `aniso fit` prints them: \"all\" is the RMS of the three channels")
      .def_property_readonly(
          "parameters",
          [](const PyFitResult& r) {
            py::dict d;
            for (size_t i = 0; i < r.result.parameters.size(); ++i)
              d[py::str(r.result.parameter_names[i])] = r.result.parameters[i];
            return d;
          },
          "the solver's parameter vector by name (\"kd.r\", \"alpha\", ...)")
      .def_property_readonly(
          "best_start", [](const PyFitResult& r) { return r.result.best_start; },
          "the start the result came from: \"moments\", \"ngan2005 NAME\", \"random K\"")
      .def_property_readonly("iterations", [](const PyFitResult& r) { return r.result.iterations; })
      .def_property_readonly("seconds", [](const PyFitResult& r) { return r.result.seconds; })
      .def_property_readonly("samples", [](const PyFitResult& r) { return r.result.samples_total; })
      .def_property_readonly("samples_in_solver", [](const PyFitResult& r) { return r.result.samples_used; })
      .def_property_readonly("termination", [](const PyFitResult& r) { return r.result.termination; })
      .def_property_readonly(
          "anisotropic", [](const PyFitResult& r) { return r.result.anisotropic; },
          "whether the fitted model is anisotropic (with its rotation_deg)")
      .def_property_readonly(
          "anisotropy_reason", [](const PyFitResult& r) { return r.result.anisotropy_reason; },
          "why: the auto rule's decision and figures, or the option")
      .def_property_readonly(
          "tied", [](const PyFitResult& r) { return r.result.tied; },
          "parameters the data did not constrain, tied to their isotropic partner (docs/fitting.md)")
      .def_property_readonly("weakly_constrained", [](const PyFitResult& r) { return r.result.weakly_constrained; })
      .def_property_readonly(
          "largest_albedo", [](const PyFitResult& r) { return r.result.largest_albedo; },
          "the fitted material's largest directional albedo over the grid of docs/fitting.md")
      .def_property_readonly(
          "fit", [](const PyFitResult& r) { return to_py(r.provenance); },
          "the \"fit\" object of `aniso fit`'s fitted.json (data, options, errors, solver)")
      .def(
          "to_dict",
          [](const PyFitResult& r) {
            json j = r.material_json;
            j["fit"] = r.provenance;
            return to_py(j);
          },
          "fitted.json as `aniso fit -o` writes it: the material's keys plus the \"fit\" object.")
      .def(
          "to_json",
          [](const PyFitResult& r, int indent) {
            json j = r.material_json;
            j["fit"] = r.provenance;
            return j.dump(indent) + "\n";
          },
          py::arg("indent") = 2, "to_dict() as JSON text, the file `aniso fit -o` writes (every tool reads it).")
      .def("__iter__",
           [](const PyFitResult& r) { return py::iter(py::make_tuple(py::cast(r.material), to_py(r.provenance["error"]))); })
      .def("__repr__", [](const PyFitResult& r) {
        return fmt::format("aniso.FitResult(model={}, l2cos={:.5g}, log={:.5g}, relative_l2cos={:.4g}, best_start={})",
                           r.material_json.value("model", ""), r.result.errors.l2cos_all, r.result.errors.log_all,
                           r.result.errors.relative_l2cos, json(r.result.best_start).dump());
      });

  m.def("fit", &fit_py, py::arg("data") = py::none(), py::kw_only(), py::arg("wi") = py::none(), py::arg("wo") = py::none(),
        py::arg("value") = py::none(), py::arg("weight") = py::none(), py::arg("model") = "lafortune", py::arg("lobes") = 1,
        py::arg("anisotropic") = "auto", py::arg("allow_energy_gain") = false, py::arg("shared_exponents") = false,
        py::arg("normalization") = "ward", py::arg("metal") = py::none(), py::arg("metal_lobe") = "ggx",
        py::arg("fresnel") = "schlick", py::arg("metric") = "l2cos", py::arg("loss") = "none", py::arg("loss_scale") = 0.0,
        py::arg("starts") = 6, py::arg("seed") = 1, py::arg("threads") = 0, py::arg("max_iterations") = 200,
        py::arg("max_theta_deg") = kNganMaxThetaDeg, py::arg("progress") = py::none(), py::arg("grid") = py::none(),
        fit_doc().c_str());
  m.def(
      "fittable_models",
      [] {
        std::vector<std::string> out;
        for (const std::string_view n : fittable_models()) out.emplace_back(n);
        return out;
      },
      "The models aniso.fit fits (its model=, `aniso fit --model`), in the order `aniso fit --help` lists them:\n"
      "the fitter's table (src/fit/fit.cpp, kFittable).");
  m.def(
      "read_measured", &read_measured_py, py::arg("path"), py::kw_only(), py::arg("grid") = py::none(),
      "Reads measured reflectance as `aniso fit DATA` does (a MERL .binary, Cornell .brdf, RGL tensor .bsdf\n"
      "or CSV file of samples; Cornell spectra reduced to linear sRGB; an RGL file sampled on a grid of\n"
      "directions): {wi, wo: (N, 3) unit directions, value: (N, 3) f in 1/sr, weight: (N,), source, format,\n"
      "description (what was sampled, for an RGL file; else empty), warnings}. aniso.fit(wi=..., wo=..., value=..., weight=...)\n"
      "on them fits what aniso.fit(path) fits. grid: an RGL file's sampling grid, as aniso.fit's.");
}

}  // namespace aniso::python
