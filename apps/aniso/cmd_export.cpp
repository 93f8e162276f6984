// apps/aniso/cmd_export.cpp: `aniso export-glsl` and `aniso export-brdf` (docs/glsl.md).
// The material is read and built exactly as `aniso eval` reads it, so both reject the same
// materials with the same InputError; the file is written atomically (io/atomic_file.h), so a
// failure leaves no partial file.
#include <memory>
#include <string>

#include <fmt/format.h>

#include "aniso/gl/glsl_export.h"
#include "aniso/io/input_error.h"
#include "aniso/io/materials.h"
#include "commands.h"

namespace aniso {

namespace {

// As cmd_eval: load (validate) and build (the builder's own checks), then generate.
MaterialDesc load_checked(const std::string& material) {
  MaterialDesc d = load_material(material);
  (void)build_material<double>(d);
  return d;
}

}  // namespace

void add_export_commands(CLI::App& app) {
  struct Args {
    std::string material, output, tables;
    bool full = false;
  };
  auto args = std::make_shared<Args>();
  auto* glsl = app.add_subcommand("export-glsl",
                                  "write the material as one self-contained GLSL source (aniso_f, aniso_pdf, "
                                  "aniso_sample, aniso_f_world)");
  glsl->add_option("--material,-m", args->material, kMaterialHelp)->required();
  glsl->add_option("-o,--output", args->output, "output file (default: stdout)");
  glsl->add_flag("--full", args->full, "the whole GLSL library, not only the functions the material uses");
  glsl->add_option("--tables", args->tables,
                   "where a measured material (.bsdf, .binary) writes its tables, raw float32 for a texture (default: the "
                   "output file with .tables appended; docs/glsl.md)");
  glsl->callback([args] {
    run_command([&] {
      const MaterialDesc d = load_checked(args->material);
      const std::string tables = gl::export_glsl_tables(d);
      if (tables.empty() && !args->tables.empty())
        throw InputError(fmt::format("--tables {}: {} is an analytic material, it has no tables", args->tables, args->material));
      std::string tables_path = args->tables;
      if (!tables.empty() && tables_path.empty()) {
        if (args->output.empty())
          throw InputError(
              fmt::format("{}: a measured material's shader needs its tables file: give -o FILE (the tables go to FILE.tables) "
                          "or --tables FILE",
                          args->material));
        tables_path = args->output + ".tables";
      }
      const std::string shader = gl::export_glsl(d, args->material, args->full, tables_path);
      if (!tables.empty()) write_atomically(tables_path, tables);
      write_atomically(args->output, shader);
    });
  });
  auto* brdf = app.add_subcommand("export-brdf", "write the material as a Disney BRDF Explorer .brdf file");
  brdf->add_option("--material,-m", args->material, kMaterialHelp)->required();
  brdf->add_option("-o,--output", args->output, "output file (default: stdout)");
  brdf->callback([args] {
    run_command([&] { write_atomically(args->output, gl::export_brdf(load_checked(args->material), args->material)); });
  });
}

}  // namespace aniso
