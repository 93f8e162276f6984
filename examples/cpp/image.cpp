// examples/cpp/image.cpp: images in and out, tone mapping and labels (CMake aniso::image: OpenEXR,
// neither Embree nor Ceres).
//
// Makes a linear radiance ramp, writes it as EXR (linear float) and as PNG (tone-mapped 8-bit
// sRGB), reads both back, and checks that the EXR returns the same floats and the PNG the bytes
// tonemap() made (decoded to linear). Then draws a label on the tone-mapped image and writes it.
// Exit status 1 when a check fails.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <aniso/image/canvas.h>
#include <aniso/image/image_io.h>
#include <aniso/image/tonemap.h>
#include <aniso/io/input_error.h>

int main() {
  namespace render = aniso::render;
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("aniso-image-example-" + std::to_string(getpid()));
  fs::create_directories(dir);
  int failures = 0;

  // Radiance from 0 to 8 left to right, a little more red than blue.
  render::Image ramp(256, 32);
  for (int y = 0; y < ramp.height; ++y)
    for (int x = 0; x < ramp.width; ++x) {
      const float v = 8.0f * float(x) / float(ramp.width - 1);
      ramp.set(x, y, aniso::RGB(v, 0.8f * v, 0.6f * v));
    }

  // The format follows the extension: .exr and .pfm keep the floats, .png is tone-mapped.
  const render::ToneMapOptions tm{.exposure_stops = -1.0f, .curve = render::ToneMap::Aces};
  render::write_image((dir / "ramp.exr").string(), ramp);
  render::write_image((dir / "ramp.png").string(), ramp, tm);

  const render::Image exr = render::read_image((dir / "ramp.exr").string(), "ramp");
  if (exr.rgb != ramp.rgb) {
    std::printf("FAIL: the EXR file did not return the floats written\n");
    ++failures;
  }
  const render::DisplayImage shown = render::tonemap(ramp, tm);
  const render::Image png = render::read_image((dir / "ramp.png").string(), "ramp");
  for (size_t i = 0; i < png.rgb.size(); ++i)
    if (std::abs(png.rgb[i] - render::srgb_decode(float(shown.rgb[i]) / 255.0f)) > 1e-6f) {
      std::printf("FAIL: PNG value %zu is %g, tonemap() made byte %d\n", i, double(png.rgb[i]), int(shown.rgb[i]));
      ++failures;
      break;
    }

  // A label below the ramp, in the embedded font (DejaVu Sans), on a white strip.
  render::DisplayImage labelled(ramp.width, ramp.height + 24, 255);
  render::blit(labelled, shown, 0, 0);
  const int width = render::draw_text(labelled, 4, ramp.height + 4, "radiance 0 \u2192 8, ACES, \u22121 stop", 14.0f, {0, 0, 0});
  render::write_png((dir / "labelled.png").string(), labelled);
  std::printf("wrote %s (label %d pixels wide)\n", (dir / "labelled.png").c_str(), width);

  // Bad input is an InputError naming the file and the problem.
  try {
    render::read_image((dir / "missing.exr").string(), "example");
    std::printf("FAIL: reading a missing file did not throw\n");
    ++failures;
  } catch (const aniso::InputError& e) {
    std::printf("InputError: %s\n", e.what());
  }

  fs::remove_all(dir);
  return failures == 0 ? 0 : 1;
}
