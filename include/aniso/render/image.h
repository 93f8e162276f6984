// aniso/render/image.h: images in and out of the renderer, tone mapping, and the gallery's labels.
//
// Image is linear RGB radiance (float, Rec.709 primaries, docs/conventions.md), row 0 at the top.
// Readers: PNG / JPEG / HDR through stb_image, EXR through OpenEXR, PFM by hand (a 3-line text
// header). Writers choose the format from the extension: .png is tone-mapped 8-bit sRGB, .exr and
// .pfm hold linear RGB float. Every writer writes to a temporary file beside the target and
// renames it, so a failed or interrupted write never leaves a half-written image.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "aniso/core/math.h"

namespace aniso::render {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, row-major, row 0 = top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
  RGB at(int x, int y) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return RGB(rgb[i], rgb[i + 1], rgb[i + 2]);
  }
  void set(int x, int y, const RGB& c) {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    rgb[i] = c.x, rgb[i + 1] = c.y, rgb[i + 2] = c.z;
  }
};

// 8-bit sRGB-encoded display image (what PNGs hold), row 0 at the top.
struct DisplayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3

  DisplayImage() = default;
  DisplayImage(int w, int h, uint8_t fill = 0) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, fill) {}
};

enum class ToneMap {
  Aces,   // exposure, then the ACES filmic curve (Narkowicz 2015 fit), then the sRGB OETF
  Clamp,  // exposure, clamp to [0, 1], then the sRGB OETF
};

struct ToneMapOptions {
  float exposure_stops = 0.0f;  // radiance is multiplied by 2^exposure_stops first
  ToneMap curve = ToneMap::Aces;
};

// The sRGB transfer function (IEC 61966-2-1) and its inverse, on [0, 1]: inputs outside are
// clamped, NaN gives 0.
float srgb_encode(float linear);
float srgb_decode(float encoded);

// Per channel: radiance * 2^exposure_stops, the curve, the sRGB OETF, rounded to the nearest
// byte. NaN and negative radiance give 0, +inf gives 255.
DisplayImage tonemap(const Image& img, const ToneMapOptions& opt);

// Reads an image by extension (.png .jpg .jpeg .hdr .exr .pfm). `where` prefixes every error
// (e.g. "scene.json: environment.file"); a missing, unreadable, corrupt or empty file, or one with
// non-finite or negative values, is an InputError naming the path and the problem.
// 8-bit formats are decoded from sRGB to linear unless `linear_8bit` is set (data maps such as
// tangent maps are read with linear_8bit = true: their bytes are numbers, not colours); 16-bit
// PNGs likewise, over 65535. Grey images are expanded to RGB, alpha is dropped. Messages read
// "<where>: <path>: <problem>".
Image read_image(const std::string& path, const std::string& where, bool linear_8bit = false);

// Writes by extension: .png (tone-mapped with `tm`, 8-bit sRGB), .exr (32-bit float R, G, B, ZIP
// compression), .pfm ("PF", little endian, rows bottom to top as the format wants). An unknown
// extension is an InputError; an empty image or an I/O failure a std::runtime_error reading
// "cannot write <path>: <reason>". Atomic, through io::write_file_atomically (io/atomic_file.h:
// a temporary file beside the target, fsync, rename; mode and symbolic links kept; removed on
// failure and on SIGTERM, SIGHUP, SIGINT and SIGXFSZ).
void write_image(const std::string& path, const Image& img, const ToneMapOptions& tm = {});
void write_png(const std::string& path, const DisplayImage& img);

// Gallery composition. Text is drawn with DejaVu Sans (embedded in the binary, stb_truetype),
// anti-aliased and alpha-blended; (x, y) is the top-left corner of the text box, pixel_height
// the font's pixel height (ascender to descender), and the baseline lies at y + ascent. The text
// is UTF-8 (Greek, degree sign, ...; malformed bytes show as U+FFFD), one line, kerned; coverage is
// blended into the sRGB bytes as they are. Returns the text's advance width in pixels (rounded
// up), the same as text_width(). Pixels outside the image are skipped.
int draw_text(DisplayImage& img, int x, int y, std::string_view text, float pixel_height, const glm::u8vec3& color);
int text_width(std::string_view text, float pixel_height);
void fill_rect(DisplayImage& img, int x, int y, int w, int h, const glm::u8vec3& color);
// Copies src into dst with its top-left corner at (x, y) (clipped).
void blit(DisplayImage& dst, const DisplayImage& src, int x, int y);

}  // namespace aniso::render
