// measured/measured.cpp: sampling tables, the registry of loaded files, recognition by sha256.
#include "aniso/measured/measured.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

#include <fmt/format.h>
#include <openssl/evp.h>
#include <tbb/parallel_for.h>

#include "aniso/io/input_error.h"

namespace aniso {
namespace embedded {
extern const std::string_view merl100_sha256_csv;
}

size_t MeasuredData::sampling_bytes() const {
  return sizeof(double) * (marginal_cdf.size() + conditional_cdf.size() + v_edges.size() + cell_solid_angle.size());
}

namespace {

// Normalises the running sums cdf[1..n] (cdf[0] = 0) to a cdf ending at exactly 1; an all-zero
// row becomes uniform (never chosen when its own mass is 0, and a valid density if it is).
void normalise_cdf(double* cdf, int n) {
  const double total = cdf[n];
  for (int k = 0; k <= n; ++k) cdf[k] = total > 0.0 ? cdf[k] / total : double(k) / n;
  cdf[n] = 1.0;
}

}  // namespace

std::shared_ptr<const MeasuredData> make_measured(MerlBrdf brdf, std::string source) {
  if (brdf.table.size() != 3 * size_t(MerlLayout::kBins))
    throw InputError(
        fmt::format("{}: a MERL table has {} values, got {}", source, 3 * size_t(MerlLayout::kBins), brdf.table.size()));
  const auto start = std::chrono::steady_clock::now();
  auto d = std::make_shared<MeasuredData>();
  d->source = std::move(source);
  d->brdf = std::move(brdf);
  d->missing = d->brdf.missing_count();
  constexpr int H = MerlLayout::kThetaH;
  const int O = kMeasuredThetaOBins, P = kMeasuredPhiHBins;
  d->theta_o_bins = O;
  d->phi_h_bins = P;
  // theta_h cells are MERL's: edges theta_i = (i / 90)^2 pi / 2; v = 1 - cos theta = 2 sin^2(theta / 2)
  // (no cancellation for the smallest cells, whose v is ~1e-8).
  d->v_edges.resize(H + 1);
  for (int i = 0; i <= H; ++i) {
    const double u = double(i) / H, theta = u * u * M_PI / 2.0, s = std::sin(theta / 2.0);
    d->v_edges[i] = 2.0 * s * s;
  }
  d->cell_solid_angle.resize(H);
  for (int i = 0; i < H; ++i) d->cell_solid_angle[i] = (d->v_edges[i + 1] - d->v_edges[i]) * 2.0 * M_PI / P;
  d->marginal_cdf.assign(size_t(O) * (H + 1), 0.0);
  d->conditional_cdf.assign(size_t(O) * H * (P + 1), 0.0);
  const double* table = d->brdf.table.data();
  // Cell masses: the integral over the cell of f cos(theta_i) |d omega_i / d omega_h| d omega_h,
  // with |d omega_i / d omega_h| = 4 wo.h, by the midpoint rule on 2 x 2 points uniform in solid
  // angle (f is the mean of the three channels), for wo at the centre of its viewing-angle bin.
  constexpr int S = 2;
  tbb::parallel_for(0, O, [&](int o) {
    const double theta_o = (o + 0.5) / O * (M_PI / 2.0);
    const Vec3d wo(std::sin(theta_o), 0.0, std::cos(theta_o));
    double* mcdf = d->marginal_cdf.data() + size_t(o) * (H + 1);
    for (int i = 0; i < H; ++i) {
      double* ccdf = d->conditional_cdf.data() + (size_t(o) * H + i) * (P + 1);
      for (int j = 0; j < P; ++j) {
        double sum = 0.0;
        for (int a = 0; a < S; ++a)
          for (int b = 0; b < S; ++b) {
            const double v = d->v_edges[i] + (d->v_edges[i + 1] - d->v_edges[i]) * (a + 0.5) / S;
            const double sin_h = std::sqrt(std::max(0.0, v * (2.0 - v))), phi = (j + (b + 0.5) / S) * 2.0 * M_PI / P;
            const Vec3d h(sin_h * std::cos(phi), sin_h * std::sin(phi), 1.0 - v);
            const double woh = glm::dot(wo, h);
            if (!(woh > 0.0)) continue;
            const Vec3d wi = reflect_about(wo, h);
            if (!above_horizon(wi)) continue;
            sum += average(merl_lookup(table, wi, wo)) * wi.z * 4.0 * woh;
          }
        ccdf[j + 1] = ccdf[j] + sum / (S * S) * d->cell_solid_angle[i];
      }
      mcdf[i + 1] = mcdf[i] + ccdf[P];
      normalise_cdf(ccdf, P);
    }
    normalise_cdf(mcdf, H);
  });
  d->table_build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

std::string sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open", path));
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("sha256: OpenSSL EVP init failed");
  std::vector<char> buf(size_t(1) << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    if (in.gcount() > 0 && EVP_DigestUpdate(ctx.get(), buf.data(), size_t(in.gcount())) != 1)
      throw std::runtime_error("sha256: OpenSSL EVP update failed");
  }
  if (in.bad()) throw InputError(fmt::format("{}: read error", path));
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_DigestFinal_ex(ctx.get(), md, &len) != 1) throw std::runtime_error("sha256: OpenSSL EVP final failed");
  std::string hex;
  for (unsigned int i = 0; i < len; ++i) hex += fmt::format("{:02x}", md[i]);
  return hex;
}

namespace {

// name by sha256, from the embedded CSV (data/merl/merl100_sha256.csv: material,lfs_sha256,size).
const std::map<std::string, std::string, std::less<>>& merl_hashes() {
  static const auto table = [] {
    std::map<std::string, std::string, std::less<>> m;
    std::string_view text = embedded::merl100_sha256_csv;
    while (!text.empty()) {
      const size_t eol = text.find('\n');
      const std::string_view line = text.substr(0, eol);
      text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
      if (line.empty() || line[0] == '#') continue;
      const size_t c1 = line.find(','), c2 = line.find(',', c1 == std::string_view::npos ? c1 : c1 + 1);
      if (c1 == std::string_view::npos || c2 == std::string_view::npos) continue;
      const std::string_view name = line.substr(0, c1), hash = line.substr(c1 + 1, c2 - c1 - 1);
      if (hash.size() == 64) m.emplace(std::string(hash), std::string(name));
    }
    return m;
  }();
  return table;
}

}  // namespace

std::string merl_material_name(std::string_view sha256_hex) {
  const auto& m = merl_hashes();
  const auto it = m.find(sha256_hex);
  return it == m.end() ? std::string() : it->second;
}
size_t merl_known_count() { return merl_hashes().size(); }

std::shared_ptr<const MeasuredData> load_measured(const std::string& path) {
  namespace fs = std::filesystem;
  // Registry key: the canonical path with the file's size and modification time, so that a file
  // rewritten during the run is read again.
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  std::string key = ec ? path : canonical.string();
  if (fs::is_regular_file(path, ec)) {
    const auto size = fs::file_size(path, ec);
    const auto mtime = fs::last_write_time(path, ec).time_since_epoch().count();
    key += fmt::format("|{}|{}", size, mtime);
  }
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const MeasuredData>> registry;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = registry.find(key); it != registry.end()) return it->second;
  }
  MerlBrdf brdf = read_merl(path);
  // The hash reads the file a second time: a FIFO or a pipe has given its bytes to read_merl and
  // would block, so it stays unrecognised (no sha256).
  const std::string hash = fs::is_regular_file(path, ec) ? sha256_file(path) : std::string();
  auto built = make_measured(std::move(brdf), path);
  auto d = std::const_pointer_cast<MeasuredData>(built);
  d->sha256 = hash;
  d->merl_name = merl_material_name(hash);
  const std::lock_guard<std::mutex> lock(mutex);
  return registry.emplace(key, std::move(built)).first->second;
}

std::string describe_measured(const MeasuredData& d) {
  const std::string what = d.merl_name.empty()
                               ? fmt::format("a MERL-format table, not one of the {} MERL database files (sha256 {})",
                                             merl_known_count(), d.sha256.empty() ? "none" : d.sha256)
                               : fmt::format("MERL BRDF database material {} (sha256 {})", d.merl_name, d.sha256);
  return fmt::format("{}: {}; {} missing bins; sampling tables {:.1f} MB built in {:.2f} s", d.source, what, d.missing,
                     double(d.sampling_bytes()) / 1e6, d.table_build_seconds);
}

}  // namespace aniso
