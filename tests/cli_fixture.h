// tests/cli_fixture.h: runs the `aniso` executable (ANISO_CLI) as a separate process in a fresh
// temporary directory, with stdin from a string and stdout / stderr captured.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "input_error_text.h"

namespace aniso {

namespace fs = std::filesystem;

struct Result {
  std::string out, err;
  int code = -1;  // exit status; 128 + signal if killed by a signal
};

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// What a shell command writes to stdout (and stderr, when it says 2>&1); "" when it cannot start.
inline std::string command_output(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
  }
  return out;
}

// Blender (headless, factory settings) adding a UV sphere, running the exported `script` (its material
// lands on the active object) and then `checks` (Python, with obj the sphere), written to `driver`;
// its output, which ends in ANISO_OK when every check held.
inline std::string blender_on_a_uv_sphere(const fs::path& driver, const std::string& script, const std::string& checks) {
  std::ofstream(driver) << "import bpy\nbpy.ops.mesh.primitive_uv_sphere_add()\nexec(open(r'" << script
                        << "').read())\nobj = bpy.context.view_layer.objects.active\n"
                        << checks << "print('ANISO_OK')\n";
  return command_output("blender -b --factory-startup -P " + shell_quote(driver.string()) + " 2>&1");
}

// A fresh directory (mkdtemp) per test; run() writes stdin, stdout and stderr as files there.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "aniso-cli-XXXXXX").string();
    ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

  Result run(const std::vector<std::string>& args, const std::string& stdin_text = "") {
    const fs::path in = dir_ / "stdin.txt";
    std::ofstream(in, std::ios::binary) << stdin_text;
    return run_redirected(args, "< " + shell_quote(in.string()));
  }

  // The same with the shell redirections given (for example "< /dev/null > /dev/full"); stdout is
  // captured unless the redirections send it elsewhere.
  Result run_redirected(const std::vector<std::string>& args, const std::string& redirections) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    std::error_code ec;
    fs::remove(out, ec);
    std::string cmd = shell_quote(ANISO_CLI);
    for (const std::string& a : args) cmd.append(" ").append(shell_quote(a));
    if (redirections.find('>') == std::string::npos) cmd.append(" > ").append(shell_quote(out.string()));
    cmd.append(" ").append(redirections);
    cmd.append(" 2> ").append(shell_quote(err.string()));
    const int status = std::system(cmd.c_str());
    Result r;
    if (status != -1 && WIFEXITED(status))
      r.code = WEXITSTATUS(status);
    else if (status != -1 && WIFSIGNALED(status))
      r.code = 128 + WTERMSIG(status);
    r.out = read_file(out);
    r.err = read_file(err);
    return r;
  }

  // Bad input: non-zero exit (2, the tool's code for input errors), every expected substring on
  // stderr, and nothing at all on stdout.
  void expect_input_error(const Result& r, const std::vector<std::string>& expect) {
    EXPECT_EQ(r.code, 2) << "stderr: " << r.err;
    EXPECT_EQ(r.out, "") << "stdout must stay empty on error";
    EXPECT_FALSE(r.err.empty());
    for (const std::string& s : expect) EXPECT_TRUE(contains(r.err, s)) << "\"" << s << "\" not in stderr: " << r.err;
  }

  fs::path dir_;
};

}  // namespace aniso
