// apps/aniso/commands.h: subcommands that live in their own files (cmd_<name>.cpp).
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "aniso/io/params.h"
#include "io/text_input.h"

namespace aniso {

// Writes text to `path` with io::write_file_atomically (io/atomic_file.h); "" or "-" is stdout.
// InputError for a directory or a path that cannot be created, exit 1 for a failed write.
void write_atomically(const std::string& path, const std::string& text);

// Runs a command inside CLI11's callback with main()'s error conventions: InputError exits 2 with
// "aniso: error: <message>"; success ends parsing with exit code 0 (CLI::Success).
template <typename Fn> void run_command(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    throw CLI::RuntimeError(2);
  } catch (const std::exception& e) {
    fmt::print(stderr, "aniso: error: {}\n", e.what());
    throw CLI::RuntimeError(1);
  }
  throw CLI::Success();
}

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
