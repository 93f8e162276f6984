// apps/aniso/cmd_export.cpp: `aniso export-glsl` and `aniso export-brdf` (docs/glsl.md).
// The material is read and built exactly as `aniso eval` reads it, so both reject the same
// materials with the same InputError; the file is written atomically (io/atomic_file.h), so a
// failure leaves no partial file.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "aniso/gl/glsl_export.h"
#include "aniso/io/materials.h"
#include "commands.h"
#include "io/atomic_file.h"

namespace aniso {

// Writes all of `text` to an open stream and flushes it; a short write or a failed flush (a full
// disk, a closed pipe) is an error, exit 1 (docs/cli.md, "Exit status"), never a silent exit 0.
void write_all(std::FILE* f, const std::string& text, const std::string& what) {
  if (std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fflush(f) != 0 || std::ferror(f))
    throw std::runtime_error(fmt::format("{}: write error: {}", what, std::strerror(errno)));
}

// stdout for "" and "-"; a file otherwise, through the one atomic writer (io/atomic_file.h: a
// temporary file renamed into place, modes and symbolic links kept, nothing left behind on
// failure or on SIGTERM; a FIFO or a device written in place).
void write_atomically(const std::string& path, const std::string& text) {
  if (path.empty() || path == "-") {
    write_all(stdout, text, "stdout");
    return;
  }
  try {
    io::write_file_atomically(path, text);
  } catch (const io::FileWriteError& e) {
    if (e.reason() == "is a directory") throw InputError(fmt::format("-o {}: is a directory", path));
    if (!e.created()) throw InputError(fmt::format("-o {}: cannot open for writing: {}", path, e.reason()));
    throw std::runtime_error(fmt::format("-o {}: write error: {}", path, e.reason()));
  }
}

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
    std::string material, output;
    bool full = false;
  };
  auto args = std::make_shared<Args>();
  auto* glsl = app.add_subcommand("export-glsl",
                                  "write the material as one self-contained GLSL source (aniso_f, aniso_pdf, "
                                  "aniso_sample, aniso_f_world)");
  glsl->add_option("--material,-m", args->material, "preset name or JSON file")->required();
  glsl->add_option("-o,--output", args->output, "output file (default: stdout)");
  glsl->add_flag("--full", args->full, "the whole GLSL library, not only the functions the material uses");
  glsl->callback([args] {
    run_command(
        [&] { write_atomically(args->output, gl::export_glsl(load_checked(args->material), args->material, args->full)); });
  });
  auto* brdf = app.add_subcommand("export-brdf", "write the material as a Disney BRDF Explorer .brdf file");
  brdf->add_option("--material,-m", args->material, "preset name or JSON file")->required();
  brdf->add_option("-o,--output", args->output, "output file (default: stdout)");
  brdf->callback([args] {
    run_command([&] { write_atomically(args->output, gl::export_brdf(load_checked(args->material), args->material)); });
  });
}

}  // namespace aniso
