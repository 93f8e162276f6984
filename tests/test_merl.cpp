// MERL .binary files (include/aniso/measured/merl.h): the bin lookup against an independent transcription of
// MERL's BRDFRead.cpp, the lookup of a file written from an analytic model against the model,
// the bitwise round trip, and every kind of bad file.
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <algorithm>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/measured/merl.h"
#include "test_util.h"

namespace aniso::test {
namespace {

namespace fs = std::filesystem;

// A temporary directory removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "aniso-merl-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

// The analytic models written in MERL layout by these tests: an isotropic Ward (a broad lobe and
// colour in every channel) and a Lambertian (constant: the lookup must give it back exactly).
const nlohmann::json kWard = {{"model", "ward"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", 0.2}, {"alpha", 0.25}};
const nlohmann::json kLambert = {{"model", "lambert"}, {"kd", {0.8, 0.5, 0.2}}};

const MerlBrdf& ward_table() {
  static const MerlBrdf t = tabulate_merl(build<double>(kWard));
  return t;
}

// ---- an independent transcription of MERL's BRDFRead.cpp (acos / atan2 and rotate_vector) ----
void rotate_vector(const double* v, const double* axis, double angle, double* out) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double dot = v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2];
  const double cross[3] = {axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2], axis[0] * v[1] - axis[1] * v[0]};
  for (int i = 0; i < 3; ++i) out[i] = v[i] * c + axis[i] * dot * (1 - c) + cross[i] * s;
}
int reference_index(const Vec3d& in, const Vec3d& out) {
  double half[3] = {in.x + out.x, in.y + out.y, in.z + out.z};
  const double len = std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
  for (double& h : half) h /= len;
  const double theta_half = std::acos(half[2]), fi_half = std::atan2(half[1], half[0]);
  const double bi_normal[3] = {0, 1, 0}, normal[3] = {0, 0, 1}, v[3] = {in.x, in.y, in.z};
  double temp[3], diff[3];
  rotate_vector(v, normal, -fi_half, temp);
  rotate_vector(temp, bi_normal, -theta_half, diff);
  const double theta_diff = std::acos(diff[2]);
  double fi_diff = std::atan2(diff[1], diff[0]);
  // theta_half_index
  int th = 0;
  if (theta_half > 0.0) th = std::min(89, std::max(0, int(std::sqrt(theta_half / (M_PI / 2.0) * 90.0 * 90.0))));
  const int td = std::min(89, std::max(0, int(theta_diff / (M_PI * 0.5) * 90)));
  if (fi_diff < 0.0) fi_diff += M_PI;
  const int pd = std::min(179, std::max(0, int(fi_diff / M_PI * 360 / 2)));
  return pd + td * 360 / 2 + th * 360 / 2 * 90;
}

TEST(Merl, BinIndexMatchesMerlReferenceCode) {
  Rng rng(3);
  int differ = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    if (merl_bin(wi, wo) != reference_index(wi, wo)) ++differ;
  }
  // acos against atan2 rounds differently within ~1e-16 rad of a bin edge: a handful at most.
  EXPECT_LE(differ, 5) << "of " << n;
}

TEST(Merl, BinCentresLookUpTheirOwnBin) {
  int checked = 0;
  for (int i = 0; i < MerlBrdf::kThetaH; ++i)
    for (int j = 0; j < MerlBrdf::kThetaD; ++j)
      for (int k = 0; k < MerlBrdf::kPhiD; k += 7) {
        const auto [wi, wo] = MerlBrdf::bin_directions(i, j, k);
        ASSERT_NEAR(glm::length(wi), 1.0, 1e-12);
        ASSERT_NEAR(glm::length(wo), 1.0, 1e-12);
        ASSERT_EQ(merl_bin(wi, wo), MerlBrdf::index(i, j, k)) << i << " " << j << " " << k;
        ASSERT_EQ(merl_bin(wo, wi), MerlBrdf::index(i, j, k)) << "reciprocity " << i << " " << j << " " << k;
        ++checked;
      }
  EXPECT_EQ(checked, 90 * 90 * 26);
}

// A Lambertian is constant: its table gives it back to the file's rounding (1 ulp of the scaled
// number), everywhere above the horizon except in bins whose centre lies below it.
TEST(Merl, LookupOfATabulatedLambertianIsExact) {
  const MerlBrdf t = tabulate_merl(build<double>(kLambert));
  const Vec3d expected = Vec3d(0.8, 0.5, 0.2) / M_PI;
  Rng rng(5);
  int zero = 0;
  for (int k = 0; k < 100000; ++k) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const Vec3d f = t.lookup(wi, wo);
    if (f == Vec3d(0.0)) {
      ++zero;  // a bin whose centre is below the horizon: missing in the tabulation
      continue;
    }
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(f[c], expected[c], 4e-16 * expected[c]);
  }
  // Those bins sit next to the horizon: under 1% of uniformly random pairs.
  EXPECT_LT(zero, 1000);
  EXPECT_GT(t.missing_count(), 0u);
}

// The lookup of a table written from an analytic model gives the model's value at the centre of
// the query's bin (what the table stores), and that bin holds the query: the model's value at the
// query lies between the model's extremes over the bin (9 x 9 x 9 points of it, 1% slack for
// curvature between the points). Measured for the docs: the pointwise relative error.
TEST(Merl, LookupOfATabulatedWardEqualsTheModelWithinABin) {
  const MaterialD m = build<double>(kWard);
  const MerlBrdf& t = ward_table();
  Rng rng(9);
  std::vector<double> rel;
  for (int q = 0; q < 3000; ++q) {
    const Vec3d wi = random_upper<double>(rng), wo = random_upper<double>(rng);
    const int bin = merl_bin(wi, wo);
    const int i = bin / (90 * 180), j = (bin / 180) % 90, k = bin % 180;
    const Vec3d f = t.lookup(wi, wo);
    const auto [ci, co] = MerlBrdf::bin_directions(i, j, k);
    if (!(above_horizon(ci) && above_horizon(co))) {
      EXPECT_EQ(f, Vec3d(0.0));
      continue;
    }
    const Vec3d fc = m.f(ci, co);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(f[c], fc[c], 4e-16 * fc[c]);
    // Extremes over the bin, in MERL's own coordinates (phi_h = 0: the model is isotropic).
    Vec3d lo(1e300), hi(-1e300);
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b)
        for (int d = 0; d <= 8; ++d) {
          const double u = (i + a / 8.0) / 90.0, th = u * u * M_PI / 2, td = (j + b / 8.0) / 90.0 * M_PI / 2,
                       pd = (k + d / 8.0) / 180.0 * M_PI;
          const Vec3d dv(std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td));
          const double ct = std::cos(th), st = std::sin(th);
          const Vec3d a_in(dv.x * ct + dv.z * st, dv.y, -dv.x * st + dv.z * ct);
          const Vec3d a_out(-dv.x * ct + dv.z * st, -dv.y, dv.x * st + dv.z * ct);
          if (!(above_horizon(a_in) && above_horizon(a_out))) continue;
          const Vec3d v = m.f(a_in, a_out);
          lo = glm::min(lo, v), hi = glm::max(hi, v);
        }
    const Vec3d fq = m.f(wi, wo);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(fq[c], lo[c] * 0.99) << "query outside its bin: " << i << " " << j << " " << k;
      EXPECT_LE(fq[c], hi[c] * 1.01) << "query outside its bin: " << i << " " << j << " " << k;
    }
    rel.push_back(std::abs(f.y - fq.y) / fq.y);
  }
  std::sort(rel.begin(), rel.end());
  const double median = rel[rel.size() / 2], p99 = rel[rel.size() * 99 / 100];
  RecordProperty("median_relative_error", std::to_string(median));
  RecordProperty("p99_relative_error", std::to_string(p99));
  std::printf("Ward alpha 0.25 in MERL layout: relative error of the lookup: median %.2e, 99th percentile %.2e, max %.2e\n",
              median, p99, rel.back());
  // The table's resolution (theta_h bins up to 2 deg wide, theta_d and phi_d 1 deg): a few per cent.
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p99, 0.06);
}

// A missing sample (negative in any channel): valid() is false, the lookup gives 0 in every
// channel, the file keeps it through a write and a read, and the sampler's tables see 0 there.
TEST(Merl, MissingSamplesLookUpAsZero) {
  MerlBrdf t = tabulate_merl(build<double>(kLambert));
  const int i = 10, j = 20, k = 30;
  ASSERT_TRUE(t.valid(i, j, k));
  const size_t before = t.missing_count();
  t.table[size_t(MerlBrdf::kBins) + size_t(MerlBrdf::index(i, j, k))] = -1.0 * MerlBrdf::kScale[1];  // green only
  EXPECT_FALSE(t.valid(i, j, k));
  EXPECT_EQ(t.missing_count(), before + 1);
  const auto [wi, wo] = MerlBrdf::bin_directions(i, j, k);
  EXPECT_EQ(t.lookup(wi, wo), Vec3d(0.0));
  const auto [wi2, wo2] = MerlBrdf::bin_directions(i, j, k + 1);
  EXPECT_NEAR(t.lookup(wi2, wo2).x, 0.8 / M_PI, 1e-15);
}

TEST(Merl, WriteThenReadIsBitwise) {
  TempDir dir;
  const MerlBrdf& t = ward_table();
  const std::string a = dir.file("ward.binary"), b = dir.file("again.binary");
  write_merl(a, t);
  EXPECT_EQ(fs::file_size(a), MerlBrdf::kFileBytes);
  const MerlBrdf r = read_merl(a);
  ASSERT_EQ(r.table.size(), t.table.size());
  EXPECT_EQ(std::memcmp(r.table.data(), t.table.data(), t.table.size() * sizeof(double)), 0);
  write_merl(b, r);
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(fa)), {}), sb((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_TRUE(sa == sb) << "the file written from what was read differs from the first";
  // No temporary left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++files;
  EXPECT_EQ(files, 2);
  // The header and the first stored number as MERL's reader would see them.
  int32_t dims[3];
  double first;
  std::memcpy(dims, sa.data(), 12);
  std::memcpy(&first, sa.data() + 12, 8);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  EXPECT_EQ(first * (1.0 / 1500.0), t.table[0]);
}

// The message of read_merl(path), or "" when it succeeds.
std::string read_error(const std::string& path) {
  try {
    read_merl(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void write_bytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

TEST(Merl, BadFilesAreErrorsNamingFileAndOffset) {
  TempDir dir;
  const std::string good = dir.file("good.binary");
  write_merl(good, ward_table());
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    bytes.assign((std::istreambuf_iterator<char>(in)), {});
  }
  struct Case {
    std::string name, content, expect;
  };
  std::vector<Case> cases;
  cases.push_back({"empty.binary", "", "byte offset 0: empty file"});
  cases.push_back({"short-header.binary", bytes.substr(0, 7), "byte offset 7: truncated header"});
  std::string wrong = bytes.substr(0, 4096);
  const int32_t bad_dim = 91;
  std::memcpy(wrong.data() + 4, &bad_dim, 4);
  cases.push_back({"wrong-header.binary", wrong, "byte offset 4: header: theta_d resolution 91, expected 90"});
  cases.push_back({"text.binary", "theta_h theta_d phi_d\n1 2 3\n", "byte offset 0: header: theta_h resolution"});
  cases.push_back({"truncated-in-header-data.binary", bytes.substr(0, 12 + 8 * 1000 + 3),
                   "byte offset 8015: truncated: the file ends inside value 1000"});
  cases.push_back(
      {"truncated-blue.binary", bytes.substr(0, bytes.size() - 8),
       "truncated: the file ends inside value 4373999 of 4374000 (channel B, bin (theta_h 89, theta_d 89, phi_d 179))"});
  cases.push_back({"long.binary", bytes + "x", "byte offset 34992012: trailing data: the file is 34992013 bytes"});
  for (const Case& c : cases) {
    const std::string p = dir.file(c.name);
    write_bytes(p, c.content);
    const std::string msg = read_error(p);
    EXPECT_NE(msg.find(p + ": "), std::string::npos) << c.name << ": " << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.name << ": " << msg;
    fs::remove(p);
  }
  // A NaN and an infinity in the data, named by offset and bin.
  for (const auto& [value, what] :
       {std::pair{std::nan(""), "NaN"}, std::pair{HUGE_VAL, "infinite value"}, std::pair{1e300, "1e+300"}}) {
    std::string b = bytes;
    const size_t n = size_t(MerlBrdf::kBins) + size_t(MerlBrdf::index(3, 17, 120));  // green
    std::memcpy(b.data() + 12 + 8 * n, &value, 8);
    const std::string p = dir.file("nan.binary");
    write_bytes(p, b);
    const std::string msg = read_error(p);
    EXPECT_NE(
        msg.find(fmt::format("{}: byte offset {}: {} (channel G, bin (theta_h 3, theta_d 17, phi_d 120))", p, 12 + 8 * n, what)),
        std::string::npos)
        << msg;
    fs::remove(p);
  }
  EXPECT_NE(read_error(dir.path.string()).find("is a directory"), std::string::npos);
  EXPECT_NE(read_error(dir.file("absent.binary")).find("no such file"), std::string::npos);
}

TEST(Merl, WriteRejectsAWrongTable) {
  TempDir dir;
  MerlBrdf small;
  small.table.assign(10, 0.0);
  EXPECT_THROW(write_merl(dir.file("x.binary"), small), InputError);
  MerlBrdf nan = ward_table();
  nan.table[5] = std::nan("");
  EXPECT_THROW(write_merl(dir.file("x.binary"), nan), InputError);
  EXPECT_FALSE(fs::exists(dir.file("x.binary")));
}

}  // namespace
}  // namespace aniso::test
