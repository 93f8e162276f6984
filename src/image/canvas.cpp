// image/canvas.cpp: rectangles, copies and the label font (canvas.h).
//
// This translation unit owns the stb_truetype implementation: it is compiled here, static to
// this file, and nowhere else.
#include "aniso/image/canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "image/third_party_begin.h"  // closed by the pop below
#define STBTT_STATIC
#define STB_TRUETYPE_IMPLEMENTATION
#include <stb_truetype.h>
#pragma GCC diagnostic pop

// DejaVu Sans, embedded by the build (an .incbin in an assembler file, see CMakeLists.txt).
extern "C" const unsigned char aniso_label_font_begin[];
extern "C" const unsigned char aniso_label_font_end[];

namespace aniso::render {
namespace {

struct LabelFont {
  stbtt_fontinfo info{};
  int ascent = 0;  // font units
};

// Parsed once, on first use; C++ guarantees the initialisation of a function-local static is
// thread-safe. stb_truetype only reads `info` afterwards, so concurrent drawing is fine too.
const LabelFont& label_font() {
  static const LabelFont font = [] {
    LabelFont f;
    const unsigned char* data = aniso_label_font_begin;
    if (aniso_label_font_end <= data || !stbtt_InitFont(&f.info, data, stbtt_GetFontOffsetForIndex(data, 0)))
      throw std::runtime_error("the embedded label font (DejaVu Sans) cannot be parsed");
    int descent = 0, line_gap = 0;
    stbtt_GetFontVMetrics(&f.info, &f.ascent, &descent, &line_gap);
    return f;
  }();
  return font;
}

// UTF-8 -> code points; a malformed sequence (stray continuation byte, overlong form, surrogate,
// truncated sequence) becomes U+FFFD and decoding resumes at the next byte.
std::vector<uint32_t> decode_utf8(std::string_view s) {
  std::vector<uint32_t> out;
  out.reserve(s.size());
  size_t i = 0;
  while (i < s.size()) {
    const auto b0 = uint8_t(s[i]);
    int len = 0;
    uint32_t cp = 0, min = 0;
    if (b0 < 0x80)
      len = 1, cp = b0;
    else if ((b0 & 0xE0) == 0xC0)
      len = 2, cp = b0 & 0x1Fu, min = 0x80;
    else if ((b0 & 0xF0) == 0xE0)
      len = 3, cp = b0 & 0x0Fu, min = 0x800;
    else if ((b0 & 0xF8) == 0xF0)
      len = 4, cp = b0 & 0x07u, min = 0x10000;
    bool ok = len > 0 && i + size_t(len) <= s.size();
    for (int k = 1; ok && k < len; ++k) {
      const auto b = uint8_t(s[i + size_t(k)]);
      ok = (b & 0xC0) == 0x80;
      cp = (cp << 6) | (b & 0x3Fu);
    }
    ok = ok && cp >= min && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
    out.push_back(ok ? cp : 0xFFFD);
    i += ok ? size_t(len) : 1;
  }
  return out;
}

// Lays the text out on one line and calls draw(glyph, pen_x) for each glyph, pen_x being the
// origin of the glyph relative to the start of the text. Returns the advance width in pixels.
template <typename Draw> double layout_text(const LabelFont& font, std::string_view text, float scale, Draw&& draw) {
  double pen = 0.0;
  int prev = 0;
  for (const uint32_t cp : decode_utf8(text)) {
    if (cp < 0x20 || cp == 0x7F) continue;  // control characters: one line of text, nothing to draw
    const int glyph = stbtt_FindGlyphIndex(&font.info, int(cp));
    if (prev) pen += double(stbtt_GetGlyphKernAdvance(&font.info, prev, glyph)) * scale;
    draw(glyph, pen);
    int advance = 0, lsb = 0;
    stbtt_GetGlyphHMetrics(&font.info, glyph, &advance, &lsb);
    pen += double(advance) * scale;
    prev = glyph;
  }
  return pen;
}

bool valid_pixel_height(float pixel_height) { return std::isfinite(pixel_height) && pixel_height > 0.0f; }

}  // namespace

int text_width(std::string_view text, float pixel_height) {
  if (!valid_pixel_height(pixel_height)) return 0;
  const LabelFont& font = label_font();
  const float scale = stbtt_ScaleForPixelHeight(&font.info, pixel_height);
  return int(std::ceil(layout_text(font, text, scale, [](int, double) {})));
}

// Coverage is alpha-blended into the 8-bit values as they are, in sRGB space (what most UI text
// renderers do; blending in linear light would make dark-on-light text look thinner).
int draw_text(DisplayImage& img, int x, int y, std::string_view text, float pixel_height, const glm::u8vec3& color) {
  if (!valid_pixel_height(pixel_height)) return 0;
  const LabelFont& font = label_font();
  const float scale = stbtt_ScaleForPixelHeight(&font.info, pixel_height);
  const int64_t baseline = int64_t(y) + std::lround(double(font.ascent) * scale);
  std::vector<unsigned char> bitmap;
  const double width = layout_text(font, text, scale, [&](int glyph, double pen) {
    const double origin = double(x) + pen;
    const double origin_floor = std::floor(origin);
    const float shift = float(origin - origin_floor);  // sub-pixel position of the glyph
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    stbtt_GetGlyphBitmapBoxSubpixel(&font.info, glyph, scale, scale, shift, 0.0f, &x0, &y0, &x1, &y1);
    const int gw = x1 - x0, gh = y1 - y0;
    if (gw <= 0 || gh <= 0) return;  // a space
    const int64_t left = int64_t(origin_floor) + x0, top = baseline + y0;
    // Clip to the image; a glyph wholly outside is not even rasterised.
    const int64_t cx0 = std::max<int64_t>(left, 0), cx1 = std::min<int64_t>(left + gw, img.width);
    const int64_t cy0 = std::max<int64_t>(top, 0), cy1 = std::min<int64_t>(top + gh, img.height);
    if (cx0 >= cx1 || cy0 >= cy1) return;
    bitmap.assign(size_t(gw) * size_t(gh), 0);
    stbtt_MakeGlyphBitmapSubpixel(&font.info, bitmap.data(), gw, gh, gw, scale, scale, shift, 0.0f, glyph);
    for (int64_t py = cy0; py < cy1; ++py)
      for (int64_t px = cx0; px < cx1; ++px) {
        const unsigned a = bitmap[size_t(py - top) * size_t(gw) + size_t(px - left)];
        if (a == 0) continue;
        uint8_t* d = &img.rgb[(size_t(py) * size_t(img.width) + size_t(px)) * 3];
        for (int c = 0; c < 3; ++c) d[c] = uint8_t((d[c] * (255u - a) + unsigned(color[c]) * a + 127u) / 255u);
      }
  });
  return int(std::ceil(width));
}

void fill_rect(DisplayImage& img, int x, int y, int w, int h, const glm::u8vec3& color) {
  const int64_t x0 = std::max<int64_t>(x, 0), x1 = std::min<int64_t>(int64_t(x) + w, img.width);
  const int64_t y0 = std::max<int64_t>(y, 0), y1 = std::min<int64_t>(int64_t(y) + h, img.height);
  for (int64_t py = y0; py < y1; ++py)
    for (int64_t px = x0; px < x1; ++px) {
      uint8_t* d = &img.rgb[(size_t(py) * size_t(img.width) + size_t(px)) * 3];
      d[0] = color.x, d[1] = color.y, d[2] = color.z;
    }
}

void blit(DisplayImage& dst, const DisplayImage& src, int x, int y) {
  const int64_t x0 = std::max<int64_t>(x, 0), x1 = std::min<int64_t>(int64_t(x) + src.width, dst.width);
  const int64_t y0 = std::max<int64_t>(y, 0), y1 = std::min<int64_t>(int64_t(y) + src.height, dst.height);
  if (x0 >= x1) return;
  for (int64_t py = y0; py < y1; ++py) {
    const uint8_t* s = &src.rgb[(size_t(py - y) * size_t(src.width) + size_t(x0 - x)) * 3];
    uint8_t* d = &dst.rgb[(size_t(py) * size_t(dst.width) + size_t(x0)) * 3];
    std::copy(s, s + (x1 - x0) * 3, d);
  }
}

}  // namespace aniso::render