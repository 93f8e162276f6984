// apps/aniso/cmd_fit.cpp: `aniso fit DATA --model M ... -o fitted.json` and `aniso fit --compare
// DATA` (docs/fitting.md). The data are read and validated completely before anything is fitted;
// the fitted material is validated by the material reader and written atomically, so an error of
// any kind leaves no file behind.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <unistd.h>

#include "aniso/fit/fit.h"
#include "aniso/fit/plot.h"
#include "aniso/io/materials.h"
#include "commands.h"
#include "io/enum_names.h"
#include "io/text_input.h"

namespace aniso {
namespace {

struct FitArgs {
  FitOptionText options;  // as typed: parse_fit_options reads them (fit/fit.h)
  std::string data, output, plot, progress_after = "1", grid;
  bool compare = false, quiet = false;
};

// The progress line on stderr: shown once a fit has run for a second; redrawn in place on a
// terminal, otherwise one line per second at most.
class ProgressDisplay {
 public:
  ProgressDisplay(bool quiet, double after_s) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0), after_(after_s) {}
  ~ProgressDisplay() { finish(); }
  void operator()(const FitProgress& p) {
    if (quiet_ || p.elapsed_s < after_ || (shown_ && p.elapsed_s - last_ < (tty_ ? 0.1 : 1.0))) return;
    last_ = p.elapsed_s;
    const std::string line = fmt::format("fit: {} iteration {} cost {:.4g}  {:.1f} s, about {:.0f} s left", p.stage, p.iteration,
                                         p.cost, p.elapsed_s, p.remaining_s);
    if (tty_)
      fmt::print(stderr, "\r{:<100}", line);
    else
      fmt::print(stderr, "{}\n", line);
    shown_ = true;
    std::fflush(stderr);
  }
  void finish() {
    if (shown_ && tty_) fmt::print(stderr, "\r{:<100}\r", "");
    shown_ = false;
  }

 private:
  bool quiet_, tty_, shown_ = false;
  double after_, last_ = 0.0;
};

std::string error_table(const FitErrors& e) {
  std::string s = fmt::format("{:<22} {:>11} {:>11} {:>11} {:>11}\n", "error", "red", "green", "blue", "all");
  s += fmt::format("{:<22} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g}\n", "l2cos (Ngan 2005)", e.l2cos.x, e.l2cos.y, e.l2cos.z,
                   e.l2cos_all);
  s += fmt::format("{:<22} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g}\n", "log (relative)", e.log.x, e.log.y, e.log.z, e.log_all);
  s += fmt::format("{:<22} {:>11.5g}\n", "l2cos / data norm", e.relative_l2cos);
  return s;
}

// Lafortune in the lecture's layout (VGP352 week 5, matte steel): one row per lobe and channel.
std::string lafortune_table(const nlohmann::json& m) {
  const auto at = [](const nlohmann::json& v, int c) { return v.is_array() ? v[size_t(c)].get<double>() : v.get<double>(); };
  bool anisotropic = false;
  for (const auto& l : m["lobes"])
    for (int c = 0; c < 3; ++c) anisotropic = anisotropic || at(l["cx"], c) != at(l["cy"], c);
  std::string s = anisotropic ? fmt::format("{:<18} {:>11} {:>11} {:>11} {:>11}\n", "", "C_x", "C_y", "C_z", "s")
                              : fmt::format("{:<18} {:>11} {:>11} {:>11}\n", "", "C_xy", "C_z", "s");
  const char* names[3] = {"red", "green", "blue"};
  int k = 0;
  for (const auto& l : m["lobes"]) {
    ++k;
    for (int c = 0; c < 3; ++c) {
      const std::string label = fmt::format("Lobe {}, {}", k, names[c]);
      if (anisotropic)
        s += fmt::format("{:<18} {:>11.6g} {:>11.6g} {:>11.6g} {:>11.6g}\n", label, at(l["cx"], c), at(l["cy"], c),
                         at(l["cz"], c), at(l["n"], c));
      else
        s += fmt::format("{:<18} {:>11.6g} {:>11.6g} {:>11.6g}\n", label, at(l["cx"], c), at(l["cz"], c), at(l["n"], c));
    }
  }
  s += fmt::format("{:<18} {:>11.6g} {:>11.6g} {:>11.6g}   (red, green, blue)\n", "rho_d", at(m["rho_d"], 0), at(m["rho_d"], 1),
                   at(m["rho_d"], 2));
  return s;
}

std::string parameter_table(const FitResult& r) {
  std::string s;
  for (size_t i = 0; i < r.parameters.size(); ++i) s += fmt::format("{:<18} {:>13.6g}\n", r.parameter_names[i], r.parameters[i]);
  return s;
}

std::string fitted_file(const FitResult& r, const SampleSet& data, const FitOptions& o) {
  nlohmann::json out = r.material;
  out["fit"] = fit_provenance(r, data, o);
  // The file must be a valid material everywhere (eval, render, export): read it back.
  (void)build_material<double>(parse_material(out, "fitted material"));
  return out.dump(2) + "\n";
}

// What the fit decided for the user: anisotropy and why, tied and weak parameters, energy.
std::string fit_report(const FitResult& r, const FitOptions& o) {
  std::string s =
      r.max_theta_deg < 90.0
          ? fmt::format(
                "range: {} of {} samples have both directions within {:g} deg of the normal (Ngan 2005; --max-theta), "
                "the rest are left out of the fit and its errors\n",
                r.samples_total, r.samples_total + r.samples_beyond_range, r.max_theta_deg)
          : fmt::format("range: every sample (--max-theta 90)\n");
  s += fmt::format("anisotropy: {}\n", r.anisotropy_reason);
  for (const std::string& t : r.tied) s += fmt::format("tied: {}\n", t);
  if (!r.weakly_constrained.empty() && r.tied.empty()) {
    std::string list;
    for (const std::string& n : r.weakly_constrained) list += fmt::format("{}{}", list.empty() ? "" : ", ", n);
    s += fmt::format("warning: the data constrain these entries only weakly (or only in combination): {}\n", list);
  }
  s += fmt::format("largest directional albedo: {:.4f} at theta_o {:g} deg, phi_o {:g} deg{}\n", r.largest_albedo,
                   r.largest_albedo_theta_deg, r.largest_albedo_phi_deg,
                   o.allow_energy_gain    ? " (energy gain allowed: --allow-energy-gain)"
                   : r.energy_constrained ? fmt::format(" (constrained to <= 1: {}; without the constraint: relative l2cos "
                                                        "{:.4g}, largest albedo {:.4f})",
                                                        r.energy_method, r.unconstrained_l2cos, r.unconstrained_albedo)
                                          : "");
  return s;
}

void print_warnings(const SampleSet& data) {
  for (const std::string& w : data.warnings) fmt::print(stderr, "aniso: warning: {}\n", w);
}

// Options that only one model reads, or that --compare sets itself, are refused when they would
// be ignored: the user meant something else.
void check_options_apply(const FitArgs& a, const CLI::App& fit) {
  const auto given = [&](const char* name) { return fit.get_option(name)->count() > 0; };
  if (a.compare) {
    std::string labels;
    for (const auto& [label, options] : compare_models(FitOptions{}))
      labels += fmt::format("{}{}", labels.empty() ? "" : ", ", label);
    for (const char* name : {"--model", "--lobes", "--normalization", "--metal", "--metal-lobe", "--fresnel"})
      if (given(name))
        throw InputError(
            fmt::format("{} does not apply with --compare, which fits every model with its own settings ({})", name, labels));
    return;
  }
  const std::string& m = a.options.model;
  const struct {
    const char* option;
    const char* model;
  } only[] = {{"--lobes", "lafortune"}, {"--shared-exponents", "lafortune"}, {"--normalization", "ward"},
              {"--metal", "metal"},     {"--metal-lobe", "metal"},           {"--fresnel", "ggx"}};
  for (const auto& [option, model] : only)
    if (given(option) && m != model)
      throw InputError(fmt::format("{} applies to --model {} only, not to --model {}", option, model, m));
}

void run_fit(const FitArgs& a, const CLI::App& fit) {
  check_options_apply(a, fit);
  if (!a.plot.empty() && lower_extension(a.plot) != ".png")
    throw InputError(fmt::format("--plot {}: expected a .png file name (the plot is written as PNG)", a.plot));
  FitOptions o = parse_fit_options(a.options);
  for (const std::string& note : o.notes) fmt::print(stderr, "aniso: note: {}\n", note);
  if (!a.compare && a.output.empty()) throw InputError("-o: required: the file to write the fitted material to (fitted.json)");
  int grid = 0;
  if (!a.grid.empty()) grid = check_rgl_fit_grid(a.data, parse_integer(a.grid, INT64_MIN, INT64_MAX, "--grid"), "--grid");
  const SampleSet data = read_measured(a.data, grid);
  print_warnings(data);
  const std::optional<double> after = parse_decimal(a.progress_after);
  if (!after || !(*after >= 0.0))
    throw InputError(fmt::format("--progress-after: expected a finite decimal number >= 0, got \"{}\"", a.progress_after));
  auto display = std::make_shared<ProgressDisplay>(a.quiet, *after);
  o.progress = [display](const FitProgress& p) { (*display)(p); };
  std::string out = fmt::format("data: {} ({}, {} samples)\n", text_escape(data.source), data.format, data.samples.size());
  if (!data.description.empty()) out += fmt::format("sampled: {}\n", data.description);

  if (a.compare) {
    struct Row {
      std::string label;
      FitOptions options;
      FitResult result;
    };
    std::vector<Row> rows;
    for (const auto& [label, mo] : compare_models(o)) {
      FitOptions mo2 = mo;
      mo2.progress = [display, label = label](const FitProgress& p) {
        FitProgress q = p;
        q.stage = fmt::format("{}: {}", label, p.stage);
        (*display)(q);
      };
      rows.push_back({label, mo, fit_samples(data, mo2)});
    }
    display->finish();
    std::vector<size_t> order(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) order[i] = i;
    const bool by_log = o.metric == FitMetric::Log;
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
      return by_log ? rows[x].result.errors.log_all < rows[y].result.errors.log_all
                    : rows[x].result.errors.relative_l2cos < rows[y].result.errors.relative_l2cos;
    });
    out += fmt::format("ranked by the {} (each fitted with the {} metric); errors over every sample in range and channel\n",
                       by_log ? "log error" : "relative l2cos error (l2cos / the data's norm)", by_log ? "log" : "l2cos");
    out += fmt::format("{:<4} {:<28} {:<6} {:>11} {:>11} {:>9} {:>8}  {}\n", "rank", "model", "aniso", "l2cos", "log", "relative",
                       "time_s", "parameters");
    for (size_t i = 0; i < order.size(); ++i) {
      const Row& r = rows[order[i]];
      out += fmt::format("{:<4} {:<28} {:<6} {:>11.5g} {:>11.5g} {:>9.4f} {:>8.3f}  {}\n", i + 1, r.label,
                         r.result.anisotropic ? "yes" : "no", r.result.errors.l2cos_all, r.result.errors.log_all,
                         r.result.errors.relative_l2cos, r.result.seconds, describe_parameters(r.result));
    }
    const Row& best = rows[order[0]];
    out += fmt::format("best: {}\n", best.label);
    out += fit_report(best.result, best.options);
    std::string file;
    if (!a.output.empty()) file = fitted_file(best.result, data, best.options);
    if (!a.plot.empty()) {
      std::vector<PlotMaterial> all;  // every model, in the ranking's order
      for (size_t i : order) all.push_back({rows[i].result.material, rows[i].label});
      write_slices_plot(a.plot, data, all);
    }
    if (!a.output.empty()) write_atomically(a.output, file);
    std::fwrite(out.data(), 1, out.size(), stdout);
    return;
  }

  const FitResult r = fit_samples(data, o);
  display->finish();
  const std::string file = fitted_file(r, data, o);
  out += fmt::format("model: {}{}\n", o.model,
                     o.model == "lafortune" ? fmt::format(", {} lobe{}", o.lobes, o.lobes > 1 ? "s" : "") : std::string());
  out += o.model == "lafortune" ? lafortune_table(r.material) : parameter_table(r);
  out += error_table(r.errors);
  out += fit_report(r, o);
  out += fmt::format("best start: {}; {} iterations; {:.3f} s; {} of {} samples in the solver\n", r.best_start, r.iterations,
                     r.seconds, r.samples_used, r.samples_total);
  if (!a.plot.empty()) write_slices_plot(a.plot, data, {{r.material, o.model}});
  write_atomically(a.output, file);
  std::fwrite(out.data(), 1, out.size(), stdout);
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* fit = app.add_subcommand("fit",
                                 "fit a model to measured data (MERL .binary, Cornell .brdf, RGL .bsdf, CSV of samples): "
                                 "write the material, print the parameters and errors");
  fit->add_option(
         "data", a->data,
         "measured data: .binary (MERL), .brdf (Cornell), .bsdf (RGL tensor file), .csv (theta_i,phi_i,theta_o,phi_o,r,g,b)")
      ->required();
  std::string models;
  for (std::string_view m : fittable_models()) models += fmt::format("{}{}", models.empty() ? "" : " | ", m);
  fit->add_option("--model", a->options.model, models)->type_name("MODEL")->capture_default_str();
  fit->add_option("--lobes", a->options.lobes, "Lafortune: number of lobes, 1 to 8")->type_name("INT")->capture_default_str();
  fit->add_option_function<std::string>(
         "--anisotropic", [a](const std::string& v) { a->options.anisotropic = v.empty() ? "yes" : v; },
         "auto | yes | no: fit C_x != C_y, alpha_x != alpha_y, n_u != n_v and the orientation rotation_deg; auto "
         "when the data show anisotropy (docs/fitting.md); the bare flag means yes [default: auto]")
      ->expected(0, 1)
      ->type_name("auto|yes|no");
  fit->add_flag("--allow-energy-gain", a->options.allow_energy_gain,
                "let the fitted material reflect more than it receives (directional albedo > 1), for data that do");
  fit->add_flag("--shared-exponents", a->options.shared_exponents, "Lafortune: one exponent per lobe for all channels");
  fit->add_option("--normalization", a->options.normalization, "Ward: " + enum_names_text<WardNormalization>())
      ->type_name("NAME")
      ->capture_default_str();
  fit->add_option("--metal", a->options.metal, "metal: a measured metal's eta, k (fixed); default: fit eta and k")
      ->type_name("METAL");
  fit->add_option("--metal-lobe", a->options.metal_lobe, "metal: " + enum_names_text<SpecularLobeKind>())
      ->type_name("MODEL")
      ->capture_default_str();
  fit->add_option("--fresnel", a->options.fresnel,
                  "ggx: schlick (f90 = 1, as the renderers' GGX materials) | free-f90 (f90 fitted per channel: a Fresnel "
                  "the data can keep flat, docs/fitting.md)")
      ->type_name("NAME")
      ->capture_default_str();
  fit->add_option("--metric", a->options.metric, "l2cos (Ngan 2005's cosine-weighted L2) | log (relative)")
      ->type_name("NAME")
      ->capture_default_str();
  fit->add_option("--loss", a->options.loss, "robust loss per sample: none | huber | cauchy | soft_l1")
      ->type_name("NAME")
      ->capture_default_str();
  fit->add_option("--loss-scale", a->options.loss_scale, "the robust loss's scale (residual units); 0: from the data")
      ->type_name("FLOAT")
      ->capture_default_str();
  fit->add_option("--starts", a->options.starts,
                  "number of starts (moments, Ngan 2005's nearest fit, random), 1 to 1000; the separable grid's start "
                  "(docs/fitting.md) comes beside them")
      ->type_name("INT")
      ->capture_default_str();
  fit->add_option("--seed", a->options.seed, "seed of the random starts, 0 to 2^64-1")
      ->type_name("UINT64")
      ->capture_default_str();
  fit->add_option("--threads", a->options.threads, "solver threads; 0: all cores")->type_name("INT")->capture_default_str();
  fit->add_option("--max-theta", a->options.max_theta,
                  "leave out samples with either direction farther than this from the normal, degrees in (0, 90] (Ngan "
                  "2005's range; 90 keeps every sample)")
      ->type_name("DEG")
      ->capture_default_str();
  fit->add_option("--max-iterations", a->options.max_iterations, "Levenberg-Marquardt iterations of the final refinement")
      ->type_name("INT")
      ->capture_default_str();
  fit->add_option("--grid", a->grid,
                  "a .bsdf file's sampling: N theta_h x N/2 theta_d x N phi_d half/difference angle pairs (x 24 half-vector "
                  "azimuths for an anisotropic file), N even, 4 to 256 [default: 64 isotropic, 32 anisotropic]")
      ->type_name("N");
  fit->add_option("-o,--output", a->output, "fitted material (JSON with a \"fit\" object); required unless --compare");
  fit->add_flag("--compare", a->compare, "fit every model and print a ranking table (Ngan 2005's comparison)");
  fit->add_option("--plot", a->plot, "PNG of measured vs fitted in-plane slices at several incidence angles");
  fit->add_flag("--quiet,-q", a->quiet, "no progress display");
  fit->add_option("--progress-after", a->progress_after, "show the progress display once a fit has run this many seconds")
      ->type_name("SECONDS")
      ->capture_default_str();
  fit->callback([a, fit] { run_command([&] { run_fit(*a, *fit); }); });
}

}  // namespace aniso
