// rgl/rgl_tables.cpp: the tables of one RGL tensor file: D and sigma as an estimate names them,
// the warps, the colour tables (docs/rgl.md, steps 1 to 6).
#include "rgl/export_detail.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "aniso/measured/spectral.h"

namespace aniso::rgl {

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
      // The readers normalise each slice by its sum (pbrt-v4 sampling.h:1404-1405), so its scale
      // is free: the slice is written with mean 1 (1.01 with the mixture), which keeps a lobe
      // too sharp for the grid, whose values here are a few 1e-36 (a Lafortune lobe with n = 1e6),
      // from a float sum that underflows the readers' normalisation (src/rgl/rgl_material.cpp,
      // positive_slices).
      for (size_t k = 0; k < plane; ++k) {
        float& v = lum_t[slice * plane + k];
        v = mean > 0.0 && std::isfinite(1.0 / mean) ? float(double(v) / mean + 0.01) : 1.f;
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

}  // namespace aniso::rgl
