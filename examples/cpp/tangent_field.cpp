// examples/cpp/tangent_field.cpp: a tangent field orients the highlight (header-only: CMake
// aniso::kernels, no library).
//
// A lathe-turned disc: the brushing runs in circles about the disc's axis, so the tangent at each
// point is the concentric field of include/aniso/tangent/fields.h (axis x (p - c)). A distant light
// and viewer see the same half vector h everywhere on the flat disc; what changes from point to
// point is the tangent, and with it whether h leans along the narrow roughness (alpha_x, along the
// brushing: dark) or the wide one (alpha_y, across it: bright). The program prints f around a ring,
// and checks:
//   1. the concentric tangent is unit, orthogonal to the normal and to the radius;
//   2. shading in the field's frame equals shading in the world frame with the material turned by
//      the tangent's angle (MaterialT::rotation, the JSON key rotation_deg): a tangent field and
//      rotation_deg are two routes to the same kernel input (docs/conventions.md);
//   3. the field's own `angle` (a scene's tangent.angle_deg) turns the frame about n: a quarter
//      turn of the concentric field is the radial field (tangents are directions modulo pi).
// Exit status 1 when a check fails.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <aniso/kernels.h>

namespace {

using aniso::Vec3d;

bool close(double a, double b, double tolerance) { return std::abs(a - b) <= tolerance * std::max(1.0, std::abs(b)); }

Vec3d direction_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * std::numbers::pi / 180.0, p = phi_deg * std::numbers::pi / 180.0;
  return Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

}  // namespace

int main() {
  int failures = 0;

  // Brushed metal-like Ward: narrow (0.05) along the tangent, wide (0.3) across it.
  aniso::WardT<double> ward;
  ward.kd = aniso::RGBT<double>(0.02);
  ward.ks = aniso::RGBT<double>(0.6);
  ward.lobe.alpha_x = 0.05;
  ward.lobe.alpha_y = 0.3;
  const aniso::MaterialD material(ward);

  // The disc: the plane z = 0, normal +z, turned about the z axis through the origin.
  aniso::TangentFieldT<double> concentric;
  concentric.kind = aniso::TangentFieldKind::Concentric;
  concentric.center = Vec3d(0.0);
  concentric.axis = Vec3d(0.0, 0.0, 1.0);

  // World-space light and viewer directions (distant), both pointing away from the surface. The
  // viewer is 10 degrees of azimuth away from the mirror direction, so the half vector leans away
  // from the normal, mostly along the world's y axis.
  const Vec3d light = direction_deg(40.0, 0.0), viewer = direction_deg(40.0, 170.0);

  std::printf("point azimuth  tangent angle  f (green, 1/sr)\n");
  for (int k = 0; k < 24; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 24.0;
    aniso::SurfacePointT<double> sp;
    sp.p = Vec3d(std::cos(a), std::sin(a), 0.0);  // a ring of radius 1
    sp.n = Vec3d(0.0, 0.0, 1.0);
    sp.dpdu = Vec3d(1.0, 0.0, 0.0);  // the shape's own tangent: the concentric field ignores it

    // The shading frame at this point, and the kernel's input: both directions in its coordinates.
    const aniso::FrameT<double> frame = aniso::tangent_frame(concentric, sp);
    const aniso::RGBT<double> f = material.f(frame.to_local(light), frame.to_local(viewer));

    // 1. Unit, orthogonal to n and to the radius.
    const Vec3d radius = sp.p - concentric.center;
    if (!close(glm::length(frame.t), 1.0, 1e-12) || std::abs(glm::dot(frame.t, sp.n)) > 1e-12 ||
        std::abs(glm::dot(frame.t, radius)) > 1e-12)
      ++failures, std::printf("  concentric tangent not orthogonal at azimuth %d\n", k * 15);

    // 2. The same with the world frame (t = x, n = z here) and the material turned by the tangent's
    // angle psi about n.
    const double psi_deg = std::atan2(frame.t.y, frame.t.x) * 180.0 / std::numbers::pi;
    aniso::MaterialD turned = material;
    turned.rotation = aniso::frame_rotation_deg(psi_deg);
    const aniso::RGBT<double> f_turned = turned.f(light, viewer);
    if (!close(f.y, f_turned.y, 1e-12)) ++failures, std::printf("  field %.12g != rotation_deg %.12g\n", f.y, f_turned.y);

    // 3. A quarter turn of the concentric field is the radial field, up to the sign of t.
    aniso::TangentFieldT<double> quarter = concentric, radial = concentric;
    quarter.angle = std::numbers::pi / 2.0;
    radial.kind = aniso::TangentFieldKind::Radial;
    const double alignment = glm::dot(aniso::tangent_frame(quarter, sp).t, aniso::tangent_frame(radial, sp).t);
    if (!close(std::abs(alignment), 1.0, 1e-12)) ++failures, std::printf("  quarter turn: t . t_radial = %g\n", alignment);

    // Print a bar as long as f: the two bright arcs sit where the brushing crosses the half
    // vector's lean, the dark ones where it runs along it.
    std::printf("%8d deg %10.1f deg %12.4f  %s\n", k * 15, std::round(psi_deg * 10.0) / 10.0 + 0.0, f.y,
                std::string(int(f.y * 4.0), '#').c_str());
  }
  if (failures) std::printf("FAILED: %d checks\n", failures);
  return failures ? 1 : 0;
}
