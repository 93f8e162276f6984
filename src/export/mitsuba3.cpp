// export/mitsuba3.cpp: --to mitsuba3, the XML scene with one <bsdf>.
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

std::string write_mitsuba(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = xml_escape(identifier(name));
  if (p.contains("filename")) {
    // Mitsuba 3's own measured BSDF (src/bsdfs/measured.cpp @ b45b0a93: the "filename" property,
    // line 86; an rgb file for the RGB variants, a spectral one for the spectral variants, lines
    // 102-116; isotropic when phi_i has at most 2 entries, line 165). The file is relative to the
    // scene's folder (Mitsuba resolves it with the file resolver, line 86).
    std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
    s += "<scene version=\"3.0.0\">\n";
    s += fmt::format("    <bsdf type=\"measured\" id=\"{}\">\n", id);
    s += fmt::format("        <string name=\"filename\" value=\"{}\"/>\n", xml_escape(p["filename"].get<std::string>()));
    s += "    </bsdf>\n</scene>\n";
    return s;
  }
  if (p.contains("principled")) {
    // principled.cpp:20-105: base_color a spectrum, the rest floats; "specular" (not "eta").
    std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
    s += "<scene version=\"3.0.0\">\n";
    s += fmt::format("    <bsdf type=\"principled\" id=\"{}\">\n", id);
    s += fmt::format("        <rgb name=\"base_color\" value=\"{}\"/>\n", fmt3(col(p, "base_color")));
    for (const char* key : {"roughness", "anisotropic", "metallic", "specular", "spec_tint", "sheen", "sheen_tint", "flatness",
                            "clearcoat", "clearcoat_gloss"})
      s += fmt::format("        <float name=\"{}\" value=\"{:.9g}\"/>\n", key, num(p, key));
    s += "    </bsdf>\n</scene>\n";
    return s;
  }
  std::string conductor = "        <string name=\"distribution\" value=\"ggx\"/>\n";
  conductor += fmt::format("        <float name=\"alpha_u\" value=\"{:.9g}\"/>\n", num(p, "alpha_u"));
  conductor += fmt::format("        <float name=\"alpha_v\" value=\"{:.9g}\"/>\n", num(p, "alpha_v"));
  if (p.contains("material"))
    conductor += fmt::format("        <string name=\"material\" value=\"{}\"/>\n", xml_escape(p["material"].get<std::string>()));
  else
    conductor += fmt::format("        <rgb name=\"eta\" value=\"{}\"/>\n        <rgb name=\"k\" value=\"{}\"/>\n",
                             fmt3(col(p, "eta")), fmt3(col(p, "k")));
  std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n" + xml_comment_safe(comment) + "-->\n";
  s += "<scene version=\"3.0.0\">\n";
  if (p.contains("weight")) {
    // blendbsdf.cpp:17-21: weight 0 is the first nested BSDF, 1 the second.
    s += fmt::format("    <bsdf type=\"blendbsdf\" id=\"{}\">\n", id);
    s += fmt::format("        <float name=\"weight\" value=\"{:.9g}\"/>\n", num(p, "weight"));
    s += fmt::format("        <bsdf type=\"diffuse\">\n            <rgb name=\"reflectance\" value=\"{}\"/>\n        </bsdf>\n",
                     fmt3(col(p, "diffuse_reflectance")));
    s += "        <bsdf type=\"roughconductor\">\n";
    std::string inner;
    for (size_t i = 0, j; i < conductor.size(); i = j + 1) {
      j = conductor.find('\n', i);
      inner += "    " + conductor.substr(i, j - i + 1);
    }
    s += inner + "        </bsdf>\n    </bsdf>\n";
  } else {
    s += fmt::format("    <bsdf type=\"roughconductor\" id=\"{}\">\n", id);
    s += conductor + "    </bsdf>\n";
  }
  return s + "</scene>\n";
}

}  // namespace aniso::exporter
