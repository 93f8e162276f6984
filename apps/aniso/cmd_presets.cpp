// apps/aniso/cmd_presets.cpp: `aniso presets`, the named materials and where their numbers come
// from; `--show NAME` one of them as resolved, or what a MERL .binary or RGL .bsdf file is
// (docs/cli.md).
#include <memory>
#include <string>

#include <fmt/format.h>

#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "aniso/measured/measured.h"
#include "aniso/rgl/rgl_material.h"
#include "commands.h"
#include "io/json_read.h"
#include "io/names.h"

namespace aniso {
namespace {

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
      write_stdout(terminal_text(rgl::describe_rgl(*rgl::load_rgl(show))));
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

}  // namespace

void add_presets_command(CLI::App& app) {
  auto show = std::make_shared<std::string>();
  auto* presets_cmd = app.add_subcommand("presets", "list the named materials");
  auto* show_opt =
      presets_cmd->add_option("--show", *show,
                              "print one preset as resolved (every key, defaults filled in); for a MERL .binary file also the "
                              "MERL material it is, for an RGL .bsdf file its fields, grids and description");
  presets_cmd->callback([show, show_opt] { run_command([&] { return cmd_presets(*show, show_opt->count() > 0); }); });
}

}  // namespace aniso
