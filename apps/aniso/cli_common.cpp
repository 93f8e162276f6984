// apps/aniso/cli_common.cpp: the subcommands' shared output writers and option validators
// (cli_common.h).
#include "cli_common.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "aniso/io/input_error.h"
#include "io/atomic_file.h"
#include "io/text_escape.h"
#include "io/text_input.h"

#include <unistd.h>

namespace aniso {

std::string num(double x) { return fmt::format("{:.9g}", x + 0.0); }  // + 0.0: never print "-0"

void write_stdout(std::string_view text) {
  if (text.empty()) return;
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size())
    throw std::runtime_error(fmt::format("stdout: write error: {}", std::strerror(errno)));
}
void flush_stdout() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw std::runtime_error(fmt::format("stdout: write error: {}", std::strerror(errno)));
}

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

void check_writable(const std::string& path, std::string_view option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(fmt::format("{} {}: is a directory", option, text_escape(path)));
  const fs::path dir = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::exists(dir, ec))
    throw InputError(fmt::format("{} {}: cannot open for writing: the folder {} does not exist", option, text_escape(path),
                                 text_escape(dir.string())));
  if (!fs::is_directory(dir, ec))
    throw InputError(fmt::format("{} {}: {} is not a folder", option, text_escape(path), text_escape(dir.string())));
  if (::access(dir.c_str(), W_OK) != 0)
    throw InputError(fmt::format("{} {}: cannot write in the folder {}: {}", option, text_escape(path), text_escape(dir.string()),
                                 std::strerror(errno)));
}

CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        std::string why;
        const auto v = aniso::parse_decimal(text, &why);
        if (!v) return fmt::format("expected a finite decimal number in [{}, {}], got \"{}\" ({})", lo, hi, text, why);
        if (*v < lo || *v > hi) return fmt::format("{} is not in [{}, {}]", text, lo, hi);
        return {};
      },
      fmt::format("FLOAT in [{}, {}]", lo, hi));
}

CLI::Validator whole_range(int64_t lo, int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        try {
          text = std::to_string(aniso::parse_integer(text, lo, hi, "value"));
        } catch (const aniso::InputError& e) {
          return std::string(e.what()).substr(7);  // drop "value: "
        }
        return {};
      },
      fmt::format("INT in [{}, {}]", lo, hi));
}

CLI::Validator decimal_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string why;
        if (!aniso::parse_decimal(text, &why)) return fmt::format("expected a finite decimal number, got \"{}\" ({})", text, why);
        return {};
      },
      "FLOAT");
}

CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          text = std::to_string(aniso::parse_unsigned(text, UINT64_MAX, "value"));
        } catch (const aniso::InputError& e) {
          return std::string(e.what()).substr(7);
        }
        return {};
      },
      "UINT64");
}

}  // namespace aniso
