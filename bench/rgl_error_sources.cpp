// bench/rgl_error_sources.cpp: where the error of a written RGL tensor file comes from (docs/rgl.md,
// "Where the error comes from"). For the materials of the accuracy table it writes the file
// (export_rgl, RGB), reads it back and prints the cosine-weighted relative L1 of f per viewing
// elevation and the albedo error, as compare_rgl measures them; --decompose adds the two
// interpolations of the readers measured alone:
//   blend only: each neighbouring slice's colour grid replaced by the exact c(u) of that slice
//               (f at the half vector the slice's own warp gives u, times cos(theta_i) 4 sigma / D),
//               blended with the readers' weights after the readers' warp inversion;
//   grid only:  the readers' f against that blend (the colour grid's bilinear interpolation).
// Not a ctest: a measurement (about a minute for every material at the default grids).
//
//   aniso_rgl_error_sources [--colour N] [--theta-i N] [--phi-i N] [--ndf N] [--vndf N] [--d auto|lobe|retro|envelope] [--tilt T]
//                           [--placement blend|sigma] [--thetas T0 T1 T2 T3 T4] [--only NAME,...]
//                           [--phi-placement blend|uniform] [--phis P0,P1,... (degrees; default compare_rgl's 0,60,120,210,300)]
//                           [--decompose] [--material JSON|PRESET]   (one material instead of the table's)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "aniso/io/materials.h"
#include "aniso/measured/measured.h"
#include "aniso/measured/merl.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/rgl/tensor.h"

namespace aniso {
namespace {

using FFn = std::function<glm::dvec3(const Vec3d&, const Vec3d&)>;

Vec3d dir(double t, double p) { return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)); }

struct Errors {
  double l1[5] = {0, 0, 0, 0, 0}, albedo[5] = {0, 0, 0, 0, 0};
};

// compare_rgl's estimator (rgl::compare_view) with any f in place of the file's, at five elevations.
Errors compare(const rgl::SourceModel& src, const FFn& g, const double (&thetas)[5], const std::vector<double>& phis,
               int samples) {
  Errors r;
  for (int ti = 0; ti < 5; ++ti)
    for (const double phi_deg : phis) {
      const Vec3d wo = dir(thetas[ti] * kPi<double> / 180.0, phi_deg * kPi<double> / 180.0);
      const rgl::ViewError e = rgl::compare_view(src, g, wo, samples, 1234 + uint64_t(ti) * 7 + uint64_t(phi_deg));
      r.l1[ti] = std::max(r.l1[ti], e.l1);
      r.albedo[ti] = std::max(r.albedo[ti], e.albedo);
    }
  return r;
}

// The interval of a grid holding v and the weight of its upper end, as PL2D::param_lookup.
void neighbours(const std::vector<float>& g, float v, int& i0, double& w1) {
  i0 = 0;
  w1 = 0.0;
  if (g.size() < 2) return;
  while (i0 + 2 < int(g.size()) && g[size_t(i0) + 1] <= v) ++i0;
  w1 = std::clamp(double(v - g[size_t(i0)]) / double(g[size_t(i0) + 1] - g[size_t(i0)]), 0.0, 1.0);
}

// The readers' f (RglT::f) with the colour grid replaced by the exact colour of each neighbouring
// slice at the continuous u: what is left is the error of blending slices.
glm::dvec3 f_blend_exact(const rgl::RglData& d, const FFn& fsrc, const Vec3d& wi, const Vec3d& wo) {
  if (!(wi.z > 0 && wo.z > 0)) return glm::dvec3(0);
  const RglTables& t = d.tables;
  const Vec3d wm = glm::normalize(wi + wo);
  const float theta_o = std::acos(float(wo.z)), phi_o = std::atan2(float(wo.y), float(wo.x));
  const float theta_m = std::acos(float(wm.z)), phi_m = std::atan2(float(wm.y), float(wm.x));
  const float um_x = rgl_theta2u(theta_m);
  float um_y = rgl_phi2u(t.isotropic ? (phi_m - phi_o) : phi_m);
  um_y -= std::floor(um_y);
  const float p[2] = {phi_o, theta_o};
  const PL2DSample ui = t.vndf.invert(um_x, um_y, p);
  if (!ui.finite()) return glm::dvec3(0);
  int ia = 0, ib = 0;
  double wa = 0, wb = 0;
  neighbours(d.phi_i, phi_o, ia, wa);
  neighbours(d.theta_i, theta_o, ib, wb);
  const bool aniso_grid = d.phi_i.size() > 1;
  glm::dvec3 c(0.0);
  for (int da = 0; da < (aniso_grid ? 2 : 1); ++da)
    for (int db = 0; db < 2; ++db) {
      const double w = (aniso_grid ? (da ? wa : 1 - wa) : 1.0) * (db ? wb : 1 - wb);
      if (w == 0) continue;
      const float ph = d.phi_i[size_t(ia + da)], th = d.theta_i[size_t(ib + db)];
      const float ps[2] = {ph, th};
      const PL2DSample s = t.vndf.sample(ui.x, ui.y, ps);
      if (!s.finite()) continue;
      const Vec3d wob = dir(th, ph);
      const Vec3d m = dir(rgl_u2theta(s.x), rgl_u2phi(s.y) + (t.isotropic ? ph : 0.f));
      const Vec3d wib = 2.0 * glm::dot(wob, m) * m - wob;
      const double D = t.ndf.evaluate(s.x, s.y, nullptr);
      const double sig = t.sigma.evaluate(rgl_theta2u(th), rgl_phi2u(ph), nullptr);
      if (wib.z > 0 && D > 0) c += w * glm::max(fsrc(wib, wob), glm::dvec3(0)) * (wib.z * 4 * sig / D);
    }
  const float uo_x = rgl_theta2u(theta_o), uo_y = rgl_phi2u(phi_o);
  return c * double(t.ndf.evaluate(um_x, um_y, nullptr) / (4.f * t.sigma.evaluate(uo_x, uo_y, nullptr) * float(wi.z)));
}

struct Case {
  const char* name;
  const char* material;  // JSON or a preset name
  bool merl;             // a MERL-layout table tabulated from the material
  double rotation_deg;   // the material turned about the normal (the general path for GGX)
};

int run(int argc, char** argv) {
  std::vector<Case> cases = {
      {"ward_vector", R"({"model":"ward","kd":0.1,"ks":0.3,"alpha":0.15})", false, 0},
      {"ward_angle_duer", R"({"model":"ward","kd":0.1,"ks":0.3,"alpha":0.15,"form":"angle","normalization":"duer"})", false, 0},
      {"ward_aniso",
       R"({"model":"ward","kd":0.1,"ks":0.3,"alpha_x":0.05,"alpha_y":0.3,"form":"approx","normalization":"balanced"})", false, 0},
      {"ashikhmin_shirley", R"({"model":"ashikhmin-shirley","rd":[0.2,0.3,0.4],"rs":0.1,"n":100})", false, 0},
      {"ggx_iso", R"({"model":"ggx","kd":[0.2,0.1,0.05],"f0":0.04,"alpha":0.2})", false, 0},
      {"ggx_aniso", R"({"model":"ggx","kd":0.0,"f0":[0.9,0.6,0.3],"alpha_x":0.05,"alpha_y":0.3})", false, 0},
      {"ggx_aniso_turned", R"({"model":"ggx","kd":0.0,"f0":[0.9,0.6,0.3],"alpha_x":0.05,"alpha_y":0.3})", false, 30},
      {"matte_steel", "matte-steel", false, 0},
      {"gold", "gold", false, 0},
      {"brushed_gold", "brushed-gold", false, 0},
      {"merl_ward", R"({"model":"ward","kd":[0.3,0.2,0.1],"ks":0.2,"alpha":0.25})", true, 0},
  };
  rgl::ExportOptions o;
  o.spectral = false;
  std::string only, material;
  double thetas[5] = {0, 20, 40, 60, 80};
  std::vector<double> phis = {0, 60, 120, 210, 300};  // compare_rgl's azimuths
  bool decompose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s: expected a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--colour")
      o.colour = std::atoi(value().c_str());
    else if (a == "--theta-i")
      o.theta_i = std::atoi(value().c_str());
    else if (a == "--phi-i")
      o.phi_i = std::atoi(value().c_str());
    else if (a == "--ndf")
      o.ndf = std::atoi(value().c_str());
    else if (a == "--tilt")
      o.warp_tilt = std::atof(value().c_str());
    else if (a == "--vndf")
      o.vndf = std::atoi(value().c_str());
    else if (a == "--only")
      only = "," + value() + ",";
    else if (a == "--decompose")
      decompose = true;
    else if (a == "--material") {
      material = value();
      cases = {{material.c_str(), material.c_str(), false, 0}};
    } else if (a == "--thetas")
      for (double& t : thetas) t = std::atof(value().c_str());
    else if (a == "--d") {
      const std::string v = value();
      o.d_estimate = v == "lobe"       ? rgl::ExportOptions::DEstimate::LobeAverage
                     : v == "retro"    ? rgl::ExportOptions::DEstimate::RetroReflection
                     : v == "envelope" ? rgl::ExportOptions::DEstimate::LobeEnvelope
                                       : rgl::ExportOptions::DEstimate::Auto;
    } else if (a == "--phi-placement") {
      o.phi_placement =
          value() == "uniform" ? rgl::ExportOptions::PhiPlacement::Uniform : rgl::ExportOptions::PhiPlacement::BlendError;
    } else if (a == "--phis") {
      phis.clear();
      const std::string list = value();  // comma-separated degrees
      for (size_t at = 0; at < list.size();) {
        const size_t comma = std::min(list.find(',', at), list.size());
        phis.push_back(std::atof(list.substr(at, comma - at).c_str()));
        at = comma + 1;
      }
    } else if (a == "--placement") {
      o.placement = value() == "sigma" ? rgl::ExportOptions::Placement::ProjectedArea : rgl::ExportOptions::Placement::BlendError;
    } else {
      std::fprintf(stderr, "unknown option %s (see the head of bench/rgl_error_sources.cpp)\n", a.c_str());
      return 2;
    }
  }
  std::printf("L1 at theta_o %g %g %g %g %g deg (worst of 5 azimuths), albedo error (worst)\n", thetas[0], thetas[1], thetas[2],
              thetas[3], thetas[4]);
  for (const Case& c : cases) {
    if (!only.empty() && only.find("," + std::string(c.name) + ",") == std::string::npos) continue;
    const std::string js = c.material;
    MaterialD m = js[0] == '{' ? build_material<double>(parse_material(nlohmann::json::parse(js), c.name))
                               : build_material<double>(load_material(js));
    std::shared_ptr<const MeasuredData> keep;
    if (c.merl) {
      keep = make_measured(tabulate_merl(m), c.name);
      m = MaterialD(measured_kernel<double>(*keep));
    }
    rgl::SourceModel src = rgl::source_model(m);
    rgl::BrdfSource b = rgl::brdf_source(m);
    if (c.rotation_deg != 0.0) {  // the material turned about the normal by rotation_deg
      const double a = c.rotation_deg * kPi<double> / 180.0;
      auto rot = [](const Vec3d& v, double r) {
        return Vec3d(std::cos(r) * v.x - std::sin(r) * v.y, std::sin(r) * v.x + std::cos(r) * v.y, v.z);
      };
      src = {[=](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(m.f(rot(wi, -a), rot(wo, -a))); },
             [=](const Vec3d& wi, const Vec3d& wo) { return m.pdf(rot(wi, -a), rot(wo, -a)); },
             [=](const Vec3d& wo, double uc, const Vec2T<double>& u) {
               BSDFSampleT<double> s = m.sample(rot(wo, -a), uc, u);
               s.wi = rot(s.wi, a);
               return s;
             }};
      b.f = src.f;
      b.ggx_alpha.reset();
    }
    b.description = c.name;
    rgl::ExportReport rep;
    const std::vector<uint8_t> bytes = rgl::serialize_tensor(rgl::export_rgl(b, o, &rep));
    const std::shared_ptr<rgl::RglData> d = rgl::rgl_from_tensor(rgl::parse_tensor(bytes, std::string(c.name) + ".bsdf"));
    const RglT<double> k = rgl::rgl_kernel<double>(*d);
    const FFn file = [&](const Vec3d& wi, const Vec3d& wo) { return glm::dvec3(k.f(wi, wo)); };
    const Errors e = compare(src, file, thetas, phis, 6000);
    std::printf("%-18s L1 %6.2f %6.2f %6.2f %6.2f %6.2f %%  albedo %5.2f %%  %.2f MB  export %.2f s CPU\n  D: %s\n", c.name,
                100 * e.l1[0], 100 * e.l1[1], 100 * e.l1[2], 100 * e.l1[3], 100 * e.l1[4],
                100 * *std::max_element(e.albedo, e.albedo + 5), double(bytes.size()) / 1e6, rep.seconds, rep.d_method.c_str());
    if (decompose) {
      const FFn blend = [&](const Vec3d& wi, const Vec3d& wo) { return f_blend_exact(*d, src.f, wi, wo); };
      const Errors eb = compare(src, blend, thetas, phis, 6000);
      const Errors eg = compare({blend, src.pdf, src.sample}, file, thetas, phis, 6000);
      std::printf(
          "  blend only %6.2f %6.2f %6.2f %6.2f %6.2f %% (albedo %.2f %%)   grid only %6.2f %6.2f %6.2f %6.2f %6.2f %% (albedo "
          "%.2f %%)\n",
          100 * eb.l1[0], 100 * eb.l1[1], 100 * eb.l1[2], 100 * eb.l1[3], 100 * eb.l1[4],
          100 * *std::max_element(eb.albedo, eb.albedo + 5), 100 * eg.l1[0], 100 * eg.l1[1], 100 * eg.l1[2], 100 * eg.l1[3],
          100 * eg.l1[4], 100 * *std::max_element(eg.albedo, eg.albedo + 5));
      std::printf("  theta_i (deg):");
      for (const float t : d->theta_i) std::printf(" %.1f", double(t) * 180.0 / kPi<double>);
      std::printf("\n  phi_i (deg):");
      for (const float p : d->phi_i) std::printf(" %.1f", double(p) * 180.0 / kPi<double>);
      std::printf("\n");
    }
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace aniso

int main(int argc, char** argv) { return aniso::run(argc, argv); }
