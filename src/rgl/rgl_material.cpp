// rgl/rgl_material.cpp: reading an RGL tensor file into pbrt-v4's interpolants (rgl/rgl_material.h).
#include "aniso/rgl/rgl_material.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <set>

#include <fmt/format.h>

#include "aniso/io/params.h"
#include "aniso/measured/spectral.h"
#include "io/text_escape.h"

namespace aniso::rgl {

void PL2DTables::build(const float* in, int size_x, int size_y, const std::vector<std::vector<float>>& params, bool normalize,
                       bool build_cdf) {
  PL2D& v = view;
  v = PL2D{};
  v.size_x = size_x;
  v.size_y = size_y;
  v.dim = int(params.size());
  // sampling.h:1367-1374: strides from the last parameter (innermost) outwards.
  uint32_t slices = 1;
  for (int i = v.dim - 1; i >= 0; --i) {
    param_values[size_t(i)] = params[size_t(i)];
    v.param_size[i] = int(params[size_t(i)].size());
    v.param_stride[i] = v.param_size[i] > 1 ? int(slices) : 0;
    slices *= uint32_t(v.param_size[i]);
  }
  const size_t n_values = size_t(size_x) * size_t(size_y);
  data.assign(slices * n_values, 0.f);
  marginal_cdf.clear();
  conditional_cdf.clear();
  if (build_cdf) {
    marginal_cdf.assign(size_t(slices) * size_t(size_y), 0.f);
    conditional_cdf.assign(slices * n_values, 0.f);
    float* mcdf = marginal_cdf.data();
    float* ccdf = conditional_cdf.data();
    float* out = data.data();
    for (uint32_t slice = 0; slice < slices; ++slice) {
      // sampling.h:1386-1420 (sums in double, stored in float, as there).
      for (int y = 0; y < size_y; ++y) {
        double sum = 0.0;
        size_t i = size_t(y) * size_t(size_x);
        ccdf[i] = 0.f;
        for (int x = 0; x < size_x - 1; ++x, ++i) {
          sum += .5 * (double(in[i]) + double(in[i + 1]));
          ccdf[i + 1] = float(sum);
        }
      }
      mcdf[0] = 0.f;
      double sum = 0.0;
      for (int y = 0; y < size_y - 1; ++y) {
        sum += .5 * (double(ccdf[size_t(y + 1) * size_x - 1]) + double(ccdf[size_t(y + 2) * size_x - 1]));
        mcdf[y + 1] = float(sum);
      }
      const float normalization = 1.f / mcdf[size_y - 1];
      for (size_t i = 0; i < n_values; ++i) ccdf[i] *= normalization;
      for (int i = 0; i < size_y; ++i) mcdf[i] *= normalization;
      for (size_t i = 0; i < n_values; ++i) out[i] = in[i] * normalization;
      mcdf += size_y;
      ccdf += n_values;
      out += n_values;
      in += n_values;
    }
  } else {
    float* out = data.data();
    for (uint32_t slice = 0; slice < slices; ++slice) {
      // sampling.h:1426-1452: without normalisation the stored value is divided by the patch
      // count, which evaluate() multiplies back: evaluate() returns the interpolated input.
      float normalization = 1.f / (float(size_x - 1) * float(size_y - 1));
      if (normalize) {
        double sum = 0.0;
        for (int y = 0; y < size_y - 1; ++y) {
          size_t i = size_t(y) * size_x;
          for (int x = 0; x < size_x - 1; ++x, ++i)
            sum += double(.25f * (in[i] + in[i + 1] + in[i + size_x] + in[i + 1 + size_x]));
        }
        normalization = float(1.0 / sum);
      }
      for (size_t k = 0; k < n_values; ++k) out[k] = in[k] * normalization;
      in += n_values;
      out += n_values;
    }
  }
  v.data = data.data();
  v.marginal_cdf = marginal_cdf.empty() ? nullptr : marginal_cdf.data();
  v.conditional_cdf = conditional_cdf.empty() ? nullptr : conditional_cdf.data();
  for (int i = 0; i < v.dim; ++i) v.param_values[i] = param_values[size_t(i)].data();
}

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& field, const std::string& problem) {
  throw InputError(fmt::format("{}: field \"{}\": {}", where, field, problem));
}

const TensorField& need(const TensorFile& t, const std::string& name, const std::string& why) {
  const TensorField* f = t.find(name);
  if (!f) throw InputError(fmt::format("{}: field \"{}\" is missing ({})", t.source, name, why));
  return *f;
}

// dtype and rank, as both readers check them (bxdfs.cpp:897-935, measured.cpp:127-172).
void expect(const TensorFile& t, const TensorField& f, Dtype dtype, size_t ndim) {
  if (f.dtype != dtype) fail(t.source, f.name, fmt::format("dtype {}, expected {}", dtype_name(f.dtype), dtype_name(dtype)));
  if (f.shape.size() != ndim)
    fail(t.source, f.name, fmt::format("shape {} has {} dimensions, expected {}", f.shape_string(), f.shape.size(), ndim));
}

// Finite, >= 0 and <= kMaxTableValue: pbrt-v4 and Mitsuba build cdfs from these tables and divide
// by their sums and by sigma; a NaN or a negative density would give NaN or negative pdfs. Runs
// after zero_rounding_noise, so a negative value here is beyond float rounding of 0.
void finite_non_negative(const TensorFile& t, const std::string& name, const std::vector<float>& v) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]) || v[i] < 0.f || v[i] > kMaxTableValue)
      fail(t.source, name,
           fmt::format("value {} at flat index {} (finite, in [0, {:g}] expected{})", v[i], i, kMaxTableValue,
                       v[i] < 0.f ? fmt::format("; negatives down to {:.3g}, float rounding of 0 against the table's "
                                                "largest value, are read as 0",
                                                -rounding_noise_bound(v))
                                  : ""));
}

}  // namespace

double rounding_noise_bound(std::span<const float> v) {
  float largest = 0.f;
  for (const float x : v)
    if (std::isfinite(x)) largest = std::max(largest, std::abs(x));
  return kRoundingNoiseUlps * double(std::numeric_limits<float>::epsilon()) * double(largest);
}

std::string zero_rounding_noise(const std::string& where, const std::string& field, std::vector<float>& v) {
  const double bound = rounding_noise_bound(v);
  size_t count = 0, most_at = 0;
  float most = 0.f;
  for (size_t i = 0; i < v.size(); ++i)
    if (v[i] < 0.f && double(v[i]) >= -bound) {
      if (v[i] < most) most = v[i], most_at = i;
      v[i] = 0.f;
      ++count;
    }
  if (count == 0) return {};
  return fmt::format(
      "{}: field \"{}\": {} negative value{} read as 0 (float rounding of 0: at most {:g} x FLT_EPSILON x the table's "
      "largest value, {:.3g}; the most negative {:.6g} at flat index {})",
      where, field, count, count == 1 ? "" : "s", kRoundingNoiseUlps, bound, most, most_at);
}

namespace {

void grid_at_least_2(const TensorFile& t, const TensorField& f, size_t a, size_t b) {
  // PiecewiseLinear2D divides by (size - 1) (sampling.h:1330-1331).
  if (f.shape[a] < 2 || f.shape[b] < 2)
    fail(t.source, f.name, fmt::format("shape {}: the 2D grid needs at least 2 x 2 points", f.shape_string()));
}

void increasing(const TensorFile& t, const std::string& name, const std::vector<float>& v, float lo, float hi,
                const char* range) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i]) || v[i] < lo || v[i] > hi)
      fail(t.source, name, fmt::format("value {} at index {} outside {}", v[i], i, range));
    if (i && !(v[i] > v[i - 1]))
      fail(t.source, name, fmt::format("values not strictly increasing at index {} ({} after {})", i, v[i], v[i - 1]));
  }
}

}  // namespace

std::shared_ptr<RglData> rgl_from_tensor(const TensorFile& t) {
  const std::string& src = t.source;
  const char* why = "every RGL reader requires it: pbrt-v4 bxdfs.cpp:886-895, Mitsuba 3 measured.cpp:98-106";
  const TensorField& theta_i = need(t, "theta_i", why);
  const TensorField& phi_i = need(t, "phi_i", why);
  const TensorField& ndf = need(t, "ndf", why);
  const TensorField& sigma = need(t, "sigma", why);
  const TensorField& vndf = need(t, "vndf", why);
  const TensorField& luminance = need(t, "luminance", why);
  const TensorField& description = need(t, "description", why);
  const TensorField& jacobian = need(t, "jacobian", why);
  // Mitsuba 3 measured.cpp:108-125: a file with "wavelengths" is spectral ("spectra"), else RGB
  // ("rgb"); pbrt-v4 reads spectral files only (bxdfs.cpp:892-893).
  const bool spectral = t.find("wavelengths") != nullptr;
  const TensorField& spectra =
      spectral ? need(t, "spectra", "a file with \"wavelengths\" is spectral (Mitsuba 3 measured.cpp:113-118)")
               : need(t, "rgb", "a file without \"wavelengths\" is an RGB file (Mitsuba 3 measured.cpp:119-124)");
  expect(t, description, Dtype::UInt8, 1);
  expect(t, theta_i, Dtype::Float32, 1);
  expect(t, phi_i, Dtype::Float32, 1);
  expect(t, ndf, Dtype::Float32, 2);
  expect(t, sigma, Dtype::Float32, 2);
  expect(t, vndf, Dtype::Float32, 4);
  expect(t, luminance, Dtype::Float32, 4);
  expect(t, spectra, Dtype::Float32, 5);
  expect(t, jacobian, Dtype::UInt8, 1);
  const TensorField* wavelengths = t.find("wavelengths");
  if (spectral) expect(t, *wavelengths, Dtype::Float32, 1);
  const uint64_t n_phi = phi_i.shape[0], n_theta = theta_i.shape[0];
  const uint64_t n_lambda = spectral ? wavelengths->shape[0] : 3;
  auto shape_is = [&](const TensorField& f, std::initializer_list<uint64_t> dims, const char* expected) {
    size_t d = 0;
    for (const uint64_t s : dims) {
      if (s != 0 && f.shape[d] != s)
        fail(src, f.name,
             fmt::format("shape {}, expected {} (phi_i has {}, theta_i {})", f.shape_string(), expected, n_phi, n_theta));
      ++d;
    }
  };
  shape_is(vndf, {n_phi, n_theta, 0, 0}, "[phi_i, theta_i, *, *]");
  shape_is(luminance, {n_phi, n_theta, 0, 0}, "[phi_i, theta_i, n, n]");
  shape_is(spectra, {n_phi, n_theta, n_lambda, 0, 0},
           spectral ? "[phi_i, theta_i, wavelengths, n, n]" : "[phi_i, theta_i, 3, n, n]");
  if (luminance.shape[2] != luminance.shape[3])
    fail(src, "luminance",
         fmt::format("shape {}: the last two sizes must be equal (pbrt-v4 bxdfs.cpp:915)", luminance.shape_string()));
  if (spectra.shape[3] != spectra.shape[4])
    fail(src, spectra.name,
         fmt::format("shape {}: the last two sizes must be equal (pbrt-v4 bxdfs.cpp:921)", spectra.shape_string()));
  if (luminance.shape[2] != spectra.shape[3])
    fail(src, "luminance",
         fmt::format("shape {}: its grid must be the {} grid ({})", luminance.shape_string(), spectra.name,
                     spectra.shape_string()));
  if (jacobian.shape[0] != 1) fail(src, "jacobian", fmt::format("shape {}, expected [1]", jacobian.shape_string()));
  if (jacobian.bytes[0] != 1)
    fail(src, "jacobian",
         "value 0: pbrt-v4 always applies ndf / (4 sigma) (bxdfs.cpp:1048-1049), Mitsuba 3 only when jacobian is 1 "
         "(measured.cpp:364-366); the two renderers disagree on such a file, aniso reads only jacobian = 1");
  if (n_phi < 1 || n_theta < 1) fail(src, n_phi < 1 ? "phi_i" : "theta_i", "empty (at least 1 value expected)");
  if (spectral && n_lambda < 2) fail(src, "wavelengths", "fewer than 2 wavelengths");
  grid_at_least_2(t, ndf, 0, 1);
  grid_at_least_2(t, sigma, 0, 1);
  grid_at_least_2(t, vndf, 2, 3);
  grid_at_least_2(t, luminance, 2, 3);
  // The interpolants index the tables with 32-bit offsets (sampling.h:1537-1541).
  for (const TensorField* f : {&ndf, &sigma, &vndf, &luminance, &spectra})
    if (f->count() >= (uint64_t(1) << 31)) fail(src, f->name, fmt::format("shape {}: more than 2^31 values", f->shape_string()));

  auto d = std::make_shared<RglData>();
  d->source = src;
  d->file_size = t.size;
  d->spectral = spectral;
  d->description.assign(description.bytes.begin(), description.bytes.end());
  d->theta_i = theta_i.floats();
  d->phi_i = phi_i.floats();
  // theta_i in [0, pi/2] and phi_i in [-pi, pi] (with float rounding of the end points, 1e-5 rad),
  // both increasing: PiecewiseLinear2D's parameter search assumes sorted grids.
  increasing(t, "theta_i", d->theta_i, 0.f, kPi<float> / 2.f + 1e-5f, "[0, pi/2]");
  increasing(t, "phi_i", d->phi_i, -kPi<float> - 1e-5f, kPi<float> + 1e-5f, "[-pi, pi]");
  // bxdfs.cpp:941-948: more than 2 phi_i values means anisotropic, and then the grid must cover
  // the full circle ("reduction" 1); Mitsuba 3 would instead mirror a half or quarter circle
  // (measured.cpp:176-180, 250-256), which pbrt-v4 refuses: such a file renders differently.
  d->isotropic = n_phi <= 2;
  if (!d->isotropic) {
    const float span = d->phi_i.back() - d->phi_i.front();
    const int reduction = int(std::rint((2.f * kPi<float>) / span));
    if (reduction != 1)
      fail(src, "phi_i",
           fmt::format("covers {:.4g} of 2 pi (reduction {}): pbrt-v4 reads only a full circle, [-pi, pi] (bxdfs.cpp:943-947)",
                       span / (2.f * kPi<float>), reduction));
  }
  if (spectral) {
    d->wavelengths = wavelengths->floats();
    increasing(t, "wavelengths", d->wavelengths, 1.f, 1e5f, "[1, 1e5] nm");
  }
  std::set<std::string> changed;  // the fields read otherwise than they stand (RglData::read_as)
  std::vector<float> ndf_v = ndf.floats(), sigma_v = sigma.floats(), vndf_v = vndf.floats(), lum_v = luminance.floats();
  const std::vector<float> spec_v = spectra.floats();
  // Rounding noise of the densities read as 0, with one note per field (kRoundingNoiseUlps,
  // rgl_material.h); what is left negative is refused below. The colour tables keep their
  // negatives (next comment).
  for (auto [name, v] : {std::pair<const char*, std::vector<float>*>{"ndf", &ndf_v},
                         {"sigma", &sigma_v},
                         {"vndf", &vndf_v},
                         {"luminance", &lum_v}})
    if (std::string note = zero_rounding_noise(src, name, *v); !note.empty()) {
      d->notes.push_back(std::move(note));
      changed.insert(name);
    }
  finite_non_negative(t, "ndf", ndf_v);
  finite_non_negative(t, "sigma", sigma_v);
  finite_non_negative(t, "vndf", vndf_v);
  finite_non_negative(t, "luminance", lum_v);
  // Colour tables may hold small negative values (measurement noise; pbrt-v4 clamps the
  // interpolated value at 0, bxdfs.cpp:1045), but must be finite.
  for (size_t i = 0; i < spec_v.size(); ++i)
    if (!std::isfinite(spec_v[i]) || std::abs(spec_v[i]) > kMaxTableValue)
      fail(src, spectra.name,
           fmt::format("value {} at flat index {} (finite, magnitude <= {:g} expected)", spec_v[i], i, kMaxTableValue));
  // f divides by sigma (pbrt-v4 bxdfs.cpp:1032-1033, Mitsuba 3 measured.cpp:333-335), which the
  // readers take as it stands: a 0 there gives an infinite f at those viewing directions (sigma of
  // a flat mirror is cos(theta), 0 at the horizon). aniso raises such values to kMinSigma and says
  // so, rather than refusing a file the renderers read.
  {
    size_t raised = 0, first = 0;
    float lowest = kMinSigma;
    for (size_t i = 0; i < sigma_v.size(); ++i)
      if (sigma_v[i] < kMinSigma) {
        if (raised++ == 0) first = i;
        lowest = std::min(lowest, sigma_v[i]);
        sigma_v[i] = kMinSigma;
      }
    if (raised) changed.insert("sigma");
    if (raised)
      d->notes.push_back(
          fmt::format("{}: field \"sigma\": {} value{} below {:g} (the lowest {:g}, the first at flat index "
                      "{}) read as {:g}: f divides by sigma, the renderers would give an infinite f there",
                      src, raised, raised == 1 ? "" : "s", kMinSigma, lowest, first, kMinSigma));
  }
  // Every vndf and luminance slice is normalised by its sum (sampling.h:1404-1405): a zero slice
  // gives NaN densities.
  auto positive_slices = [&](const char* name, const std::vector<float>& v, uint64_t per_slice) {
    for (uint64_t s = 0; s * per_slice < v.size(); ++s) {
      double sum = 0.0;
      for (uint64_t k = 0; k < per_slice; ++k) sum += v[s * per_slice + k];
      // 1e-20: the slice is scaled by 1 / sum in float (sampling.h:1404); a sum near float's
      // smallest values would overflow that scale.
      if (!(sum > 1e-20))
        fail(src, name,
             fmt::format("slice (phi_i {}, theta_i {}) is all zero (sum {:g}): its density cannot be normalised", s / n_theta,
                         s % n_theta, sum));
    }
  };
  positive_slices("vndf", vndf_v, vndf.shape[2] * vndf.shape[3]);
  positive_slices("luminance", lum_v, luminance.shape[2] * luminance.shape[3]);
  for (const auto& [f, v] : {std::pair<const TensorField*, const std::vector<float>*>{&ndf, &ndf_v},
                             {&sigma, &sigma_v},
                             {&vndf, &vndf_v},
                             {&luminance, &lum_v}})
    if (changed.count(f->name)) d->read_as.push_back(make_field(f->name, f->shape, *v));

  d->ndf_shape[0] = int(ndf.shape[0]);
  d->ndf_shape[1] = int(ndf.shape[1]);
  d->sigma_shape[0] = int(sigma.shape[0]);
  d->sigma_shape[1] = int(sigma.shape[1]);
  d->vndf_grid[0] = int(vndf.shape[2]);
  d->vndf_grid[1] = int(vndf.shape[3]);
  d->colour_grid = int(spectra.shape[3]);
  for (const TensorField& f : t.fields)
    d->field_summary.push_back(fmt::format("{} {} {}", f.name, dtype_name(f.dtype), f.shape_string()));

  // bxdfs.cpp:950-985 / measured.cpp:183-231: the same constructors and arguments.
  const std::vector<std::vector<float>> angle_params{d->phi_i, d->theta_i};
  d->ndf.build(ndf_v.data(), int(ndf.shape[1]), int(ndf.shape[0]), {}, false, false);
  d->sigma.build(sigma_v.data(), int(sigma.shape[1]), int(sigma.shape[0]), {}, false, false);
  d->vndf.build(vndf_v.data(), int(vndf.shape[3]), int(vndf.shape[2]), angle_params, true, true);
  d->luminance.build(lum_v.data(), int(luminance.shape[3]), int(luminance.shape[2]), angle_params, true, true);
  const int n = int(spectra.shape[3]);
  const size_t plane = size_t(n) * size_t(n);
  std::vector<float> rgb_v;
  if (spectral) {
    // Reduced to linear sRGB once, per grid point, with aniso's spectral reduction
    // (measured/spectral.h: CIE 1931 over the file's wavelengths, equal-energy white): the
    // interpolant is linear in the table, so reducing the table equals reducing each evaluation
    // (before pbrt-v4's per-wavelength clamp at 0, which the colour clamp replaces).
    std::vector<double> lambda(d->wavelengths.begin(), d->wavelengths.end());
    const SpectralToRgb reduce(lambda);
    const size_t slices = size_t(n_phi * n_theta);
    rgb_v.assign(slices * 3 * plane, 0.f);
    for (size_t s = 0; s < slices; ++s)
      for (size_t j = 0; j < n_lambda; ++j) {
        const glm::dvec3 w = reduce.weights[j];
        const float* in = spec_v.data() + (s * n_lambda + j) * plane;
        for (int c = 0; c < 3; ++c) {
          float* out = rgb_v.data() + (s * 3 + size_t(c)) * plane;
          for (size_t k = 0; k < plane; ++k) out[k] += float(w[c]) * in[k];
        }
      }
  } else {
    rgb_v = spec_v;
  }
  static const std::vector<float> kChannels{0.f, 1.f, 2.f};  // Mitsuba's rgb_wavelengths (measured.cpp:111)
  d->rgb.build(rgb_v.data(), n, n, {d->phi_i, d->theta_i, kChannels}, false, false);
  d->tables = RglTables{d->ndf.view, d->sigma.view, d->vndf.view, d->luminance.view, d->rgb.view, d->isotropic};
  return d;
}

namespace {
std::mutex& note_mutex() {
  static std::mutex m;
  return m;
}
std::function<void(const std::string&)>& note_sink() {
  static std::function<void(const std::string&)> sink;
  return sink;
}
}  // namespace

void set_note_sink(std::function<void(const std::string&)> sink) {
  std::lock_guard lock(note_mutex());
  note_sink() = std::move(sink);
}

std::shared_ptr<const RglData> load_rgl(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const RglData>> registry;
  {
    std::lock_guard lock(mutex);
    if (auto it = registry.find(path); it != registry.end()) return it->second;
  }
  std::shared_ptr<const RglData> d = rgl_from_tensor(read_tensor_file(path));
  std::unique_lock lock(mutex);
  const auto [it, inserted] = registry.emplace(path, d);
  lock.unlock();
  // Once per file and process: the thread that registered it tells.
  if (inserted) {
    std::lock_guard note_lock(note_mutex());
    if (note_sink())
      for (const std::string& n : it->second->notes) note_sink()(n);
  }
  return it->second;
}

bool is_rgl_file_name(const std::string& spec) {
  if (spec.size() < 5) return false;
  std::string ext = spec.substr(spec.size() - 5);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bsdf";
}

std::string describe_rgl(const RglData& d) {
  std::string s = fmt::format("{}: RGL tensor file, {} bytes, {} ({}), {}\n", d.source, d.file_size,
                              d.spectral ? fmt::format("spectral, {} wavelengths {:.0f}-{:.0f} nm", d.wavelengths.size(),
                                                       d.wavelengths.front(), d.wavelengths.back())
                                         : std::string("RGB"),
                              d.spectral ? "pbrt-v4 and Mitsuba 3 spectral variants" : "Mitsuba 3 RGB variants",
                              d.isotropic ? "isotropic" : "anisotropic");
  s += fmt::format("  grids: theta_i {} ({:.1f} to {:.1f} deg), phi_i {}, ndf {}x{}, sigma {}x{}, vndf {}x{}, colour {}x{}\n",
                   d.theta_i.size(), d.theta_i.front() * 180.0 / M_PI, d.theta_i.back() * 180.0 / M_PI, d.phi_i.size(),
                   d.ndf_shape[0], d.ndf_shape[1], d.sigma_shape[0], d.sigma_shape[1], d.vndf_grid[0], d.vndf_grid[1],
                   d.colour_grid, d.colour_grid);
  s += "  fields:\n";
  for (const std::string& f : d.field_summary) s += "    " + f + "\n";
  s += "  description: " + text_escape(d.description) + "\n";  // the file's bytes: no control byte to the terminal
  return s;
}

}  // namespace aniso::rgl
