// gl/glsl_library.cpp: the embedded GLSL library and the name handling the exports use.
#include "gl/glsl_library.h"

#include <cctype>
#include <regex>
#include <sstream>
#include <vector>

namespace aniso::embedded {
extern const std::string_view glsl_core_platform, glsl_core_math, glsl_core_frame, glsl_core_sampling,
    glsl_core_lobe_mixture, glsl_brdf_fresnel, glsl_brdf_lambert, glsl_brdf_phong, glsl_brdf_ward,
    glsl_brdf_ashikhmin_shirley, glsl_brdf_ggx, glsl_brdf_lafortune, glsl_brdf_metal, glsl_brdf_material,
    glsl_tangent_fields;
}

namespace aniso::gl {

std::span<const GlslFile> glsl_library_files() {
  using namespace aniso::embedded;
  static const GlslFile files[] = {
      {"include/aniso/core/platform.glsl", glsl_core_platform},
      {"include/aniso/core/math.glsl", glsl_core_math},
      {"include/aniso/core/frame.glsl", glsl_core_frame},
      {"include/aniso/core/sampling.glsl", glsl_core_sampling},
      {"include/aniso/core/lobe_mixture.glsl", glsl_core_lobe_mixture},
      {"include/aniso/brdf/fresnel.glsl", glsl_brdf_fresnel},
      {"include/aniso/brdf/lambert.glsl", glsl_brdf_lambert},
      {"include/aniso/brdf/phong.glsl", glsl_brdf_phong},
      {"include/aniso/brdf/ward.glsl", glsl_brdf_ward},
      {"include/aniso/brdf/ashikhmin_shirley.glsl", glsl_brdf_ashikhmin_shirley},
      {"include/aniso/brdf/ggx.glsl", glsl_brdf_ggx},
      {"include/aniso/brdf/lafortune.glsl", glsl_brdf_lafortune},
      {"include/aniso/brdf/metal.glsl", glsl_brdf_metal},
      {"include/aniso/brdf/material.glsl", glsl_brdf_material},
      {"include/aniso/tangent/fields.glsl", glsl_tangent_fields},
  };
  return files;
}

std::string glsl_library_source() {
  std::string out;
  for (const GlslFile& f : glsl_library_files()) {
    out += "// ---- ";
    out += f.path;
    out += "\n";
    out += f.source;
    if (!out.empty() && out.back() != '\n') out += '\n';
  }
  return out;
}

namespace {

// The identifiers of a line of GLSL outside its // comment (the library has no /* */ comments).
void identifiers(std::string_view code, std::set<std::string>& out) {
  size_t i = 0;
  while (i < code.size()) {
    const unsigned char c = static_cast<unsigned char>(code[i]);
    if (std::isalpha(c) || c == '_') {
      size_t j = i;
      while (j < code.size() && (std::isalnum(static_cast<unsigned char>(code[j])) || code[j] == '_')) ++j;
      out.emplace(code.substr(i, j - i));
      i = j;
    } else if (std::isdigit(c)) {  // a number and its suffix (1e-6, 0x80000000u): no identifier
      while (i < code.size() && (std::isalnum(static_cast<unsigned char>(code[i])) || code[i] == '.')) ++i;
    } else {
      ++i;
    }
  }
}

std::string_view code_part(std::string_view line) {
  const size_t c = line.find("//");
  return c == std::string_view::npos ? line : line.substr(0, c);
}

}  // namespace

std::string glsl_library_subset(std::string_view used) {
  // The library as file-scope items, each with the comment lines before it: a declaration starts
  // in column 0 (as glsl_declared_names reads them) and ends where its braces and parentheses
  // close on a line ending in '}' or ';'.
  struct Item {
    std::string text;
    std::set<std::string> names, uses;
  };
  std::vector<Item> items;
  std::string pending;  // comment and blank lines before the next item
  const std::string lib = glsl_library_source();
  std::istringstream in(lib);
  std::string line;
  Item* open = nullptr;
  int depth = 0;
  while (std::getline(in, line)) {
    const std::string_view code = code_part(line);
    if (!open) {
      if (code.find_first_not_of(" \t\r") == std::string_view::npos) {
        pending += line + "\n";
        continue;
      }
      items.push_back(Item{std::move(pending), glsl_declared_names(line), {}});
      pending.clear();
      open = &items.back();
      depth = 0;
    }
    open->text += line + "\n";
    identifiers(code, open->uses);
    for (char c : code) depth += (c == '{' || c == '(') ? 1 : (c == '}' || c == ')') ? -1 : 0;
    const size_t last = code.find_last_not_of(" \t\r");
    if (depth == 0 && last != std::string_view::npos && (code[last] == ';' || code[last] == '}')) open = nullptr;
  }
  // What `used` needs, transitively: every item declaring a name it mentions (all overloads).
  std::set<std::string> wanted;
  std::vector<std::string> todo;
  std::set<std::string> first;
  std::istringstream uin{std::string(used)};
  while (std::getline(uin, line)) identifiers(code_part(line), first);
  todo.assign(first.begin(), first.end());
  std::vector<bool> keep(items.size(), false);
  while (!todo.empty()) {
    const std::string name = todo.back();
    todo.pop_back();
    if (!wanted.insert(name).second) continue;
    for (size_t i = 0; i < items.size(); ++i) {
      if (keep[i] || !items[i].names.count(name)) continue;
      keep[i] = true;
      todo.insert(todo.end(), items[i].uses.begin(), items[i].uses.end());
    }
  }
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (keep[i] || items[i].names.empty()) out += items[i].text;  // an item without a name: kept
  }
  return out;
}

std::string glsl_preamble(GlslDialect dialect) {
  switch (dialect) {
    case GlslDialect::Core330: return "#version 330 core\n";
    case GlslDialect::Es300: return "#version 300 es\nprecision highp float;\nprecision highp int;\n";
    case GlslDialect::Core450Compute: return "#version 450 core\n";
  }
  return "";
}

std::set<std::string> glsl_declared_names(std::string_view source) {
  // File-scope declarations start in column 0 in the library and in the generated code:
  //   struct Name {         const T Name = ...;        uniform T Name;        T Name(args) {
  static const std::regex decl(R"(^(?:struct\s+(\w+)|const\s+\w+\s+(\w+)\s*=|uniform\s+\w+\s+(\w+)\s*;|\w+\s+(\w+)\s*\())");
  std::set<std::string> names;
  std::istringstream in{std::string(source)};
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, decl)) continue;
    for (int i = 1; i <= 4; ++i)
      if (m[i].matched) names.insert(m[i].str());
  }
  return names;
}

std::set<std::string> glsl_library_names() {
  static const std::set<std::string> names = glsl_declared_names(glsl_library_source());
  return names;
}

std::string glsl_prefix_names(std::string_view source, std::string_view prefix) {
  const std::set<std::string>& names = glsl_library_names();
  std::string out;
  out.reserve(source.size() + source.size() / 8);
  size_t i = 0;
  while (i < source.size()) {
    const char c = source[i];
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      size_t j = i;
      while (j < source.size() && (std::isalnum(static_cast<unsigned char>(source[j])) || source[j] == '_')) ++j;
      const std::string word(source.substr(i, j - i));
      if (names.count(word)) out += prefix;
      out += word;
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      // A number (with its suffix or exponent, e.g. 1e-12, 0x80000000u) is never renamed.
      size_t j = i;
      while (j < source.size() && (std::isalnum(static_cast<unsigned char>(source[j])) || source[j] == '.' ||
                                   ((source[j] == '-' || source[j] == '+') && (source[j - 1] == 'e' || source[j - 1] == 'E'))))
        ++j;
      out += source.substr(i, j - i);
      i = j;
    } else {
      out += c;
      ++i;
    }
  }
  return out;
}

}  // namespace aniso::gl
