// tests/test_glsl_functions.cpp: the building blocks of the GLSL twin, function by function,
// against their C++ twins (float) on random arguments: a drift fails naming the function.
// The models as a whole are compared in test_glsl.cpp.
#include <glm/gtc/noise.hpp>
#include "aniso/brdf/material.h"
#include "aniso/tangent/fields.h"
#include "glsl_util.h"
#include "test_util.h"

namespace aniso::test {
namespace {

// One function: its GLSL (statements over wi, wo, u setting f and pdf), its C++ twin returning
// (f, pdf), and whether the result is a direction (compared within 1e-4 absolute, as sampled
// directions are) or a value (1e-4 relative or 1e-6 absolute).
struct Twin {
  std::string name;
  std::string glsl;
  std::function<glm::vec4(const Vec3&, const Vec3&, const Vec3&)> cpp;
  bool direction = false;
  // Instead of the relative test: an absolute tolerance for values that cross zero by cancellation
  // (simplex noise sums four cancelling corner terms; its range is [-1, 1] and its slope ~3, so at
  // arguments ~50, where a float's ulp is 4e-6, 1e-4 of the range is a few ulp of the argument).
  double abs_tol = 0.0;
};

// Arguments from u: roughness in [0.05, 0.55], exponents in [1, 301], eta in [0.1, 3.1], k in [0, 5].
std::vector<Twin> twins() {
  using V = Vec3;
  auto ax = [](const V& u) { return 0.05f + 0.5f * u.x; };
  auto ay = [](const V& u) { return 0.05f + 0.5f * u.y; };
  auto hn = [](const V& wi, const V& wo) { return glm::normalize(wi + wo); };
  std::vector<Twin> t;
  const std::string AX = "(0.05 + 0.5 * u.x)", AY = "(0.05 + 0.5 * u.y)";
  t.push_back({"F_Schlick(float)", "pdf = F_Schlick(u.x, wi.z);",
               [](const V& wi, const V&, const V& u) { return glm::vec4(0, 0, 0, F_Schlick(u.x, wi.z)); }});
  t.push_back({"F_Schlick(vec3)", "f = F_Schlick(u, wi.z);",
               [](const V& wi, const V&, const V& u) { return glm::vec4(F_Schlick(u, wi.z), 0); }});
  t.push_back({"F_Conductor", "pdf = F_Conductor(wi.z, 0.1 + 3.0 * u.x, 5.0 * u.y);", [](const V& wi, const V&, const V& u) {
                 return glm::vec4(0, 0, 0, F_Conductor(wi.z, 0.1f + 3.0f * u.x, 5.0f * u.y));
               }});
  t.push_back({"D_GGX_Aniso", "vec3 h = normalize(wi + wo); pdf = D_GGX_Aniso(h.x, h.y, h.z, " + AX + ", " + AY + ");",
               [=](const V& wi, const V& wo, const V& u) {
                 const V h = hn(wi, wo);
                 return glm::vec4(0, 0, 0, D_GGX_Aniso(h.x, h.y, h.z, ax(u), ay(u)));
               }});
  t.push_back({"Lambda_GGX_Aniso", "pdf = Lambda_GGX_Aniso(wi, " + AX + ", " + AY + ");",
               [=](const V& wi, const V&, const V& u) { return glm::vec4(0, 0, 0, Lambda_GGX_Aniso(wi, ax(u), ay(u))); }});
  t.push_back(
      {"GGX_SampleVisibleNormal", "f = GGX_SampleVisibleNormal(wo, u.yz, " + AX + ", " + AY + ");",
       [=](const V&, const V& wo, const V& u) { return glm::vec4(GGX_SampleVisibleNormal(wo, Vec2(u.y, u.z), ax(u), ay(u)), 0); },
       true});
  t.push_back({"E_Ward_Vector", "vec3 h = wi + wo; pdf = E_Ward_Vector(h.x, h.y, h.z, " + AX + ", " + AY + ");",
               [=](const V& wi, const V& wo, const V& u) {
                 const V h = wi + wo;
                 return glm::vec4(0, 0, 0, E_Ward_Vector(h.x, h.y, h.z, ax(u), ay(u)));
               }});
  t.push_back(
      {"Ward_HalfAngles + E_Ward_Angle",
       "float th, c, s; Ward_HalfAngles(normalize(wi + wo), th, c, s); f = vec3(th, c, s); pdf = E_Ward_Angle(th, c, s, " + AX +
           ", " + AY + ");",
       [=](const V& wi, const V& wo, const V& u) {
         float th, c, s;
         Ward_HalfAngles(hn(wi, wo), th, c, s);
         return glm::vec4(th, c, s, E_Ward_Angle(th, c, s, ax(u), ay(u)));
       }});
  t.push_back({"E_Ward_Approx", "vec3 h = normalize(wi + wo); pdf = E_Ward_Approx(h.x, h.y, h.z, " + AX + ", " + AY + ");",
               [=](const V& wi, const V& wo, const V& u) {
                 const V h = hn(wi, wo);
                 return glm::vec4(0, 0, 0, E_Ward_Approx(h.x, h.y, h.z, ax(u), ay(u)));
               }});
  t.push_back({"N_Ward1992 / N_Duer / N_Balanced",
               "vec3 h = wi + wo; f = vec3(N_Ward1992(wi.z, wo.z, " + AX + ", " + AY + "), N_Duer(wi.z, wo.z, " + AX + ", " + AY +
                   "), N_Balanced(dot(h, h), h.z, " + AX + ", " + AY + "));",
               [=](const V& wi, const V& wo, const V& u) {
                 const V h = wi + wo;
                 return glm::vec4(N_Ward1992(wi.z, wo.z, ax(u), ay(u)), N_Duer(wi.z, wo.z, ax(u), ay(u)),
                                  N_Balanced(glm::dot(h, h), h.z, ax(u), ay(u)), 0);
               }});
  t.push_back({"Ward_PdfHalf", "pdf = Ward_PdfHalf(normalize(wi + wo), " + AX + ", " + AY + ");",
               [=](const V& wi, const V& wo, const V& u) { return glm::vec4(0, 0, 0, Ward_PdfHalf(hn(wi, wo), ax(u), ay(u))); }});
  t.push_back({"Ward_SampleHalf", "f = Ward_SampleHalf(u.yz, " + AX + ", " + AY + ");",
               [=](const V&, const V&, const V& u) { return glm::vec4(Ward_SampleHalf(Vec2(u.y, u.z), ax(u), ay(u)), 0); },
               true});
  const std::string NU = "(1.0 + 300.0 * u.x)", NV = "(1.0 + 300.0 * u.y)";
  auto nu = [](const V& u) { return 1.0f + 300.0f * u.x; };
  auto nv = [](const V& u) { return 1.0f + 300.0f * u.y; };
  t.push_back({"AS_Specular",
               "vec3 h = normalize(wi + wo); pdf = AS_Specular(h.x, h.y, h.z, dot(h, wi), wi.z, wo.z, " + NU + ", " + NV + ");",
               [=](const V& wi, const V& wo, const V& u) {
                 const V h = hn(wi, wo);
                 return glm::vec4(0, 0, 0, AS_Specular(h.x, h.y, h.z, glm::dot(h, wi), wi.z, wo.z, nu(u), nv(u)));
               }});
  t.push_back({"AS_Diffuse", "pdf = AS_Diffuse(wi.z, wo.z);",
               [](const V& wi, const V& wo, const V&) { return glm::vec4(0, 0, 0, AS_Diffuse(wi.z, wo.z)); }});
  t.push_back({"AS_PdfHalf", "pdf = AS_PdfHalf(normalize(wi + wo), " + NU + ", " + NV + ");",
               [=](const V& wi, const V& wo, const V& u) { return glm::vec4(0, 0, 0, AS_PdfHalf(hn(wi, wo), nu(u), nv(u))); }});
  t.push_back({"AS_SampleHalf", "f = AS_SampleHalf(u.yz, " + NU + ", " + NV + ");",
               [=](const V&, const V&, const V& u) { return glm::vec4(AS_SampleHalf(Vec2(u.y, u.z), nu(u), nv(u)), 0); }, true});
  t.push_back({"sample_cosine_hemisphere", "f = sample_cosine_hemisphere(u.xy);",
               [](const V&, const V&, const V& u) { return glm::vec4(sample_cosine_hemisphere(Vec2(u.x, u.y)), 0); }, true});
  t.push_back({"sample_cosine_power", "f = sample_cosine_power(wo, 1.0 + 50.0 * u.z, u.xy);",
               [](const V&, const V& wo, const V& u) {
                 return glm::vec4(sample_cosine_power(wo, 1.0f + 50.0f * u.z, Vec2(u.x, u.y)), 0);
               },
               true});
  t.push_back({"cosine_power_pdf / Phong_Lobe / Lafortune_Lobe",
               "f = vec3(cosine_power_pdf(dot(wi, wo), 1.0 + 50.0 * u.z), Phong_Lobe(dot(reflect_about_normal(wi), wo), 1.0 + "
               "50.0 * u.z), "
               "Lafortune_Lobe(dot(wi, wo), 1.0 + 50.0 * u.z, 0.5 + u.x));",
               [](const V& wi, const V& wo, const V& u) {
                 return glm::vec4(cosine_power_pdf(glm::dot(wi, wo), 1.0f + 50.0f * u.z),
                                  Phong_Lobe(glm::dot(reflect_about_normal(wi), wo), 1.0f + 50.0f * u.z),
                                  Lafortune_Lobe(glm::dot(wi, wo), 1.0f + 50.0f * u.z, 0.5f + u.x), 0);
               }});
  t.push_back({"Frame_from_normal", "Frame fr = Frame_from_normal(normalize(wo - vec3(0.0, 0.0, 0.5))); f = fr.t; pdf = fr.b.x;",
               [](const V&, const V& wo, const V&) {
                 const Frame fr = Frame::from_normal(glm::normalize(wo - V(0, 0, 0.5f)));
                 return glm::vec4(fr.t, fr.b.x);
               },
               true});
  t.push_back({"Frame_from_normal_tangent + Frame_rotated",
               "Frame fr = Frame_rotated(Frame_from_normal_tangent(wo, wi), 6.0 * u.x); f = fr.t; pdf = fr.b.y;",
               [](const V& wi, const V& wo, const V& u) {
                 const Frame fr = Frame::from_normal_tangent(wo, wi).rotated(6.0f * u.x);
                 return glm::vec4(fr.t, fr.b.y);
               },
               true});
  t.push_back(
      {"tangent_field_direction (Swirl) / Tangent_Radial",
       "TangentField tf = TangentField(TangentFieldKind_Swirl, vec3(1.0, 0.0, 0.0), u, normalize(wi), 0.7, 1.0, 0.5, 0.0);"
       "SurfacePoint sp = SurfacePoint(wo * 2.0, wo, vec3(1.0, 0.0, 0.0), vec2(0.0));"
       "f = tangent_field_direction(tf, sp); pdf = Tangent_Radial(sp.p, u, normalize(wi)).x;",
       [](const V& wi, const V& wo, const V& u) {
         TangentFieldT<float> tf;
         tf.kind = TangentFieldKind::Swirl;
         tf.center = u;
         tf.axis = glm::normalize(wi);
         tf.swirl = 0.7f;
         SurfacePointT<float> sp;
         sp.p = wo * 2.0f;
         sp.n = wo;
         return glm::vec4(tangent_field_direction(tf, sp), Tangent_Radial(sp.p, u, glm::normalize(wi)).x);
       },
       true});
  t.push_back({"TangentMap_DecodeAngle / ToDoubled / FromDoubled",
               "vec2 d = TangentMap_DecodeAngle(u.x); vec2 q = TangentMap_ToDoubled(d); f = vec3(TangentMap_FromDoubled(q), "
               "q.x); pdf = d.y;",
               [](const V&, const V&, const V& u) {
                 const Vec2 d = TangentMap_DecodeAngle(u.x);
                 const Vec2 q = TangentMap_ToDoubled(d);
                 const Vec2 b = TangentMap_FromDoubled(q);
                 return glm::vec4(b.x, b.y, q.x, d.y);
               },
               true});
  t.push_back({"simplex (glm::simplex) / Tangent_NoiseAngle",
               "f = vec3(simplex(wi * 7.0 + u * 40.0), simplex(-wo * 3.0), Tangent_NoiseAngle(u * 20.0, 1.5, 0.5));",
               [](const V& wi, const V& wo, const V& u) {
                 return glm::vec4(glm::simplex(wi * 7.0f + u * 40.0f), glm::simplex(-wo * 3.0f),
                                  Tangent_NoiseAngle(u * 20.0f, 1.5f, 0.5f), 0);
               },
               false, 1e-4});
  t.push_back({"tangent_frame (Noise)",
               "TangentField tf = TangentField(TangentFieldKind_Noise, vec3(1.0, 0.0, 0.0), vec3(0.0), vec3(0.0, 1.0, 0.0), 0.7, "
               "2.0, 0.5, 0.3);"
               "SurfacePoint sp = SurfacePoint(u * 10.0, wo, wi, vec2(0.0));"
               "Frame fr = tangent_frame(tf, sp); f = fr.t; pdf = fr.b.z;",
               [](const V& wi, const V& wo, const V& u) {
                 TangentFieldT<float> tf;
                 tf.kind = TangentFieldKind::Noise;
                 tf.scale = 2.0f;
                 tf.strength = 0.5f;
                 tf.angle = 0.3f;
                 SurfacePointT<float> sp;
                 sp.p = u * 10.0f;
                 sp.n = wo;
                 sp.dpdu = wi;
                 const Frame fr = tangent_frame(tf, sp);
                 return glm::vec4(fr.t, fr.b.z);
               },
               true});
  return t;
}

TEST(GlslFunctions, EachMatchesItsCppTwin) {
  ANISO_REQUIRE_GL();
  Rng rng(21);
  std::vector<glm::vec3> wi, wo, u;
  for (int i = 0; i < 512; ++i) {
    wi.push_back(random_upper<float>(rng));
    wo.push_back(random_upper<float>(rng));
    u.push_back(glm::vec3(float(rng.uniform()), float(rng.uniform()), float(rng.uniform())));
  }
  for (const Twin& t : twins()) {
    const auto r = run_pairs("", "  {\n    " + t.glsl + "\n  }\n", wi, wo, u);
    int bad = 0;
    for (size_t i = 0; i < wi.size() && bad < 3; ++i) {
      const glm::vec4 c = t.cpp(wi[i], wo[i], u[i]);
      const glm::vec4 g(r[i].f, r[i].pdf);
      for (int k = 0; k < 4; ++k) {
        const bool ok = t.direction ? std::abs(g[k] - c[k]) <= 1e-4f
                                    : (t.abs_tol > 0.0 ? std::abs(g[k] - c[k]) <= t.abs_tol : close(g[k], c[k]));
        if (!ok) {
          ADD_FAILURE() << "GLSL " << t.name << " drifted from its C++ twin: component " << k << " GLSL " << g[k] << " vs C++ "
                        << c[k] << " at wi = (" << wi[i].x << ", " << wi[i].y << ", " << wi[i].z << "), wo = (" << wo[i].x << ", "
                        << wo[i].y << ", " << wo[i].z << "), u = (" << u[i].x << ", " << u[i].y << ", " << u[i].z << ")";
          ++bad;
        }
      }
    }
  }
}

}  // namespace
}  // namespace aniso::test
