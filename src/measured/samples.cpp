// measured/samples.cpp: the CSV and Cornell readers, MERL bins and RGL tables as samples (samples.h).
#include "aniso/measured/samples.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "aniso/io/input_error.h"
#include "aniso/measured/merl.h"
#include "aniso/measured/spectral.h"
#include "aniso/rgl/rgl_material.h"
#include "io/json_read.h"
#include "io/text_input.h"

namespace aniso {

Vec3d direction_from_angles(double theta, double phi) {
  const double s = std::sin(theta);
  return Vec3d(s * std::cos(phi), s * std::sin(phi), std::cos(theta));
}

namespace {

constexpr double kPiD = 3.14159265358979323846;
// The largest BRDF value a sample may hold: the bound the material reader puts on a Lafortune
// lobe's peak (docs/models/lafortune.md), the largest value any fitted model can take. Measured
// BRDFs stay far below (MERL's largest values are about 1e4); far larger ones (1e300) would
// overflow the fit's squared residuals. A CSV colour and a Cornell spectral value are held to it
// alike: the spectral-to-RGB weights sum to 1 per channel with a few small negative ones
// (spectral.h), so a spectrum within the bound gives channels of the same order, never near overflow.
constexpr double kMaxSampleValue = 1e30;

std::string_view trim(std::string_view s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string_view> split(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  size_t start = 0;
  while (true) {
    const size_t p = line.find(sep, start);
    out.push_back(trim(line.substr(start, p == std::string_view::npos ? std::string_view::npos : p - start)));
    if (p == std::string_view::npos) break;
    start = p + 1;
  }
  return out;
}

std::vector<std::string_view> split_whitespace(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const size_t b = i;
    while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

// Iterates the lines of a text with their 1-based numbers.
struct LineReader {
  std::string_view text;
  size_t pos = 0, number = 0;
  bool next(std::string_view& line) {
    if (pos >= text.size()) return false;
    const size_t e = text.find('\n', pos);
    line = text.substr(pos, e == std::string_view::npos ? std::string_view::npos : e - pos);
    pos = e == std::string_view::npos ? text.size() : e + 1;
    ++number;
    return true;
  }
};

[[noreturn]] void fail_at(const std::string& path, size_t line, const std::string& what) {
  throw InputError(fmt::format("{}: line {}: {}", path, line, what));
}

double number_at(std::string_view token, const std::string& path, size_t line, std::string_view what) {
  std::string why;
  const std::optional<double> v = parse_decimal(token, &why);
  if (!v) fail_at(path, line, fmt::format("{}: expected a finite decimal number, got \"{}\"", what, text_escape(token)));
  return *v;
}

// theta in [0, pi/2): above the horizon, where every model is defined (docs/conventions.md).
void check_theta(double theta, double full_turn, const std::string& path, size_t line, std::string_view name) {
  if (!(theta >= 0.0 && theta < full_turn / 4.0))
    fail_at(
        path, line,
        fmt::format("{} = {:g}: out of range, expected [0, {:g}) (strictly above the horizon)", name, theta, full_turn / 4.0));
}
void check_phi(double phi, double full_turn, const std::string& path, size_t line, std::string_view name) {
  if (!(phi >= -full_turn && phi <= full_turn))
    fail_at(path, line, fmt::format("{} = {:g}: out of range, expected [{:g}, {:g}]", name, phi, -full_turn, full_turn));
}

}  // namespace

SampleSet read_samples_csv(const std::string& path) {
  const std::string text = read_text_file(path, "a CSV file of samples", kMaxSampleFileBytes);
  SampleSet set;
  set.source = path;
  set.format = "csv";
  LineReader lines{text};
  std::string_view line;
  // The header: the first line that is neither blank nor a comment.
  bool have_header = false;
  while (lines.next(line)) {
    if (is_blank_or_comment(line)) continue;
    have_header = true;
    break;
  }
  if (!have_header)
    throw InputError(
        fmt::format("{}: empty file: expected a header line naming the columns "
                    "theta_i,phi_i,theta_o,phi_o,r,g,b",
                    path));
  const size_t header_line = lines.number;
  const std::vector<std::string_view> names = split(line, ',');
  // Column roles: the four angles (radians or degrees), the colour, the optional weight.
  constexpr std::string_view kAngles[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};
  constexpr std::string_view kColour[3] = {"r", "g", "b"};
  int angle_col[4] = {-1, -1, -1, -1}, colour_col[3] = {-1, -1, -1}, weight_col = -1;
  bool degrees[4] = {false, false, false, false};
  std::vector<std::string> ignored;
  for (size_t c = 0; c < names.size(); ++c) {
    const std::string_view n = names[c];
    if (n.empty()) fail_at(path, header_line, fmt::format("column {}: empty name", c + 1));
    for (size_t d = 0; d < c; ++d)
      if (names[d] == n) fail_at(path, header_line, fmt::format("column \"{}\" appears twice", text_escape(n)));
    bool known = false;
    for (int a = 0; a < 4; ++a) {
      const bool rad = n == kAngles[a], deg = n == fmt::format("{}_deg", kAngles[a]);
      if (!rad && !deg) continue;
      if (angle_col[a] >= 0) fail_at(path, header_line, fmt::format("both \"{0}\" and \"{0}_deg\" given: give one", kAngles[a]));
      angle_col[a] = int(c);
      degrees[a] = deg;
      known = true;
    }
    for (int k = 0; k < 3; ++k)
      if (n == kColour[k]) colour_col[k] = int(c), known = true;
    if (n == "weight") weight_col = int(c), known = true;
    if (!known) ignored.push_back(std::string(n));
  }
  std::string missing;
  for (int a = 0; a < 4; ++a)
    if (angle_col[a] < 0) missing += fmt::format("{}\"{}\" (or \"{}_deg\")", missing.empty() ? "" : ", ", kAngles[a], kAngles[a]);
  for (int k = 0; k < 3; ++k)
    if (colour_col[k] < 0) missing += fmt::format("{}\"{}\"", missing.empty() ? "" : ", ", kColour[k]);
  if (!missing.empty())
    fail_at(path, header_line,
            fmt::format("missing column{} {}; the header must name theta_i,phi_i,theta_o,phi_o,r,g,b "
                        "(radians; theta_i_deg etc. for degrees)",
                        missing.find(',') == std::string::npos ? "" : "s", missing));
  for (const std::string& n : ignored)
    set.warnings.push_back(
        fmt::format("{}: line {}: column \"{}\" is not used and is ignored", path, header_line, text_escape(n)));

  while (lines.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const std::vector<std::string_view> fields = split(line, ',');
    if (fields.size() != names.size())
      fail_at(path, lines.number,
              fmt::format("{} columns, but the header (line {}) names {}", fields.size(), header_line, names.size()));
    double ang[4];
    for (int a = 0; a < 4; ++a) {
      const std::string_view name = names[size_t(angle_col[a])];
      ang[a] = number_at(fields[size_t(angle_col[a])], path, lines.number, fmt::format("column {}", name));
      const double full_turn = degrees[a] ? 360.0 : 2.0 * kPiD;
      if (a % 2 == 0)
        check_theta(ang[a], full_turn, path, lines.number, name);
      else
        check_phi(ang[a], full_turn, path, lines.number, name);
      if (degrees[a]) ang[a] *= kPiD / 180.0;
    }
    MeasuredSample s;
    s.wi = direction_from_angles(ang[0], ang[1]);
    s.wo = direction_from_angles(ang[2], ang[3]);
    for (int k = 0; k < 3; ++k) {
      const double v = number_at(fields[size_t(colour_col[k])], path, lines.number, fmt::format("column {}", kColour[k]));
      if (!(v >= 0.0))
        fail_at(path, lines.number, fmt::format("column {} = {:g}: a BRDF value cannot be negative", kColour[k], v));
      if (v > kMaxSampleValue)
        fail_at(path, lines.number,
                fmt::format("column {} = {:g}: expected a BRDF value of at most {:g} (1/sr)", kColour[k], v, kMaxSampleValue));
      s.value[k] = v + 0.0;
    }
    if (weight_col >= 0) {
      s.weight = number_at(fields[size_t(weight_col)], path, lines.number, "column weight");
      if (!(s.weight > 0.0)) fail_at(path, lines.number, fmt::format("column weight = {:g}: expected a number > 0", s.weight));
    }
    set.samples.push_back(s);
  }
  if (set.samples.empty()) throw InputError(fmt::format("{}: no samples after the header (line {})", path, header_line));
  return set;
}

SampleSet read_cornell(const std::string& path) {
  const std::string text = read_text_file(path, "a Cornell .brdf file", kMaxSampleFileBytes);
  SampleSet set;
  set.source = path;
  set.format = "cornell";
  LineReader lines{text};
  std::string_view line;
  // 1. the number of wavelengths; 2. the wavelengths (over one or more lines); 3. the rows.
  int wavelength_count = -1;
  std::vector<double> lambda;
  std::optional<SpectralToRgb> to_rgb;
  std::vector<double> spectrum;
  constexpr int kMaxWavelengths = 10000;  // far beyond any spectrometer's 31 to a few hundred
  while (lines.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const std::vector<std::string_view> tokens = split_whitespace(line);
    if (wavelength_count < 0) {
      if (tokens.size() != 1)
        fail_at(path, lines.number,
                fmt::format("expected the number of wavelengths alone on the line, got {} values", tokens.size()));
      const double n = number_at(tokens[0], path, lines.number, "number of wavelengths");
      if (!(n >= 2 && n <= kMaxWavelengths && n == std::floor(n)))
        fail_at(path, lines.number,
                fmt::format("number of wavelengths = {:g}: expected a whole number in [2, {}]", n, kMaxWavelengths));
      wavelength_count = int(n);
      continue;
    }
    if (int(lambda.size()) < wavelength_count) {
      if (int(lambda.size() + tokens.size()) > wavelength_count)
        fail_at(path, lines.number,
                fmt::format("{} more wavelengths, but only {} of {} were missing", tokens.size(),
                            wavelength_count - int(lambda.size()), wavelength_count));
      for (std::string_view t : tokens) {
        const double l = number_at(t, path, lines.number, "wavelength");
        if (!(l > 0.0 && l < 1e5)) fail_at(path, lines.number, fmt::format("wavelength {:g} nm: expected (0, 1e5) nm", l));
        if (!lambda.empty() && !(l > lambda.back()))
          fail_at(path, lines.number,
                  fmt::format("wavelength {:g} nm after {:g} nm: wavelengths must increase", l, lambda.back()));
        lambda.push_back(l);
      }
      if (int(lambda.size()) == wavelength_count) to_rgb.emplace(lambda);
      continue;
    }
    const size_t expected = 4 + size_t(wavelength_count);
    if (tokens.size() != expected)
      fail_at(
          path, lines.number,
          fmt::format("{} values, expected {} (theta_i phi_i theta_s phi_s and {} spectral values){}", tokens.size(), expected,
                      wavelength_count, tokens.size() < expected && lines.pos >= text.size() ? ": the file is truncated" : ""));
    constexpr std::string_view kNames[4] = {"theta_i", "phi_i", "theta_s", "phi_s"};
    double ang[4];
    for (int a = 0; a < 4; ++a) {
      ang[a] = number_at(tokens[size_t(a)], path, lines.number, kNames[a]);
      if (a % 2 == 0)
        check_theta(ang[a], 2.0 * kPiD, path, lines.number, kNames[a]);
      else
        check_phi(ang[a], 2.0 * kPiD, path, lines.number, kNames[a]);
    }
    spectrum.resize(size_t(wavelength_count));
    for (int j = 0; j < wavelength_count; ++j) {
      const double v = number_at(tokens[4 + size_t(j)], path, lines.number, fmt::format("spectral value {}", j + 1));
      if (!(v >= 0.0))
        fail_at(path, lines.number,
                fmt::format("spectral value {} ({:g} nm) = {:g}: a BRDF value cannot be negative", j + 1, lambda[size_t(j)], v));
      if (v > kMaxSampleValue)
        fail_at(path, lines.number,
                fmt::format("spectral value {} ({:g} nm) = {:g}: expected a BRDF value of at most {:g} (1/sr)", j + 1,
                            lambda[size_t(j)], v, kMaxSampleValue));
      spectrum[size_t(j)] = v;
    }
    MeasuredSample s;
    s.wi = direction_from_angles(ang[0], ang[1]);
    s.wo = direction_from_angles(ang[2], ang[3]);
    s.value = (*to_rgb)(spectrum);
    set.samples.push_back(s);
  }
  if (wavelength_count < 0)
    throw InputError(fmt::format("{}: empty file: expected the number of wavelengths, the wavelengths, then the samples", path));
  if (int(lambda.size()) < wavelength_count)
    throw InputError(fmt::format("{}: line {}: the file is truncated: {} of {} wavelengths", path, lines.number, lambda.size(),
                                 wavelength_count));
  if (set.samples.empty()) throw InputError(fmt::format("{}: line {}: no samples after the wavelengths", path, lines.number));
  return set;
}

SampleSet merl_samples(const MerlBrdf& brdf, const std::string& source) {
  SampleSet set;
  set.source = source;
  set.format = "merl";
  set.samples.reserve(size_t(MerlBrdf::kBins) * 3 / 4);
  const HalfDiffGrid grid;  // MERL's own bins
  size_t missing = 0;
  for (int i = 0; i < MerlBrdf::kThetaH; ++i)
    for (int j = 0; j < MerlBrdf::kThetaD; ++j)
      for (int k = 0; k < MerlBrdf::kPhiD; ++k) {
        const auto [wi, wo] = grid.directions(i, j, k);
        if (!(wi.z > 1e-12 && wo.z > 1e-12)) continue;  // the double horizon (docs/conventions.md)
        if (!brdf.valid(i, j, k)) {
          ++missing;
          continue;
        }
        const int b = MerlBrdf::index(i, j, k);
        MeasuredSample s;
        s.wi = wi;
        s.wo = wo;
        for (int c = 0; c < 3; ++c) s.value[c] = brdf.table[size_t(b) + size_t(c) * size_t(MerlBrdf::kBins)];
        s.weight = grid.weight(i, j);
        set.samples.push_back(s);
      }
  if (missing > 0)
    set.warnings.push_back(fmt::format("{}: {} missing bins (negative values) above the horizon skipped", source, missing));
  if (set.samples.empty()) throw InputError(fmt::format("{}: every bin is missing: nothing to fit", source));
  return set;
}

HalfDiffGrid rgl_sample_grid(bool isotropic, int n_theta_h) {
  HalfDiffGrid g;
  g.phi_d_range = 2.0 * kPiD;
  if (n_theta_h > 0) {
    if (n_theta_h < 4 || n_theta_h % 2 != 0)
      throw InputError(fmt::format("the RGL sample grid: expected an even number of theta_h bins >= 4, got {}", n_theta_h));
    g.n_theta_h = n_theta_h, g.n_theta_d = n_theta_h / 2, g.n_phi_d = n_theta_h, g.n_phi_h = isotropic ? 1 : 24;
  } else if (isotropic) {
    // 64 x 32 x 64 = 131,072 pairs (98,564 above the horizon): MERL's layout at a resolution whose
    // pairs the fitter uses (a 32,768-sample solver subset, errors over all), theta_h bins from
    // 0.022 degrees wide at the highlight to 2.8 at 90, theta_d bins of 2.8 degrees, phi_d of 5.6.
    g.n_theta_h = 64, g.n_theta_d = 32, g.n_phi_d = 64, g.n_phi_h = 1;
  } else {
    // 32 x 16 x 32 x 24 = 393,216 pairs (295,968 above the horizon): half the resolution in theta_h
    // (the first bin 0.088 degrees wide), theta_d and phi_d, and 24 half-vector azimuths 15 degrees
    // apart: modulo 180 degrees, one in each of the fitter's 12 azimuth bins (docs/fitting.md, "The
    // auto rule"). Evaluating the file there takes 0.25 to 0.6 s on 2 cores.
    g.n_theta_h = 32, g.n_theta_d = 16, g.n_phi_d = 32, g.n_phi_h = 24;
  }
  return g;
}

SampleSet rgl_samples(const rgl::RglData& data, const std::string& source, const HalfDiffGrid& grid) {
  SampleSet set;
  set.source = source;
  set.format = "rgl";
  const RglT<double> f = rgl::rgl_kernel<double>(data);
  // Every grid point in a fixed order, evaluated in parallel (f of a file: about 2 us per pair),
  // then the pairs above the horizon kept in that order: the same set whatever the thread count.
  const size_t per_theta_h = grid.size() / size_t(grid.n_theta_h);
  std::vector<MeasuredSample> all(grid.size());
  std::vector<char> keep(grid.size(), 0);
  tbb::parallel_for(0, grid.n_theta_h, [&](int i) {
    size_t n = size_t(i) * per_theta_h;
    for (int j = 0; j < grid.n_theta_d; ++j)
      for (int k = 0; k < grid.n_phi_d; ++k)
        for (int l = 0; l < grid.n_phi_h; ++l, ++n) {
          const auto [wi, wo] = grid.directions(i, j, k, l);
          if (!(wi.z > 1e-12 && wo.z > 1e-12)) continue;  // the double horizon (docs/conventions.md)
          MeasuredSample& s = all[n];
          s.wi = wi;
          s.wo = wo;
          s.value = glm::dvec3(f.f(wi, wo));
          s.weight = grid.weight(i, j);
          keep[n] = 1;
        }
  });
  for (size_t n = 0; n < all.size(); ++n)
    if (keep[n]) set.samples.push_back(all[n]);
  if (set.samples.empty()) throw InputError(fmt::format("{}: the sample grid has no pair above the horizon", source));
  const std::string azimuths = grid.n_phi_h == 1 ? std::string("phi_h 0") : fmt::format("{} phi_h over 360 deg", grid.n_phi_h);
  set.description = fmt::format(
      "RGL tensor file ({}, {} x {} theta_i x phi_i, {} colour grid {}x{}) sampled with pbrt-v4's MeasuredBxDF::f at the "
      "centres of a MERL-style half/difference-angle grid (Rusinkiewicz 1998): {} theta_h (square-root spaced) x {} theta_d "
      "x {} phi_d over {:g} deg x {}; {} pairs with both directions above the horizon, weighted by solid angle",
      data.isotropic ? "isotropic" : "anisotropic", data.theta_i.size(), data.phi_i.size(), data.spectral ? "spectral" : "rgb",
      data.colour_grid, data.colour_grid, grid.n_theta_h, grid.n_theta_d, grid.n_phi_d, grid.phi_d_range * 180.0 / kPiD, azimuths,
      set.samples.size());
  return set;
}

int check_rgl_fit_grid(const std::string& data_path, int64_t n, const std::string& what) {
  if (std::filesystem::path(data_path).extension().string() != ".bsdf")
    throw InputError(
        fmt::format("{} applies to an RGL tensor file (.bsdf) only, which has no samples of its own; {} "
                    "is sampled where it was measured",
                    what, data_path));
  if (n < 4 || n > 256) throw InputError(fmt::format("{}: expected an even number from 4 to 256, got {}", what, n));
  if (n % 2 != 0) throw InputError(fmt::format("{}: expected an even number (theta_d gets half of it), got {}", what, n));
  return int(n);
}

SampleSet read_measured(const std::string& path, int rgl_grid) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".csv") return read_samples_csv(path);
  if (ext == ".brdf") return read_cornell(path);
  if (ext == ".binary") return merl_samples(read_merl(path), path);
  if (ext == ".bsdf") {
    const std::shared_ptr<const rgl::RglData> d = rgl::load_rgl(path);  // InputError naming the file, the field and the problem
    return rgl_samples(*d, path, rgl_sample_grid(d->isotropic, rgl_grid));
  }
  throw InputError(
      fmt::format("{}: unknown data format \"{}\": expected .csv (samples), .brdf (Cornell), .binary (MERL), "
                  ".bsdf (RGL tensor file)",
                  path, text_escape(ext)));
}

}  // namespace aniso
