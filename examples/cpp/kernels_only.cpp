// examples/cpp/kernels_only.cpp: the header-only kernels alone (CMake aniso::kernels, pkg-config
// aniso-kernels): two materials built from numbers, f and pdf at a few (theta, phi) pairs, and
// three checks of the interface. No aniso library is linked; the only other dependency is glm:
//
//   g++ -std=c++20 -I<prefix>/include -DGLM_FORCE_XYZW_ONLY kernels_only.cpp -o kernels_only
//
// Output: for each material a line "# material <the same material as JSON>", then one line per
// direction pair, "theta_i phi_i theta_o phi_o f_r f_g f_b pdf" (degrees; the numbers as
// `aniso eval --angles --material <JSON>` prints them; compare_with_cli.sh runs that comparison).
// Exit status 1 when a check fails.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <aniso/kernels.h>

namespace {

using aniso::MaterialD;  // MaterialT<double>; a renderer would use aniso::Material (float)
using aniso::Vec3d;

// w = (sin theta cos phi, sin theta sin phi, cos theta), angles in degrees: the local shading frame
// of docs/conventions.md (z = normal, x = tangent, phi measured from the tangent towards y).
Vec3d direction_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * std::numbers::pi / 180.0, p = std::fmod(phi_deg, 360.0) * std::numbers::pi / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

// Ward 1992, Eq. 5a (the angle form) with its own normalisation, written out independently of the
// kernel (which evaluates the equivalent vector form, docs/models/ward.md):
//   f = kd / pi + ks exp(-tan^2 theta_h (cos^2 phi_h / ax^2 + sin^2 phi_h / ay^2))
//                    / (4 pi ax ay sqrt(cos theta_i cos theta_o))
double ward1992_reference(double kd, double ks, double ax, double ay, const Vec3d& wi, const Vec3d& wo) {
  const Vec3d h = glm::normalize(wi + wo);
  const double theta_h = std::acos(h.z), phi_h = std::atan2(h.y, h.x);
  const double e =
      std::exp(-std::pow(std::tan(theta_h), 2) * (std::pow(std::cos(phi_h) / ax, 2) + std::pow(std::sin(phi_h) / ay, 2)));
  return kd / std::numbers::pi + ks * e / (4.0 * std::numbers::pi * ax * ay * std::sqrt(wi.z * wo.z));
}

bool close(double a, double b, double relative) { return std::abs(a - b) <= relative * std::max(std::abs(a), std::abs(b)); }

struct Pair {
  double theta_i, phi_i, theta_o, phi_o;  // degrees
};
// The mirror configuration (h = n); the half vector tilted 10 degrees of azimuth away from it,
// towards the bitangent (the second pair, where the wide alpha_y keeps the Ward highlight bright)
// and towards the tangent (the third, where the narrow alpha_x darkens it); then a few others.
constexpr Pair kPairs[] = {{30, 0, 30, 180},  {30, 0, 30, 160}, {30, 90, 30, 250},
                           {45, 20, 60, 200}, {10, 0, 70, 180}, {80, 0, 80, 180}};

// Prints f and pdf at every pair and checks three properties of the interface:
// Helmholtz reciprocity f(wi, wo) = f(wo, wi) (docs/conventions.md), and for a sample() at each wo
// that its pdf is pdf(wi, wo) and its weight f cos(theta_i) / pdf (docs/conventions.md, "The
// sampling interface").
int print_and_check(const char* json, const MaterialD& m) {
  int failures = 0;
  std::printf("# material %s\n", json);
  for (const Pair& p : kPairs) {
    const Vec3d wi = direction_deg(p.theta_i, p.phi_i), wo = direction_deg(p.theta_o, p.phi_o);
    const aniso::RGBT<double> f = m.f(wi, wo);  // the BRDF, 1/sr, without the cosine
    const double pdf = m.pdf(wi, wo);           // solid-angle density of sample() giving wi for this wo
    std::printf("%g %g %g %g %.9g %.9g %.9g %.9g\n", p.theta_i, p.phi_i, p.theta_o, p.phi_o, f.x, f.y, f.z, pdf);

    const aniso::RGBT<double> f_swapped = m.f(wo, wi);
    for (int c = 0; c < 3; ++c)
      if (!close(f[c], f_swapped[c], 1e-12)) ++failures, std::printf("reciprocity: %g != %g\n", f[c], f_swapped[c]);

    // uc picks the lobe, u places the direction; all uniform in [0, 1).
    const aniso::BSDFSampleT<double> s = m.sample(wo, 0.3, aniso::Vec2T<double>(0.6, 0.2));
    if (s.valid) {
      const aniso::RGBT<double> fs = m.f(s.wi, wo);
      if (!close(s.pdf, m.pdf(s.wi, wo), 1e-12)) ++failures, std::printf("sample pdf: %g != %g\n", s.pdf, m.pdf(s.wi, wo));
      for (int c = 0; c < 3; ++c)
        if (!close(s.weight[c], fs[c] * s.wi.z / s.pdf, 1e-12)) ++failures, std::printf("sample weight: %g\n", s.weight[c]);
    }
  }
  return failures;
}

}  // namespace

int main() {
  int failures = 0;

  // A brushed Ward material (Ward 1992; Walter 2005's sampling): narrow along the tangent,
  // wide along the bitangent. WardT = a Lambertian kd / pi plus ks times the Ward lobe.
  aniso::WardT<double> ward;
  ward.kd = aniso::RGBT<double>(0.1);
  ward.ks = aniso::RGBT<double>(0.5, 0.4, 0.3);
  ward.lobe.alpha_x = 0.05;
  ward.lobe.alpha_y = 0.3;
  ward.lobe.form = aniso::WardForm::Vector;
  ward.lobe.normalization = aniso::WardNormalization::Ward1992;
  const MaterialD ward_material(ward);  // MaterialT's converting constructor: any model struct
  failures += print_and_check(R"({"model": "ward", "kd": 0.1, "ks": [0.5, 0.4, 0.3], "alpha_x": 0.05, "alpha_y": 0.3, )"
                              R"("form": "vector", "normalization": "ward"})",
                              ward_material);
  // The kernel against Ward's own equation, on the green channel (ks = 0.4).
  for (const Pair& p : kPairs) {
    const Vec3d wi = direction_deg(p.theta_i, p.phi_i), wo = direction_deg(p.theta_o, p.phi_o);
    const double reference = ward1992_reference(0.1, 0.4, 0.05, 0.3, wi, wo);
    if (!close(ward_material.f(wi, wo).y, reference, 1e-9))
      ++failures, std::printf("Ward 1992 Eq. 5a: kernel %.12g, reference %.12g\n", ward_material.f(wi, wo).y, reference);
  }

  // Anisotropic GGX (Walter et al. 2007; Heitz 2014's height-correlated Smith G2; Heitz 2018's
  // visible-normal sampling), Schlick's Fresnel from f0, turned by 30 degrees about the normal (the
  // JSON key rotation_deg: MaterialT turns the directions, the kernel never sees the angle).
  aniso::GGXT<double> ggx;
  ggx.kd = aniso::RGBT<double>(0.05);
  ggx.f0 = aniso::RGBT<double>(0.9, 0.6, 0.3);
  ggx.lobe.alpha_x = 0.1;
  ggx.lobe.alpha_y = 0.4;
  MaterialD ggx_material(ggx);
  ggx_material.rotation = aniso::frame_rotation_deg(30.0);
  failures += print_and_check(
      R"({"model": "ggx", "kd": 0.05, "f0": [0.9, 0.6, 0.3], "alpha_x": 0.1, "alpha_y": 0.4, "rotation_deg": 30})", ggx_material);

  if (failures) std::printf("FAILED: %d checks\n", failures);
  return failures ? 1 : 0;
}
