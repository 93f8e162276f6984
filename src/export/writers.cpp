// export/writers.cpp: what the writers share (writers.h): the escaping of names and text, the
// report as a comment.
#include "export/writers.h"
#include "aniso/version.h"

#include <cctype>
#include <string>

#include <fmt/format.h>

#include "io/text_escape.h"

namespace aniso::exporter {

std::string xml_escape(std::string_view s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      default: o += c;
    }
  }
  return o;
}
// Text inside an XML comment may not contain "--".
std::string xml_comment_safe(std::string s) {
  for (size_t i; (i = s.find("--")) != std::string::npos;) s.replace(i, 2, "- -");
  return s;
}
std::string identifier(std::string_view s) {
  std::string o;
  for (char c : s) o += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
  if (o.empty()) o = "material";
  return o;
}
// A Python string literal (the Python Language Reference, 2.4.1, "String and Bytes literals") holding
// exactly the text: backslash, quote and every control character (C0, DEL, C1) and line separator
// as an escape sequence, so a name can neither end the literal nor the line. Text that is not UTF-8
// (a script must be, PEP 3120) is made so first by text_escape (its bad bytes become "\xNN").
std::string py_string(std::string_view in) {
  const std::string s = first_invalid_utf8(in) ? text_escape(in) : std::string(in);
  std::string o = "\"";
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '\\' || c == '"')
      o += '\\', o += s[i];
    else if (c == '\n')
      o += "\\n";
    else if (c == '\r')
      o += "\\r";
    else if (c == '\t')
      o += "\\t";
    else if (c < 0x20 || c == 0x7f)
      o += fmt::format("\\x{:02x}", c);
    else if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) < 0xa0)  // U+0080 to U+009F
      o += fmt::format("\\x{:02x}", static_cast<unsigned char>(s[++i]));
    else if (c == 0xe2 && s.compare(i + 1, 1, "\x80") == 0 && i + 2 < s.size() && (s[i + 2] == '\xa8' || s[i + 2] == '\xa9'))
      o += s[i + 2] == '\xa8' ? "\\u2028" : "\\u2029", i += 2;
    else
      o += s[i];
  }
  return o + "\"";
}

// A MaterialX element name: letters, digits, '_' and ':' only (MaterialX source/MaterialXCore/
// Util.cpp:25-28, invalidNameChar, which Element::validate checks), the rest replaced by '_' as
// createValidName does.
std::string materialx_name(std::string_view s) {
  std::string o(s.empty() ? std::string_view("material") : s);
  for (char& c : o)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != ':') c = '_';
  return o;
}

// The report as a comment of the written file, `pre` starting each line ("# " for Python and pbrt-v4,
// whose comments end at '\n' or '\r'; spaces inside an XML comment). The source's label (a file
// name, a scene object's name) and every other line go through text_escape: no line break, control
// byte or invalid UTF-8 from an input can end the comment, so no input text becomes code.
std::string comment_block(const ExportReport& r, const std::string& source, std::string_view pre) {
  const std::string raw = "Exported by aniso " ANISO_VERSION " from " + text_escape(source) + "\n" + r.text("");
  std::string s;
  for (size_t i = 0, j; i < raw.size(); i = j + 1) {
    j = raw.find('\n', i);
    if (j == std::string::npos) j = raw.size();
    s += std::string(pre) + text_escape(std::string_view(raw).substr(i, j - i)) + "\n";
  }
  return s;
}

double num(const json& p, const char* k) { return p.at(k).get<double>(); }
glm::dvec3 col(const json& p, const char* k) {
  const json& a = p.at(k);
  return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}

}  // namespace aniso::exporter
