// examples/cpp/eval.cpp: `aniso eval --angles` in a few lines of C++ (CMake aniso::host).
//
//   eval MATERIAL THETA_I PHI_I THETA_O PHI_O [THETA_I PHI_I THETA_O PHI_O ...]
//
// MATERIAL is whatever `aniso eval --material` takes: a preset name (`aniso presets`), a JSON file,
// a MERL .binary file or an inline JSON object. Angles in degrees, theta from the normal, phi from
// the tangent. Prints "# material MATERIAL", then per pair "theta_i phi_i theta_o phi_o f_r f_g f_b
// pdf" with 9 significant digits, as the CLI prints them (compare_with_cli.sh compares the two).
// A bad material is an aniso::InputError: its message goes to stderr and the exit status is 2, as
// the CLI's.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include <aniso/aniso.h>

namespace {

// w = (sin theta cos phi, sin theta sin phi, cos theta) in the local shading frame (z = normal,
// x = tangent), angles in degrees, as `aniso eval --angles` reads them.
aniso::Vec3d direction_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * std::numbers::pi / 180.0, p = std::fmod(phi_deg, 360.0) * std::numbers::pi / 180.0;
  return aniso::Vec3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6 || (argc - 2) % 4 != 0) {
    std::fprintf(stderr, "usage: %s MATERIAL THETA_I PHI_I THETA_O PHI_O [...] (degrees)\n", argv[0]);
    return 2;
  }
  try {
    // Read and validate (InputError on bad input), then build the kernel value in double, as the
    // CLI does. A measured material's kernel points into tables that load_material keeps loaded
    // for the whole run (include/aniso/measured/measured.h).
    const aniso::MaterialDesc desc = aniso::load_material(argv[1]);
    const aniso::MaterialD material = aniso::build_material<double>(desc);

    std::printf("# material %s\n", argv[1]);
    for (int a = 2; a + 3 < argc; a += 4) {
      const double theta_i = std::atof(argv[a]), phi_i = std::atof(argv[a + 1]);
      const double theta_o = std::atof(argv[a + 2]), phi_o = std::atof(argv[a + 3]);
      const aniso::Vec3d wi = direction_deg(theta_i, phi_i);  // towards the light
      const aniso::Vec3d wo = direction_deg(theta_o, phi_o);  // towards the viewer
      const aniso::RGBT<double> f = material.f(wi, wo);       // 1/sr, no cosine
      const double pdf = material.pdf(wi, wo);                // of material.sample(wo, ...) giving wi
      std::printf("%s %s %s %s %.9g %.9g %.9g %.9g\n", argv[a], argv[a + 1], argv[a + 2], argv[a + 3], f.x + 0.0, f.y + 0.0,
                  f.z + 0.0, pdf + 0.0);  // + 0.0: no "-0"
    }
  } catch (const aniso::InputError& e) {
    std::fprintf(stderr, "eval: %s\n", e.what());
    return 2;
  }
  return 0;
}
