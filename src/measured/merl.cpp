// measured/merl.cpp: MERL .binary read / write / tabulate (format: merl.h, docs/measured.md).
#include "aniso/measured/merl.h"

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "aniso/io/input_error.h"
#include "io/atomic_file.h"

namespace aniso {

// The files are little-endian (MERL wrote them on x86 PCs); so is every machine aniso targets.
static_assert(std::endian::native == std::endian::little, "MERL .binary I/O assumes a little-endian host");

namespace {

constexpr const char* kChannelName[3] = {"R", "G", "B"};

// "channel G, bin (theta_h 3, theta_d 17, phi_d 120)" for the value number n of the data.
std::string describe_value(size_t n) {
  const int channel = int(n / MerlLayout::kBins);
  const int k = int(n % MerlLayout::kBins);
  const int i_phi_d = k % MerlLayout::kPhiD, i_theta_d = (k / MerlLayout::kPhiD) % MerlLayout::kThetaD,
            i_theta_h = k / (MerlLayout::kPhiD * MerlLayout::kThetaD);
  return fmt::format("channel {}, bin (theta_h {}, theta_d {}, phi_d {})", kChannelName[channel], i_theta_h, i_theta_d, i_phi_d);
}

[[noreturn]] void fail(const std::string& path, size_t offset, const std::string& what) {
  throw InputError(fmt::format("{}: byte offset {}: {}", path, offset, what));
}

}  // namespace

RGBT<double> MerlBrdf::lookup(const Vec3T<double>& wi, const Vec3T<double>& wo) const {
  if (table.size() != 3 * size_t(kBins))
    throw std::invalid_argument(
        fmt::format("MerlBrdf::lookup: table has {} values, expected {}", table.size(), 3 * size_t(kBins)));
  return merl_lookup(table.data(), wi, wo);
}

std::pair<Vec3T<double>, Vec3T<double>> MerlBrdf::bin_directions(int i_theta_h, int i_theta_d, int i_phi_d) {
  return HalfDiffGrid{}.directions(i_theta_h, i_theta_d, i_phi_d);
}

std::pair<Vec3T<double>, Vec3T<double>> HalfDiffGrid::directions(int i_theta_h, int i_theta_d, int i_phi_d, int i_phi_h) const {
  const double u = (i_theta_h + 0.5) / n_theta_h;
  const double theta_h = u * u * (M_PI / 2.0);
  const double theta_d = (i_theta_d + 0.5) / n_theta_d * (M_PI / 2.0);
  const double phi_d = (i_phi_d + 0.5) / n_phi_d * phi_d_range;
  // The difference vector d (wi in the frame where h = z) and its mirror about h (wo), rotated by
  // theta_h about the bitangent, then by phi_h about the normal: the inverse of merl_bin()'s
  // rotations.
  const Vec3T<double> d(std::sin(theta_d) * std::cos(phi_d), std::sin(theta_d) * std::sin(phi_d), std::cos(theta_d));
  const double ct = std::cos(theta_h), st = std::sin(theta_h);
  const auto rotate = [&](const Vec3T<double>& v) { return Vec3T<double>(v.x * ct + v.z * st, v.y, -v.x * st + v.z * ct); };
  std::pair<Vec3T<double>, Vec3T<double>> w{rotate(d), rotate(Vec3T<double>(-d.x, -d.y, d.z))};
  if (i_phi_h == 0) return w;  // phi_h = 0: MERL's bins, unrotated (bit for bit what they always were)
  const double phi_h = 2.0 * M_PI * i_phi_h / n_phi_h, cp = std::cos(phi_h), sp = std::sin(phi_h);
  const auto turn = [&](const Vec3T<double>& v) { return Vec3T<double>(v.x * cp - v.y * sp, v.x * sp + v.y * cp, v.z); };
  return {turn(w.first), turn(w.second)};
}

double HalfDiffGrid::weight(int i_theta_h, int i_theta_d) const {
  const double u = (i_theta_h + 0.5) / n_theta_h;
  const double theta_h = u * u * (M_PI / 2.0);
  const double theta_d = (i_theta_d + 0.5) / n_theta_d * (M_PI / 2.0);
  return std::cos(theta_d) * std::sin(theta_h) * std::sin(theta_d) * (2 * i_theta_h + 1);
}

bool MerlBrdf::valid(int i_theta_h, int i_theta_d, int i_phi_d) const {
  const size_t k = size_t(index(i_theta_h, i_theta_d, i_phi_d));
  return table[k] >= 0.0 && table[k + kBins] >= 0.0 && table[k + 2 * size_t(kBins)] >= 0.0;
}

size_t MerlBrdf::missing_count() const {
  size_t n = 0;
  for (size_t k = 0; k < size_t(kBins); ++k)
    n += (table[k] < 0.0 || table[k + kBins] < 0.0 || table[k + 2 * size_t(kBins)] < 0.0) ? 1 : 0;
  return n;
}

MerlBrdf read_merl(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(fmt::format("{}: cannot open: no such file", path));
  if (fs::is_directory(st)) throw InputError(fmt::format("{}: is a directory, expected a MERL .binary file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));

  int32_t dims[3] = {0, 0, 0};
  in.read(reinterpret_cast<char*>(dims), sizeof dims);
  const size_t header_read = size_t(in.gcount());
  if (header_read == 0 && in.eof())
    fail(path, 0,
         fmt::format("empty file; a MERL .binary file is {} bytes (a 12-byte header, then 3 x 90 x 90 x 180 doubles)",
                     MerlBrdf::kFileBytes));
  if (header_read < sizeof dims)
    fail(path, header_read,
         fmt::format("truncated header: the file ends after {} bytes, the header has 12 (three int32: 90 90 180)", header_read));
  constexpr int32_t kExpected[3] = {MerlLayout::kThetaH, MerlLayout::kThetaD, MerlLayout::kPhiD};
  constexpr const char* kDimName[3] = {"theta_h", "theta_d", "phi_d"};
  for (int i = 0; i < 3; ++i)
    if (dims[i] != kExpected[i])
      fail(path, size_t(4 * i),
           fmt::format("header: {} resolution {}, expected {} (a MERL .binary header is the int32s 90 90 180; got {} {} {})",
                       kDimName[i], dims[i], kExpected[i], dims[0], dims[1], dims[2]));

  MerlBrdf m;
  m.table.resize(3 * size_t(MerlLayout::kBins));
  const size_t want = m.table.size() * sizeof(double);
  in.read(reinterpret_cast<char*>(m.table.data()), std::streamsize(want));
  const size_t got = size_t(in.gcount());
  if (got < want) {
    const size_t end = 12 + got;
    fail(path, end,
         fmt::format("truncated: the file ends inside value {} of {} ({}); a MERL .binary file is {} bytes", got / 8,
                     m.table.size(), describe_value(got / 8), MerlBrdf::kFileBytes));
  }
  if (in.peek() != std::char_traits<char>::eof()) {
    const uintmax_t size = fs::file_size(path, ec);
    fail(path, MerlBrdf::kFileBytes,
         fmt::format("trailing data: the file is {} bytes, a MERL .binary file {} (wrong file, or not the 90 x 90 x 180 layout)",
                     ec ? std::string("longer") : fmt::format("{}", size), MerlBrdf::kFileBytes));
  }
  for (size_t n = 0; n < m.table.size(); ++n) {
    const double raw = m.table[n];
    if (!std::isfinite(raw))
      fail(path, 12 + 8 * n,
           fmt::format("{} ({}): expected a finite number (negative marks a missing sample)",
                       std::isnan(raw) ? "NaN" : "infinite value", describe_value(n)));
    if (raw > MerlBrdf::kMaxStored)
      fail(path, 12 + 8 * n,
           fmt::format("{:g} ({}): above {:g}, no measured reflectance (a corrupt file?)", raw, describe_value(n),
                       MerlBrdf::kMaxStored));
    m.table[n] = raw * MerlBrdf::kScale[n / MerlLayout::kBins];
  }
  return m;
}

namespace {

// The stored number whose product with the scale is v, searched within 2 ulps of v / scale (the
// division's rounding): read_merl then gives v back exactly. When no such number exists (v is not
// a product number * scale), v / scale itself.
double stored_number(double v, double scale) {
  const double q = v / scale;
  if (q * scale == v) return q;
  double up = q, down = q;
  for (int step = 0; step < 2; ++step) {
    up = std::nextafter(up, HUGE_VAL);
    down = std::nextafter(down, -HUGE_VAL);
    if (up * scale == v) return up;
    if (down * scale == v) return down;
  }
  return q;
}

}  // namespace

void write_merl(const std::string& path, const MerlBrdf& brdf) {
  if (brdf.table.size() != 3 * size_t(MerlLayout::kBins))
    throw InputError(fmt::format("{}: cannot write a MERL table of {} values, expected {}", path, brdf.table.size(),
                                 3 * size_t(MerlLayout::kBins)));
  std::vector<double> raw(brdf.table.size());
  for (size_t n = 0; n < raw.size(); ++n) {
    if (!std::isfinite(brdf.table[n]))
      throw InputError(fmt::format("{}: cannot write value {} ({}): not finite", path, n, describe_value(n)));
    raw[n] = stored_number(brdf.table[n], MerlBrdf::kScale[n / MerlLayout::kBins]);
    if (raw[n] > MerlBrdf::kMaxStored)
      throw InputError(fmt::format("{}: cannot write value {} ({}): {:g} / sr is above what a MERL file holds ({:g} stored)",
                                   path, n, describe_value(n), brdf.table[n], MerlBrdf::kMaxStored));
  }
  const int32_t dims[3] = {MerlLayout::kThetaH, MerlLayout::kThetaD, MerlLayout::kPhiD};
  io::AtomicFile out(path);
  out.write(dims, sizeof dims);
  out.write(raw.data(), raw.size() * sizeof(double));
  out.commit();
}

MerlBrdf tabulate_merl(const MaterialD& m) {
  MerlBrdf out;
  out.table.assign(3 * size_t(MerlLayout::kBins), 0.0);
  tbb::parallel_for(0, MerlLayout::kThetaH, [&](int i) {
    for (int j = 0; j < MerlLayout::kThetaD; ++j)
      for (int k = 0; k < MerlLayout::kPhiD; ++k) {
        const auto [wi, wo] = MerlBrdf::bin_directions(i, j, k);
        const size_t n = size_t(MerlBrdf::index(i, j, k));
        const bool above = above_horizon(wi) && above_horizon(wo);
        const RGBT<double> f = above ? m.f(wi, wo) : RGBT<double>(0.0);
        for (int c = 0; c < 3; ++c) {
          // The number a file would store, times the scale: exactly what read_merl returns.
          const double stored = above ? f[c] / MerlBrdf::kScale[c] : -1.0;
          out.table[n + size_t(c) * MerlLayout::kBins] = stored * MerlBrdf::kScale[c];
        }
      }
  });
  return out;
}

}  // namespace aniso
