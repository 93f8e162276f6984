// apps/aniso/cmd_render_only.cpp: `fit` and `export` in the executable of the render-only
// configuration (ANISO_RENDER_ONLY, `make render`), which is built without the fitting library
// (aniso_fit: Ceres) and the exports that fit (aniso_export): each says how to build them.
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "commands.h"

namespace aniso {

namespace {

// The command is kept (its name, a line of help, any arguments) so that `aniso fit ...` is
// answered with how to get it, exit 2, instead of CLI11's "unknown command".
void add_missing_command(CLI::App& app, const char* name, const char* what) {
  auto* cmd = app.add_subcommand(name, fmt::format("{} (not in this build: `make build` adds it)", what));
  cmd->allow_extras();
  cmd->callback([name] {
    fmt::print(stderr,
               "aniso: error: `aniso {}` is not in this executable: it was configured by `make render` "
               "(ANISO_RENDER_ONLY=ON: the gallery's libraries only, without Ceres and the fitting library). "
               "`make build` (or cmake -DANISO_RENDER_ONLY=OFF, then cmake --build) builds the full aniso in the "
               "same build directory\n",
               name);
    throw CLI::RuntimeError(2);
  });
}

}  // namespace

void add_fit_command(CLI::App& app) { add_missing_command(app, "fit", "fit a model to measured data (docs/fitting.md)"); }

void add_export_target_command(CLI::App& app) {
  add_missing_command(app, "export", "write the material for a renderer (docs/export.md)");
}

}  // namespace aniso
