// rgl/rgl_source.cpp: the source of export-rgl (rgl/rgl_export.h): its f and spectra, and whether
// it is isotropic.
#include "rgl/export_detail.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "aniso/measured/spectral.h"

namespace aniso::rgl {

std::vector<float> export_wavelengths() {
  std::vector<float> l;
  for (int nm = 380; nm <= 780; nm += 20) l.push_back(float(nm));
  return l;
}

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
  // (rotation_deg) takes the general path, like every other model. Which models have one, and their
  // alphas, is the kernel's answer (ggx_distribution, the question exact_ggx in
  // src/export/ggx_source.cpp asks too). A GGX with the separable Smith G (the principled model)
  // takes the general path too: its files came out worse with the exact D than with the round
  // trip's choice (rgb, default grids, mean cosine-weighted L1: 0.0103 / 0.0094 for the default
  // principled, 0.0828 / 0.0162 metallic 0.3 roughness 0.2 sheen 0.5, 0.0186 / 0.0095 metallic 1
  // roughness 0.15; 0.0108 / 0.0113 metallic 1 roughness 0.4 anisotropic 0.9).
  if (!m.rotation.identity()) return s;
  const GgxDistributionT<double> d = m.ggx_distribution();
  if (d.part == GgxPart::None || d.masking != GgxMasking::HeightCorrelated) return s;
  s.ggx_alpha = glm::dvec2(d.alpha_x, d.alpha_y);
  if (d.part == GgxPart::Whole) {
    // The diffuse term kd / pi gets a uniform share of the distribution, in proportion to its
    // albedo against the specular one (Schlick at normal incidence bounds it); a conductor has none.
    const double kd = luminance_of(glm::dvec3(d.kd)), ks = luminance_of(glm::dvec3(d.f0));
    // At most 0.2: more spreads the colour grid over the diffuse part and leaves the specular peak
    // to few grid points (measured: GGX alpha 0.2 with kd 0.2, L1 at 80 degrees 8 % with 0.75, 2.6 % with 0.2).
    s.uniform_weight = kd > 0.0 ? std::clamp(kd / (kd + ks), 0.02, 0.2) : 0.0;
  } else {
    // A GGX lobe beside broad terms that are not Lambertian (a metal's directional diffuse lobe,
    // the principled model's diffuse and sheen): a tenth of the distribution for them.
    s.uniform_weight = 0.1;
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

}  // namespace aniso::rgl
