// python/bench_eval_cpp.cpp: the C++ half of python/bench_eval.py. Reads N direction pairs
// (float64, wi.xyz wo.xyz per row, the file bench_eval.py writes), converts them to the batch
// API's structure of arrays once, and times batch::evaluate (Threads::All, the SIMD kernels) on
// all N, best of `reps`. Prints "seconds_best seconds_median" for float and for double.
//   aniso_bench_eval_cpp PAIRS.bin MATERIAL REPS
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "aniso/batch/batch.h"
#include "io/materials.h"

using namespace aniso;

template <typename T> std::vector<double> time_evaluate(const MaterialDesc& desc, const std::vector<double>& rows, size_t n, int reps) {
  const MaterialT<T> m = build_material<T>(desc);
  batch::DirectionArray<T> wi(n), wo(n);
  for (size_t i = 0; i < n; ++i) {
    const double* r = &rows[6 * i];
    wi.set(i, Vec3T<T>(T(r[0]), T(r[1]), T(r[2])));
    wo.set(i, Vec3T<T>(T(r[3]), T(r[4]), T(r[5])));
  }
  batch::ColorArray<T> f(n);
  std::vector<double> seconds;
  for (int k = 0; k < reps; ++k) {
    const auto start = std::chrono::steady_clock::now();
    batch::evaluate(m, wi.view(), wo.view(), n, f.view());
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return {seconds.front(), seconds[seconds.size() / 2]};
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: aniso_bench_eval_cpp PAIRS.bin MATERIAL REPS\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  if (!in) {
    std::fprintf(stderr, "aniso_bench_eval_cpp: %s: cannot open\n", argv[1]);
    return 2;
  }
  const size_t bytes = size_t(in.tellg());
  in.seekg(0);
  std::vector<double> rows(bytes / sizeof(double));
  in.read(reinterpret_cast<char*>(rows.data()), std::streamsize(rows.size() * sizeof(double)));
  const size_t n = rows.size() / 6;
  const int reps = std::max(1, std::stoi(argv[3]));
  try {
    const MaterialDesc desc = load_material(argv[2]);
    const auto f = time_evaluate<float>(desc, rows, n, reps);
    const auto d = time_evaluate<double>(desc, rows, n, reps);
    std::printf("%.9g %.9g %.9g %.9g %s\n", f[0], f[1], d[0], d[1], batch::simd_target());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aniso_bench_eval_cpp: %s\n", e.what());
    return 2;
  }
  return 0;
}
