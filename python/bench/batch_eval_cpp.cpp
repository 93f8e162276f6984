// python/bench/batch_eval_cpp.cpp: the C++ side of the Python bindings' benchmark and tests. Reads N
// direction pairs (float64, "wi.x wi.y wi.z wo.x wo.y wo.z" per row, raw, as NumPy's tofile writes
// them), converts them once into the batch API's structure of arrays, and
//   time PAIRS.bin MATERIAL REPS   times batch::evaluate (Threads::All, the SIMD kernels) on all N,
//                                  REPS times after a warm-up call, and prints the best wall-clock
//                                  and the best process CPU seconds, for float and then double,
//                                  then the same for batch::evaluate_interleaved on the pairs as
//                                  (N, 3) rows: "wall cpu wall cpu wall cpu wall cpu target"
//                                  (python/bench/bench_eval.py)
//   dump PAIRS.bin MATERIAL OUT    writes batch::evaluate's f (N x 3, row by row) and batch::pdf
//                                  (N) in float, then in double, raw (python/tests/test_eval.py)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "aniso/batch/batch.h"
#include "aniso/io/materials.h"

using namespace aniso;

template <typename T> struct Pairs {
  batch::DirectionArray<T> wi, wo;
  size_t n = 0;
  explicit Pairs(const std::vector<double>& rows) : wi(rows.size() / 6), wo(rows.size() / 6), n(rows.size() / 6) {
    for (size_t i = 0; i < n; ++i) {
      const double* r = &rows[6 * i];
      wi.set(i, Vec3T<T>(T(r[0]), T(r[1]), T(r[2])));
      wo.set(i, Vec3T<T>(T(r[3]), T(r[4]), T(r[5])));
    }
  }
};

// CPU time of the whole process (every thread): what the work costs, whatever else the machine runs.
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// {best wall-clock seconds, best process CPU seconds} of `reps` calls after one warm-up call.
template <typename T> std::vector<double> time_evaluate(const MaterialDesc& desc, const std::vector<double>& rows, int reps) {
  const MaterialT<T> m = build_material<T>(desc);
  const Pairs<T> p(rows);
  batch::ColorArray<T> f(p.n);
  batch::evaluate(m, p.wi.view(), p.wo.view(), p.n, f.view());
  double wall = 1e300, cpu = 1e300;
  for (int k = 0; k < reps; ++k) {
    const double cpu_start = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    batch::evaluate(m, p.wi.view(), p.wo.view(), p.n, f.view());
    wall = std::min(wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    cpu = std::min(cpu, process_cpu_seconds() - cpu_start);
  }
  return {wall, cpu};
}

// The same for evaluate_interleaved: rows in, RGB rows out (the layout of a C-ordered NumPy array).
template <typename T>
std::vector<double> time_evaluate_interleaved(const MaterialDesc& desc, const std::vector<double>& rows, int reps) {
  const MaterialT<T> m = build_material<T>(desc);
  const size_t n = rows.size() / 6;
  std::vector<T> wi(3 * n), wo(3 * n), f(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) wi[3 * i + c] = T(rows[6 * i + c]), wo[3 * i + c] = T(rows[6 * i + 3 + c]);
  const auto call = [&] { batch::evaluate_interleaved(m, {wi.data(), 3}, {wo.data(), 3}, n, f.data()); };
  call();
  double wall = 1e300, cpu = 1e300;
  for (int k = 0; k < reps; ++k) {
    const double cpu_start = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    call();
    wall = std::min(wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    cpu = std::min(cpu, process_cpu_seconds() - cpu_start);
  }
  return {wall, cpu};
}

template <typename T> void dump(const MaterialDesc& desc, const std::vector<double>& rows, std::ofstream& out) {
  const MaterialT<T> m = build_material<T>(desc);
  const Pairs<T> p(rows);
  batch::ColorArray<T> f(p.n);
  std::vector<T> pdf(p.n), aos(3 * p.n);
  batch::evaluate(m, p.wi.view(), p.wo.view(), p.n, f.view());
  batch::pdf(m, p.wi.view(), p.wo.view(), p.n, pdf.data());
  for (size_t i = 0; i < p.n; ++i) aos[3 * i] = f.r[i], aos[3 * i + 1] = f.g[i], aos[3 * i + 2] = f.b[i];
  out.write(reinterpret_cast<const char*>(aos.data()), std::streamsize(aos.size() * sizeof(T)));
  out.write(reinterpret_cast<const char*>(pdf.data()), std::streamsize(pdf.size() * sizeof(T)));
}

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (argc != 5 || (mode != "time" && mode != "dump")) {
    std::fprintf(stderr,
                 "usage: aniso_batch_eval_cpp time PAIRS.bin MATERIAL REPS\n"
                 "       aniso_batch_eval_cpp dump PAIRS.bin MATERIAL OUT.bin\n");
    return 2;
  }
  std::ifstream in(argv[2], std::ios::binary | std::ios::ate);
  if (!in) {
    std::fprintf(stderr, "aniso_batch_eval_cpp: %s: cannot open\n", argv[2]);
    return 2;
  }
  const size_t bytes = size_t(in.tellg());
  in.seekg(0);
  std::vector<double> rows(bytes / sizeof(double) / 6 * 6);
  in.read(reinterpret_cast<char*>(rows.data()), std::streamsize(rows.size() * sizeof(double)));
  try {
    const MaterialDesc desc = load_material(argv[3]);
    if (mode == "time") {
      const int reps = std::max(1, std::stoi(argv[4]));
      const auto f = time_evaluate<float>(desc, rows, reps);
      const auto d = time_evaluate<double>(desc, rows, reps);
      const auto fi = time_evaluate_interleaved<float>(desc, rows, reps);
      const auto di = time_evaluate_interleaved<double>(desc, rows, reps);
      std::printf("%.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %s\n", f[0], f[1], d[0], d[1], fi[0], fi[1], di[0], di[1],
                  batch::simd_target());
    } else {
      std::ofstream out(argv[4], std::ios::binary | std::ios::trunc);
      dump<float>(desc, rows, out);
      dump<double>(desc, rows, out);
      if (!out) throw std::runtime_error(std::string(argv[4]) + ": write failed");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aniso_batch_eval_cpp: %s\n", e.what());
    return 2;
  }
  return 0;
}
