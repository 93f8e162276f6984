// rgl/rgl_warp.cpp: the warps of export-rgl's files and the placement of their slices in theta_i
// and phi_i (docs/rgl.md, steps 4 and 6).
#include "rgl/export_detail.h"

#include <algorithm>
#include <cmath>

namespace aniso::rgl {

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

}  // namespace

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

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace aniso::rgl
