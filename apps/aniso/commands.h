// apps/aniso/commands.h: subcommands that live in their own files (cmd_<name>.cpp).
#pragma once

#include <cstdio>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "aniso/io/params.h"
#include "cli_common.h"
#include "io/text_escape.h"
#include "io/text_input.h"

namespace aniso {

// A command that ran to its end with an exit status other than 0 (130: `aniso render` stopped by
// Ctrl-C after writing what it had): main() returns it once stdout is known to hold everything.
struct CommandExit {
  int status;
};

// Runs a command inside CLI11's callback with main()'s error conventions (docs/cli.md, "Exit
// status"): InputError exits 2 with "aniso: error: <message>", out of memory and any other error
// exit 1 (the message through terminal_text: no control byte or invalid UTF-8 from an input reaches
// the terminal); success ends parsing with exit code 0 (CLI::Success). `fn` returns nothing or the
// command's exit status (CommandExit when it is not 0).
template <typename Fn> void run_command(Fn&& fn) {
  int status = 0;
  try {
    if constexpr (std::is_void_v<std::invoke_result_t<Fn&>>)
      fn();
    else
      status = fn();
  } catch (const InputError& e) {
    fmt::print(stderr, "aniso: error: {}\n", terminal_text(e.what()));
    throw CLI::RuntimeError(2);
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "aniso: error: out of memory\n");
    throw CLI::RuntimeError(1);
  } catch (const std::exception& e) {
    fmt::print(stderr, "aniso: error: {}\n", terminal_text(e.what()));
    throw CLI::RuntimeError(1);
  }
  if (status != 0) throw CommandExit{status};
  throw CLI::Success();
}

// The scripting commands (exact formats; other tools and tests depend on them, docs/cli.md), each
// in cmd_<name>.cpp: eval, sample, albedo, fresnel; metals, presets and models for discovery.
void add_eval_command(CLI::App& app);
void add_sample_command(CLI::App& app);
void add_albedo_command(CLI::App& app);
void add_fresnel_command(CLI::App& app);
void add_metals_command(CLI::App& app);
void add_presets_command(CLI::App& app);
void add_models_command(CLI::App& app);

// render: a scene file, a material's preview scene or the gallery (cmd_render.cpp, docs/scenes.md).
void add_render_command(CLI::App& app);

// fit and fit --compare (cmd_fit.cpp, docs/fitting.md).
void add_fit_command(CLI::App& app);

// fit-db: every model on every material of a database (cmd_fit_db.cpp, docs/fit-db.md). main()
// calls run_fit_db for `aniso fit-db ...` before parsing: it runs python/aniso/fit_db.py.
void add_fit_db_command(CLI::App& app);
int run_fit_db(int argc, char** argv);

// export-glsl and export-brdf (cmd_export.cpp, docs/glsl.md).
void add_export_commands(CLI::App& app);

// export --to TARGET: Blender, Mitsuba 3, pbrt-v4, MaterialX, glTF (cmd_export_targets.cpp, docs/export.md).
void add_export_target_command(CLI::App& app);

// export-rgl: an RGL tensor file (.bsdf) for pbrt-v4 and Mitsuba 3 (cmd_rgl.cpp, docs/rgl.md).
void add_rgl_command(CLI::App& app);

// view: the interactive explorer (cmd_view.cpp, view_app.cpp, docs/explorer.md).
void add_view_command(CLI::App& app);

// web-data and serve: the browser explorer's generated data and its local server (cmd_web.cpp, docs/web.md).
void add_web_commands(CLI::App& app);

}  // namespace aniso
