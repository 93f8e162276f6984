// apps/aniso/cmd_export_targets.cpp: `aniso export --to TARGET` (docs/export.md): a material in the
// native format of Blender, Mitsuba 3, pbrt-v4, MaterialX (standard_surface, OpenPBR) or glTF, with the target's conventions
// (include/aniso/export/targets.h) and a report of how close it is (include/aniso/export/export.h).
//
// Everything is computed and every output path checked before anything is written; each file goes
// through the one atomic writer (io/atomic_file.h). glTF writes two files: the .bin first, then the
// .gltf; a --preview comes last. If a later file cannot be written, the files this command created
// are removed again, so a failed export leaves nothing new.
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "aniso/export/export.h"
#include "aniso/io/materials.h"
#include "aniso/render/scene.h"
#include "commands.h"
#include "io/json_read.h"
#include "io/text_escape.h"

namespace aniso {

namespace {

bool to_stdout_path(const std::string& output) { return output.empty() || output == "-"; }

struct ExportArgs {
  std::string to, material, output, name, metric = "l2cos", help_target, preview, scene, object;
  int starts = 4, grid = 6, preview_size = 256;
  double blender_version = 4.3;
  uint64_t seed = 1;
  bool list = false, analytic = false;
};

// --scene FILE --object NAME|INDEX: that object's material and its tangent's angle_deg (docs/scenes.md,
// "Tangents"), which export_material composes with the material's rotation_deg. The scene is read
// (and validated) by the renderer's own reader; the angle is read from the document in double
// precision (the renderer keeps it in float radians). A field or map is no single turn of dp/du:
// only its angle_deg travels, with a note.
struct SceneObject {
  MaterialDesc desc;
  std::string label, name;  // name: the object's "name", else its material's
  double angle_deg = 0.0;
  std::vector<std::string> notes;
};
SceneObject scene_object(const std::string& path, const std::string& which) {
  const render::Scene scene = render::load_scene(path);
  const nlohmann::json doc = parse_json_text(read_text_file(path, "a scene file"), path);
  const nlohmann::json& objects = doc.at("objects");
  size_t index = objects.size();
  if (!which.empty() && which.find_first_not_of("0123456789") == std::string::npos) {
    index = which.size() < 10 ? std::stoul(which) : objects.size();
    if (index >= objects.size())
      throw InputError(
          fmt::format("--object {}: {} has {} objects (indices 0 to {})", which, path, objects.size(), objects.size() - 1));
  } else {
    std::string names;
    for (size_t i = 0; i < objects.size(); ++i) {
      const auto it = objects[i].find("name");
      const std::string n = it != objects[i].end() && it->is_string() ? it->get<std::string>() : std::string();
      if (!n.empty()) names += (names.empty() ? "\"" : ", \"") + n + "\"";
      if (n != which) continue;
      if (index != objects.size())
        throw InputError(
            fmt::format("--object {}: {} has several objects of that name (objects[{}] and objects[{}]): "
                        "give the index",
                        which, path, index, i));
      index = i;
    }
    if (index == objects.size())
      throw InputError(
          fmt::format("--object {}: {} has no object of that name (its named objects: {}); give a name or "
                      "an index from 0 to {}",
                      which, path, names.empty() ? "none" : names, objects.size() - 1));
  }
  SceneObject o;
  o.desc = *scene.objects[index].material_desc;
  o.label = fmt::format("{} objects[{}] ({})", path, index, scene.objects[index].material_name);
  const nlohmann::json& obj = objects[index];
  o.name = obj.contains("name") && obj["name"].is_string() && !obj["name"].get<std::string>().empty()
               ? obj["name"].get<std::string>()
               : scene.objects[index].material_name;
  if (const auto t = obj.find("tangent"); t != obj.end()) {
    if (const auto a = t->find("angle_deg"); a != t->end()) o.angle_deg = a->get<double>();
    for (const char* key : {"field", "map"})
      if (t->contains(key))
        o.notes.push_back(
            fmt::format("the scene object's tangent {} is no single turn of dp/du: only its angle_deg travels; give the mesh "
                        "tangents that follow the {} in the target",
                        key, key));
  }
  return o;
}

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
  if (!a.scene.empty() && !a.material.empty())
    throw InputError("--scene and --material: give one (with --scene, --object names the object whose material is exported)");
  if (!a.scene.empty() && a.object.empty()) throw InputError("--scene needs --object NAME|INDEX (the object to export)");
  if (a.scene.empty() && !a.object.empty()) throw InputError("--object needs --scene FILE");
  if (a.material.empty() && a.scene.empty())
    throw InputError(fmt::format("--material is required ({}), or --scene with --object", kMaterialHelp));
  if (info->target == Target::Gltf && (a.output.empty() || a.output == "-"))
    throw InputError("--to gltf writes two files (.gltf and .bin): give -o FILE.gltf");
  if (const std::optional<size_t> bad = first_invalid_utf8(a.name))
    throw InputError(
        fmt::format("--name: expected UTF-8 text (the name is written into the file), got the byte 0x{:02x} at "
                    "offset {} in \"{}\"",
                    static_cast<unsigned char>(a.name[*bad]), *bad, text_escape(a.name)));
  namespace fs = std::filesystem;
  std::string bin_name;
  if (info->target == Target::Gltf) {
    // The buffer goes beside the .gltf as <stem>.bin: an -o of that very name would write the JSON
    // over its own buffer.
    bin_name = fs::path(a.output).stem().string() + ".bin";
    if (fs::path(a.output).filename() == bin_name)
      throw InputError(fmt::format("-o {}: --to gltf writes its buffer beside the .gltf as {}: give -o FILE.gltf",
                                   text_escape(a.output), text_escape(bin_name)));
  }
  // Every output checked before any is written (docs/cli.md: exit 2, nothing written).
  if (!a.preview.empty()) {
    if (!a.preview.ends_with(".png") && !a.preview.ends_with(".pfm") && !a.preview.ends_with(".exr"))
      throw InputError(
          fmt::format("--preview {}: expected a .png file (or .pfm / .exr: linear radiance)", text_escape(a.preview)));
    check_writable(a.preview, "--preview");
  }
  if (!a.output.empty() && a.output != "-") {
    check_writable(a.output, "-o");
    if (!a.preview.empty() && fs::weakly_canonical(a.preview) == fs::weakly_canonical(a.output))
      throw InputError(fmt::format("--preview {}: the same file as -o", text_escape(a.preview)));
  }
  ExportOptions o;
  o.analytic = a.analytic;
  o.target = a.to;
  o.name = a.name;
  o.starts = a.starts;
  o.seed = a.seed;
  o.grid = a.grid;
  o.blender_version = a.blender_version;
  FitOptionText metric_only;
  metric_only.metric = a.metric;
  o.metric = parse_fit_options(metric_only).metric;  // `aniso fit`'s check and message
  std::optional<SceneObject> object;
  if (!a.scene.empty()) object = scene_object(a.scene, a.object);
  const MaterialDesc desc = object ? object->desc : load_material(a.material);
  (void)build_material<double>(desc);
  if (writes_measured(info->target, desc, o)) {
    // The renderer's own measured BSDF, its tensor file beside -o (measured_file_name: -o's stem,
    // made safe): checked like every output before anything is written.
    if (to_stdout_path(a.output))
      throw InputError(
          fmt::format("--to {} of a measured source writes two files (the scene and the tensor file beside it): "
                      "give -o FILE{} (or --analytic for the fitted analytic material alone)",
                      info->name, info->extension));
    bin_name = measured_file_name_for_path(info->target, a.output);
    const std::string side = (fs::path(a.output).parent_path() / bin_name).string();
    check_writable(side, "the tensor file beside -o");
    for (const std::string& other : {a.output, a.preview})
      if (!other.empty() && fs::weakly_canonical(side) == fs::weakly_canonical(other))
        throw InputError(
            fmt::format("-o {}: the tensor file written beside it, {}, would be the same file as {}: choose "
                        "another name",
                        text_escape(a.output), text_escape(bin_name), text_escape(other)));
  }
  if (object) {
    o.tangent_angle_deg = object->angle_deg;
    o.extra_notes = object->notes;
    if (o.name.empty()) o.name = object->name;
  }
  const std::string label = object ? object->label : a.material;
  const ExportResult r = export_material(desc, label, o, bin_name);
  const bool to_stdout = a.output.empty() || a.output == "-";
  // The files in order (the .bin before the .gltf that names it, the preview last); if one fails,
  // the files this command created are removed again, so a failed export leaves nothing new.
  std::vector<std::string> created;
  std::error_code ec;
  const auto write = [&](const std::string& path, const auto& writer) {
    const bool existed = !path.empty() && path != "-" && fs::exists(path, ec);
    writer();
    if (!existed && !path.empty() && path != "-") created.push_back(path);
  };
  try {
    if (r.files.size() == 2) {
      const std::string bin = (fs::path(a.output).parent_path() / r.files[1].path).string();
      write(bin, [&] { write_atomically(bin, r.files[1].content); });
    }
    write(a.output, [&] { write_atomically(a.output, r.files[0].content); });
    if (!a.preview.empty()) {
      MaterialDesc plain = desc;
      if (plain.params.values.count("rotation_deg")) plain.params.values["rotation_deg"] = 0.0;
      write(a.preview, [&] {
        write_preview(a.preview, build_material<double>(plain), r.model, "source: " + desc.model,
                      std::string(info->name) + (r.report.exact ? " (exact)" : " (fitted)"), a.preview_size);
      });
    }
  } catch (...) {
    for (const std::string& path : created) fs::remove(path, ec);
    throw;
  }
  fmt::print(to_stdout ? stderr : stdout, "{}", r.report.text());
  if (r.report.image.warn())
    fmt::print(stderr,
               "aniso: warning: the export renders {:.0f} % from the source on the sphere's mean and {:.0f} % on its lit "
               "region (bounds {:g} % and {:g} %; --preview FILE.png shows both)\n",
               100.0 * r.report.image.mean_difference, 100.0 * r.report.image.lit_difference, 100.0 * kCheckWarnMean,
               100.0 * kCheckWarnLit);
  if (!to_stdout)
    fmt::print("wrote {}{}\n", text_escape(a.output),
               r.files.size() == 2 ? " and " + text_escape(r.files[1].path) : std::string());
}

}  // namespace

void add_export_target_command(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand("export",
                                 "write the material for a renderer: blender, mitsuba3, pbrt-v4, materialx, "
                                 "openpbr, gltf (docs/export.md)");
  cmd->add_option("--to", a->to, "target: blender | mitsuba3 | pbrt-v4 | materialx | openpbr | gltf");
  cmd->add_option("--material,-m", a->material, kMaterialHelp);
  cmd->add_option("--scene", a->scene,
                  "a scene file (docs/scenes.md): export the material of --object, its tangent angle_deg composed with "
                  "the material's rotation_deg");
  cmd->add_option("--object", a->object, "with --scene: the object's name or index in objects");
  cmd->add_option("-o,--output", a->output, "output file (default: stdout; glTF needs a file)");
  cmd->add_option("--name", a->name, "material name in the file (default: from the source)");
  cmd->add_option("--metric", a->metric, "fitted path: l2cos (default) or log");
  cmd->add_option("--starts", a->starts, "fitted path: starts of the fit (default 4)")
      ->check(CLI::Range(1, exporter::kExportStartsMax));
  cmd->add_option("--seed", a->seed, "fitted path: random seed (default 1)");
  cmd->add_option("--grid", a->grid,
                  "sampling of an analytic source: 4n x 4n x 2n x 2n half / difference angle pairs (default 6); a measured one "
                  "(.bsdf, .binary) is fitted and measured on its own samples, as aniso fit's")
      ->check(CLI::Range(exporter::kExportGridMin, exporter::kExportGridMax));
  cmd->add_option("--blender-version", a->blender_version,
                  "--to blender: the Blender whose model the report measures (default 4.3: conductors as the Metallic "
                  "BSDF with n, k; 4.0: the Principled BSDF's F82 tint; 3.4: the Principled BSDF v1); the script "
                  "adapts to the Blender running it")
      ->check(CLI::Range(exporter::kBlenderVersionMin, exporter::kBlenderVersionMax));
  cmd->add_option("--preview", a->preview,
                  "also write a PNG: the source (left) and the target model (right), shaded by aniso (.pfm / .exr: "
                  "linear radiance, no labels)");
  cmd->add_option("--preview-size", a->preview_size, "pixels of each sphere of --preview (default 256)")
      ->check(CLI::Range(16, 2048));
  cmd->add_flag("--analytic", a->analytic,
                "--to mitsuba3 / pbrt-v4 with a measured source (.bsdf, .binary): write the fitted analytic material "
                "instead of the renderer's own measured BSDF and its tensor file");
  cmd->add_flag("--list-targets", a->list, "list the targets and exit");
  cmd->add_option("--help-target", a->help_target, "what a target's export writes and how to use it");
  cmd->callback([a] { run_command([&] { run_export(*a); }); });
}

}  // namespace aniso
