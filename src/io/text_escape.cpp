// io/text_escape.cpp: see text_escape.h.
#include "io/text_escape.h"

#include <fmt/format.h>

namespace aniso {

namespace {

// The length of the well-formed UTF-8 sequence starting at s[i] (1 to 4), or 0 if s[i] starts none.
// The Unicode Standard 15.0, Sec. 3.9, Table 3-7 (well-formed UTF-8 byte sequences).
size_t utf8_sequence(std::string_view s, size_t i) {
  const auto b = [&](size_t k) { return i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0u; };
  const auto cont = [&](size_t k, unsigned lo = 0x80, unsigned hi = 0xbf) { return b(k) >= lo && b(k) <= hi; };
  const unsigned c = b(0);
  if (c < 0x80) return 1;
  if (c >= 0xc2 && c <= 0xdf) return cont(1) ? 2 : 0;
  if (c == 0xe0) return cont(1, 0xa0) && cont(2) ? 3 : 0;
  if ((c >= 0xe1 && c <= 0xec) || c == 0xee || c == 0xef) return cont(1) && cont(2) ? 3 : 0;
  if (c == 0xed) return cont(1, 0x80, 0x9f) && cont(2) ? 3 : 0;  // no UTF-16 surrogates
  if (c == 0xf0) return cont(1, 0x90) && cont(2) && cont(3) ? 4 : 0;
  if (c >= 0xf1 && c <= 0xf3) return cont(1) && cont(2) && cont(3) ? 4 : 0;
  if (c == 0xf4) return cont(1, 0x80, 0x8f) && cont(2) && cont(3) ? 4 : 0;  // at most U+10FFFF
  return 0;
}

std::string escape(std::string_view s, bool keep_lines) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const size_t n = utf8_sequence(s, i);
    const auto c = static_cast<unsigned char>(s[i]);
    if (n == 0) {
      out += fmt::format("\\x{:02x}", c);
      ++i;
      continue;
    }
    if (n == 1) {
      if (c == '\n')
        out += keep_lines ? "\n" : "\\n";
      else if (c == '\t')
        out += keep_lines ? "\t" : "\\t";
      else if (c == '\r')
        out += "\\r";
      else if (c < 0x20 || c == 0x7f)
        out += fmt::format("\\u{:04x}", c);
      else
        out += s[i];
    } else {
      const auto c1 = static_cast<unsigned char>(s[i + 1]);
      if (c == 0xc2 && c1 < 0xa0)  // U+0080 to U+009F: the C1 controls (CSI, NEL, ...)
        out += fmt::format("\\u{:04x}", c1);
      else if (c == 0xe2 && c1 == 0x80 && (s[i + 2] == '\xa8' || s[i + 2] == '\xa9'))  // U+2028, U+2029
        out += s[i + 2] == '\xa8' ? "\\u2028" : "\\u2029";
      else if (c == 0xef && c1 == 0xbf && (s[i + 2] == '\xbe' || s[i + 2] == '\xbf'))  // U+FFFE, U+FFFF
        out += s[i + 2] == '\xbe' ? "\\ufffe" : "\\uffff";
      else
        out.append(s.substr(i, n));
    }
    i += n;
  }
  return out;
}

}  // namespace

std::string text_escape(std::string_view s) { return escape(s, false); }

std::string terminal_text(std::string_view s) { return escape(s, true); }

std::optional<size_t> first_invalid_utf8(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    const size_t n = utf8_sequence(s, i);
    if (n == 0) return i;
    i += n;
  }
  return std::nullopt;
}

}  // namespace aniso
