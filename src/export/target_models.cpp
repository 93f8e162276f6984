// export/target_models.cpp: GGX -> each target: the dispatch target_model over the targets' models
// (each in its writer's file, target_models.h) and what they share.
#include "export/target_models.h"

#include <cmath>

#include <fmt/format.h>

namespace aniso::exporter {

double major_first(double& ax, double& ay) {
  if (ax >= ay * (1.0 - 1e-9)) return 0.0;  // (nearly) isotropic fits stay unturned
  std::swap(ax, ay);
  return 90.0;
}

RoughAniso invert_aspect(double& ax, double& ay, double scale, double cap, std::string_view who,
                         std::vector<std::string>& notes) {
  RoughAniso r;
  r.extra = major_first(ax, ay);
  r.aniso = std::max(0.0, (1.0 - ay / ax) / scale);
  if (r.aniso < 1e-9) r.aniso = 0.0;
  if (r.aniso > cap) {
    notes.push_back(
        fmt::format("alpha ratio {:.3g} exceeds {}'s largest, {:.3g} (anisotropy {:.3g}): written with "
                    "anisotropy {:.3g} and the same mean alpha",
                    ax / ay, who, 1.0 / (1.0 - scale * cap), cap, cap));
    r.aniso = cap;
  }
  r.rough = std::sqrt(std::sqrt(ax * ay));
  if (r.rough > 1.0) notes.push_back("roughness above 1 clamped to 1"), r.rough = 1.0;
  return r;
}

double wrap_turn(double t) {
  t = std::fmod(t, 1.0);
  if (t < 0.0) t += 1.0;
  if (t >= 1.0 - 1e-12) t = 0.0;
  return t + 0.0;  // -0 is written as "-0"
}

ExactFresnel match_schlick(double f0, double scale, bool allow_conductor) {
  const auto cost = [&](double eta, double k) {
    double e = 0.0;
    for (int i = 0; i < 64; ++i) {
      const double c = (i + 0.5) / 64.0, m = 1.0 - c;
      const double want = std::min(1.0, (f0 + (1.0 - f0) * m * m * m * m * m) / scale);
      e += sqr(F_Conductor(c, eta, k) - want);
    }
    return e;
  };
  const auto golden = [](auto&& f, double lo, double hi) {
    const double r = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = lo, b = hi, x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = f(x1), f2 = f(x2);
    for (int i = 0; i < 80; ++i) {
      if (f1 < f2)
        b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = f(x1);
      else
        a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = f(x2);
    }
    return (a + b) / 2.0;
  };
  ExactFresnel d;
  d.eta = golden([&](double e) { return cost(e, 0.0); }, 1.0001, 60.0);
  if (!allow_conductor) return d;
  ExactFresnel c;
  c.eta = 1.0;
  c.k = golden([&](double k) { return cost(1.0, k); }, 0.0, 60.0);
  return cost(c.eta, c.k) < cost(d.eta, 0.0) ? c : d;
}

TintedDielectric tinted_dielectric(const glm::dvec3& f0_in) {
  const glm::dvec3 f0 = glm::clamp(f0_in, 0.0, 1.0);
  const double m = max3(f0);
  return {match_schlick(m, 1.0, false).eta, m > 0.0 ? f0 / m : glm::dvec3(1.0)};
}

TargetBrdf target_model(Target t, const GgxSource& g, json* params_out, std::vector<std::string>* notes_out,
                        double blender_version, BlenderV1Nodes nodes) {
  json p = json::object();
  std::vector<std::string> notes;
  TargetBrdf m;
  switch (t) {
    case Target::Blender: m = blender_model(g, p, notes, blender_version, nodes); break;
    case Target::Mitsuba3:
    case Target::PbrtV4: m = mitsuba_pbrt_model(t, g, p, notes); break;
    case Target::MaterialX: m = materialx_model(g, p, notes); break;
    case Target::OpenPbr: m = openpbr_model(g, p, notes); break;
    case Target::Gltf: m = gltf_model(g, p, notes); break;
  }
  if (params_out) *params_out = p;
  if (notes_out) *notes_out = notes;
  return m;
}

}  // namespace aniso::exporter
