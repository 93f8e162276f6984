// examples/cpp/quickstart.cpp: the README's example (CMake aniso::host). A preset read and built,
// then f and pdf for light and viewer 30 degrees from the normal on either side, along the
// tangent, the numbers `aniso eval --angles -m brushed-gold` prints for "30 0 30 180".
#include <cstdio>

#include <aniso/aniso.h>

int main() {
  const aniso::MaterialDesc desc = aniso::load_material("brushed-gold");  // or a file, or inline JSON
  const aniso::MaterialD m = aniso::build_material<double>(desc);         // MaterialT<double>
  const aniso::Vec3d wi(0.5, 0.0, 0.8660254037844386);                    // to the light (shading frame, z = normal)
  const aniso::Vec3d wo(-0.5, 0.0, 0.8660254037844386);                   // to the viewer
  const aniso::RGBT<double> f = m.f(wi, wo);                              // 1/sr, without the cosine
  std::printf("%.9g %.9g %.9g %.9g\n", f.x, f.y, f.z, m.pdf(wi, wo));
}
