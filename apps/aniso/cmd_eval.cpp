// apps/aniso/cmd_eval.cpp: `aniso eval -m MATERIAL`, f and pdf of direction pairs read on stdin
// (docs/cli.md): 'wi.x wi.y wi.z wo.x wo.y wo.z' or, with --angles, 'theta_i phi_i theta_o phi_o'
// lines in, 'f_r f_g f_b pdf' lines out, 9 significant digits, computed in double precision.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <unistd.h>

#include "aniso/batch/batch.h"
#include "aniso/io/materials.h"
#include "commands.h"
#include "io/text_input.h"

namespace aniso {
namespace {

using Mat = MaterialT<double>;

// One line of stdin without its newline; false at the end of input. A read error (a directory as
// stdin, a closed descriptor) is an error, not the end of input; lines are capped at 1 MiB (a
// direction pair needs under 200 bytes) so that a line without newline cannot exhaust memory.
// Byte by byte (getc_unlocked, no lock per byte): fgets cannot tell a NUL byte from the end of what
// it read, so with fgets a line holding a NUL would lose its rest and be joined to the next one.
bool read_stdin_line(std::string& line, size_t line_no) {
  constexpr size_t kMaxLine = size_t(1) << 20;
  line.clear();
  int c;
  while ((c = getc_unlocked(stdin)) != EOF) {
    if (c == '\n') return true;
    line.push_back(char(c));
    if (line.size() > kMaxLine) throw InputError(fmt::format("stdin line {}: longer than 1 MiB", line_no));
  }
  if (std::ferror(stdin)) throw InputError(fmt::format("stdin: read error after line {}: {}", line_no - 1, std::strerror(errno)));
  return !line.empty();  // a last line without newline
}

// Reads direction-pair lines (io/text_input.h) and writes 'f_r f_g f_b pdf' per line.
// Piped input: every line is checked before anything is printed, so a bad line leaves no
// half-written output. On a terminal each result is printed as its line is entered (a bad line
// still ends the command with exit 2).
// Piped input is evaluated in blocks of kEvalBlock pairs; a block of kEvalBatchThreshold pairs or
// more goes through the batch path on all cores, with the scalar kernels (batch::Kernels::Scalar),
// so that a line's output never depends on how many lines came with it: the SIMD twins agree to
// ~1e-14 relative in double, which still flips a 9th printed digit now and then (within the first
// 2000 numbers of tests/test_batch.cpp's input). Below it, the plain loop.
// Memory stays bounded whatever the input's length: the output waits in memory up to
// kEvalMemory bytes, beyond that in an unnamed temporary file (EvalSpool), until the input ends.
constexpr size_t kEvalBatchThreshold = 1024, kEvalBlock = size_t(1) << 16, kEvalMemory = size_t(16) << 20;

// The output of piped `aniso eval` while the input is still being checked: in memory, then, past
// kEvalMemory bytes, in a temporary file in $TMPDIR (or /tmp), unlinked at once so that nothing is
// left behind whatever ends the program. A temporary file rather than streaming: a bad line must
// leave stdout empty (docs/cli.md, "Output streams").
class EvalSpool {
 public:
  ~EvalSpool() {
    if (file_) std::fclose(file_);
  }
  void add(std::string& text) {
    if (!file_ && text.size() <= kEvalMemory) return;
    if (!file_) open();
    if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
      throw std::runtime_error(fmt::format("eval: temporary file in {}: write error: {}", dir_, std::strerror(errno)));
    text.clear();
  }
  // Everything to stdout: the temporary file's contents, then `rest`.
  void finish(const std::string& rest) {
    if (file_) {
      if (std::fflush(file_) != 0 || std::fseek(file_, 0, SEEK_SET) != 0)
        throw std::runtime_error(fmt::format("eval: temporary file in {}: write error: {}", dir_, std::strerror(errno)));
      std::vector<char> buf(size_t(1) << 20);
      size_t n;
      while ((n = std::fread(buf.data(), 1, buf.size(), file_)) > 0) write_stdout(std::string_view(buf.data(), n));
      if (std::ferror(file_))
        throw std::runtime_error(fmt::format("eval: temporary file in {}: read error: {}", dir_, std::strerror(errno)));
    }
    write_stdout(rest);
  }

 private:
  void open() {
    std::error_code ec;
    dir_ = std::filesystem::temp_directory_path(ec).string();
    if (ec) dir_ = "/tmp";
    std::string name = (std::filesystem::path(dir_) / "aniso-eval-XXXXXX").string();
    const int fd = mkstemp(name.data());
    if (fd < 0)
      throw std::runtime_error(fmt::format("eval: cannot create a temporary file in {}: {}", dir_, std::strerror(errno)));
    unlink(name.c_str());
    file_ = fdopen(fd, "w+b");
    if (!file_) {
      close(fd);
      throw std::runtime_error(fmt::format("eval: cannot open a temporary file in {}: {}", dir_, std::strerror(errno)));
    }
  }
  std::FILE* file_ = nullptr;
  std::string dir_;
};

// Appends the results of one block of piped pairs to `out`.
void eval_block(const Mat& m, const std::vector<Vec3d>& wis, const std::vector<Vec3d>& wos, std::string& out) {
  const size_t n = wis.size();
  std::vector<RGBT<double>> f(n);
  std::vector<double> pdf(n);
  if (n >= kEvalBatchThreshold) {
    batch::DirectionArray<double> bwi(n), bwo(n);
    for (size_t i = 0; i < n; ++i) bwi.set(i, wis[i]), bwo.set(i, wos[i]);
    batch::ColorArray<double> bf(n);
    batch::evaluate(m, bwi.view(), bwo.view(), n, bf.view(), batch::Threads::All, batch::Kernels::Scalar);
    batch::pdf(m, bwi.view(), bwo.view(), n, pdf.data(), batch::Threads::All, batch::Kernels::Scalar);
    for (size_t i = 0; i < n; ++i) f[i] = bf.get(i);
  } else {
    for (size_t i = 0; i < n; ++i) f[i] = m.f(wis[i], wos[i]), pdf[i] = m.pdf(wis[i], wos[i]);
  }
  for (size_t i = 0; i < n; ++i) out += fmt::format("{} {} {} {}\n", num(f[i].x), num(f[i].y), num(f[i].z), num(pdf[i]));
}

int cmd_eval(const std::string& material, bool angles) {
  const Mat m = build_material<double>(load_material(material));
  const bool interactive = isatty(STDIN_FILENO) != 0;
  std::string out, line;
  size_t line_no = 0;
  std::vector<Vec3d> wis, wos;
  EvalSpool spool;
  while (read_stdin_line(line, ++line_no)) {
    if (is_blank_or_comment(line)) continue;
    const DirectionPair d = parse_direction_line(line, line_no, angles);
    if (!interactive) {  // evaluated by blocks, printed at the end
      wis.push_back(d.wi);
      wos.push_back(d.wo);
      if (wis.size() == kEvalBlock) {
        eval_block(m, wis, wos, out);
        spool.add(out);
        wis.clear();
        wos.clear();
      }
      continue;
    }
    const RGBT<double> f = m.f(d.wi, d.wo);
    out += fmt::format("{} {} {} {}\n", num(f.x), num(f.y), num(f.z), num(m.pdf(d.wi, d.wo)));
    write_stdout(out);
    flush_stdout();
    out.clear();
  }
  eval_block(m, wis, wos, out);
  spool.finish(out);
  return 0;
}

}  // namespace

void add_eval_command(CLI::App& app) {
  struct Args {
    std::string material;
    bool angles = false;
  };
  auto a = std::make_shared<Args>();
  auto* eval = app.add_subcommand("eval", "read 'wi.x wi.y wi.z wo.x wo.y wo.z' lines on stdin, write 'f_r f_g f_b pdf'");
  eval->add_option("--material,-m", a->material, kMaterialHelp)->required();
  eval->add_flag("--angles", a->angles,
                 "input lines are 'theta_i phi_i theta_o phi_o' in degrees (theta from the normal, phi from the tangent)");
  eval->callback([a] { run_command([&] { return cmd_eval(a->material, a->angles); }); });
}

}  // namespace aniso
