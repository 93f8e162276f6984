// tests/reference/reference_brdfs.h: an independent, deliberately plain double-precision
// evaluation of every model, written from the formulas of the project's specification
// (docs/reference/models-spec.md) and the lecture (docs/reference/vgp352-week5-*.txt), not from
// include/aniso. tests/test_reference.cpp holds the library against it.
//
// Independence is the point, so the formulas are written in a *different* form from the kernels
// wherever the specification allows one:
// - Ward (every form and normalisation): the angle form, theta_h = acos(h.z) and
//   phi_h = atan2(h.y, h.x) of the unit half vector (the lecture's first formula), never the
//   vector form; the 1992 approximation exactly as printed (h unit).
// - Ashikhmin-Shirley: the exponent n_u cos^2 phi_h + n_v sin^2 phi_h with phi_h from atan2.
// - GGX: D and Lambda written with theta and phi (tan^2 theta, cos^2 phi, sin^2 phi).
// - Conductor Fresnel: complex arithmetic (std::complex<double>), Born & Wolf / pbrt-v4's
//   FrComplex, while the library uses the real a^2 + b^2 form.
// Only the standard library is used; directions are unit vectors in the local frame
// (z = normal, x = tangent), wi towards the light, wo towards the viewer.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <vector>

namespace aniso_ref {

constexpr double kPi = 3.14159265358979323846;

struct V3 {
  double x = 0, y = 0, z = 0;
};
using C3 = std::array<double, 3>;  // an RGB triple

inline double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 add(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 normalize(const V3& a) {
  const double l = std::sqrt(dot(a, a));
  return {a.x / l, a.y / l, a.z / l};
}
inline C3 grey(double v) { return {v, v, v}; }

// Both directions strictly above the horizon and wi + wo != 0 (models-spec.md: otherwise f = 0).
inline bool valid(const V3& wi, const V3& wo) { return wi.z > 0.0 && wo.z > 0.0; }

// Angles of the unit half vector: theta_h from z, phi_h from x (atan2 of the projection onto the
// xy plane; at h = n the projection has no direction and atan2(0, 0) = 0, where tan theta_h = 0).
struct HalfAngles {
  V3 h;          // unit half vector
  double theta;  // theta_h
  double phi;    // phi_h
};
inline HalfAngles half_angles(const V3& wi, const V3& wo) {
  HalfAngles a;
  a.h = normalize(add(wi, wo));
  a.theta = std::acos(std::clamp(a.h.z, -1.0, 1.0));
  a.phi = std::atan2(a.h.y, a.h.x);
  return a;
}

// ---------------------------------------------------------------------------------------------
// Lambert and Phong
inline C3 lambert(const C3& kd, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  return {kd[0] / kPi, kd[1] / kPi, kd[2] / kPi};
}

// Phong: k = ks (v . r)^s, r = 2 (n . l) n - l (the lecture), l = wi, v = wo, n = z.
inline C3 phong(const C3& kd, const C3& ks, double s, bool normalized, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  const V3 n{0.0, 0.0, 1.0};
  const double nl = dot(n, wi);
  const V3 r{2.0 * nl * n.x - wi.x, 2.0 * nl * n.y - wi.y, 2.0 * nl * n.z - wi.z};
  const double c = dot(r, wo);
  double lobe = c > 0.0 ? std::pow(c, s) : 0.0;
  if (normalized) lobe *= (s + 2.0) / (2.0 * kPi);
  C3 out;
  for (int i = 0; i < 3; ++i) out[i] = kd[i] / kPi + ks[i] * lobe;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Ward 1992 and its variants
enum class WardForm { Vector, Angle, Approx };
enum class WardNorm { Ward1992, Duer, Balanced };

// The Gaussian term. Vector and Angle are the same function (models-spec.md, Ward point 3), so both are
// computed from the angles; Approx is Ward's Eq. 5b, with the unit h.
inline double ward_exponential(double ax, double ay, WardForm form, const V3& wi, const V3& wo) {
  const HalfAngles a = half_angles(wi, wo);
  if (form == WardForm::Approx) {
    const double u = a.h.x / ax, v = a.h.y / ay;
    return std::exp(-2.0 * (u * u + v * v) / (1.0 + a.h.z));
  }
  const double t = std::tan(a.theta), cp = std::cos(a.phi), sp = std::sin(a.phi);
  return std::exp(-t * t * (cp * cp / (ax * ax) + sp * sp / (ay * ay)));
}

inline double ward_normalization(double ax, double ay, WardNorm norm, const V3& wi, const V3& wo) {
  const double ci = wi.z, co = wo.z;
  switch (norm) {
    case WardNorm::Ward1992: return 1.0 / (4.0 * kPi * ax * ay * std::sqrt(ci * co));
    case WardNorm::Duer: return 1.0 / (4.0 * kPi * ax * ay * ci * co);
    case WardNorm::Balanced: {
      const V3 h = add(wi, wo);  // unnormalised
      const double hn = h.z;
      return dot(h, h) / (kPi * ax * ay * hn * hn * hn * hn);
    }
  }
  return 0.0;
}

// The colourless specular lobe (ks = 1).
inline double ward_lobe(double ax, double ay, WardForm form, WardNorm norm, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  return ward_normalization(ax, ay, norm, wi, wo) * ward_exponential(ax, ay, form, wi, wo);
}

inline C3 ward(const C3& kd, const C3& ks, double ax, double ay, WardForm form, WardNorm norm, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  const double s = ward_lobe(ax, ay, form, norm, wi, wo);
  C3 out;
  for (int i = 0; i < 3; ++i) out[i] = kd[i] / kPi + ks[i] * s;
  return out;
}

// Walter 2005: pdf(wi) = exp(-tan^2 theta_h (cos^2 phi_h / ax^2 + sin^2 phi_h / ay^2))
//                        / (4 pi ax ay (h . wo) cos^3 theta_h)
inline double ward_pdf(double ax, double ay, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  const HalfAngles a = half_angles(wi, wo);
  const double t = std::tan(a.theta), cp = std::cos(a.phi), sp = std::sin(a.phi), ct = std::cos(a.theta);
  const double e = std::exp(-t * t * (cp * cp / (ax * ax) + sp * sp / (ay * ay)));
  return e / (4.0 * kPi * ax * ay * dot(a.h, wo) * ct * ct * ct);
}

// ---------------------------------------------------------------------------------------------
// Ashikhmin-Shirley 2000
inline double schlick(double f0, double c) { return f0 + (1.0 - f0) * std::pow(1.0 - c, 5.0); }

inline double as_exponent(double nu, double nv, double phi_h) {
  const double cp = std::cos(phi_h), sp = std::sin(phi_h);
  return nu * cp * cp + nv * sp * sp;
}

// f_s with F = 1: sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e / ((h.w) max(n.wi, n.wo)).
inline double as_lobe(double nu, double nv, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  const HalfAngles a = half_angles(wi, wo);
  const double e = as_exponent(nu, nv, a.phi);
  return std::sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * kPi) * std::pow(std::cos(a.theta), e) /
         (dot(a.h, wi) * std::max(wi.z, wo.z));
}

inline C3 ashikhmin_shirley(const C3& rd, const C3& rs, double nu, double nv, const C3& kd, const C3& ks_scale, const V3& wi,
                            const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  const HalfAngles a = half_angles(wi, wo);
  const double lobe = as_lobe(nu, nv, wi, wo);
  const double wh = dot(wi, a.h);
  const double di = 1.0 - std::pow(1.0 - wi.z / 2.0, 5.0), dout = 1.0 - std::pow(1.0 - wo.z / 2.0, 5.0);
  C3 out;
  for (int i = 0; i < 3; ++i) {
    const double fs = lobe * schlick(rs[i], wh);
    const double fd = 28.0 * rd[i] / (23.0 * kPi) * (1.0 - rs[i]) * di * dout;
    out[i] = ks_scale[i] * fs + fd + kd[i] / kPi;
  }
  return out;
}

// p_h(h) = sqrt((nu + 1)(nv + 1)) / (2 pi) (n . h)^e;  pdf(wi) = p_h / (4 (wo . h)).
inline double as_pdf(double nu, double nv, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  const HalfAngles a = half_angles(wi, wo);
  const double ph = std::sqrt((nu + 1.0) * (nv + 1.0)) / (2.0 * kPi) * std::pow(std::cos(a.theta), as_exponent(nu, nv, a.phi));
  return ph / (4.0 * dot(wo, a.h));
}

// ---------------------------------------------------------------------------------------------
// Lafortune 1997
struct LafortuneLobe {
  C3 cx, cy, cz, n, scale{1.0, 1.0, 1.0};
};

inline C3 lafortune(const C3& rho_d, const std::vector<LafortuneLobe>& lobes, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  C3 out;
  for (int c = 0; c < 3; ++c) {
    double sum = rho_d[c] / kPi;
    for (const LafortuneLobe& l : lobes) {
      const double base = l.cx[c] * wi.x * wo.x + l.cy[c] * wi.y * wo.y + l.cz[c] * wi.z * wo.z;
      if (base > 0.0) sum += l.scale[c] * std::pow(base, l.n[c]);
    }
    out[c] = sum;
  }
  return out;
}

// The lecture's matte steel (three lobes, C_xy, C_z, s per channel), typed in from models-spec.md.
inline std::vector<LafortuneLobe> matte_steel_lobes() {
  const double t[3][3][3] = {// [lobe][channel] = {C_xy, C_z, s}
                             {{-1.11954, 1.01272, 15.8708}, {-1.11845, 1.01469, 15.6489}, {-1.11999, 1.01942, 15.4571}},
                             {{-1.05334, 0.69541, 111.267}, {-1.06409, 0.662178, 88.9222}, {-1.08378, 0.626672, 65.2179}},
                             {{-1.01684, 1.00132, 180.181}, {-1.01635, 1.00112, 184.152}, {-1.01529, 1.00108, 195.773}}};
  std::vector<LafortuneLobe> lobes(3);
  for (int l = 0; l < 3; ++l)
    for (int c = 0; c < 3; ++c) {
      lobes[l].cx[c] = lobes[l].cy[c] = t[l][c][0];
      lobes[l].cz[c] = t[l][c][1];
      lobes[l].n[c] = t[l][c][2];
    }
  return lobes;
}

// ---------------------------------------------------------------------------------------------
// Anisotropic GGX with height-correlated Smith masking
// D(h) = 1 / (pi ax ay cos^4 theta_h (1 + tan^2 theta_h (cos^2 phi_h / ax^2 + sin^2 phi_h / ay^2))^2)
inline double ggx_D(double ax, double ay, double theta_h, double phi_h) {
  const double t = std::tan(theta_h), c = std::cos(theta_h), cp = std::cos(phi_h), sp = std::sin(phi_h);
  const double q = 1.0 + t * t * (cp * cp / (ax * ax) + sp * sp / (ay * ay));
  return 1.0 / (kPi * ax * ay * c * c * c * c * q * q);
}

// Lambda(w) = (-1 + sqrt(1 + alpha(phi)^2 tan^2 theta)) / 2, alpha(phi)^2 = ax^2 cos^2 phi + ay^2 sin^2 phi
// (the same as (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2).
inline double ggx_Lambda(double ax, double ay, const V3& w) {
  const double theta = std::acos(std::clamp(w.z, -1.0, 1.0)), phi = std::atan2(w.y, w.x);
  const double t = std::tan(theta), cp = std::cos(phi), sp = std::sin(phi);
  const double a2 = ax * ax * cp * cp + ay * ay * sp * sp;
  return (-1.0 + std::sqrt(1.0 + a2 * t * t)) / 2.0;
}

// D G2 / (4 cos_i cos_o), G2 = 1 / (1 + Lambda(wi) + Lambda(wo)).
inline double ggx_lobe(double ax, double ay, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  const HalfAngles a = half_angles(wi, wo);
  const double G2 = 1.0 / (1.0 + ggx_Lambda(ax, ay, wi) + ggx_Lambda(ax, ay, wo));
  return ggx_D(ax, ay, a.theta, a.phi) * G2 / (4.0 * wi.z * wo.z);
}

// Schlick's F with a reflectance F90 at grazing incidence, as a blend of the two ends (Filament's
// F_Schlick(f0, f90, VoH); Karis 2013): F0 (1 - w) + F90 w, w = (1 - c)^5. F90 = 1 is schlick().
inline double schlick_f90(double f0, double f90, double c) {
  const double w = std::pow(1.0 - c, 5.0);
  return f0 * (1.0 - w) + f90 * w;
}

inline C3 ggx(const C3& kd, const C3& f0, double ax, double ay, const V3& wi, const V3& wo, const C3& f90 = grey(1.0)) {
  if (!valid(wi, wo)) return grey(0.0);
  const HalfAngles a = half_angles(wi, wo);
  const double lobe = ggx_lobe(ax, ay, wi, wo), c = dot(wi, a.h);
  C3 out;
  for (int i = 0; i < 3; ++i) out[i] = kd[i] / kPi + schlick_f90(f0[i], f90[i], c) * lobe;
  return out;
}

// Visible-normal sampling (Heitz 2018): D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z,
// G1 = 1 / (1 + Lambda(wo)); pdf(wi) = D_wo(h) / (4 wo.h).
inline double ggx_pdf(double ax, double ay, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return 0.0;
  const HalfAngles a = half_angles(wi, wo);
  const double G1 = 1.0 / (1.0 + ggx_Lambda(ax, ay, wo));
  const double woh = dot(wo, a.h);
  const double Dwo = G1 * std::max(0.0, woh) * ggx_D(ax, ay, a.theta, a.phi) / wo.z;
  return Dwo / (4.0 * woh);
}

// ---------------------------------------------------------------------------------------------
// Conductor Fresnel, complex arithmetic (Born & Wolf Sec. 14.2; pbrt-v4 FrComplex):
//   m = eta + i k, cos_t = sqrt(1 - sin^2 theta / m^2) (principal root),
//   r_par = (m cos_i - cos_t) / (m cos_i + cos_t), r_perp = (cos_i - m cos_t) / (cos_i + m cos_t),
//   F = (|r_par|^2 + |r_perp|^2) / 2.
inline double fresnel_conductor(double cos_i, double eta, double k) {
  using cd = std::complex<double>;
  const cd m(eta, k);
  const double sin2 = std::max(0.0, 1.0 - cos_i * cos_i);
  const cd cos_t = std::sqrt(cd(1.0) - sin2 / (m * m));
  const cd r_par = (m * cos_i - cos_t) / (m * cos_i + cos_t);
  const cd r_perp = (cos_i - m * cos_t) / (cos_i + m * cos_t);
  return (std::norm(r_par) + std::norm(r_perp)) / 2.0;
}

// ---------------------------------------------------------------------------------------------
// Metal: F_conductor(wi.h; eta, k) x colourless lobe + optional directional diffuse.
// The directional-diffuse lobe follows the convention documented for the metal material
// (include/aniso/brdf/metal.h header comment; Ngan 2005's Lafortune normalisation):
//   albedo F0 (n + 2) / (2 pi) max(0, (cx wi.x wo.x + cy wi.y wo.y + cz wi.z wo.z) / max|C|)^n,
// and the specular part is scaled by (1 - albedo),
// F0 = F_conductor(normal incidence; eta, k) per channel.
enum class MetalLobe { Ward, AS, GGX };
struct MetalParams {
  C3 eta, k;
  MetalLobe lobe = MetalLobe::Ward;
  double ax = 0.1, ay = 0.1;  // Ward / GGX
  WardForm form = WardForm::Vector;
  WardNorm norm = WardNorm::Ward1992;
  double nu = 100, nv = 100;  // AS
  bool dd = false;
  C3 dd_albedo{0.1, 0.1, 0.1};
  double dd_cx = -1, dd_cy = -1, dd_cz = 1, dd_n = 5;
};

inline C3 metal(const MetalParams& p, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  const HalfAngles a = half_angles(wi, wo);
  double lobe = 0.0;
  switch (p.lobe) {
    case MetalLobe::Ward: lobe = ward_lobe(p.ax, p.ay, p.form, p.norm, wi, wo); break;
    case MetalLobe::AS: lobe = as_lobe(p.nu, p.nv, wi, wo); break;
    case MetalLobe::GGX: lobe = ggx_lobe(p.ax, p.ay, wi, wo); break;
  }
  const double c = dot(wi, a.h);
  C3 out;
  // With a directional-diffuse lobe of albedo a, the specular lobe keeps (1 - a) of its energy.
  for (int i = 0; i < 3; ++i) out[i] = (p.dd ? 1.0 - p.dd_albedo[i] : 1.0) * fresnel_conductor(c, p.eta[i], p.k[i]) * lobe;
  if (p.dd) {
    const double cmax = std::max({std::abs(p.dd_cx), std::abs(p.dd_cy), std::abs(p.dd_cz)});
    const double base = (p.dd_cx * wi.x * wo.x + p.dd_cy * wi.y * wo.y + p.dd_cz * wi.z * wo.z) / cmax;
    const double l = base > 0.0 ? std::pow(base, p.dd_n) : 0.0;
    for (int i = 0; i < 3; ++i)
      out[i] += p.dd_albedo[i] * fresnel_conductor(1.0, p.eta[i], p.k[i]) * (p.dd_n + 2.0) / (2.0 * kPi) * l;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Disney principled BRDF, from Burley 2012 ("Physically-Based Shading at Disney", Sec. 5.3-5.6 and
// Appendix B) and the BRDF Explorer's disney.brdf, with base_color linear. Written with the
// angles theta_l, theta_v, theta_h, theta_d (Burley's notation) and phi_h, not the kernels' dot
// products:
//   diffuse  C / pi (1 + (F_D90 - 1)(1 - cos theta_l)^5)(1 + (F_D90 - 1)(1 - cos theta_v)^5),
//            F_D90 = 0.5 + 2 roughness cos^2 theta_d                     (Burley Sec. 5.3)
//   subsurface 1.25 C / pi (F_ss (1 / (cos theta_l + cos theta_v) - 0.5) + 0.5), F_ss the same
//            product with F_SS90 = roughness cos^2 theta_d (Hanrahan-Krueger; disney.brdf)
//   specular D_GTR2aniso(theta_h, phi_h) F(theta_d) G1(l) G1(v) / (4 cos theta_l cos theta_v),
//            G1 separable Smith GGX, alpha(phi)^2 tan^2 theta form (the reference's ggx_D and
//            ggx_Lambda above), F = Schlick from Cspec0
//   sheen    sheen Csheen (1 - cos theta_d)^5
//   clearcoat 0.25 clearcoat D_GTR1(theta_h) F(0.04, theta_d) G1(l; 0.25) G1(v; 0.25) / (4 cos cos),
//            D_GTR1 = (a^2 - 1) / (pi ln a^2 (a^2 cos^2 theta_h + sin^2 theta_h)), a = lerp(0.1, 0.001, gloss)
//   f = ((1 - subsurface) diffuse + subsurface ss + sheen) (1 - metallic) + specular + clearcoat
struct PrincipledParams {
  C3 base_color{0.5, 0.5, 0.5};
  double metallic = 0, subsurface = 0, specular = 0.5, roughness = 0.5, specular_tint = 0, anisotropic = 0, sheen = 0,
         sheen_tint = 0.5, clearcoat = 0, clearcoat_gloss = 1;
};

inline double schlick_weight(double cos_theta) { return std::pow(1.0 - cos_theta, 5.0); }
inline double lerp(double a, double b, double t) { return a + (b - a) * t; }

// Smith G1 for an isotropic GGX of roughness a, from the angle: 2 / (1 + sqrt(1 + a^2 tan^2 theta)).
inline double smith_g1_iso(double a, double theta) {
  const double t = std::tan(theta);
  return 2.0 / (1.0 + std::sqrt(1.0 + a * a * t * t));
}

inline C3 principled(const PrincipledParams& p, const V3& wi, const V3& wo) {
  if (!valid(wi, wo)) return grey(0.0);
  const HalfAngles a = half_angles(wi, wo);
  const double theta_l = std::acos(wi.z), theta_v = std::acos(wo.z);
  const double theta_d = std::acos(std::clamp(dot(wi, a.h), -1.0, 1.0));
  const double cl = std::cos(theta_l), cv = std::cos(theta_v), cd = std::cos(theta_d);
  const C3& C = p.base_color;
  const double lum = 0.3 * C[0] + 0.6 * C[1] + 0.1 * C[2];
  C3 tint, spec0, csheen;
  for (int i = 0; i < 3; ++i) {
    tint[i] = lum > 0.0 ? C[i] / lum : 1.0;
    spec0[i] = lerp(p.specular * 0.08 * lerp(1.0, tint[i], p.specular_tint), C[i], p.metallic);
    csheen[i] = lerp(1.0, tint[i], p.sheen_tint);
  }
  const double FL = schlick_weight(cl), FV = schlick_weight(cv), FH = schlick_weight(cd);
  const double fd90 = 0.5 + 2.0 * p.roughness * cd * cd;
  const double diffuse = (1.0 + (fd90 - 1.0) * FL) * (1.0 + (fd90 - 1.0) * FV);
  const double fss90 = p.roughness * cd * cd;
  const double fss = (1.0 + (fss90 - 1.0) * FL) * (1.0 + (fss90 - 1.0) * FV);
  const double ss = 1.25 * (fss * (1.0 / (cl + cv) - 0.5) + 0.5);
  const double aspect = std::sqrt(1.0 - 0.9 * p.anisotropic);
  const double ax = std::max(0.001, p.roughness * p.roughness / aspect), ay = std::max(0.001, p.roughness * p.roughness * aspect);
  const double G1l = 1.0 / (1.0 + ggx_Lambda(ax, ay, wi)), G1v = 1.0 / (1.0 + ggx_Lambda(ax, ay, wo));
  const double spec = ggx_D(ax, ay, a.theta, a.phi) * G1l * G1v / (4.0 * cl * cv);
  const double ga = lerp(0.1, 0.001, p.clearcoat_gloss), ga2 = ga * ga;
  const double ch = std::cos(a.theta), sh = std::sin(a.theta);
  const double d_gtr1 = (ga2 - 1.0) / (kPi * std::log(ga2) * (ga2 * ch * ch + sh * sh));
  const double coat = 0.25 * p.clearcoat * d_gtr1 * lerp(0.04, 1.0, FH) * smith_g1_iso(0.25, theta_l) *
                      smith_g1_iso(0.25, theta_v) / (4.0 * cl * cv);
  C3 out;
  for (int i = 0; i < 3; ++i) {
    const double base = lerp(diffuse, ss, p.subsurface) * C[i] / kPi + FH * p.sheen * csheen[i];
    out[i] = base * (1.0 - p.metallic) + spec * lerp(spec0[i], 1.0, FH) + coat;
  }
  return out;
}

}  // namespace aniso_ref
