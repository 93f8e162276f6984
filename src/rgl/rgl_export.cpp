// rgl/rgl_export.cpp: an RGL tensor file from any BRDF (rgl/rgl_export.h; docs/rgl.md).
#include "aniso/rgl/rgl_export.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include <fmt/format.h>

#include "aniso/measured/spectral.h"
#include "aniso/rgl/rgl_material.h"
#include "stats/rng.h"

namespace aniso::rgl {
namespace {

constexpr double kPiD = 3.14159265358979323846;
// The tilt of the warps that export_rgl tries with the estimated D (docs/rgl.md, step 4: measured,
// L1 at 80 degrees, lobe-mean D: anisotropic Ward 6.7 % at 0, 4.8 % at 0.15, 5.1 % at 0.3).
constexpr double kAutoTilt = 0.15;

double luminance_of(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }  // Rec. 709 Y

Vec3d dir(double theta, double phi) {
  return Vec3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Grid node k of n on [0, 1] and the (u_theta, u_phi) -> angle maps of pbrt-v4 bxdfs.h:1058-1065.
double node(int k, int n) { return double(k) / double(n - 1); }
double u2theta(double u) { return u * u * (kPiD / 2.0); }
double u2phi(double u) { return (2.0 * u - 1.0) * kPiD; }

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// sigma(w) = integral of D(m) <w, m>+ over the hemisphere of m: the projected area of the
// microfacets (Dupuy & Jakob 2018, Sec. 3; for GGX, cos(theta) (1 + Lambda(w)), Heitz 2014 Eq. 80).
double sigma_ggx(const Vec3d& w, double ax, double ay) {
  return 0.5 * (w.z + std::sqrt(w.z * w.z + ax * ax * w.x * w.x + ay * ay * w.y * w.y));
}
double d_ggx(const Vec3d& m, double ax, double ay) {
  const double d = (m.x / ax) * (m.x / ax) + (m.y / ay) * (m.y / ay) + m.z * m.z;
  return 1.0 / (kPiD * ax * ay * d * d);
}
// The uniform distribution D = 1/pi (normalised: integral of D cos = 1) has sigma = (1 + cos) / 2.
double sigma_uniform(const Vec3d& w) { return 0.5 * (1.0 + w.z); }

}  // namespace

std::vector<float> export_wavelengths() {
  std::vector<float> l;
  for (int nm = 380; nm <= 780; nm += 20) l.push_back(float(nm));
  return l;
}

namespace {
double box(int c, double nm) {  // c: 0 red, 1 green, 2 blue
  const int band = nm < 490.0 ? 2 : (nm < 590.0 ? 1 : 0);
  return band == c ? 1.0 : 0.0;
}
}  // namespace

glm::dmat3 rgb_to_box_coefficients() {
  const std::vector<float> lf = export_wavelengths();
  const std::vector<double> l(lf.begin(), lf.end());
  const SpectralToRgb reduce(l);
  glm::dmat3 a(0.0);  // column c: the RGB of box c
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v(l.size());
    for (size_t j = 0; j < l.size(); ++j) v[j] = box(c, l[j]);
    a[c] = reduce(v);
  }
  return glm::inverse(a);
}

namespace {
// The box spectrum whose reduction is rgb (coefficients clamped at 0, as for the colour tables),
// at each of the export wavelengths.
std::vector<double> box_spectrum(const glm::dvec3& rgb) {
  const std::vector<float> lambda = export_wavelengths();
  const glm::dvec3 coef = glm::max(rgb_to_box_coefficients() * rgb, glm::dvec3(0.0));
  std::vector<double> v(lambda.size(), 0.0);
  for (size_t j = 0; j < lambda.size(); ++j)
    for (int c = 0; c < 3; ++c) v[j] += coef[c] * box(c, lambda[j]);
  return v;
}

// A metal's f per wavelength: (1 - a) F(<wi, h>; n(lambda), k(lambda)) specular(wi, wo) +
// directional_diffuse(wi, wo) (aniso/brdf/metal.h), the conductor Fresnel equation at the
// measured n, k (docs/metals.md, steps 2-3) where the RGB model has the per-channel fit. The
// (1 - a) weight and the directional-diffuse lobe are RGB quantities of the model: their box
// spectra. Their RGB is the same in every direction for the weight, not for the lobe, whose
// box spectrum is therefore taken per call.
void set_metal_spectra(BrdfSource& s, const MaterialD& m, const MetalData& metal) {
  const std::vector<float> lambda = export_wavelengths();
  std::vector<glm::dvec2> nk;
  for (const float l : lambda) nk.push_back(metal_nk(metal, l));
  const std::vector<double> weight = box_spectrum(glm::dvec3(m.metal.specular_weight));
  const glm::dmat3 inv = rgb_to_box_coefficients();
  s.f_spectral = [m, nk, weight, inv, lambda](const Vec3d& wi_in, const Vec3d& wo_in, double* out) {
    const Vec3d wi = m.rotation.to_model(wi_in), wo = m.rotation.to_model(wo_in);
    std::fill(out, out + nk.size(), 0.0);
    if (!same_upper_hemisphere(wi, wo)) return;
    const MetalT<double>& mt = m.metal;
    const double cos_d = glm::dot(wi, glm::normalize(wi + wo)), spec = mt.specular(wi, wo);
    glm::dvec3 dd(0.0);
    if (mt.has_directional_diffuse) dd = glm::max(inv * glm::dvec3(mt.directional_diffuse.eval(wi, wo)), glm::dvec3(0.0));
    for (size_t j = 0; j < nk.size(); ++j) {
      out[j] = weight[j] * F_Conductor(cos_d, nk[j].x, nk[j].y) * spec;
      for (int c = 0; c < 3; ++c) out[j] += dd[c] * box(c, lambda[j]);
    }
  };
  s.spectral_origin = fmt::format("the Fresnel reflectance of {}'s measured n, k ({})", metal.name, metal.source);
}
}  // namespace

BrdfSource brdf_source(const MaterialD& m, const MetalData* metal) {
  BrdfSource s;
  s.f = [m](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(wi, wo)); };
  s.measured = m.kind == ModelKind::Rgl || m.kind == ModelKind::Measured;
  if (m.kind == ModelKind::Measured)
    s.isotropic_by_construction = "a MERL table is isotropic by construction (theta_h, theta_d, phi_d)";
  if (m.kind == ModelKind::Rgl && m.rgl.t->isotropic)
    s.isotropic_by_construction =
        "the tensor file has one phi_i, which pbrt-v4 and Mitsuba 3 read isotropic (bxdfs.cpp:938, measured.cpp:165)";
  if (metal && m.kind == ModelKind::Metal) set_metal_spectra(s, m, *metal);
  // The closed-form GGX distribution is the lobe's in its own frame: a turned material
  // (rotation_deg) takes the general path, like every other model.
  if (!m.rotation.identity()) return s;
  if (m.kind == ModelKind::GGX) {
    s.ggx_alpha = glm::dvec2(m.ggx.lobe.alpha_x, m.ggx.lobe.alpha_y);
    // The diffuse term kd / pi gets a uniform share of the distribution, in proportion to its
    // albedo against the specular one (Schlick at normal incidence bounds it).
    const double kd = luminance_of(glm::dvec3(m.ggx.kd)), ks = luminance_of(glm::dvec3(m.ggx.f0));
    // At most 0.2: more spreads the colour grid over the diffuse part and leaves the specular peak
    // to few grid points (measured: GGX alpha 0.2 with kd 0.2, L1 at 80 degrees 8 % with 0.75, 2.6 % with 0.2).
    s.uniform_weight = kd > 0.0 ? std::clamp(kd / (kd + ks), 0.02, 0.2) : 0.0;
  } else if (m.kind == ModelKind::Metal && m.metal.lobe_kind == SpecularLobeKind::GGX) {
    s.ggx_alpha = glm::dvec2(m.metal.ggx.alpha_x, m.metal.ggx.alpha_y);
    s.uniform_weight = m.metal.has_directional_diffuse ? 0.1 : 0.0;
  }
  return s;
}

bool is_isotropic(const BrdfSource& src) {
  // A fixed low-discrepancy set of pairs (golden-ratio sequences) and rotation angles.
  for (int k = 0; k < 64; ++k) {
    const double a = std::fmod(0.5 + k * 0.6180339887498949, 1.0), b = std::fmod(0.3 + k * 0.7548776662466927, 1.0);
    const double c = std::fmod(0.1 + k * 0.5698402909980532, 1.0), d = std::fmod(0.7 + k * 0.3247179572447460, 1.0);
    const double th_i = 1.4 * a, ph_i = 2 * kPiD * b, th_o = 1.4 * c, ph_o = 2 * kPiD * d, rot = 0.3 + 2.0 * a * d;
    const glm::dvec3 f0 = src.f(dir(th_i, ph_i), dir(th_o, ph_o)), f1 = src.f(dir(th_i, ph_i + rot), dir(th_o, ph_o + rot));
    for (int ch = 0; ch < 3; ++ch)
      if (std::abs(f0[ch] - f1[ch]) > 1e-6 * std::max({std::abs(f0[ch]), std::abs(f1[ch]), 1e-12})) return false;
  }
  return true;
}

double rotation_difference(const BrdfSource& src) {
  constexpr int kPairs = 256;
  constexpr double kMaxTheta = 80.0 * kPiD / 180.0;  // Ngan et al. 2005's range
  double num = 0.0, den = 0.0;
  for (int k = 0; k < kPairs; ++k) {
    // Golden-ratio sequences (as is_isotropic): fixed, evenly spread.
    const double a = std::fmod(0.5 + k * 0.6180339887498949, 1.0), b = std::fmod(0.3 + k * 0.7548776662466927, 1.0);
    const double c = std::fmod(0.1 + k * 0.5698402909980532, 1.0), e = std::fmod(0.7 + k * 0.3247179572447460, 1.0);
    const double rot = 0.3 + 2.0 * std::fmod(0.2 + k * 0.4142135623730950, 1.0);
    const Vec3d wo = dir(kMaxTheta * std::sqrt(a), 2.0 * kPiD * b);  // sqrt: uniform in solid angle near the normal
    Vec3d wi;
    if (k % 2 == 0) {
      // A mirror pair about h, theta_h = 60 deg x c^2: half of these within 15 degrees of the normal.
      const Vec3d h = dir((60.0 * kPiD / 180.0) * c * c, 2.0 * kPiD * e);
      wi = 2.0 * glm::dot(wo, h) * h - wo;
      if (!(wi.z > std::cos(kMaxTheta))) continue;
    } else {
      wi = dir(kMaxTheta * std::sqrt(c), 2.0 * kPiD * e);
    }
    const double turn_o = std::atan2(wo.y, wo.x) + rot, turn_i = std::atan2(wi.y, wi.x) + rot;
    const double ti = std::acos(std::clamp(wi.z, -1.0, 1.0)), to = std::acos(std::clamp(wo.z, -1.0, 1.0));
    const glm::dvec3 f0 = src.f(wi, wo), f1 = src.f(dir(ti, turn_i), dir(to, turn_o));
    const double w = wi.z * wo.z;
    const glm::dvec3 d = f1 - f0, m = 0.5 * (f0 + f1);
    num += w * glm::dot(d, d);
    den += w * glm::dot(m, m);
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

IsotropyDecision decide_isotropy(const BrdfSource& src, const ExportOptions& opt) {
  IsotropyDecision r;
  using I = ExportOptions::Isotropy;
  if (opt.isotropy != I::Auto) {
    r.isotropic = opt.isotropy == I::Isotropic;
    r.why = r.isotropic ? "--isotropic: one phi_i slice, f as seen from azimuth 0" : "--anisotropic: phi_i over the full circle";
    return r;
  }
  if (!src.isotropic_by_construction.empty()) {
    r.isotropic = true;
    r.why = src.isotropic_by_construction;
    return r;
  }
  if (src.measured) {
    r.rotation_difference = rotation_difference(src);
    r.isotropic = r.rotation_difference <= kMeasuredIsotropyTolerance;
    r.why = fmt::format(
        "f changes by {:.2f} % (relative RMS) under rotations about the normal, {} the {:.0f} % allowed for "
        "measurement noise (--isotropic or --anisotropic decide otherwise)",
        100.0 * r.rotation_difference, r.isotropic ? "within" : "beyond", 100.0 * kMeasuredIsotropyTolerance);
    return r;
  }
  r.isotropic = is_isotropic(src);
  r.why =
      r.isotropic ? "f is unchanged (to 1e-6) under rotations about the normal" : "f changes under rotations about the normal";
  return r;
}

namespace {

// The density of the vndf warp for one incident direction w, D(m) <w, m>+ times the Jacobian
// 2 pi^2 u_theta sin(theta_m) on the N x N (u_theta, u_phi) grid (the vndf table's slice; the
// readers normalise it). Isotropic tables measure phi_m from phi of w.
void vndf_slice(const PL2D& ndf, bool iso, const Vec3d& w, double phi_w, int N, float* out) {
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x) {
      const double ut = node(x, N), up = node(y, N), th = u2theta(ut);
      const Vec3d m = dir(th, u2phi(up) + (iso ? phi_w : 0.0));
      const double d = ndf.evaluate(float(ut), float(up), nullptr);
      out[size_t(y) * N + x] = float(d * std::max(0.0, glm::dot(w, m)) * 2.0 * kPiD * kPiD * ut * std::sin(th));
    }
}

// The warp of one incident direction wo on the N x N (u_theta, u_phi) grid: the VNDF of the file's
// D (vndf_slice), mixed, with weight f_share, with the density of the slice's own f: Y(f(wi, wo))
// cos(theta_i) |d wi / d m| = Y(f) cos(theta_i) 4 <wo, m> (Walter et al. 2007, Eq. 14), times
// the same Jacobian 2 pi^2 u_theta sin(theta_m); each part normalised to sum 1 before the mix.
// Any positive density is a valid warp (the readers build it from the field alone and the colour
// table is made through it, step 5 of docs/rgl.md): it only decides where the colour nodes lie,
// and the f share puts them where f cos is, which the common D does not follow at grazing angles.
void warp_slice(const BrdfSource& src, const PL2D& ndf, bool iso, const Vec3d& wo, double phi_w, int N, double tilt,
                double f_share, float* out) {
  vndf_slice(ndf, iso, tilt > 0.0 ? glm::normalize((1.0 - tilt) * wo + tilt * Vec3d(0.0, 0.0, 1.0)) : wo, phi_w, N, out);
  if (!(f_share > 0.0)) return;
  const size_t n2 = size_t(N) * N;
  std::vector<double> g(n2, 0.0);
  double sum_g = 0.0, sum_v = 0.0;
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x) {
      const double ut = node(x, N), up = node(y, N), th = u2theta(ut);
      const Vec3d m = dir(th, u2phi(up) + (iso ? phi_w : 0.0));
      const double om = glm::dot(wo, m);
      const Vec3d wi = 2.0 * om * m - wo;
      double v = 0.0;
      if (om > 0.0 && wi.z > 0.0)
        v = luminance_of(glm::max(src.f(wi, wo), glm::dvec3(0.0))) * wi.z * 4.0 * om * 2.0 * kPiD * kPiD * ut * std::sin(th);
      if (!std::isfinite(v)) v = 0.0;
      g[size_t(y) * N + x] = v;
      sum_g += v;
      sum_v += out[size_t(y) * N + x];
    }
  if (sum_g > 0.0 && sum_v > 0.0)  // f = 0 for this wo: the VNDF alone
    for (size_t k = 0; k < n2; ++k) out[k] = float((1.0 - f_share) * out[k] / sum_v + f_share * g[k] / sum_g);
}

// The colour a slice at wo would hold, c(u) = Y(f(wi, wo)) cos(theta_i) 4 sigma(wo) / D(m), at the
// centres of an nc x nc grid of u over the slice's own exact warp (warp_slice of wo alone), into
// out[nc * nc]; returns the sum (the slice's mass, its albedo up to a constant). A slice of the
// colour table holds c(u) over the warp's square, and the cosine-weighted L1 of f at wo is the
// plain integral of |c_read(u) - c(u)| du over that square (the warp maps du to D <wo, m> / sigma
// dm, and dwi = 4 <wo, m> dm): second differences of c between slices measure the readers' blend error.
double slice_content(const BrdfSource& src, const PL2D& ndf, const PL2D& sigma, bool iso, int N, double tilt, double f_share,
                     double th_o, double ph_o, int nc, std::vector<float>& scratch, double* out) {
  const Vec3d wo = dir(th_o, ph_o);
  scratch.resize(size_t(N) * N);
  warp_slice(src, ndf, iso, wo, ph_o, N, tilt, f_share, scratch.data());
  PL2DTables warp;
  warp.build(scratch.data(), N, N, {}, true, true);
  const double sig = sigma.evaluate(rgl_theta2u(float(th_o)), rgl_phi2u(float(ph_o)), nullptr);
  double mass = 0.0;
  for (int y = 0; y < nc; ++y)
    for (int x = 0; x < nc; ++x) {
      double& c_out = out[size_t(y) * nc + x];
      c_out = 0.0;
      const PL2DSample s = warp.view.sample(float((x + 0.5) / nc), float((y + 0.5) / nc), nullptr);
      if (!s.finite()) continue;
      const Vec3d m = dir(rgl_u2theta(s.x), rgl_u2phi(s.y) + (iso ? ph_o : 0.0));
      const Vec3d wi = 2.0 * glm::dot(wo, m) * m - wo;
      const double d = ndf.evaluate(s.x, s.y, nullptr);
      if (!(wi.z > 0.0 && d > 0.0)) continue;
      const double c = luminance_of(glm::max(src.f(wi, wo), glm::dvec3(0.0))) * wi.z * 4.0 * sig / d;
      if (!std::isfinite(c)) continue;
      c_out = c;
      mass += c;
    }
  return mass;
}

// theta_i placed where the readers' linear blend between neighbouring slices errs (slice_content).
// The error of linear interpolation in theta with spacing h is h^2 |c''| / 8, so spacing the slices
// as |c''|^(-1/2) equalises it (de Boor, "A Practical Guide to Splines", Ch. II, the optimal knots
// of piecewise-linear interpolation). c is evaluated on a 16 x 16 grid of the exact single-slice
// warp at 90 elevations (8 azimuths when anisotropic), |c''| by second differences relative to the
// slice's mass (its albedo); the density is mixed with a uniform share `uniform` so that no
// interval grows without bound where the estimate is small.
std::vector<float> place_theta_by_blend_error(const BrdfSource& src, const PL2D& ndf, const PL2D& sigma, bool iso, int N,
                                              double tilt, double f_share, double theta_max, int count, double uniform) {
  const int K = 90, nc = 16, nphi = iso ? 1 : 8;
  const size_t per = size_t(nphi) * nc * nc;
  std::vector<double> content(size_t(K) * per, 0.0), mass(size_t(K), 0.0);
  std::vector<float> scratch;
  for (int k = 0; k < K; ++k) {
    const double th_o = theta_max * k / (K - 1);
    for (int j = 0; j < nphi; ++j) {
      const double ph_o = iso ? 0.0 : u2phi((j + 0.5) / nphi);
      mass[size_t(k)] += slice_content(src, ndf, sigma, iso, N, tilt, f_share, th_o, ph_o, nc, scratch,
                                       content.data() + size_t(k) * per + size_t(j) * nc * nc);
    }
  }
  // sqrt of the relative second difference per step: the error density's square root.
  std::vector<double> rho(size_t(K), 0.0);
  for (int k = 1; k + 1 < K; ++k) {
    double dd = 0.0;
    for (size_t q = 0; q < per; ++q)
      dd += std::abs(content[size_t(k - 1) * per + q] - 2.0 * content[size_t(k) * per + q] + content[size_t(k + 1) * per + q]);
    const double ref = std::max(mass[size_t(k)], 1e-3 * std::max(mass[size_t(k - 1)], mass[size_t(k + 1)]));
    rho[size_t(k)] = ref > 0.0 ? std::sqrt(dd / ref) : 0.0;
  }
  rho.front() = rho[1];
  rho.back() = rho[size_t(K - 2)];
  double total = 0.0;
  for (int k = 0; k + 1 < K; ++k) total += 0.5 * (rho[size_t(k)] + rho[size_t(k + 1)]);
  // Cumulative density over the K - 1 intervals: (1 - uniform) of the error density, uniform of
  // the angle (all uniform when the estimate is 0: a constant f).
  const double w_err = total > 0.0 ? 1.0 - uniform : 0.0;
  std::vector<double> cum(size_t(K), 0.0);
  for (int k = 1; k < K; ++k)
    cum[size_t(k)] = cum[size_t(k - 1)] + w_err * 0.5 * (rho[size_t(k - 1)] + rho[size_t(k)]) / std::max(total, 1e-300) +
                     (1.0 - w_err) / (K - 1);
  std::vector<float> theta(static_cast<size_t>(count));
  for (int q = 0; q < count; ++q) {
    const double target = cum.back() * q / (count - 1);
    const size_t k = std::min(size_t(std::lower_bound(cum.begin(), cum.end(), target) - cum.begin()), size_t(K - 1));
    double t = theta_max * double(k) / (K - 1);
    if (k > 0 && cum[k] > cum[k - 1]) t = theta_max * (double(k - 1) + (target - cum[k - 1]) / (cum[k] - cum[k - 1])) / (K - 1);
    theta[size_t(q)] = float(t);
  }
  theta.front() = 0.f;
  theta.back() = float(theta_max);
  for (int q = 1; q < count; ++q)  // strictly increasing (the readers' rule), in float
    theta[size_t(q)] = std::max(theta[size_t(q)], std::nextafter(theta[size_t(q - 1)], 2.f));
  return theta;
}

// The mirror image of v in the line of the tangent plane at angle b from the x axis.
Vec3d mirror(const Vec3d& v, double b) {
  const double c = std::cos(2.0 * b), s = std::sin(2.0 * b);
  return Vec3d(c * v.x + s * v.y, s * v.x - c * v.y, v.z);
}

// The largest relative change of f when both directions are mirrored in the line at angle b, over
// a fixed set of pairs (golden-ratio sequences, as is_isotropic).
double mirror_asymmetry(const BrdfSource& src, double b) {
  double worst = 0.0;
  for (int k = 0; k < 24; ++k) {
    const double a = std::fmod(0.5 + k * 0.6180339887498949, 1.0), c = std::fmod(0.3 + k * 0.7548776662466927, 1.0);
    const double e = std::fmod(0.1 + k * 0.5698402909980532, 1.0), d = std::fmod(0.7 + k * 0.3247179572447460, 1.0);
    const Vec3d wi = dir(1.4 * a, 2 * kPiD * c), wo = dir(1.4 * e, 2 * kPiD * d);
    const glm::dvec3 f0 = src.f(wi, wo), f1 = src.f(mirror(wi, b), mirror(wo, b));
    for (int ch = 0; ch < 3; ++ch) {
      const double ref = std::max({std::abs(f0[ch]), std::abs(f1[ch]), 1e-12});
      worst = std::max(worst, std::abs(f0[ch] - f1[ch]) / ref);
    }
  }
  return worst;
}

// A mirror axis of an anisotropic f (a line of the tangent plane in which mirroring both
// directions leaves f unchanged, relative tolerance 1e-6 as is_isotropic): the tangent or the
// bitangent of Ward, GGX, Ashikhmin-Shirley and the metals, turned with the material's
// rotation_deg. Found by a scan in 0.5-degree steps refined by golden-section search; none: nullopt.
std::optional<double> mirror_axis(const BrdfSource& src) {
  const int steps = 360;
  double best = 1e300, b_best = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double b = kPiD * k / steps, a = mirror_asymmetry(src, b);
    if (a < best) best = a, b_best = b;
  }
  double lo = b_best - kPiD / steps, hi = b_best + kPiD / steps;
  const double g = 0.6180339887498949;
  for (int it = 0; it < 60; ++it) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    if (mirror_asymmetry(src, x1) < mirror_asymmetry(src, x2))
      hi = x2;
    else
      lo = x1;
  }
  const double b = 0.5 * (lo + hi);
  if (!(mirror_asymmetry(src, b) <= 1e-6)) return std::nullopt;
  return b - kPiD * std::floor(b / kPiD);  // in [0, pi)
}

// phi_i placed where the readers' linear blend between neighbouring azimuth slices errs, as
// theta_i (place_theta_by_blend_error: slices spaced as |d^2 c / d phi^2|^(-1/2), de Boor Ch. II).
// c is evaluated at 72 azimuths and at every theta_i slice up to 86 degrees (the blend in phi
// happens at every elevation of the grid; the one beyond it, 89 degrees, holds the grazing limit
// alone); the error density at an azimuth is the largest over the elevations (the target is the
// error at every incident direction). A mirror axis b of f makes the density symmetric about b
// and b + pi/2 when that is an axis too (the density is averaged over the mirror images), and
// the slices are placed from b on, so that a slice lies on the axis, where c is extremal in phi
// and a chord would cut the extremum. The readers need the circle's end points -pi and pi
// (pbrt-v4 bxdfs.cpp:940-946, Mitsuba 3 measured.cpp:167-172); they hold one direction, so count
// values place count - 1 distinct azimuths. When none of them falls on -pi (the axes of a turned
// material), -pi is added: count + 1 values, so that the slices keep the symmetry of the material.
// The readers find any increasing grid's interval by bisection (pbrt-v4 util/sampling.h:1468-1477,
// Mitsuba 3 core/distr_2d.h:264-283): non-uniform azimuths are within the format.
std::vector<float> place_phi_by_blend_error(const BrdfSource& src, const PL2D& ndf, const PL2D& sigma, int N, double tilt,
                                            double f_share, const std::vector<float>& theta_i, int count, double uniform) {
  const int K = 72, nc = 16;
  const double h = 2.0 * kPiD / K;
  std::vector<double> thetas;
  for (const float t : theta_i)
    if (t > 0.f && t <= float(86.0 * kPiD / 180.0)) thetas.push_back(t);
  const size_t per = size_t(nc) * nc;
  std::vector<double> rho(size_t(K), 0.0);
  std::vector<float> scratch;
  for (const double th : thetas) {
    std::vector<double> content(size_t(K) * per, 0.0), mass(size_t(K), 0.0);
    for (int k = 0; k < K; ++k)
      mass[size_t(k)] = slice_content(src, ndf, sigma, false, N, tilt, f_share, th, -kPiD + h * k, nc, scratch,
                                      content.data() + size_t(k) * per);
    for (int k = 0; k < K; ++k) {
      const size_t km = size_t((k + K - 1) % K), kp = size_t((k + 1) % K);
      double dd = 0.0;
      for (size_t q = 0; q < per; ++q)
        dd += std::abs(content[km * per + q] - 2.0 * content[size_t(k) * per + q] + content[kp * per + q]);
      const double ref = std::max(mass[size_t(k)], 1e-3 * std::max(mass[km], mass[kp]));
      if (ref > 0.0) rho[size_t(k)] = std::max(rho[size_t(k)], std::sqrt(dd / ref));
    }
  }
  // Symmetric about the mirror axes: the mean over the images of each azimuth (linear in the
  // periodic samples).
  const std::optional<double> axis = mirror_axis(src);
  if (axis) {
    std::vector<double (*)(double, double)> images = {[](double p, double) { return p; },
                                                      [](double p, double b) { return 2.0 * b - p; }};
    if (mirror_asymmetry(src, *axis + 0.5 * kPiD) <= 1e-6) {
      images.push_back([](double p, double b) { return 2.0 * b + kPiD - p; });
      images.push_back([](double p, double) { return p + kPiD; });
    }
    auto at = [&](double p) {
      const double t = (p + kPiD) / h;
      const double fl = std::floor(t), w = t - fl;
      const int k0 = int(((long(fl) % K) + K) % K);
      return (1.0 - w) * rho[size_t(k0)] + w * rho[size_t((k0 + 1) % K)];
    };
    std::vector<double> sym(size_t(K), 0.0);
    for (int k = 0; k < K; ++k) {
      for (auto* img : images) sym[size_t(k)] += at(img(-kPiD + h * k, *axis));
      sym[size_t(k)] /= double(images.size());
    }
    rho = sym;
  }
  // Periodic cumulative density from -pi: (1 - uniform) of the error density, uniform of the angle.
  double total = 0.0;
  for (int k = 0; k < K; ++k) total += 0.5 * (rho[size_t(k)] + rho[size_t((k + 1) % K)]);
  const double w_err = total > 0.0 ? 1.0 - uniform : 0.0;
  std::vector<double> cum(size_t(K) + 1, 0.0);
  for (int k = 0; k < K; ++k)
    cum[size_t(k) + 1] =
        cum[size_t(k)] + w_err * 0.5 * (rho[size_t(k)] + rho[size_t((k + 1) % K)]) / std::max(total, 1e-300) + (1.0 - w_err) / K;
  auto cum_at = [&](double p) {  // p in [-pi, pi]
    const double t = std::clamp((p + kPiD) / h, 0.0, double(K));
    const int k = std::min(int(t), K - 1);
    return cum[size_t(k)] + (t - k) * (cum[size_t(k) + 1] - cum[size_t(k)]);
  };
  auto inverse = [&](double c) {  // c in [0, 1)
    const size_t k = std::min(size_t(std::upper_bound(cum.begin(), cum.end(), c) - cum.begin()), size_t(K)) - 1;
    const double span = cum[k + 1] - cum[k];
    return -kPiD + h * (double(k) + (span > 0.0 ? (c - cum[k]) / span : 0.0));
  };
  // count - 1 azimuths at equal steps of the cumulative density, from the axis (else from -pi).
  const double start = axis ? cum_at(*axis) : 0.0;
  std::vector<double> p;
  for (int q = 0; q < count - 1; ++q) p.push_back(inverse(std::fmod(start + double(q) / (count - 1), 1.0)));
  std::sort(p.begin(), p.end());
  const double tol = 1e-6;
  if (kPiD - p.back() <= tol) {  // a slice on pi: it is the one on -pi
    p.pop_back();
    p.insert(p.begin(), -kPiD);
  } else if (p.front() + kPiD > tol) {  // no slice on -pi (a turned material's axes): -pi as well
    p.insert(p.begin(), -kPiD);
  }
  p.front() = -kPiD;
  p.push_back(kPiD);
  std::vector<float> phi(p.size());
  for (size_t q = 0; q < p.size(); ++q) phi[q] = float(p[q]);
  phi.front() = float(-kPiD);
  phi.back() = float(kPiD);
  for (size_t q = 1; q + 1 < phi.size(); ++q)  // strictly increasing (the readers' rule), in float
    phi[q] = std::max(phi[q], std::nextafter(phi[q - 1], 4.f));
  return phi;
}

// The tables of one file, D as opt.d_estimate names it (LobeAverage, else the retro-reflection).
std::vector<TensorField> export_tables(const BrdfSource& src, const ExportOptions& opt, ExportReport* report) {
  const double t0 = cpu_seconds();
  // export_rgl passes its decision (decide_isotropy); Auto only from a direct caller.
  const bool iso = opt.isotropy == ExportOptions::Isotropy::Auto ? decide_isotropy(src, opt).isotropic
                                                                 : opt.isotropy == ExportOptions::Isotropy::Isotropic;
  const int N = opt.ndf;
  const int NV = opt.vndf > 0 ? opt.vndf : (iso ? N : 32);  // the vndf grid (below, "vndf")
  // The share of each slice's own f in its warp (warp_slice): 0.8 with the envelope D (measured on
  // matte-steel, L1 at 80 degrees: 0 -> 10 %, 0.6 -> 3.7 %, 0.8 -> 3.2 %; docs/rgl.md), 0 otherwise.
  const double f_share = !src.ggx_alpha && opt.d_estimate == ExportOptions::DEstimate::LobeEnvelope ? 0.8 : 0.0;
  // The direction whose VNDF each slice's warp is: wo tilted towards the normal by opt.warp_tilt
  // (warp_slice); an exact GGX D keeps wo's own VNDF.
  const double tilt = src.ggx_alpha ? 0.0 : std::max(0.0, opt.warp_tilt);
  const std::string warp_made = tilt > 0.0 ? fmt::format("; warps tilted {:.2f} towards the normal", tilt) : "";
  // ndf and sigma: [phi rows, theta columns] over (u_phi, u_theta) (pbrt-v4 bxdfs.cpp:950-957:
  // xSize = shape[1] is u_theta, ySize = shape[0] is u_phi). Isotropic: 2 constant rows.
  const int rows = iso ? 2 : N;
  // D and sigma at the nodes of an N x N (u_theta, u_phi) grid; isotropic ones are evaluated at
  // phi = 0 and repeated.
  const int nphi_q = N;  // phi nodes of the integration grid
  std::vector<double> D(size_t(N) * nphi_q), S(size_t(N) * nphi_q);
  std::vector<Vec3d> m_dir(size_t(N) * nphi_q);
  std::vector<double> w_quad(size_t(N) * nphi_q);
  for (int j = 0; j < nphi_q; ++j)
    for (int i = 0; i < N; ++i) {
      const double ut = node(i, N), up = node(j, nphi_q);
      const double th = u2theta(ut);
      m_dir[size_t(j) * N + i] = dir(th, u2phi(up));
      // Trapezoid weights in u_theta and in u_phi (the last phi node repeats the first: weight
      // 1/2 at each end makes the periodic sum exact), times the Jacobian 2 pi^2 u_theta sin(theta)
      // of (u_theta, u_phi) -> solid angle (the factor in pbrt-v4 bxdfs.cpp:1081).
      const double wt = (i == 0 || i == N - 1) ? 0.5 : 1.0, wp = (j == 0 || j == nphi_q - 1) ? 0.5 : 1.0;
      w_quad[size_t(j) * N + i] = wt * wp / double(N - 1) / double(nphi_q - 1) * 2.0 * kPiD * kPiD * ut * std::sin(th);
    }
  std::string d_method;
  auto sigma_of = [&](const Vec3d& w) {
    double s = 0.0;
    for (size_t k = 0; k < D.size(); ++k) s += w_quad[k] * D[k] * std::max(0.0, glm::dot(w, m_dir[k]));
    return s;
  };
  // The estimates from f (LobeAverage, LobeEnvelope): isotropic, one value per theta_m (the mean
  // over the row); then normalised to integral of D cos(theta_m) = 1 (the projected area of the
  // macrosurface), or uniform when f = 0 wherever it was looked at.
  auto row_mean_and_normalise = [&]() {
    if (iso)
      for (int i = 0; i < N; ++i) {
        double sum = 0.0;
        for (int j = 0; j < nphi_q; ++j) sum += D[size_t(j) * N + i];
        for (int j = 0; j < nphi_q; ++j) D[size_t(j) * N + i] = sum / nphi_q;
      }
    double norm = 0.0;
    for (size_t k = 0; k < D.size(); ++k) norm += w_quad[k] * D[k] * m_dir[k].z;
    if (norm > 0.0 && std::isfinite(norm))
      for (double& d : D) d /= norm;
    else
      std::fill(D.begin(), D.end(), 1.0 / kPiD);
  };
  if (src.ggx_alpha) {
    const double ax = src.ggx_alpha->x, ay = src.ggx_alpha->y, u = src.uniform_weight;
    for (size_t k = 0; k < D.size(); ++k) {
      D[k] = (1.0 - u) * d_ggx(m_dir[k], ax, ay) + u / kPiD;
      S[k] = (1.0 - u) * sigma_ggx(m_dir[k], ax, ay) + u * sigma_uniform(m_dir[k]);
    }
    d_method = u > 0 ? fmt::format("exact GGX D and sigma, {:.2f} uniform for the diffuse part", u) : "exact GGX D and sigma";
  } else if (opt.d_estimate == ExportOptions::DEstimate::LobeAverage) {
    // The lobe's shape over the viewing directions: under the microfacet model f = D G2 F /
    // (4 cos_i cos_o) (Walter et al. 2007, Eq. 20), so 4 f(wi, wo) cos_i cos_o estimates D(m)
    // (times G2 F) from every wo whose mirror about m, wi, is above the horizon. Averaged over wo
    // at 0 to 80 degrees (and 8 azimuths when anisotropic), weighted by cos_i cos_o (where G2 and
    // the estimate's spread are small). One D serves every slice: where it follows f at all
    // viewing angles, c = f cos_i 4 sigma / D varies little over each slice's square and from
    // one slice to the next, which the colour grid and the readers' blend between slices need.
    std::vector<double> wsum(D.size(), 0.0);
    std::fill(D.begin(), D.end(), 0.0);
    const int n_th = 9, n_ph = iso ? 1 : 8;
    for (int a = 0; a < n_ph; ++a)
      for (int b = 0; b < n_th; ++b) {
        const Vec3d wo = dir(kPiD / 180.0 * 10.0 * b, iso ? 0.0 : u2phi((a + 0.5) / n_ph));
        for (size_t k = 0; k < D.size(); ++k) {
          const double om = glm::dot(wo, m_dir[k]);
          const Vec3d wi = 2.0 * om * m_dir[k] - wo;
          if (!(om > 0.0) || !(wi.z > 1e-3)) continue;
          const double est = 4.0 * std::max(0.0, luminance_of(src.f(wi, wo))) * wi.z * wo.z;
          if (!std::isfinite(est)) continue;
          D[k] += wi.z * wo.z * est;
          wsum[k] += wi.z * wo.z;
        }
      }
    for (size_t k = 0; k < D.size(); ++k) D[k] = wsum[k] > 0.0 ? D[k] / wsum[k] : 0.0;
    row_mean_and_normalise();
    d_method = "the lobe's mean shape over viewing angles 0 to 80 degrees, 2% uniform";
  } else if (opt.d_estimate == ExportOptions::DEstimate::LobeEnvelope) {
    // The envelope of the slices' own distributions: for each wo, the D that would make its slice's
    // colour constant, D_wo(m) proportional to f(wi, wo) cos(theta_i) (c = f cos_i 4 sigma / D,
    // step 5), normalised to integral of D_wo cos(theta_m) = 1 over the half vectors whose wi is
    // above the horizon; D is the largest of them at each m (wo at 30 elevations from 0 to 89
    // degrees, 8 azimuths when anisotropic). Every slice's c is then at most about 1 where
    // its own lobe is and changes less from slice to slice than under the mean shape, whose
    // cos_i cos_o weights leave out the grazing lobes of a Lafortune fit.
    std::fill(D.begin(), D.end(), 0.0);
    std::vector<double> est(D.size());
    const int n_th = 30, n_ph = iso ? 1 : 8;
    for (int a = 0; a < n_ph; ++a)
      for (int b = 0; b < n_th; ++b) {
        const Vec3d wo = dir(kPiD / 180.0 * 89.0 * b / (n_th - 1), iso ? 0.0 : u2phi((a + 0.5) / n_ph));
        double mass = 0.0;
        for (size_t k = 0; k < D.size(); ++k) {
          est[k] = 0.0;
          const double om = glm::dot(wo, m_dir[k]);
          const Vec3d wi = 2.0 * om * m_dir[k] - wo;
          if (!(om > 0.0) || !(wi.z > 1e-3)) continue;
          const double e = std::max(0.0, luminance_of(src.f(wi, wo))) * wi.z;
          if (!std::isfinite(e)) continue;
          est[k] = e;
          mass += w_quad[k] * e * m_dir[k].z;
        }
        if (mass > 0.0 && std::isfinite(mass))
          for (size_t k = 0; k < D.size(); ++k) D[k] = std::max(D[k], est[k] / mass);
      }
    row_mean_and_normalise();
    d_method = "the envelope of the slices' own distributions over 0 to 89 degrees, 2% uniform; warps 80% the slice's own f";
  } else {
    // Dupuy, Heitz, Iehl, Poulin & Ostromoukhov 2015, "Extracting Microfacet-based BRDF Parameters
    // from Arbitrary Materials with Power Iterations", Eq. 6-8: under the microfacet model the
    // retro-reflection is f(w, w) = F D(w) G1(w) / (4 cos^2) with G1 = cos / sigma(w), so
    // D(w) is proportional to f(w, w) cos(w) sigma(w): the leading eigenvector of the linear map
    // D -> f(w, w) cos(w) sigma_D(w), found by power iteration (Dupuy & Jakob 2018, Sec. 5.1).
    std::vector<double> retro(D.size());
    for (size_t k = 0; k < D.size(); ++k) {
      const Vec3d w = m_dir[k];
      retro[k] = w.z > 0 ? std::max(0.0, luminance_of(src.f(w, w))) * w.z : 0.0;
    }
    D = retro;
    for (int it = 0; it < opt.power_iterations; ++it) {
      std::vector<double> next(D.size());
      if (iso) {
        std::vector<double> s_row(N);
        for (int i = 0; i < N; ++i) s_row[size_t(i)] = sigma_of(m_dir[size_t(i)]);
        for (size_t k = 0; k < D.size(); ++k) next[k] = retro[k] * s_row[k % size_t(N)];
      } else {
        for (size_t k = 0; k < D.size(); ++k) next[k] = retro[k] * sigma_of(m_dir[k]);
      }
      double norm = 0.0;  // integral of D cos(theta_m) = 1 (the projected area of the macrosurface)
      for (size_t k = 0; k < D.size(); ++k) norm += w_quad[k] * next[k] * m_dir[k].z;
      if (!(norm > 0.0) || !std::isfinite(norm)) {
        std::fill(next.begin(), next.end(), 1.0 / kPiD);  // no retro-reflection at all: uniform D
        norm = 1.0;
      }
      for (size_t k = 0; k < D.size(); ++k) D[k] = next[k] / norm;
    }
    d_method = fmt::format("power iteration on the retro-reflection ({} steps), 2% uniform", opt.power_iterations);
  }
  if (!src.ggx_alpha) {
    // 2 % of the uniform distribution: every half vector keeps a positive density, so the vndf
    // warp reaches wherever f > 0 even where the estimate is 0 (a forward lobe).
    for (double& d : D) d = 0.98 * d + 0.02 / kPiD;
    if (iso)
      for (int i = 0; i < N; ++i) {
        const double s = sigma_of(m_dir[size_t(i)]);
        for (int j = 0; j < nphi_q; ++j) S[size_t(j) * N + i] = s;
      }
    else
      for (size_t k = 0; k < D.size(); ++k) S[k] = sigma_of(m_dir[k]);
  }
  // Stored tables: rows x N. Isotropic: the phi = 0 column repeated in 2 rows.
  std::vector<float> ndf_t(size_t(rows) * N), sigma_t(size_t(rows) * N);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < N; ++i) {
      const size_t k = iso ? size_t(i) : size_t(r) * N + i;
      ndf_t[size_t(r) * N + i] = float(D[k]);
      sigma_t[size_t(r) * N + i] = float(std::max(S[k], 1e-6));  // sigma >= cos/... > 0; 1e-6 guards float underflow
    }
  PL2DTables ndf_pl, sigma_pl;
  ndf_pl.build(ndf_t.data(), N, rows, {}, false, false);
  sigma_pl.build(sigma_t.data(), N, rows, {}, false, false);

  // theta_i on [0, theta_max], theta_max = 89 degrees: at 90 the cosine factors of f vanish or
  // diverge (Ward's 1 / sqrt(cos cos)); the readers use the last slice beyond it (sampling.h:1494
  // clamps the weight). Placed by the error of the readers' blend (place_theta_by_blend_error), or
  // by inverting s(theta) = (theta / theta_max + (sigma(0) - sigma(theta)) / (sigma(0) -
  // sigma(theta_max))) / 2, half uniform in angle, half uniform in projected area.
  const double theta_max = 89.0 * kPiD / 180.0;
  auto sigma_avg = [&](double th) {
    double s = 0.0;
    const int np = iso ? 1 : 8;
    for (int j = 0; j < np; ++j) s += sigma_pl.view.evaluate(float(std::sqrt(th / (kPiD / 2))), float(j + 0.5) / np, nullptr);
    return s / np;
  };
  std::vector<float> theta_i(size_t(opt.theta_i));
  if (opt.placement == ExportOptions::Placement::BlendError) {
    theta_i = place_theta_by_blend_error(src, ndf_pl.view, sigma_pl.view, iso, NV, tilt, f_share, theta_max, opt.theta_i,
                                         opt.placement_uniform);
  } else {
    const int fine = 2048;
    std::vector<double> s(fine + 1), th(fine + 1);
    const double s0 = sigma_avg(0.0), s1 = sigma_avg(theta_max);
    const double span = s0 - s1;
    double run = 0.0;
    for (int k = 0; k <= fine; ++k) {
      th[size_t(k)] = theta_max * k / fine;
      const double area = span > 1e-9 ? (s0 - sigma_avg(th[size_t(k)])) / span : double(k) / fine;
      run = std::max(run, std::clamp(area, 0.0, 1.0));  // monotone
      s[size_t(k)] = 0.5 * (double(k) / fine + run);
    }
    for (int q = 0; q < opt.theta_i; ++q) {
      const double target = s.back() * q / (opt.theta_i - 1);
      const size_t k = size_t(std::lower_bound(s.begin(), s.end(), target) - s.begin());
      double t = th[std::min(k, size_t(fine))];
      if (k > 0 && k <= size_t(fine) && s[k] > s[k - 1])
        t = th[k - 1] + (th[k] - th[k - 1]) * (target - s[k - 1]) / (s[k] - s[k - 1]);
      theta_i[size_t(q)] = float(t);
    }
    theta_i.front() = 0.f;
    theta_i.back() = float(theta_max);
  }
  // phi_i: isotropic: one value (0), the readers then measure phi relative to phi_i (bxdfs.cpp:
  // 1033-1034); anisotropic: the full circle [-pi, pi] (bxdfs.cpp:941-948).
  std::vector<float> phi_i;
  if (iso)
    phi_i = {0.f};
  else if (opt.phi_placement == ExportOptions::PhiPlacement::BlendError)
    phi_i =
        place_phi_by_blend_error(src, ndf_pl.view, sigma_pl.view, NV, tilt, f_share, theta_i, opt.phi_i, opt.placement_uniform);
  else
    for (int j = 0; j < opt.phi_i; ++j) phi_i.push_back(float(u2phi(node(j, opt.phi_i))));
  const size_t n_phi = phi_i.size(), n_theta = theta_i.size();

  // vndf: per incident direction w, the density of visible normals over (u_theta, u_phi),
  // D(m) <w, m>+ / sigma(w) times the Jacobian 2 pi^2 u_theta sin(theta_m) of (u_theta, u_phi) ->
  // solid angle (Dupuy & Jakob 2018, Sec. 4); the readers normalise each slice (sampling.h:
  // 1404-1416), so the 1 / sigma is left out; warp_slice tilts it or mixes in the slice's own f
  // (docs/rgl.md, step 4: with the lobe mean's D, a warp following f made the slices' colours
  // differ more, which the readers' linear blend between slices pays for; with the envelope D it
  // does not).
  // The warp's grid is its own (opt.vndf): the readers build it from the field's shape alone
  // (pbrt-v4 bxdfs.cpp:956-960, Mitsuba 3 measured.cpp:188-196), and since the colour table is made
  // through the warp the readers rebuild, f is exact at every colour node for any warp; the warp
  // only places the nodes. Anisotropic files: 32 x 32 (the default) is half the file of 64 x 64 at
  // the same accuracy; isotropic files are small and keep the ndf's grid (at 32 the Lafortune fit's
  // albedo error grows from 2.3 to 3.1 %; docs/rgl.md).
  const size_t vslice = size_t(NV) * NV;
  std::vector<float> vndf_t(n_phi * n_theta * vslice);
  for (size_t a = 0; a < n_phi; ++a)
    for (size_t b = 0; b < n_theta; ++b)
      warp_slice(src, ndf_pl.view, iso, dir(theta_i[b], phi_i[a]), phi_i[a], NV, tilt, f_share,
                 vndf_t.data() + (a * n_theta + b) * vslice);
  PL2DTables vndf_pl;
  vndf_pl.build(vndf_t.data(), NV, NV, {phi_i, theta_i}, true, true);

  // Colour on the VNDF-warped square: at grid point u of the sample space, m = vndf.sample(u),
  // wi = reflect(wo, m), and the table holds what MeasuredBxDF::f multiplies back:
  // f cos(theta_i) 4 sigma(wo) / D(m) (bxdfs.cpp:1048-1049), with sigma and D the tables'
  // own interpolants, so that f is reproduced exactly at every grid point.
  const int n = opt.colour;
  const size_t plane = size_t(n) * n;
  std::vector<float> rgb_t(n_phi * n_theta * 3 * plane, 0.f), lum_t(n_phi * n_theta * plane, 0.f);
  // A source with spectra of its own fills the spectral table here, with the same factor as the
  // colour table; otherwise it is made from the colour table below.
  const std::vector<float> lambda = export_wavelengths();
  const bool own_spectra = opt.spectral && bool(src.f_spectral);
  std::vector<float> spec_t(own_spectra ? n_phi * n_theta * lambda.size() * plane : 0, 0.f);
  std::vector<double> spec_node(lambda.size());
  for (size_t a = 0; a < n_phi; ++a)
    for (size_t b = 0; b < n_theta; ++b) {
      const Vec3d wo = dir(theta_i[b], phi_i[a]);
      const float p[2] = {phi_i[a], theta_i[b]};
      const float sig = sigma_pl.view.evaluate(rgl_theta2u(theta_i[b]), rgl_phi2u(phi_i[a]), nullptr);
      const size_t slice = a * n_theta + b;
      double mean = 0.0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          PL2DSample s = vndf_pl.view.sample(float(node(x, n)), float(node(y, n)), p);
          // At a node on the border of a region of zero density the warp can give 0 / 0
          // (PL2DSample::finite); the point 1e-4 inside the square stands in for it.
          if (!s.finite())
            s = vndf_pl.view.sample(float(std::clamp(node(x, n), 1e-4, 1.0 - 1e-4)),
                                    float(std::clamp(node(y, n), 1e-4, 1.0 - 1e-4)), p);
          if (!s.finite()) continue;  // the table keeps 0 there
          const double th_m = rgl_u2theta(s.x), ph_m = rgl_u2phi(s.y) + (iso ? phi_i[a] : 0.f);
          const Vec3d m = dir(th_m, ph_m);
          const Vec3d wi = 2.0 * glm::dot(wo, m) * m - wo;
          glm::dvec3 c(0.0);
          double lum = 0.0;
          const double d = ndf_pl.view.evaluate(s.x, s.y, nullptr);
          if (wi.z > 0.0 && d > 0.0) {
            const glm::dvec3 f = glm::max(src.f(wi, wo), glm::dvec3(0.0));
            c = f * (wi.z * 4.0 * sig / d);
            if (own_spectra) {
              src.f_spectral(wi, wo, spec_node.data());
              for (size_t j = 0; j < lambda.size(); ++j)
                spec_t[(slice * lambda.size() + j) * plane + size_t(y) * n + x] =
                    float(std::max(0.0, spec_node[j]) * (wi.z * 4.0 * sig / d));
            }
            // The luminance table: the density of the sample space that makes the wi density
            // proportional to Y(f) cos (pbrt-v4 bxdfs.cpp:1054-1082: pdf(wi) = luminance(u)
            // vndf_pdf(m) / (4 <wo, m> 2 pi^2 u_theta sin(theta_m))): Y(f) cos times that Jacobian
            // over the warp's density: Y of the colour table (the paper's luminance), computed this way so
            // that it stays right for any warp.
            const double jac = 4.0 * glm::dot(wo, m) * std::max(2.0 * kPiD * kPiD * s.x * std::sin(th_m), 1e-6);
            lum = s.pdf > 0.f ? luminance_of(f) * wi.z * jac / s.pdf : 0.0;
            if (!std::isfinite(lum)) lum = 0.0;
          }
          const size_t k = size_t(y) * n + x;
          for (int ch = 0; ch < 3; ++ch) rgb_t[(slice * 3 + size_t(ch)) * plane + k] = float(c[ch]);
          lum_t[slice * plane + k] = float(lum);
          mean += lum / double(plane);
        }
      // 1 % of the slice's mean luminance everywhere: a defensive mixture (Hesterberg 1995) with
      // plain VNDF sampling, so no direction with f > 0 gets a zero pdf; all zero (black): uniform.
      for (size_t k = 0; k < plane; ++k) {
        float& v = lum_t[slice * plane + k];
        v = mean > 0.0 ? v + float(0.01 * mean) : 1.f;
      }
    }

  std::vector<TensorField> fields;
  const std::string& desc = src.description;
  fields.push_back(
      make_field("description", {desc.size()}, std::span(reinterpret_cast<const uint8_t*>(desc.data()), desc.size())));
  fields.push_back(make_field("phi_i", {n_phi}, phi_i));
  fields.push_back(make_field("theta_i", {n_theta}, theta_i));
  fields.push_back(make_field("ndf", {uint64_t(rows), uint64_t(N)}, ndf_t));
  fields.push_back(make_field("sigma", {uint64_t(rows), uint64_t(N)}, sigma_t));
  fields.push_back(make_field("vndf", {n_phi, n_theta, uint64_t(NV), uint64_t(NV)}, vndf_t));
  fields.push_back(make_field("luminance", {n_phi, n_theta, uint64_t(n), uint64_t(n)}, lum_t));
  std::string spectra_made = "none (an rgb file)";
  if (own_spectra) {
    fields.push_back(make_field("wavelengths", {lambda.size()}, lambda));
    fields.push_back(make_field("spectra", {n_phi, n_theta, lambda.size(), uint64_t(n), uint64_t(n)}, spec_t));
    spectra_made = src.spectral_origin;
  } else if (opt.spectral) {
    // rgb -> three non-negative box spectra whose reduction is that rgb (rgb_to_box_coefficients);
    // a negative coefficient (a colour outside what the boxes reach) is clamped to 0.
    spectra_made = "box spectra of the RGB f";
    const glm::dmat3 inv = rgb_to_box_coefficients();
    std::vector<float> spec(n_phi * n_theta * lambda.size() * plane);
    for (size_t s = 0; s < n_phi * n_theta; ++s)
      for (size_t k = 0; k < plane; ++k) {
        const glm::dvec3 rgb(rgb_t[(s * 3) * plane + k], rgb_t[(s * 3 + 1) * plane + k], rgb_t[(s * 3 + 2) * plane + k]);
        const glm::dvec3 coef = glm::max(inv * rgb, glm::dvec3(0.0));
        for (size_t j = 0; j < lambda.size(); ++j) {
          double v = 0.0;
          for (int c = 0; c < 3; ++c) v += coef[c] * box(c, lambda[j]);
          spec[(s * lambda.size() + j) * plane + k] = float(v);
        }
      }
    fields.push_back(make_field("wavelengths", {lambda.size()}, lambda));
    fields.push_back(make_field("spectra", {n_phi, n_theta, lambda.size(), uint64_t(n), uint64_t(n)}, spec));
  } else {
    fields.push_back(make_field("rgb", {n_phi, n_theta, 3, uint64_t(n), uint64_t(n)}, rgb_t));
  }
  const uint8_t one = 1;
  fields.push_back(make_field("jacobian", {1}, std::span(&one, 1)));
  if (report) {
    report->isotropic = iso;
    report->d_method = d_method + warp_made;
    report->spectra = spectra_made;
    report->seconds = cpu_seconds() - t0;
  }
  return fields;
}

// How well a written file reproduces src: the mean over viewing directions (elevations 10, 30, 50,
// 65, 75 and 85 degrees; 4 azimuths when anisotropic) of the cosine-weighted relative L1 of f plus
// the albedo's relative error, by importance sampling (half the file's own sampler, half cosine;
// 1000 samples, fixed seeds). Only f of the source is needed.
double roundtrip_score(const BrdfSource& src, const std::vector<TensorField>& fields) {
  const std::shared_ptr<RglData> d = rgl_from_tensor(parse_tensor(serialize_tensor(fields), "candidate.bsdf"));
  const RglT<double> k = rgl_kernel<double>(*d);
  double sum = 0.0;
  int count = 0;
  const int np = d->isotropic ? 1 : 4;
  for (const double th_deg : {10.0, 30.0, 50.0, 65.0, 75.0, 85.0})
    for (int a = 0; a < np; ++a) {
      const Vec3d wo = dir(th_deg * kPiD / 180.0, 2.0 * kPiD * (a + 0.25) / np);
      Rng rng(4321 + uint64_t(th_deg) * 11 + uint64_t(a));
      double diff = 0.0, ref = 0.0, a_src = 0.0, a_file = 0.0;
      for (int n = 0; n < 1000; ++n) {
        const Vec2T<double> u(rng.uniform(), rng.uniform());
        Vec3d wi;
        if (n % 2 == 0) {
          const BSDFSampleT<double> s = k.sample(wo, rng.uniform(), u);
          if (!s.valid) continue;
          wi = s.wi;
        } else {
          wi = sample_cosine_hemisphere(u);
        }
        const double pdf = 0.5 * k.pdf(wi, wo) + 0.5 * cosine_hemisphere_pdf(wi.z);
        if (!(pdf > 0.0) || !(wi.z > 0.0)) continue;
        const glm::dvec3 fs = glm::max(src.f(wi, wo), glm::dvec3(0.0)), ff = k.f(wi, wo);
        const double w = wi.z / pdf;
        diff += (std::abs(ff.x - fs.x) + std::abs(ff.y - fs.y) + std::abs(ff.z - fs.z)) * w;
        ref += (fs.x + fs.y + fs.z) * w;
        a_src += luminance_of(fs) * w;
        a_file += luminance_of(ff) * w;
      }
      sum += (ref > 0.0 ? diff / ref : 0.0) + (a_src > 0.0 ? std::abs(a_file - a_src) / a_src : 0.0);
      ++count;
    }
  return sum / count;
}
}  // namespace

std::vector<TensorField> transcode_tensor(const RglData& d, const BrdfSource& src, bool spectral) {
  const TensorFile t = read_tensor_file(d.source);
  std::vector<TensorField> out;
  const std::string desc = src.description.empty() ? d.description : fmt::format("{} ({})", d.description, src.description);
  for (const TensorField& f : t.fields) {
    if (f.name == "description") {
      out.push_back(
          make_field("description", {desc.size()}, std::span(reinterpret_cast<const uint8_t*>(desc.data()), desc.size())));
      continue;
    }
    if (auto it = std::find_if(d.read_as.begin(), d.read_as.end(), [&](const TensorField& r) { return r.name == f.name; });
        it != d.read_as.end()) {
      out.push_back(*it);
      continue;
    }
    const bool colour = f.name == "rgb" || f.name == "spectra" || f.name == "wavelengths";
    if (!colour || spectral == d.spectral) {
      out.push_back(f);
      continue;
    }
    if (f.name != (d.spectral ? "spectra" : "rgb")) continue;  // wavelengths: written with the spectra, or dropped
    const size_t slices = size_t(f.shape[0] * f.shape[1]), plane = size_t(f.shape[3] * f.shape[4]);
    const std::vector<float> in = f.floats();
    if (spectral) {
      // rgb -> box spectra: each grid point's coefficients (rgb_to_box_coefficients, clamped at 0
      // as box_spectrum's) spread over its band; the reduction gives the rgb back within the box
      // gamut.
      const std::vector<float> lambda = export_wavelengths();
      const glm::dmat3 to_box = rgb_to_box_coefficients();
      std::vector<float> spec(slices * lambda.size() * plane);
      for (size_t s = 0; s < slices; ++s)
        for (size_t k = 0; k < plane; ++k) {
          const glm::dvec3 rgb(in[(s * 3 + 0) * plane + k], in[(s * 3 + 1) * plane + k], in[(s * 3 + 2) * plane + k]);
          const glm::dvec3 coef = glm::max(to_box * rgb, glm::dvec3(0.0));
          for (size_t j = 0; j < lambda.size(); ++j) {
            double v = 0.0;
            for (int c = 0; c < 3; ++c) v += coef[c] * box(c, lambda[j]);
            spec[(s * lambda.size() + j) * plane + k] = float(v);
          }
        }
      out.push_back(make_field("wavelengths", {lambda.size()}, lambda));
      out.push_back(make_field("spectra", {f.shape[0], f.shape[1], lambda.size(), f.shape[3], f.shape[4]}, spec));
    } else {
      // spectra -> rgb: the reduction rgl_from_tensor applies (measured/spectral.h).
      const std::vector<double> lambda(d.wavelengths.begin(), d.wavelengths.end());
      const SpectralToRgb reduce(lambda);
      std::vector<float> rgb(slices * 3 * plane, 0.f);
      for (size_t s = 0; s < slices; ++s)
        for (size_t j = 0; j < lambda.size(); ++j)
          for (int c = 0; c < 3; ++c)
            for (size_t k = 0; k < plane; ++k)
              rgb[(s * 3 + size_t(c)) * plane + k] += float(reduce.weights[j][c]) * in[(s * lambda.size() + j) * plane + k];
      out.push_back(make_field("rgb", {f.shape[0], f.shape[1], 3, f.shape[3], f.shape[4]}, rgb));
    }
  }
  return out;
}

std::vector<TensorField> export_rgl(const BrdfSource& src, const ExportOptions& opt_in, ExportReport* report) {
  const double t_start = cpu_seconds();
  const IsotropyDecision decision = decide_isotropy(src, opt_in);
  ExportOptions opt = opt_in;
  opt.isotropy = decision.isotropic ? ExportOptions::Isotropy::Isotropic : ExportOptions::Isotropy::Anisotropic;
  const std::string decided = fmt::format("{}: {}", decision.isotropic ? "isotropic" : "anisotropic", decision.why);
  // A tensor source whose isotropy stays: its own tables, exactly (no grid of ours can do better,
  // and the file stays the source's size; docs/rgl.md "From a tensor file").
  if (src.tensor && !opt.resample && decision.isotropic == src.tensor->isotropic) {
    std::vector<TensorField> fields = transcode_tensor(*src.tensor, src, opt.spectral);
    if (report) {
      *report = ExportReport{};
      report->isotropic = decision.isotropic;
      report->transcoded = true;
      report->d_method = "the source file's own tables";
      report->spectra = !opt.spectral          ? ""
                        : src.tensor->spectral ? "the source file's own spectra"
                                               : "box spectra of the source file's rgb values";
      report->isotropy = decided;
      report->seconds = cpu_seconds() - t_start;
    }
    return fields;
  }
  if (src.ggx_alpha || opt.d_estimate != ExportOptions::DEstimate::Auto) {
    ExportOptions o = opt;  // a fixed D: the tilt chosen by the caller, or none
    o.warp_tilt = std::max(0.0, opt.warp_tilt);
    std::vector<TensorField> fields = export_tables(src, o, report);
    if (report) report->isotropy = decided;
    return fields;
  }
  // No estimate of D wins for every model (docs/rgl.md, "Where the error comes from"): the lobe's
  // mean shape follows forward and grazing lobes (Ashikhmin-Shirley, anisotropic Ward), the
  // retro-reflection suits tables whose grazing values are least like a microfacet lobe (a MERL
  // table), the envelope with warps that follow f lobes that turn towards the horizon (a
  // Lafortune fit); and the warps of the two first either follow each wo (its VNDF) or, tilted
  // towards the normal, change less from slice to slice (warp_tilt). Each file is written (RGB)
  // and the one that reproduces f best is kept; warp_tilt >= 0 fixes the tilt.
  using E = ExportOptions::DEstimate;
  struct Candidate {
    E d;
    double tilt;
    const char* name;
  };
  std::vector<Candidate> candidates;
  for (const double t : opt.warp_tilt >= 0.0 ? std::vector<double>{opt.warp_tilt} : std::vector<double>{0.0, kAutoTilt}) {
    candidates.push_back({E::LobeAverage, t, t > 0.0 ? "lobe mean, tilted" : "lobe mean"});
    candidates.push_back({E::RetroReflection, t, t > 0.0 ? "retro-reflection, tilted" : "retro-reflection"});
  }
  candidates.push_back({E::LobeEnvelope, std::max(0.0, opt.warp_tilt), "envelope"});
  ExportOptions o = opt;
  o.spectral = false;
  std::vector<TensorField> best;
  ExportReport best_report;
  Candidate pick = candidates.front();
  double best_score = 0.0;
  std::string scores;
  for (const Candidate& c : candidates) {
    o.d_estimate = c.d;
    o.warp_tilt = c.tilt;
    ExportReport r;
    std::vector<TensorField> fields = export_tables(src, o, &r);
    const double score = roundtrip_score(src, fields);
    scores += fmt::format("{}{} {:.2f} %", scores.empty() ? "" : ", ", c.name, 100.0 * score);
    if (best.empty() || score < best_score) best = std::move(fields), best_report = r, best_score = score, pick = c;
  }
  if (opt.spectral) {
    o = opt;
    o.d_estimate = pick.d;
    o.warp_tilt = pick.tilt;
    best = export_tables(src, o, &best_report);
  }
  if (report) {
    *report = best_report;
    report->d_method += fmt::format(" (chosen by the round trip: error {:.2f} %; {})", 100.0 * best_score, scores);
    report->seconds = cpu_seconds() - t_start;
    report->isotropy = decided;
  }
  return best;
}

SourceModel source_model(const MaterialD& m) {
  return {[m](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(wi, wo)); },
          [m](const Vec3d& wi, const Vec3d& wo) { return m.pdf(wi, wo); },
          [m](const Vec3d& wo, double uc, const Vec2T<double>& u) { return m.sample(wo, uc, u); }};
}

RoundTripStats compare_rgl(const SourceModel& src, const RglT<double>& file, int samples) {
  RoundTripStats r;
  int count = 0;
  for (int ti = 0; ti <= 4; ++ti)
    for (const double phi_deg : {0.0, 60.0, 120.0, 210.0, 300.0}) {
      const Vec3d wo = dir(ti * 20.0 * kPiD / 180.0, phi_deg * kPiD / 180.0);
      Rng rng(1234 + uint64_t(ti) * 7 + uint64_t(phi_deg));
      double diff = 0.0, ref = 0.0, a_src = 0.0, a_file = 0.0;
      for (int k = 0; k < samples; ++k) {
        const Vec2T<double> u(rng.uniform(), rng.uniform());
        Vec3d wi;
        if (k % 2 == 0) {
          const BSDFSampleT<double> s = src.sample(wo, rng.uniform(), u);
          if (!s.valid) continue;  // counted: the estimator divides by all samples
          wi = s.wi;
        } else {
          wi = sample_cosine_hemisphere(u);
        }
        const double pdf = 0.5 * src.pdf(wi, wo) + 0.5 * cosine_hemisphere_pdf(wi.z);
        if (!(pdf > 0.0) || !(wi.z > 0.0)) continue;
        const glm::dvec3 fs = src.f(wi, wo), ff = file.f(wi, wo);
        const double w = wi.z / pdf;
        diff += (std::abs(ff.x - fs.x) + std::abs(ff.y - fs.y) + std::abs(ff.z - fs.z)) * w;
        ref += (fs.x + fs.y + fs.z) * w;
        a_src += luminance_of(fs) * w;
        a_file += luminance_of(ff) * w;
      }
      const double l1 = ref > 0.0 ? diff / ref : 0.0;
      const double alb = a_src > 0.0 ? std::abs(a_file - a_src) / a_src : 0.0;
      if (l1 > r.l1_max) {
        r.l1_max = l1;
        r.worst_theta_deg = ti * 20.0;
        r.worst_phi_deg = phi_deg;
      }
      r.albedo_max = std::max(r.albedo_max, alb);
      r.l1_by_theta[ti] = std::max(r.l1_by_theta[ti], l1);
      r.l1_mean += l1;
      ++count;
    }
  r.l1_mean /= count;
  return r;
}

}  // namespace aniso::rgl
