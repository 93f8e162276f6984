// apps/aniso/commands.h: subcommands that live in their own files (cmd_<name>.cpp).
#pragma once

#include <CLI/CLI.hpp>

namespace aniso {

// export-glsl and export-brdf (cmd_export.cpp, docs/glsl.md).
void add_export_commands(CLI::App& app);

}  // namespace aniso
