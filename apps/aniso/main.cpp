// aniso: the command-line tool (docs/cli.md). The app, its global options (--help, --version),
// the dispatch of argv to the subcommands (apps/aniso/cmd_<name>.cpp, commands.h) with the
// messages for a missing or unknown command or option, and the exit status: 0, 1 for a failure
// that is not the input's fault, 2 for bad input or a bad command line, and 1 when stdout did not
// take everything written to it.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <unistd.h>

#include "aniso/version.h"
#include "commands.h"
#include "io/json_read.h"
#include "io/names.h"

namespace aniso {
namespace {

// Whether everything written to stdout reached it (closed stdout, a full disk, a closed pipe):
// "" or the message. Help and version text goes through CLI11's std::cout, which shares stdio's
// buffer (sync_with_stdio), so one flush checks both.
std::string stdout_error() {
  errno = 0;
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.good();
  if (!failed) return {};
  // A write that failed before (std::endl's flush of a closed stdout) left no errno: ask the
  // descriptor itself (fcntl sets EBADF for a closed one).
  if (errno == 0) (void)fcntl(STDOUT_FILENO, F_GETFD);
  return fmt::format("stdout: write error: {}", errno ? std::strerror(errno) : "output failed");
}

// The names a command's options are typed with ("--material", "-m").
std::vector<std::string> option_names(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::Option* o : cmd.get_options()) {
    for (const std::string& l : o->get_lnames()) out.push_back("--" + l);
    for (const std::string& c : o->get_snames()) out.push_back("-" + c);
  }
  return out;
}

// A mistyped option would otherwise be reported by CLI11 as a missing required one ("--material is
// required" for --materail) or as an unexpected argument. The first argument from argv[first] on
// that looks like an option ("--word", "-x") and that `cmd` does not know, named with the nearest
// spellings; "" when there is none. Values such as "-1" or "-0.5" are not options.
std::string unknown_option_message(const CLI::App& cmd, const std::string& command, int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    const std::string_view t = argv[i];
    if (t == "--") break;
    const bool long_form = t.size() > 2 && t.substr(0, 2) == "--";
    const bool short_form = t.size() == 2 && t[0] == '-' && std::isalpha(static_cast<unsigned char>(t[1]));
    if (!long_form && !short_form) continue;
    const std::string name(t.substr(0, t.find('=')));
    if (cmd.get_option_no_throw(name)) continue;
    std::string near = nearest_names(name, option_names(cmd));
    near.erase(std::remove(near.begin(), near.end(), '"'), near.end());
    return fmt::format("unknown option {}{}{} (`{} --help` lists the options)", text_escape(name),
                       command.empty() ? "" : " for " + command, near.empty() ? "" : fmt::format("; did you mean {}?", near),
                       command.empty() ? "aniso" : command);
  }
  return {};
}

// The commands and what they do, for `aniso` alone and an unknown command.
std::string command_list(const CLI::App& app) {
  std::string out = "usage: aniso COMMAND [OPTIONS] (aniso COMMAND --help for its options)\ncommands:\n";
  for (const CLI::App* sub : app.get_subcommands({}))
    out += fmt::format("  {:<13} {}\n", sub->get_name(), sub->get_description());
  return out;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) {
  using namespace aniso;
  // A closed pipe (`aniso sample ... | head`) is a write error with a message and exit 1
  // (docs/cli.md, "Exit status"), not death by SIGPIPE: every write to stdout is checked.
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App app{"aniso: anisotropic and measured reflectance (models, sampling, metals, rendering)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("aniso ") + ANISO_VERSION);
  // --help shows the defaults that are values (capture_default_str); the others ("the scene's",
  // "all cores") are said in the option's text.

  add_eval_command(app);
  add_sample_command(app);
  add_albedo_command(app);
  add_fresnel_command(app);
  add_metals_command(app);
  add_presets_command(app);
  add_models_command(app);
  add_render_command(app);
  add_export_commands(app);
  add_export_target_command(app);
  add_rgl_command(app);
  add_fit_command(app);
  add_fit_db_command(app);
  add_view_command(app);
  add_web_commands(app);

  // `aniso` alone: the commands. An unknown command would otherwise be reported by CLI11 as "A
  // subcommand is required", an unknown option as a missing one.
  if (argc == 1) {
    fmt::print(stderr, "aniso: error: no command given\n{}", command_list(app));
    return 2;
  }
  if (std::string_view(argv[1]) == "fit-db") return run_fit_db(argc, argv);
  if (argv[1][0] != '-') {
    std::vector<std::string> names;
    const CLI::App* cmd = nullptr;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names.push_back(sub->get_name());
      if (sub->check_name(argv[1])) cmd = sub;
    }
    if (!cmd) {
      std::string near = nearest_names(argv[1], names);
      near.erase(std::remove(near.begin(), near.end(), '"'), near.end());
      fmt::print(stderr, "aniso: error: unknown command \"{}\"{}\n{}", text_escape(argv[1]),
                 near.empty() ? "" : fmt::format("; did you mean {}?", near), command_list(app));
      return 2;
    }
    // A command that takes any arguments (the render-only build's fit and export: cmd_render_only.cpp)
    // answers for itself.
    if (const std::string msg = cmd->get_allow_extras()
                                    ? std::string()
                                    : unknown_option_message(*cmd, fmt::format("aniso {}", cmd->get_name()), argc, argv, 2);
        !msg.empty()) {
      fmt::print(stderr, "aniso: error: {}\n", msg);
      return 2;
    }
  } else if (const std::string msg = unknown_option_message(app, "", argc, argv, 1); !msg.empty()) {
    fmt::print(stderr, "aniso: error: {}\n", msg);
    return 2;
  }
  // The exit status once stdout is known to hold everything written to it (exit 1 otherwise,
  // unless the command already failed with 2).
  const auto finish = [](int rc) {
    const std::string err = stdout_error();
    if (err.empty()) return rc;
    fmt::print(stderr, "aniso: error: {}\n", err);
    return rc == 0 ? 1 : rc;
  };
  try {
    app.parse(argc, argv);
  } catch (const CommandExit& e) {
    // A command that ended with a status of its own (an interrupted render: 130) after writing
    // what it had: that status, once stdout is known to hold it.
    return finish(e.status);
  } catch (const CLI::RuntimeError& e) {
    // A command run inside CLI11's callback (run_command, commands.h) has printed its message and
    // chosen the exit status itself: 2 for bad input, 1 for a write error. A failed one is not
    // checked again: its own message may already be stdout's write error (export-glsl without -o
    // > /dev/full), and one error is one line (docs/cli.md, "Exit status").
    return e.get_exit_code() == 0 ? finish(0) : e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help); every command-line error exits 2, like input errors.
    // A command that succeeded ends parsing with CLI::Success, exit 0.
    const int code = app.exit(e);
    return finish(code == 0 ? 0 : 2);
  }
  // No command ran: `fit-db` after a global option (main() hands it to run_fit_db only as the
  // first argument).
  return finish(1);
}
