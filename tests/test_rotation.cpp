// tests/test_rotation.cpp: a material's rotation_deg (material.h, FrameRotationT) is the scene's
// tangent.angle_deg: the material turned by a, seen in a frame, equals the unturned material seen in
// the frame turned by a (aniso/core/frame.h, FrameT::rotated, which tangent.angle_deg applies), in
// f, pdf and sample; it composes with the frame's own angle; isotropic models refuse the key. The
// batch, GLSL, GL-renderer and chi-square suites run the rotated materials of test_util.h
// (all_model_materials: *_rotated); test_render.cpp renders both ways.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/core/frame.h"
#include "aniso/io/input_error.h"
#include "aniso/io/materials.h"
#include "stats/rng.h"
#include "test_util.h"

namespace aniso {
namespace {

using nlohmann::json;

constexpr double kDeg = 0.017453292519943295769;

// The unit directions of the upper hemisphere, with some grazing ones.
Vec3d random_upper(Rng& rng) {
  const double z = rng.uniform(), phi = 2.0 * M_PI * rng.uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Directions of the frame's own coordinates re-expressed in the frame turned by psi (the scene's
// tangent.angle_deg): the coordinates a kernel sees under that tangent.
Vec3d in_turned_frame(const Vec3d& w, double psi) {
  const FrameT<double> turned = FrameT<double>{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}.rotated(psi);
  return turned.to_local(w);
}

struct Rotated {
  const char* name;
  json material;  // without rotation_deg
  double degrees;
};

std::vector<Rotated> cases() {
  return {
      {"ward", {{"model", "ward"}, {"kd", 0.1}, {"ks", 0.4}, {"alpha_x", 0.083}, {"alpha_y", 0.27}}, 30.0},
      {"ashikhmin-shirley", {{"model", "ashikhmin-shirley"}, {"rd", 0.3}, {"rs", 0.1}, {"n_u", 180.0}, {"n_v", 25.0}}, 130.0},
      {"lafortune",
       {{"model", "lafortune"},
        {"rho_d", 0.1},
        {"lobes", json::array({{{"cx", -0.8}, {"cy", -1.1}, {"cz", 0.95}, {"n", 20.0}}})}},
       -75.0},
      {"ggx", {{"model", "ggx"}, {"kd", 0.2}, {"f0", 0.5}, {"alpha_x", 0.05}, {"alpha_y", 0.4}}, 250.0},
      {"metal", {{"model", "metal"}, {"metal", "gold"}, {"lobe", {{"model", "ggx"}, {"alpha_x", 0.3}, {"alpha_y", 0.05}}}}, 45.0},
      {"principled", {{"model", "principled"}, {"metallic", 1.0}, {"roughness", 0.5}, {"anisotropic", 0.8}}, 200.0},
  };
}

MaterialD build(json j, double degrees) {
  if (degrees != 0.0) j["rotation_deg"] = degrees;
  return build_material<double>(parse_material(j, "test"));
}

TEST(MaterialRotation, EqualsTheTangentTurnedByTheSameAngle) {
  for (const Rotated& c : cases()) {
    const MaterialD turned = build(c.material, c.degrees), plain = build(c.material, 0.0);
    Rng rng(11);
    double worst = 0.0, largest = 0.0, moved = 0.0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3d wi = random_upper(rng), wo = random_upper(rng);
      const Vec3d ti = in_turned_frame(wi, c.degrees * kDeg), to = in_turned_frame(wo, c.degrees * kDeg);
      const RGBT<double> a = turned.f(wi, wo), b = plain.f(ti, to), unturned = plain.f(wi, wo);
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(a[k] - b[k]) / (std::abs(b[k]) + 1e-300));
        largest = std::max(largest, b[k]);
        moved = std::max(moved, std::abs(a[k] - unturned[k]));
      }
      const double pa = turned.pdf(wi, wo), pb = plain.pdf(ti, to);
      worst = std::max(worst, std::abs(pa - pb) / (pb + 1e-300));
    }
    EXPECT_LT(worst, 1e-9) << c.name;
    EXPECT_GT(moved, 0.05 * largest) << c.name << ": the rotation changes nothing";
  }
}

// sample(): the same random numbers give the direction turned back into the frame, the same weight
// and pdf.
TEST(MaterialRotation, SamplesAreTheTurnedFramesSamples) {
  for (const Rotated& c : cases()) {
    const MaterialD turned = build(c.material, c.degrees), plain = build(c.material, 0.0);
    const FrameT<double> frame = FrameT<double>{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}.rotated(c.degrees * kDeg);
    Rng rng(5);
    int valid = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3d wo = random_upper(rng);
      const double uc = rng.uniform();
      const Vec2T<double> u(rng.uniform(), rng.uniform());
      const BSDFSampleT<double> a = turned.sample(wo, uc, u), b = plain.sample(frame.to_local(wo), uc, u);
      ASSERT_EQ(a.valid, b.valid) << c.name;
      if (!a.valid) continue;
      ++valid;
      const Vec3d back = frame.to_world(b.wi);
      EXPECT_LT(glm::length(a.wi - back), 1e-12) << c.name;
      EXPECT_NEAR(a.pdf, b.pdf, 1e-9 * b.pdf) << c.name;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.weight[k], b.weight[k], 1e-9 * (b.weight[k] + 1e-300)) << c.name;
    }
    EXPECT_GT(valid, 1000) << c.name;
  }
}

// A frame turned by 20 degrees seeing a material turned by 10 equals the unturned material in the
// frame turned by 30: the two add.
TEST(MaterialRotation, ComposesWithTheFramesAngle) {
  const json ward = {{"model", "ward"}, {"ks", 0.5}, {"alpha_x", 0.05}, {"alpha_y", 0.3}};
  const MaterialD ten = build(ward, 10.0), plain = build(ward, 0.0);
  Rng rng(3);
  for (int i = 0; i < 500; ++i) {
    const Vec3d wi = random_upper(rng), wo = random_upper(rng);
    const RGBT<double> a = ten.f(in_turned_frame(wi, 20 * kDeg), in_turned_frame(wo, 20 * kDeg));
    const RGBT<double> b = plain.f(in_turned_frame(wi, 30 * kDeg), in_turned_frame(wo, 30 * kDeg));
    EXPECT_NEAR(a[0], b[0], 1e-9 * (std::abs(b[0]) + 1e-12));
  }
}

// 0 is the identity bit for bit; 180 degrees turns an anisotropic lobe onto itself (h.x^2, h.y^2).
TEST(MaterialRotation, ZeroIsExactAndAHalfTurnChangesNothing) {
  const json ggx = {{"model", "ggx"}, {"f0", 0.9}, {"alpha_x", 0.05}, {"alpha_y", 0.4}};
  const MaterialD zero = build(ggx, 0.0), half = build(ggx, 180.0);
  json explicit_zero = ggx;
  explicit_zero["rotation_deg"] = 0.0;
  const MaterialD zero2 = build_material<double>(parse_material(explicit_zero, "test"));
  EXPECT_TRUE(zero2.rotation.identity());
  Rng rng(4);
  for (int i = 0; i < 500; ++i) {
    const Vec3d wi = random_upper(rng), wo = random_upper(rng);
    EXPECT_EQ(zero.f(wi, wo)[0], zero2.f(wi, wo)[0]);
    EXPECT_NEAR(half.f(wi, wo)[0], zero.f(wi, wo)[0], 1e-9 * zero.f(wi, wo)[0] + 1e-300);
  }
}

TEST(MaterialRotation, IsotropicModelsRefuseTheKey) {
  for (const json& j :
       {json{{"model", "lambert"}, {"kd", 0.5}, {"rotation_deg", 30}}, json{{"model", "phong"}, {"rotation_deg", 30}}}) {
    try {
      (void)parse_material(j, "m.json");
      ADD_FAILURE() << j.dump();
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("m.json: key \"rotation_deg\""), std::string::npos) << msg;
      EXPECT_NE(msg.find("isotropic"), std::string::npos) << msg;
      EXPECT_NE(msg.find("no effect"), std::string::npos) << msg;
      EXPECT_NE(msg.find("ward, ashikhmin-shirley, lafortune, ggx, metal, principled"), std::string::npos) << msg;
    }
  }
  // Out of range, as every key.
  EXPECT_THROW((void)parse_material(json{{"model", "ward"}, {"rotation_deg", 400}}, "m.json"), InputError);
}

}  // namespace
}  // namespace aniso
