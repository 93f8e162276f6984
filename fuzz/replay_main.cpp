// fuzz/replay_main.cpp: the driver a fuzz target is linked with when libFuzzer is not available
// (g++, or clang without libclang-rt-14-dev). It takes libFuzzer's command line: files and
// directories are inputs (a directory: every regular file in it, in name order), arguments that
// start with '-' (libFuzzer's flags, e.g. -max_total_time=10) are ignored. Each input is passed
// to LLVMFuzzerTestOneInput once; a finding aborts the process as under libFuzzer. No search:
// this replays the seed corpus and the regression inputs (docs/testing.md).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {
int run_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "replay: cannot open %s\n", p.c_str());
    return 1;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // A copy in a buffer of exactly its size, so that AddressSanitizer sees a read past the end.
  std::vector<uint8_t> data(bytes.begin(), bytes.end());
  LLVMFuzzerTestOneInput(data.empty() ? nullptr : data.data(), data.size());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  size_t inputs = 0;
  int errors = 0;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (!arg.empty() && arg[0] == '-') continue;
    std::vector<fs::path> files;
    if (fs::is_directory(arg)) {
      for (const auto& e : fs::directory_iterator(arg))
        if (e.is_regular_file()) files.push_back(e.path());
      std::sort(files.begin(), files.end());
    } else {
      files.push_back(arg);
    }
    for (const fs::path& f : files) {
      errors += run_file(f);
      ++inputs;
    }
  }
  std::fprintf(stderr, "replay: %zu inputs, no findings\n", inputs);
  return errors == 0 ? 0 : 1;
}
