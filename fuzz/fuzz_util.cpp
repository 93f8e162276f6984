// fuzz/fuzz_util.cpp: the shared parts of the fuzz targets (fuzz_util.h).
#include "fuzz_util.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>

namespace aniso::fuzz {

void rejected(const std::exception& e) {
  static const bool verbose = std::getenv("ANISO_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "rejected: %s\n", e.what());
}

const std::string& scratch_dir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/aniso-fuzz-XXXXXX";
    if (!::mkdtemp(templ.data())) {
      std::perror("aniso fuzz: mkdtemp");
      std::abort();
    }
    static const std::string keep = templ;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(keep, ec);
    });
    return templ;
  }();
  return dir;
}

std::string write_scratch_file(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = scratch_dir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  FUZZ_CHECK(out.good());
  return path;
}

namespace {
constexpr double kTiny = std::numeric_limits<double>::min();          // 2.2e-308, smallest normal double
constexpr double kSub = std::numeric_limits<double>::denorm_min();    // 4.9e-324
constexpr double kTinyF = double(std::numeric_limits<float>::min());  // 1.2e-38, smallest normal float
}  // namespace

const FuzzPair kPairs[] = {
    {{0, 0, 1}, {0, 0, 1}},
    {{0.6, 0, 0.8}, {-0.6, 0, 0.8}},  // mirror pair in the tangent plane
    {{0, 0.6, 0.8}, {0, -0.6, 0.8}},  // mirror pair in the bitangent plane
    {{0.3, 0.1, 0.9}, {-0.2, 0.4, 0.8}},
    {{0.6, 0, 0.8}, {0.6, 0, 0.8}},     // retro-reflection
    {{1, 0, 1e-170}, {-1, 0, 1e-170}},  // issue 13: normalize(wi + wo) underflow
    {{1, 0, 1e-120}, {-1, 0, 1e-120}},  // issue 13: mirror pairs near the double range
    {{1, 0, 1e-15}, {1, 0, 1e-15}},     // issue 13: float pdf NaN at wi = wo, z = 1e-15
    {{1, 0, 1e-12}, {-1, 0, 1e-12}},    // at the double horizon cosine
    {{1, 0, 1.0000001e-12}, {-1, 0, 1.0000001e-12}},
    {{1, 0, 1e-6}, {-1, 0, 1e-6}},  // at the float horizon cosine
    {{1, 0, 1.01e-6}, {0, 1, 1.01e-6}},
    {{1, 0, kTinyF}, {-1, 0, kTinyF}},
    {{1, 0, kTiny}, {-1, 0, kTiny}},
    {{1, 0, kSub}, {-1, 0, kSub}},
    {{0, 0, 1}, {1, 0, kTiny}},
    {{0.7071067811865476, 0.7071067811865476, 1e-9}, {0, 0, 1}},
    {{0, 0, 1}, {0, 0, -1}},  // below the horizon: f = pdf = 0
    {{0, 0, -1}, {0.3, 0.1, 0.9}},
    {{1, 0, 0}, {0, 1, 0}},  // exactly on the horizon
};
const size_t kPairCount = sizeof(kPairs) / sizeof(kPairs[0]);

template <typename T> void check_material(const MaterialT<T>& m) {
  using V = Vec3T<T>;
  const auto dir = [](const double* d) {
    // The CLI's normalisation (io/text_input.h): the largest component first, so tiny components survive.
    const double s = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
    const double x = d[0] / s, y = d[1] / s, z = d[2] / s, len = std::sqrt(x * x + y * y + z * z);
    return V(T(x / len), T(y / len), T(z / len));
  };
  for (size_t p = 0; p < kPairCount; ++p) {
    const V wi = dir(kPairs[p].wi), wo = dir(kPairs[p].wo);
    const RGBT<T> f = m.f(wi, wo);
    const T pdf = m.pdf(wi, wo);
    for (int c = 0; c < 3; ++c) FUZZ_CHECK(std::isfinite(f[c]) && f[c] >= T(0));
    FUZZ_CHECK(std::isfinite(pdf) && pdf >= T(0));
    // Sampling from this wo over a small stratified grid of random numbers, including the corners.
    constexpr int kGrid = 4;
    for (int a = 0; a <= kGrid; ++a)
      for (int b = 0; b <= kGrid; ++b)
        for (const double uc : {0.0, 0.37, 0.999999}) {
          const double ux = std::min(double(a) / kGrid, 0.999999), uy = std::min(double(b) / kGrid, 0.999999);
          const BSDFSampleT<T> s = m.sample(wo, T(uc), Vec2T<T>(T(ux), T(uy)));
          if (!s.valid) continue;
          FUZZ_CHECK(std::isfinite(s.wi.x) && std::isfinite(s.wi.y) && std::isfinite(s.wi.z));
          FUZZ_CHECK(std::abs(glm::length(s.wi) - T(1)) < T(1e-3));
          FUZZ_CHECK(s.wi.z > T(0));
          for (int c = 0; c < 3; ++c) FUZZ_CHECK(std::isfinite(s.weight[c]) && s.weight[c] >= T(0));
          FUZZ_CHECK(std::isfinite(s.pdf) && s.pdf > T(0));
        }
  }
}
template void check_material<float>(const MaterialT<float>&);
template void check_material<double>(const MaterialT<double>&);

}  // namespace aniso::fuzz
