// aniso/image/canvas.h: drawing on a DisplayImage, for the gallery, the fitter's plots and the
// exports' previews: rectangles, copies, and one-line labels in the embedded font.
#pragma once

#include <string_view>

#include "aniso/core/math.h"
#include "aniso/image/image.h"

namespace aniso::render {

// Text is drawn with DejaVu Sans (embedded in the binary, stb_truetype), anti-aliased and
// alpha-blended; (x, y) is the top-left corner of the text box, pixel_height the font's pixel
// height (ascender to descender), and the baseline lies at y + ascent. The text is UTF-8 (Greek,
// degree sign, ...; malformed bytes show as U+FFFD), one line, kerned; coverage is blended into the
// sRGB bytes as they are. Returns the text's advance width in pixels (rounded up), the same as
// text_width(). Pixels outside the image are skipped.
int draw_text(DisplayImage& img, int x, int y, std::string_view text, float pixel_height, const glm::u8vec3& color);
int text_width(std::string_view text, float pixel_height);
void fill_rect(DisplayImage& img, int x, int y, int w, int h, const glm::u8vec3& color);
// Copies src into dst with its top-left corner at (x, y) (clipped).
void blit(DisplayImage& dst, const DisplayImage& src, int x, int y);

}  // namespace aniso::render
