// export/materialx.cpp: --to materialx (standard_surface, MaterialX 1.38) and --to openpbr
// (open_pbr_surface, MaterialX 1.39): the two MaterialX documents.
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

std::string write_materialx(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = materialx_name(name);
  std::string s = "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n  <!--\n" + xml_comment_safe(comment) + "  -->\n";
  s += fmt::format("  <standard_surface name=\"SR_{}\" type=\"surfaceshader\">\n", xml_escape(id));
  const auto f = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"float\" value=\"{:.9g}\" />\n", k, num(p, k));
  };
  const auto c = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"color3\" value=\"{}\" />\n", k, fmt3(col(p, k)));
  };
  f("base");
  c("base_color");
  f("metalness");
  f("specular");
  c("specular_color");
  f("specular_roughness");
  if (p.contains("specular_IOR")) f("specular_IOR");
  f("specular_anisotropy");
  f("specular_rotation");
  s += "  </standard_surface>\n";
  s += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", xml_escape(id));
  s += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_{}\" />\n", xml_escape(id));
  s += "  </surfacematerial>\n</materialx>\n";
  return s;
}

// A MaterialX 1.39 document (open_pbr_surface's nodedef is version 1.1.1 in MaterialX 1.39's
// libraries/bxdf/open_pbr_surface.mtlx:2-6); input names and types of its nodedef (lines 8-25, 86).
// A turned tangent: tangent and normal (world space) into rotate3d and normalize, as
// standard_surface.mtlx:153-164 builds its own, into geometry_tangent.
std::string write_openpbr(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = materialx_name(name);
  std::string s = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n  <!--\n" + xml_comment_safe(comment) + "  -->\n";
  const double turn = num(p, "geometry_tangent_rotate3d_deg");
  if (turn != 0.0) {
    s += fmt::format(
        "  <tangent name=\"T_{0}\" type=\"vector3\">\n    <input name=\"space\" type=\"string\" value=\"world\" />\n  "
        "</tangent>\n"
        "  <normal name=\"N_{0}\" type=\"vector3\">\n    <input name=\"space\" type=\"string\" value=\"world\" />\n  </normal>\n"
        "  <rotate3d name=\"T_{0}_rotate\" type=\"vector3\">\n"
        "    <input name=\"in\" type=\"vector3\" nodename=\"T_{0}\" />\n"
        "    <input name=\"amount\" type=\"float\" value=\"{1:.9g}\" />\n"
        "    <input name=\"axis\" type=\"vector3\" nodename=\"N_{0}\" />\n  </rotate3d>\n"
        "  <normalize name=\"T_{0}_rotate_normalize\" type=\"vector3\">\n"
        "    <input name=\"in\" type=\"vector3\" nodename=\"T_{0}_rotate\" />\n  </normalize>\n",
        id, turn);
  }
  s += fmt::format("  <open_pbr_surface name=\"SR_{}\" type=\"surfaceshader\">\n", id);
  const auto f = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"float\" value=\"{:.9g}\" />\n", k, num(p, k));
  };
  const auto c = [&](const char* k) {
    s += fmt::format("    <input name=\"{}\" type=\"color3\" value=\"{}\" />\n", k, fmt3(col(p, k)));
  };
  f("base_weight");
  c("base_color");
  f("base_diffuse_roughness");
  f("base_metalness");
  f("specular_weight");
  c("specular_color");
  f("specular_roughness");
  if (p.contains("specular_ior")) f("specular_ior");
  f("specular_roughness_anisotropy");
  if (turn != 0.0)
    s += fmt::format("    <input name=\"geometry_tangent\" type=\"vector3\" nodename=\"T_{}_rotate_normalize\" />\n", id);
  s += "  </open_pbr_surface>\n";
  s += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", id);
  s += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_{}\" />\n", id);
  s += "  </surfacematerial>\n</materialx>\n";
  return s;
}

}  // namespace aniso::exporter
