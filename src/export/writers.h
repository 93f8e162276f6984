// export/writers.h (private): the writers of the targets' files (one file each: blender.cpp,
// mitsuba3.cpp, pbrt_v4.cpp, materialx.cpp for MaterialX and OpenPBR, gltf.cpp, which also hold the
// target models, target_models.h) and what they share
// (writers.cpp): the report as a comment, the escaping of names and text.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "export/common.h"

namespace aniso::exporter {

std::string xml_escape(std::string_view s);
// Text inside an XML comment may not contain "--".
std::string xml_comment_safe(std::string s);
// The name as an identifier: letters, digits, '_' and '-', the rest '_' ("material" when empty).
std::string identifier(std::string_view s);
// A Python string literal holding exactly the text (writers.cpp).
std::string py_string(std::string_view in);
// A MaterialX element name (writers.cpp).
std::string materialx_name(std::string_view s);
// The report as a comment of the written file, `pre` starting each line (writers.cpp).
std::string comment_block(const ExportReport& r, const std::string& source, std::string_view pre);
// A number and a colour of the parameters the target model wrote.
double num(const json& p, const char* k);
glm::dvec3 col(const json& p, const char* k);

std::string write_blender(const std::string& name, const json& p, const std::string& comment);
std::string write_mitsuba(const std::string& name, const json& p, const std::string& comment);
std::string write_pbrt(const std::string& name, const json& p, const std::string& comment);
std::string write_materialx(const std::string& name, const json& p, const std::string& comment);
std::string write_openpbr(const std::string& name, const json& p, const std::string& comment);
// The .gltf (files[0], name "") and its .bin (bin_name).
void write_gltf(const std::string& name, const json& p, const ExportReport& r, const std::string& source,
                const std::string& bin_name, std::vector<ExportFile>& files);

}  // namespace aniso::exporter
