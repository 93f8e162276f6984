// apps/aniso/cmd_export_targets.cpp: `aniso export --to TARGET` (docs/export.md): a material in the
// native format of Blender, Mitsuba 3, pbrt-v4, MaterialX or glTF, with the target's conventions
// (include/aniso/export/targets.h) and a report of how close it is (include/aniso/export/export.h).
//
// Everything is computed before anything is written; each file goes through the one atomic writer
// (io/atomic_file.h). glTF writes two files: the .bin first, then the .gltf; if the .gltf cannot be
// written, a .bin this command created is removed again, so a failed export leaves nothing.
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "aniso/export/export.h"
#include "aniso/io/materials.h"
#include "commands.h"

namespace aniso {

namespace {

struct ExportArgs {
  std::string to, material, output, name, metric = "l2cos", help_target, preview;
  int starts = 4, grid = 6, preview_size = 256;
  double blender_version = 4.3;
  uint64_t seed = 1;
  bool list = false;
};

void run_export(const ExportArgs& a) {
  using namespace exporter;
  if (a.list) {
    for (const TargetInfo& t : targets()) fmt::print("{:<10} {:<6} {}\n", t.name, t.extension, t.summary);
    return;
  }
  if (!a.help_target.empty()) {
    const TargetInfo* t = find_target(a.help_target);
    if (!t)
      throw InputError(fmt::format("--help-target: unknown target \"{}\"; the targets are {}", a.help_target, target_names()));
    fmt::print("{} ({}): {}\n\n{}\n", t->name, t->extension, t->summary, t->help);
    return;
  }
  if (a.to.empty()) throw InputError(fmt::format("--to is required: one of {} (--list-targets)", target_names()));
  const TargetInfo* info = find_target(a.to);
  if (!info) throw InputError(fmt::format("--to: unknown target \"{}\"; the targets are {}", a.to, target_names()));
  if (a.material.empty()) throw InputError("--material is required (a preset name, a JSON file or inline JSON)");
  if (info->target == Target::Gltf && (a.output.empty() || a.output == "-"))
    throw InputError("--to gltf writes two files (.gltf and .bin): give -o FILE.gltf");
  ExportOptions o;
  o.target = a.to;
  o.name = a.name;
  o.starts = a.starts;
  o.seed = a.seed;
  o.grid = a.grid;
  o.blender_version = a.blender_version;
  FitOptionText metric_only;
  metric_only.metric = a.metric;
  o.metric = parse_fit_options(metric_only).metric;  // `aniso fit`'s check and message
  const MaterialDesc desc = load_material(a.material);
  (void)build_material<double>(desc);
  namespace fs = std::filesystem;
  std::string bin_name;
  if (info->target == Target::Gltf) bin_name = fs::path(a.output).stem().string() + ".bin";
  const ExportResult r = export_material(desc, a.material, o, bin_name);
  const bool to_stdout = a.output.empty() || a.output == "-";
  if (!a.preview.empty()) {
    if (!a.preview.ends_with(".png") && !a.preview.ends_with(".pfm") && !a.preview.ends_with(".exr"))
      throw InputError(fmt::format("--preview {}: expected a .png file (or .pfm / .exr: linear radiance)", a.preview));
    if (fs::is_directory(a.preview)) throw InputError(fmt::format("--preview {}: is a directory", a.preview));
  }
  if (r.files.size() == 2) {
    const fs::path bin = fs::path(a.output).parent_path() / r.files[1].path;
    std::error_code ec;
    const bool existed = fs::exists(bin, ec);
    // The .gltf's folder must be writable before the .bin is written next to it.
    if (fs::is_directory(a.output, ec)) throw InputError(fmt::format("-o {}: is a directory", a.output));
    write_atomically(bin.string(), r.files[1].content);
    try {
      write_atomically(a.output, r.files[0].content);
    } catch (...) {
      if (!existed) fs::remove(bin, ec);
      throw;
    }
  } else {
    write_atomically(a.output, r.files[0].content);
  }
  if (!a.preview.empty()) {
    MaterialDesc plain = desc;
    if (plain.params.values.count("rotation_deg")) plain.params.values["rotation_deg"] = 0.0;
    write_preview(a.preview, build_material<double>(plain), r.model, "source: " + desc.model,
                  std::string(info->name) + (r.report.exact ? " (exact)" : " (fitted)"), a.preview_size);
  }
  fmt::print(to_stdout ? stderr : stdout, "{}", r.report.text());
  if (!to_stdout) fmt::print("wrote {}{}\n", a.output, r.files.size() == 2 ? " and " + r.files[1].path : std::string());
}

}  // namespace

void add_export_target_command(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand("export",
                                 "write the material for a renderer: blender, mitsuba3, pbrt-v4, materialx, "
                                 "gltf (docs/export.md)");
  cmd->add_option("--to", a->to, "target: blender | mitsuba3 | pbrt-v4 | materialx | gltf");
  cmd->add_option("--material,-m", a->material, "preset name, JSON file or inline JSON");
  cmd->add_option("-o,--output", a->output, "output file (default: stdout; glTF needs a file)");
  cmd->add_option("--name", a->name, "material name in the file (default: from the source)");
  cmd->add_option("--metric", a->metric, "fitted path: l2cos (default) or log");
  cmd->add_option("--starts", a->starts, "fitted path: starts of the fit (default 4)")->check(CLI::Range(1, 100));
  cmd->add_option("--seed", a->seed, "fitted path: random seed (default 1)");
  cmd->add_option("--grid", a->grid, "sampling of the source: 4n x 4n x 2n x 2n half / difference angle pairs (default 6)")
      ->check(CLI::Range(1, 12));
  cmd->add_option("--blender-version", a->blender_version,
                  "--to blender: the Blender whose model the report measures (default 4.3: conductors as the Metallic "
                  "BSDF with n, k; 4.0: the Principled BSDF's F82 tint; 3.4: the Principled BSDF v1); the script "
                  "adapts to the Blender running it")
      ->check(CLI::Range(3.0, 10.0));
  cmd->add_option("--preview", a->preview,
                  "also write a PNG: the source (left) and the target model (right), shaded by aniso (.pfm / .exr: "
                  "linear radiance, no labels)");
  cmd->add_option("--preview-size", a->preview_size, "pixels of each sphere of --preview (default 256)")
      ->check(CLI::Range(16, 2048));
  cmd->add_flag("--list-targets", a->list, "list the targets and exit");
  cmd->add_option("--help-target", a->help_target, "what a target's export writes and how to use it");
  cmd->callback([a] { run_command([&] { run_export(*a); }); });
}

}  // namespace aniso
