// apps/aniso/cmd_fit_db.cpp: `aniso fit-db INPUTS... --models ... -o DIR` (docs/fit-db.md). The
// scheduling lives in the Python package (python/aniso/fit_db.py): Dask, which runs the tasks on a
// cluster, is a Python engine, and the local pool and the cluster share one implementation there.
// This command only finds an interpreter and the package and replaces itself with
// `python3 -c <run aniso.fit_db.main>` (execv: Ctrl-C, the exit status and the streams are the
// Python program's own).
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.h"

#ifndef ANISO_PYTHON_EXECUTABLE
#define ANISO_PYTHON_EXECUTABLE "/usr/bin/python3"
#endif
#ifndef ANISO_PYTHON_INSTALL_DIR
#define ANISO_PYTHON_INSTALL_DIR "lib/python3/dist-packages"
#endif

namespace aniso {
namespace {

namespace fs = std::filesystem;

// The folder holding the aniso package next to this executable: the build tree
// (build/<preset>/bin/aniso -> build/<preset>/python/aniso) or an install prefix
// (<prefix>/bin/aniso -> <prefix>/lib/python3/dist-packages/aniso). Empty: none found, the
// interpreter's own sys.path decides (a pip install in its venv).
std::string package_root() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path prefix = exe.parent_path().parent_path();
  const fs::path install_dir = ANISO_PYTHON_INSTALL_DIR;
  for (const fs::path& root : {prefix / "python", install_dir.is_absolute() ? install_dir : prefix / install_dir})
    if (fs::is_regular_file(root / "aniso" / "fit_db.py", ec)) return root.string();
  return "";
}

// Run by the interpreter: a clear error, not a traceback, when the package or Dask is missing.
constexpr const char* kLauncher = R"(import sys
try:
    import aniso.fit_db
except ImportError as e:
    sys.stderr.write("aniso: error: fit-db needs the aniso Python package built for this interpreter "
                     "(" + sys.executable + "): " + str(e) + " (make build builds it into build/release/python; "
                     "docs/fit-db.md)\n")
    sys.exit(2)
sys.exit(aniso.fit_db.main(sys.argv[1:]))
)";

}  // namespace

int run_fit_db(int argc, char** argv) {
  const char* env_python = std::getenv("ANISO_PYTHON");
  const std::string python = env_python && *env_python ? env_python : ANISO_PYTHON_EXECUTABLE;
  if (::access(python.c_str(), X_OK) != 0) {
    fmt::print(stderr,
               "aniso: error: fit-db runs in Python: cannot run the interpreter {} ({}); set ANISO_PYTHON to a python3 "
               "with NumPy and the aniso package (docs/fit-db.md)\n",
               python, std::strerror(errno));
    return 2;
  }
#ifdef ANISO_FIT_DB_PRELOAD
  // The sanitizer build: the package's module is instrumented and the interpreter is not, so the
  // interpreter starts with the ASan runtime preloaded (python/CMakeLists.txt; leaks are
  // CPython's own by design).
  ::setenv("LD_PRELOAD", ANISO_FIT_DB_PRELOAD, 1);
  ::setenv("ASAN_OPTIONS", "detect_leaks=0:abort_on_error=1", 1);
#endif
  const std::string root = package_root();
  if (!root.empty()) {
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = old && *old ? root + ":" + old : root;
    ::setenv("PYTHONPATH", path.c_str(), 1);
  }
  std::vector<char*> args;
  std::string dash_c = "-c", launcher = kLauncher;
  args.push_back(const_cast<char*>(python.c_str()));
  args.push_back(dash_c.data());
  args.push_back(launcher.data());
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(python.c_str(), args.data());
  fmt::print(stderr, "aniso: error: fit-db: cannot start {}: {}\n", python, std::strerror(errno));
  return 2;
}

void add_fit_db_command(CLI::App& app) {
  // Listed with the other commands; main() hands `aniso fit-db ...` to run_fit_db before CLI11
  // parses anything (the options are Python's: `aniso fit-db --help`).
  app.add_subcommand("fit-db",
                     "fit every model to every material of a database, on this machine or a Dask cluster "
                     "(results.csv, report.md; resumable): aniso fit-db --help, docs/fit-db.md")
      ->allow_extras()
      ->prefix_command();
}

}  // namespace aniso
