// apps/aniso/cli_common.h: what the subcommands (cmd_<name>.cpp) share: how numbers are printed,
// how output is written (every write checked: a full disk or a closed pipe is exit 1 with a
// message, docs/cli.md "Exit status"), and the option validators that read numbers as
// io/text_input.h does (decimal only, finite, in range).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace aniso {

// A number as the scripting commands print it: 9 significant digits, never "-0".
std::string num(double x);

// The help text of every --material option: the forms io/materials.h's load_material reads.
inline constexpr const char* kMaterialHelp = "preset name, JSON file, inline JSON object, MERL .binary or RGL .bsdf file";

// Every write to stdout goes through here: a short write (a full disk, a closed pipe) is an error
// with a message and exit 1, never a silent exit 0 (docs/cli.md, "Exit status").
void write_stdout(std::string_view text);
void flush_stdout();

// Writes all of `text` to an open stream and flushes it; a short write or a failed flush (a full
// disk, a closed pipe) is an error, exit 1 (docs/cli.md, "Exit status"), never a silent exit 0.
void write_all(std::FILE* f, const std::string& text, const std::string& what);

// Writes text to `path` with io::write_file_atomically (io/atomic_file.h); "" or "-" is stdout.
// InputError for a directory or a path that cannot be created, exit 1 for a failed write.
void write_atomically(const std::string& path, const std::string& text);

// For a command that writes several files: checks, before any is written, that `path` can be
// written (not a directory; its folder exists, is a folder and is writable), else InputError naming
// `option` (exit 2, docs/cli.md "Exit status": nothing written).
void check_writable(const std::string& path, std::string_view option);

// A numeric option's range check that also rejects NaN (CLI11's Range lets NaN through: every
// comparison with NaN is false) and says what the option means by its range.
CLI::Validator finite_range(double lo, double hi);

// A whole-number option, decimal only (CLI11 would read "010" as octal 8, and wrap "-1" for an
// unsigned seed): checked by io/text_input.h's rule, then handed to CLI11 in canonical form.
CLI::Validator whole_range(int64_t lo, int64_t hi);

// A number option's value, decimal only (CLI11 itself would read "0x1", "nan" and "inf"), range
// checked by the command.
CLI::Validator decimal_value();

// A seed option: a whole number in [0, 2^64 - 1], decimal only, handed to CLI11 in canonical form.
CLI::Validator seed_value();

}  // namespace aniso
