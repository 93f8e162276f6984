// fuzz/fuzz_image.cpp: the image readers (image/image_io.cpp): PNG and JPEG through stb_image, HDR
// through stb_image, EXR through OpenEXR, PFM by hand. The first byte chooses the extension (and
// whether 8-bit data is read as linear numbers, as tangent maps are, or decoded from sRGB); the
// rest is the file. Selector byte: (b & 0x7f) % 5 picks .png .hdr .exr .pfm .jpg; b & 0x80 reads
// 8-bit data as linear. An accepted image must have a positive size, width * height * 3 values, each
// finite and >= 0 (read_image's contract, image/image_io.h).
#include "aniso/image/image_io.h"
#include "aniso/io/input_error.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  if (size == 0) return 0;
  static const char* const kExt[] = {".png", ".hdr", ".exr", ".pfm", ".jpg"};
  const std::string path = fuzz::write_scratch_file(std::string("image") + kExt[(data[0] & 0x7f) % 5], data + 1, size - 1);
  render::Image img;
  try {
    img = render::read_image(path, "fuzz", /*linear_8bit=*/(data[0] & 0x80) != 0);
  } catch (const InputError& e) {
    fuzz::rejected(e);
    return 0;
  }
  FUZZ_CHECK(img.width > 0 && img.height > 0);
  FUZZ_CHECK(img.rgb.size() == size_t(img.width) * size_t(img.height) * 3);
  for (const float v : img.rgb) FUZZ_CHECK(std::isfinite(v) && v >= 0.0f);
  return 0;
}
