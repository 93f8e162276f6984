// export/pbrt_v4.cpp: --to pbrt-v4, the MakeNamedMaterial statements.
#include "export/writers.h"

#include <fmt/format.h>

namespace aniso::exporter {

namespace {

std::string pbrt_conductor(const json& p) {
  std::string s = "    \"string type\" \"conductor\"\n";
  if (p.contains("reflectance"))
    s += fmt::format("    \"rgb reflectance\" [ {} ]\n", fmt3(col(p, "reflectance"), " "));
  else if (p["eta"].is_string())
    s += fmt::format("    \"spectrum eta\" \"{}\"\n    \"spectrum k\" \"{}\"\n", p["eta"].get<std::string>(),
                     p["k"].get<std::string>());
  else
    s += fmt::format("    \"rgb eta\" [ {} ]\n    \"rgb k\" [ {} ]\n", fmt3(col(p, "eta"), " "), fmt3(col(p, "k"), " "));
  s += fmt::format("    \"float uroughness\" {:.9g}\n    \"float vroughness\" {:.9g}\n    \"bool remaproughness\" false\n",
                   num(p, "uroughness"), num(p, "vroughness"));
  return s;
}

}  // namespace

std::string write_pbrt(const std::string& name, const json& p, const std::string& comment) {
  const std::string id = identifier(name);
  std::string s = comment + "\n";
  if (p.contains("filename")) {
    // pbrt-v4's MeasuredMaterial (src/pbrt/materials.cpp @ 5f7a6068: "measured", line 661; its
    // "string filename", lines 610-620, resolved against the scene file's folder) reads the
    // tensor file with MeasuredBxDFData::Create (src/pbrt/bxdfs.cpp:889-932), which needs the
    // "spectra" and "wavelengths" fields: the spectral form. The name is measured_file_name's:
    // letters, digits, '-', '_' and '.', nothing to escape in a quoted string.
    s += fmt::format("MakeNamedMaterial \"{}\"\n    \"string type\" \"measured\"\n    \"string filename\" \"{}\"\n", id,
                     p["filename"].get<std::string>());
    return s;
  }
  if (p.contains("amount")) {
    s += fmt::format("MakeNamedMaterial \"{}-diffuse\"\n    \"string type\" \"diffuse\"\n    \"rgb reflectance\" [ {} ]\n", id,
                     fmt3(col(p, "diffuse_reflectance"), " "));
    s += fmt::format("MakeNamedMaterial \"{}-specular\"\n", id) + pbrt_conductor(p);
    // materials.h:285-293: amount is the probability of materials[1].
    s += fmt::format(
        "MakeNamedMaterial \"{}\"\n    \"string type\" \"mix\"\n    \"string materials\" [ \"{}-diffuse\" "
        "\"{}-specular\" ]\n    \"float amount\" {:.9g}\n",
        id, id, id, num(p, "amount"));
  } else {
    s += fmt::format("MakeNamedMaterial \"{}\"\n", id) + pbrt_conductor(p);
  }
  return s;
}

}  // namespace aniso::exporter
