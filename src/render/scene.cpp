// render/scene.cpp: the scene reader. Every key is checked once here, with its JSON path in the
// message (docs/scenes.md is the reference for the keys); the renderer trusts what it gets.
#include "aniso/render/scene.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include "aniso/image/image_io.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "io/json_read.h"
#include "io/text_input.h"

namespace aniso::render {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// One JSON object being read, with its path ("objects[2].tangent") for messages. Every key read is
// remembered; finish() rejects the keys nobody asked for.
class Node {
 public:
  Node(const json& obj, std::string source, std::string path) : obj_(obj), source_(std::move(source)), path_(std::move(path)) {
    if (!obj_.is_object()) fail_at(path_, fmt::format("expected an object, got {}", json_type_name(obj_)));
  }

  std::string key_path(std::string_view key) const { return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key); }
  [[noreturn]] void fail_at(const std::string& path, const std::string& what) const {
    throw InputError(fmt::format("{}: {}: {}", source_, path.empty() ? "(top level)" : path, what));
  }
  [[noreturn]] void fail(std::string_view key, const std::string& what) const { fail_at(key_path(key), what); }

  bool has(std::string_view key) {
    known_.insert(std::string(key));
    return obj_.contains(key);
  }
  const json& get(std::string_view key) {
    if (!has(key)) fail(key, "missing (required)");
    return obj_.at(std::string(key));
  }

  // The bounds are compared in double, with the JSON number as written (a float bound would be
  // rounded: 1e15 is 999999986991104, 0.05f is 0.0500000007, refusing the documented limits).
  float number(std::string_view key, double def, double lo, double hi, bool required = false, bool lo_exclusive = false) {
    if (!has(key)) {
      if (required)
        fail(key, fmt::format("missing (required): expected a number in {}{}, {}]", lo_exclusive ? "(" : "[", lo, hi));
      return float(def);
    }
    const json& v = obj_.at(std::string(key));
    const double x = v.is_number() ? v.get<double>() : NAN;
    const bool ok = v.is_number() && std::isfinite(x) && (lo_exclusive ? x > lo : x >= lo) && x <= hi;
    if (!ok)
      fail(key, fmt::format("expected a number in {}{}, {}], got {}", lo_exclusive ? "(" : "[", lo, hi, json_type_name(v)));
    return float(x);
  }
  int integer(std::string_view key, int def, int lo, int hi) {
    if (!has(key)) return def;
    const json& v = obj_.at(std::string(key));
    if (!v.is_number_integer() || v.get<int64_t>() < lo || v.get<int64_t>() > hi)
      fail(key, fmt::format("expected an integer in [{}, {}], got {}", lo, hi, json_type_name(v)));
    return int(v.get<int64_t>());
  }
  Vec3 vec3(std::string_view key, const Vec3& def, bool required = false) {
    if (!has(key)) {
      if (required) fail(key, "missing (required): expected [x, y, z]");
      return def;
    }
    const json& v = obj_.at(std::string(key));
    if (!v.is_array() || v.size() != 3)
      fail(key, fmt::format("expected [x, y, z] (3 finite numbers), got {}", json_type_name(v)));
    Vec3 r;
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()) || std::fabs(v[i].get<double>()) > 1e30)
        fail_at(fmt::format("{}[{}]", key_path(key), i), fmt::format("expected a finite number, got {}", json_type_name(v[i])));
      r[i] = float(v[i].get<double>());
    }
    return r;
  }
  // A direction: non-zero and finite; returned normalised.
  Vec3 direction(std::string_view key, const Vec3& def, bool required = false) {
    const bool given = has(key);
    const Vec3 v = vec3(key, def, required);
    const float len = glm::length(v);
    if (!(len > 1e-20f) || !std::isfinite(len)) {
      if (given) fail(key, fmt::format("expected a non-zero direction, got [{}, {}, {}]", v.x, v.y, v.z));
    }
    return v / len;
  }
  // A colour: one number (grey) or [r, g, b], each finite and >= 0.
  RGB color(std::string_view key, const RGB& def, bool required = false) {
    if (!has(key)) {
      if (required) fail(key, "missing (required): expected a colour (a number >= 0 or [r, g, b])");
      return def;
    }
    const json& v = obj_.at(std::string(key));
    const auto ok = [](const json& x) {
      return x.is_number() && std::isfinite(x.get<double>()) && x.get<double>() >= 0.0 && x.get<double>() < 1e30;
    };
    if (ok(v)) return RGB(float(v.get<double>()));
    if (!v.is_array() || v.size() != 3)
      fail(key, fmt::format("expected a colour (a number >= 0 or [r, g, b]), got {}", json_type_name(v)));
    RGB c;
    for (int i = 0; i < 3; ++i) {
      if (!ok(v[i]))
        fail_at(fmt::format("{}[{}]", key_path(key), i),
                fmt::format("expected a finite number >= 0, got {}", json_type_name(v[i])));
      c[i] = float(v[i].get<double>());
    }
    return c;
  }
  std::string choice(std::string_view key, std::initializer_list<std::string_view> allowed, bool required,
                     std::string_view def = "") {
    if (!has(key)) {
      if (required) fail(key, fmt::format("missing (required): expected one of {}", list(allowed)));
      return std::string(def);
    }
    const json& v = obj_.at(std::string(key));
    if (v.is_string())
      for (auto a : allowed)
        if (v.get<std::string>() == a) return std::string(a);
    fail(key, fmt::format("expected one of {}, got {}", list(allowed), json_type_name(v)));
  }
  std::string string(std::string_view key, bool required = true) {
    if (!has(key)) {
      if (required) fail(key, "missing (required): expected a string");
      return {};
    }
    const json& v = obj_.at(std::string(key));
    if (!v.is_string() || v.get<std::string>().empty())
      fail(key, fmt::format("expected a non-empty string, got {}", json_type_name(v)));
    return v.get<std::string>();
  }

  // Free text: optional, any string (empty included), but a string.
  std::string text(std::string_view key) {
    if (!has(key)) return {};
    const json& v = obj_.at(std::string(key));
    if (!v.is_string()) fail(key, fmt::format("expected a string (free text), got {}", json_type_name(v)));
    return v.get<std::string>();
  }

  void finish() const {
    for (const auto& [k, v] : obj_.items()) {
      if (known_.count(k)) continue;
      std::string allowed;
      for (const auto& a : known_) allowed += (allowed.empty() ? "" : ", ") + a;
      fail(k, fmt::format("unknown key; allowed here: {}", allowed));
    }
  }
  const std::string& path() const { return path_; }
  const std::string& source() const { return source_; }

 private:
  static std::string list(std::initializer_list<std::string_view> allowed) {
    std::string s;
    for (auto a : allowed) s += fmt::format("{}\"{}\"", s.empty() ? "" : ", ", a);
    return s;
  }
  const json& obj_;
  std::string source_, path_;
  std::set<std::string> known_;
};

std::string resolve_path(const std::string& file, const std::string& base_dir) {
  const fs::path p(file);
  if (p.is_absolute() || base_dir.empty()) return file;
  return (fs::path(base_dir) / p).string();
}

Camera read_camera(Node n) {
  Camera c;
  c.position = n.vec3("position", c.position, true);
  c.look_at = n.vec3("look_at", c.look_at, true);
  c.up = n.direction("up", c.up);
  c.fov_deg = n.number("fov_deg", c.fov_deg, 0.0f, 179.0f, false, true);
  n.finish();
  const Vec3 fwd = c.look_at - c.position;
  if (!(glm::length(fwd) > 0.0f)) n.fail("look_at", "must differ from position");
  if (glm::length(glm::cross(glm::normalize(fwd), c.up)) < 1e-4f) n.fail("up", "must not be parallel to the viewing direction");
  return c;
}

Environment read_environment(Node n, const std::string& base_dir) {
  const std::string type = n.choice("type", {"uniform", "sky", "map"}, true);
  Environment env;
  if (type == "uniform") {
    env = Environment::uniform(n.color("radiance", RGB(1.0f), true));
  } else if (type == "sky") {
    SkyParams p;
    p.sun_to = n.direction("sun_to", p.sun_to);
    p.sun_radiance = n.color("sun_radiance", p.sun_radiance);
    p.sun_radius_deg = n.number("sun_radius_deg", p.sun_radius_deg, 0.05, 45.0);
    p.zenith = n.color("zenith", p.zenith);
    p.horizon = n.color("horizon", p.horizon);
    p.ground = n.color("ground", p.ground);
    p.resolution = n.integer("resolution", p.resolution, 16, 8192);
    env = Environment::sky(p);
  } else {
    const std::string file = n.string("file");
    const float scale = n.number("scale", 1.0, 0.0, 1e12);
    const float rotation = n.number("rotation_deg", 0.0f, -360.0f, 360.0f);
    Image img = read_image(resolve_path(file, base_dir), fmt::format("{}: {}", n.source(), n.key_path("file")));
    env = Environment::from_image(std::move(img), scale, rotation);
  }
  n.finish();
  return env;
}

Light read_light(Node n) {
  Light l;
  const std::string type = n.choice("type", {"point", "directional", "sphere"}, true);
  if (type == "point") {
    l.kind = LightKind::Point;
    l.position = n.vec3("position", l.position, true);
    l.power = n.color("intensity", RGB(0.0f), true);
  } else if (type == "directional") {
    l.kind = LightKind::Directional;
    l.to_light = n.direction("to_light", l.to_light, true);
    l.power = n.color("irradiance", RGB(0.0f), true);
  } else {
    l.kind = LightKind::Sphere;
    l.position = n.vec3("center", l.position, true);
    l.radius = n.number("radius", 1.0f, 0.0f, 1e15, true, true);
    l.power = n.color("radiance", RGB(0.0f), true);
  }
  n.finish();
  return l;
}

TangentMap read_tangent_map(const std::string& file, const std::string& encoding, const std::string& where) {
  const Image img = read_image(file, where, /*linear_8bit=*/true);
  TangentMap m;
  m.width = img.width;
  m.height = img.height;
  m.doubled.resize(size_t(img.width) * size_t(img.height));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const RGB c = img.at(x, y);
      // The encodings are defined on [0, 1] (docs/scenes.md); float formats (PFM, EXR, HDR) can
      // hold anything, and a value such as 1e26 overflowed the doubled-angle filter to NaN (found
      // by fuzz/fuzz_tangent_map.cpp).
      const int channels = encoding == "angle" ? 1 : 2;
      for (int k = 0; k < channels; ++k)
        if (!(c[k] >= 0.0f && c[k] <= 1.0f))
          throw InputError(fmt::format("{}: {}: texel ({}, {}): {} channel is {}; a tangent map holds numbers in [0, 1]", where,
                                       file, x, y, k == 0 ? "red" : "green", c[k]));
      const Vec2 d = encoding == "angle" ? TangentMap_DecodeAngle(c.x) : TangentMap_DecodeXY(c.x, c.y);
      // Below 1e-3 (a quarter of one 8-bit step from the (0.5, 0.5) centre) the direction of an xy
      // texel is quantisation noise, not a tangent.
      if (!(glm::length(d) > 1e-3f) || !std::isfinite(d.x) || !std::isfinite(d.y))
        throw InputError(
            fmt::format("{}: {}: texel ({}, {}) encodes a zero-length or non-finite tangent "
                        "(xy encoding: red and green must not both be 0.5)",
                        where, file, x, y));
      m.doubled[size_t(y) * size_t(img.width) + size_t(x)] = TangentMap_ToDoubled(d);
    }
  return m;
}

// The mesh's smooth per-vertex UV tangents: per triangle, dp/du from the UV gradient (Lengyel
// 2001, "Computing Tangent Space Basis Vectors"), weighted by the corner angle and summed at the
// vertices as MikkTSpace does (Mikkelsen 2008), then made orthogonal to the vertex normal.
void compute_uv_tangents(Mesh& m) {
  m.tangents.assign(m.positions.size(), Vec3(0.0f));
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const uint32_t i[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
    const Vec3 e1 = m.positions[i[1]] - m.positions[i[0]], e2 = m.positions[i[2]] - m.positions[i[0]];
    const Vec2 d1 = m.uvs[i[1]] - m.uvs[i[0]], d2 = m.uvs[i[2]] - m.uvs[i[0]];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::fabs(det) > 0.0f)) continue;  // degenerate UVs: this triangle has no u direction
    const Vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = m.positions[i[(c + 1) % 3]] - m.positions[i[c]];
      const Vec3 b = m.positions[i[(c + 2) % 3]] - m.positions[i[c]];
      const float la = glm::length(a), lb = glm::length(b);
      if (!(la > 0.0f && lb > 0.0f)) continue;
      const float angle = std::acos(glm::clamp(glm::dot(a, b) / (la * lb), -1.0f, 1.0f));
      m.tangents[i[c]] += angle * dpdu;
    }
  }
  for (size_t v = 0; v < m.tangents.size(); ++v) {
    const Vec3 n = m.normals[v];
    const Vec3 t = m.tangents[v] - glm::dot(m.tangents[v], n) * n;
    const float len = glm::length(t);
    m.tangents[v] = len > 1e-12f ? t / len : Vec3(0.0f);
  }
}

glm::mat3 rotation_xyz_deg(const Vec3& deg) {
  const Vec3 r = glm::radians(deg);
  const glm::mat3 rx(1, 0, 0, 0, std::cos(r.x), std::sin(r.x), 0, -std::sin(r.x), std::cos(r.x));
  const glm::mat3 ry(std::cos(r.y), 0, -std::sin(r.y), 0, 1, 0, std::sin(r.y), 0, std::cos(r.y));
  const glm::mat3 rz(std::cos(r.z), std::sin(r.z), 0, -std::sin(r.z), std::cos(r.z), 0, 0, 0, 1);
  return rz * ry * rx;  // X first, then Y, then Z
}

// Checks every number on the OBJ's "v", "vn" and "vt" lines and every index on its "f" lines
// before tinyobjloader reads them. tinyobjloader's parser turns text that is not a number ("v hello
// -1 0", "nan", "inf") into 0 and a missing coordinate ("v -1") into 0 without a word, so after it
// has read the file the mistake can no longer be told from a real 0. Its face indices go through
// atoi (tiny_obj_loader.h parseTriple): "1.5" is read as 1, 4294967297 and 9223372036854775808
// wrap to some int, and a "vt" or "vn" index past the last one only drops the mesh's UVs or
// normals. Numbers follow the CLI's rule (io/text_input.h: decimal, finite); "v" takes x y z [w] or
// x y z r g b (tinyobjloader's two forms, parseVertexWithColor), "vn" x y z, "vt" u [v [w]]. A face
// vertex is v, v/vt, v//vn or v/vt/vn, each a whole decimal number: 1 to the number of such
// elements in the file, or negative, counting back from the last one read before the face
// (Wavefront's relative indices, as tinyobjloader's fixIndex); a face has at least 3 vertices.
void check_obj_text(const std::string& file, const std::string& where) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: {}: cannot open ({})", where, file, std::strerror(errno)));
  std::string line;
  size_t line_no = 0;
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  // Elements read so far: v, vt, vn; and per kind the largest positive index a face names, with
  // where (checked against the whole file's count at the end: a face may name a later element).
  int64_t count[3] = {0, 0, 0};
  struct Largest {
    int64_t index = 0;
    size_t line_no = 0;
    std::string line, token;
  } largest[3];
  constexpr const char* kKind[3] = {"v", "vt", "vn"};
  const auto quote = [](std::string_view s, size_t n) { return text_escape(s.substr(0, n)); };
  while (std::getline(in, line)) {
    ++line_no;
    size_t i = 0;
    while (i < line.size() && is_space(line[i])) ++i;
    const auto fail = [&](const std::string& problem) {
      throw InputError(fmt::format("{}: {}: line {}: \"{}\": {}", where, file, line_no, quote(line, 80), problem));
    };
    const size_t comment = line.find('#', i);
    if (i < line.size() && line[i] == 'f' && i + 1 < line.size() && is_space(line[i + 1])) {
      const std::string_view rest =
          std::string_view(line).substr(i + 1, comment == std::string::npos ? std::string::npos : comment - i - 1);
      size_t j = 0, vertices = 0;
      while (true) {
        while (j < rest.size() && is_space(rest[j])) ++j;
        if (j == rest.size()) break;
        size_t end = j;
        while (end < rest.size() && !is_space(rest[end])) ++end;
        const std::string_view token = rest.substr(j, end - j);
        ++vertices;
        // Up to three parts separated by '/': v, vt (may be empty when vn follows), vn.
        size_t start = 0;
        for (int part = 0; part < 3 && start <= token.size(); ++part) {
          const size_t slash = token.find('/', start);
          const std::string_view text =
              token.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
          const bool last = slash == std::string_view::npos;
          if (part == 2 && !last)
            fail(fmt::format("vertex {} \"{}\": expected v, v/vt, v//vn or v/vt/vn", vertices, quote(token, 40)));
          if (!(part == 1 && text.empty() && !last)) {
            const auto bad = [&](const std::string& why) {
              fail(fmt::format("vertex {} \"{}\": {} index \"{}\": {}", vertices, quote(token, 40), kKind[part], quote(text, 40),
                               why));
            };
            std::string why;
            const std::optional<double> v = parse_decimal(text, &why);
            if (!v || *v != std::floor(*v) || text.find_first_of(".eE") != std::string_view::npos)
              bad("expected a whole decimal number (1 is the first element, -1 the last one read)");
            if (*v == 0) bad("expected a number from 1, or negative (0 is no element in OBJ)");
            if (*v < 0) {
              if (-*v > double(count[part]))
                bad(fmt::format("counts back past the first element: {} \"{}\" line{} before this face", count[part], kKind[part],
                                count[part] == 1 ? "" : "s"));
            } else if (*v > double(std::numeric_limits<int>::max())) {
              bad(fmt::format("above {} (the largest index this reader takes)", std::numeric_limits<int>::max()));
            } else if (int64_t(*v) > largest[part].index) {
              largest[part] = Largest{int64_t(*v), line_no, line.substr(0, 80), std::string(token.substr(0, 40))};
            }
          }
          if (last) break;
          start = slash + 1;
          if (part == 0 && start == token.size())
            fail(fmt::format("vertex {} \"{}\": expected an index after \"/\"", vertices, quote(token, 40)));
        }
        j = end;
      }
      if (vertices < 3) fail(fmt::format("a face needs at least 3 vertices, got {}", vertices));
      continue;
    }
    if (i >= line.size() || line[i] != 'v') continue;
    size_t k = i + 1;
    char kind = 'v';  // "v", "vn" or "vt"; any other word starting with v ("vp") is not checked
    if (k < line.size() && (line[k] == 'n' || line[k] == 't')) kind = line[k++];
    if (k < line.size() && !is_space(line[k])) continue;
    const char* name = kind == 'v' ? "v" : kind == 'n' ? "vn" : "vt";
    const char* layout = kind == 'v' ? "x y z [w], or x y z r g b" : kind == 'n' ? "x y z" : "u [v [w]]";
    const size_t min = kind == 't' ? 1 : 3, max = kind == 'v' ? 6 : 3;
    i = k;
    const std::string_view rest =
        std::string_view(line).substr(i, comment == std::string::npos ? std::string::npos : comment - i);
    size_t n = 0, j = 0;
    while (true) {
      while (j < rest.size() && is_space(rest[j])) ++j;
      if (j == rest.size()) break;
      size_t end = j;
      while (end < rest.size() && !is_space(rest[end])) ++end;
      std::string why;
      if (!parse_decimal(rest.substr(j, end - j), &why))
        fail(fmt::format("field {}: expected a finite decimal number, got \"{}\" ({})", n + 1,
                         text_escape(rest.substr(j, std::min<size_t>(end - j, 40))), why));
      ++n;
      j = end;
    }
    if (n < min || n > max || (kind == 'v' && n == 5))
      fail(fmt::format("expected the numbers of a \"{}\" line ({}), got {}", name, layout, n));
    ++count[kind == 'v' ? 0 : kind == 't' ? 1 : 2];
  }
  if (in.bad()) throw InputError(fmt::format("{}: {}: read error ({})", where, file, std::strerror(errno)));
  for (int part = 0; part < 3; ++part) {
    const Largest& l = largest[part];
    if (l.index > count[part])
      throw InputError(fmt::format("{}: {}: line {}: \"{}\": vertex \"{}\": {} index {}: the file has {} \"{}\" line{}", where,
                                   file, l.line_no, text_escape(l.line), text_escape(l.token), kKind[part], l.index, count[part],
                                   kKind[part], count[part] == 1 ? "" : "s"));
  }
}

std::shared_ptr<Mesh> load_obj(const std::string& file, const std::string& where) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(fmt::format("{}: {}: no such file", where, file));
  if (!fs::is_regular_file(file, ec)) throw InputError(fmt::format("{}: {}: not a regular file", where, file));
  if (const uintmax_t size = fs::file_size(file, ec); !ec && size > kMaxObjFileBytes)
    throw InputError(fmt::format("{}: {}: {} bytes: larger than {}, the limit for an OBJ file (docs/cli.md, \"Size limits\")",
                                 where, file, size, mib_text(kMaxObjFileBytes)));
  check_obj_text(file, where);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(file, cfg)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw InputError(fmt::format("{}: {}: cannot read the OBJ file: {}", where, file, err.empty() ? "unknown error" : err));
  }
  const auto& attrib = reader.GetAttrib();
  auto mesh = std::make_shared<Mesh>();
  std::map<std::tuple<int, int, int>, uint32_t> remap;
  bool all_normals = true, all_uvs = true;
  for (const auto& shape : reader.GetShapes()) {
    for (const auto& idx : shape.mesh.indices) {
      if (idx.vertex_index < 0 || size_t(idx.vertex_index) * 3 + 2 >= attrib.vertices.size())
        throw InputError(fmt::format("{}: {}: face refers to a vertex that does not exist", where, file));
      all_normals = all_normals && idx.normal_index >= 0 && size_t(idx.normal_index) * 3 + 2 < attrib.normals.size();
      all_uvs = all_uvs && idx.texcoord_index >= 0 && size_t(idx.texcoord_index) * 2 + 1 < attrib.texcoords.size();
    }
  }
  for (const auto& shape : reader.GetShapes()) {
    for (const auto& idx : shape.mesh.indices) {
      const auto key = std::make_tuple(idx.vertex_index, all_normals ? idx.normal_index : -1, all_uvs ? idx.texcoord_index : -1);
      auto [it, inserted] = remap.try_emplace(key, uint32_t(mesh->positions.size()));
      if (inserted) {
        const size_t v = size_t(idx.vertex_index);
        mesh->positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);
        if (all_normals) {
          const size_t k = size_t(idx.normal_index);
          mesh->normals.emplace_back(attrib.normals[3 * k], attrib.normals[3 * k + 1], attrib.normals[3 * k + 2]);
        }
        if (all_uvs) {
          const size_t k = size_t(idx.texcoord_index);
          mesh->uvs.emplace_back(attrib.texcoords[2 * k], attrib.texcoords[2 * k + 1]);
        }
      }
      mesh->indices.push_back(it->second);
    }
  }
  if (mesh->indices.empty()) throw InputError(fmt::format("{}: {}: the OBJ file has no faces", where, file));
  for (size_t i = 0; i < mesh->positions.size(); ++i) {
    const Vec3& p = mesh->positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(fmt::format("{}: {}: vertex {} is not finite", where, file, i + 1));
    if (!mesh->normals.empty()) {
      const float len = glm::length(mesh->normals[i]);
      if (!(len > 0.0f) || !std::isfinite(len))
        throw InputError(fmt::format("{}: {}: normal of vertex {} is zero or not finite", where, file, i + 1));
      mesh->normals[i] /= len;
    }
  }
  return mesh;
}

void transform_mesh(Mesh& m, const Vec3& translate, float scale, const Vec3& rotate_deg) {
  const glm::mat3 r = rotation_xyz_deg(rotate_deg);
  for (Vec3& p : m.positions) p = translate + r * (scale * p);
  for (Vec3& n : m.normals) n = glm::normalize(r * n);
  for (Vec3& t : m.tangents) t = r * t;
}

TangentSource read_tangent(Node n, const Object& obj, const std::string& base_dir) {
  TangentSource ts;
  TangentFieldT<float>& f = ts.field;
  f.angle = glm::radians(n.number("angle_deg", 0.0f, -360.0f, 360.0f));
  const bool has_field = n.has("field"), has_map = n.has("map");
  if (has_field && has_map) n.fail("map", "give either \"field\" or \"map\", not both");
  if (has_field) {
    const std::string kind = n.choice("field", {"projected", "radial", "concentric", "swirl", "noise", "uv"}, true);
    const Vec3 default_axis = obj.shape == ShapeKind::Disc || obj.shape == ShapeKind::Rectangle ? obj.normal : Vec3(0, 1, 0);
    if (kind == "projected") {
      f.kind = TangentFieldKind::Projected;
      f.direction = n.direction("direction", f.direction, true);
    } else if (kind == "radial" || kind == "concentric" || kind == "swirl") {
      f.kind = kind == "radial" ? TangentFieldKind::Radial
                                : (kind == "concentric" ? TangentFieldKind::Concentric : TangentFieldKind::Swirl);
      f.center = n.vec3("center", obj.center);
      f.axis = n.direction("axis", default_axis);
      if (kind == "swirl") f.swirl = glm::radians(n.number("swirl_deg", 45.0f, -90.0f, 90.0f));
    } else if (kind == "noise") {
      f.kind = TangentFieldKind::Noise;
      f.scale = n.number("scale", 1.0f, 0.0f, 1e6f, false, true);
      // strength k in [0, 1]: the largest rotation is k * 90 degrees (1 = every orientation).
      f.strength = n.number("strength", 0.5f, 0.0f, 1.0f) * kPiOver2<float>;
    } else {
      if (obj.shape != ShapeKind::Mesh) n.fail("field", "\"uv\" tangents need a mesh with UVs (shape \"mesh\")");
      if (obj.mesh->normals.empty() || obj.mesh->uvs.empty())
        n.fail("field", fmt::format("\"uv\" tangents need per-vertex normals and UVs; the mesh has {}",
                                    obj.mesh->normals.empty() && obj.mesh->uvs.empty() ? "neither"
                                    : obj.mesh->normals.empty()                        ? "no normals"
                                                                                       : "no UVs"));
      ts.uv_tangents = true;
    }
  } else if (has_map) {
    const std::string file = n.string("map");
    const std::string encoding = n.choice("encoding", {"angle", "xy"}, false, "angle");
    if (obj.shape == ShapeKind::Mesh && obj.mesh->uvs.empty())
      n.fail("map", "a tangent map needs a mesh with UVs; this mesh has none");
    ts.map = std::make_shared<TangentMap>(
        read_tangent_map(resolve_path(file, base_dir), encoding, fmt::format("{}: {}", n.source(), n.key_path("map"))));
  }
  n.finish();
  return ts;
}

Object read_object(Node n, const std::string& base_dir) {
  Object o;
  const std::string shape = n.choice("shape", {"sphere", "disc", "rectangle", "mesh", "torus"}, true);
  if (shape == "sphere") {
    o.shape = ShapeKind::Sphere;
    o.center = n.vec3("center", o.center, true);
    o.radius = n.number("radius", 1.0f, 0.0f, 1e15, true, true);
  } else if (shape == "disc") {
    o.shape = ShapeKind::Disc;
    o.center = n.vec3("center", o.center, true);
    o.normal = n.direction("normal", o.normal, true);
    o.radius = n.number("radius", 1.0f, 0.0f, 1e15, true, true);
  } else if (shape == "rectangle") {
    o.shape = ShapeKind::Rectangle;
    o.center = n.vec3("center", o.center, true);
    o.normal = n.direction("normal", o.normal, true);
    const Vec3 u = n.direction("u", Vec3(1, 0, 0), true);
    const Vec3 u_perp = u - glm::dot(u, o.normal) * o.normal;
    if (glm::length(u_perp) < 1e-4f) n.fail("u", "must not be parallel to \"normal\"");
    o.u_axis = glm::normalize(u_perp);
    // At most 1e15, as every other length (radius, scale): 1e39 is finite in the JSON's double
    // but infinite in the renderer's float.
    const json& s = n.get("size");
    const auto side_ok = [](const json& x) { return x.is_number() && x.get<double>() > 0.0 && x.get<double>() <= 1e15; };
    if (!s.is_array() || s.size() != 2 || !side_ok(s[0]) || !side_ok(s[1]))
      n.fail("size", fmt::format("expected [width, height], two numbers in (0, 1e15], got {}", json_type_name(s)));
    o.size = Vec2(float(s[0].get<double>()), float(s[1].get<double>()));
  } else if (shape == "torus") {
    o.shape = ShapeKind::Mesh;
    o.center = n.vec3("center", o.center, true);
    const float major = n.number("major_radius", 1.0f, 0.0f, 1e15, false, true);
    const float minor = n.number("minor_radius", 0.35f, 0.0f, 1e15, false, true);
    if (!(minor < major)) n.fail("minor_radius", "must be smaller than major_radius");
    auto mesh = make_torus(Vec3(0.0f), major, minor, 192, 64);
    transform_mesh(*mesh, o.center, 1.0f, n.vec3("rotate_deg", Vec3(0.0f)));
    o.mesh = mesh;
  } else {
    o.shape = ShapeKind::Mesh;
    const std::string file = n.string("file");
    const Vec3 translate = n.vec3("translate", Vec3(0.0f));
    const float scale = n.number("scale", 1.0f, 0.0f, 1e15, false, true);
    const Vec3 rot = n.vec3("rotate_deg", Vec3(0.0f));
    auto mesh = load_obj(resolve_path(file, base_dir), fmt::format("{}: {}", n.source(), n.key_path("file")));
    transform_mesh(*mesh, translate, scale, rot);
    o.center = translate;
    o.mesh = mesh;
  }
  o.material = resolve_material(n.get("material"), fmt::format("{}: {}", n.source(), n.key_path("material")), base_dir,
                                &o.material_name, &o.material_desc);
  if (n.has("tangent")) {
    o.tangent = read_tangent(Node(n.get("tangent"), n.source(), n.key_path("tangent")), o, base_dir);
    if (o.tangent.uv_tangents) compute_uv_tangents(*std::const_pointer_cast<Mesh>(o.mesh));
  }
  n.text("name");  // a label, free text (the gallery uses it)
  n.finish();
  return o;
}

}  // namespace

Material resolve_material(const json& m, const std::string& where, const std::string& base_dir, std::string* display_name,
                          std::shared_ptr<const MaterialDesc>* desc) {
  const auto build = [&](MaterialDesc d) {
    auto shared = std::make_shared<const MaterialDesc>(std::move(d));
    if (desc) *desc = shared;
    return build_material<float>(*shared);
  };
  try {
    if (m.is_string()) {
      const std::string name = m.get<std::string>();
      if (display_name) *display_name = name;
      if (find_preset(name)) return build(load_material(name));
      return build(load_material(resolve_path(name, base_dir)));
    }
    if (m.is_object()) {
      if (display_name) *display_name = m.value("model", std::string("material"));
      return build(parse_material(m, "material", base_dir));
    }
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
  throw InputError(
      fmt::format("{}: expected a preset name, a JSON file name or a material object, got {}", where, json_type_name(m)));
}

Vec2 TangentMap::lookup(const Vec2& uv) const {
  // Texel centres at (i + 0.5) / width; v up, row 0 at v = 1; wrap-around (repeat).
  const float fx = uv.x * float(width) - 0.5f, fy = (1.0f - uv.y) * float(height) - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  const int x0 = wrap(int(x0f), width), y0 = wrap(int(y0f), height);
  const int x1 = wrap(x0 + 1, width), y1 = wrap(y0 + 1, height);
  const auto at = [&](int x, int y) { return doubled[size_t(y) * size_t(width) + size_t(x)]; };
  const Vec2 q = (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) + ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
  return TangentMap_FromDoubled(q);
}

std::shared_ptr<Mesh> make_torus(const Vec3& center, float R, float r, int nu, int nv) {
  auto m = std::make_shared<Mesh>();
  // u goes around the major circle (about +y), v around the tube; seams duplicated so UVs are continuous.
  for (int j = 0; j <= nv; ++j) {
    const float v = float(j) / float(nv), phi = 2.0f * kPi<float> * v;
    for (int i = 0; i <= nu; ++i) {
      const float u = float(i) / float(nu), theta = 2.0f * kPi<float> * u;
      const Vec3 dir(std::cos(theta), 0.0f, -std::sin(theta));  // about +y, counter-clockwise from above
      const Vec3 n = std::cos(phi) * dir + std::sin(phi) * Vec3(0, 1, 0);
      m->positions.push_back(center + R * dir + r * n);
      m->normals.push_back(n);
      m->uvs.emplace_back(u, v);
      m->tangents.push_back(Vec3(-std::sin(theta), 0.0f, -std::cos(theta)));  // d dir / d theta
    }
  }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1), d = c + 1;
      m->indices.insert(m->indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

void resize_film(Film& film, int width, int height) {
  const double aspect = double(film.width) / double(film.height);
  if (width > 0) film.width = width;
  if (height > 0) film.height = height;
  if (width > 0 && height == 0) film.height = std::clamp(int(std::lround(width / aspect)), 1, 16384);
  if (height > 0 && width == 0) film.width = std::clamp(int(std::lround(height * aspect)), 1, 16384);
}

Scene parse_scene(const json& doc, const std::string& source, const std::string& base_dir) {
  Node top(doc, source, "");
  Scene s;
  s.source = source;
  s.camera = read_camera(Node(top.get("camera"), source, "camera"));
  if (top.has("film")) {
    Node f(top.get("film"), source, "film");
    s.film.width = f.integer("width", s.film.width, 1, 16384);
    s.film.height = f.integer("height", s.film.height, 1, 16384);
    s.film.spp = f.integer("spp", s.film.spp, 1, 1 << 20);
    s.film.noise_threshold = f.number("noise_threshold", s.film.noise_threshold, 0.0f, 1.0f);
    s.film.min_spp = f.integer("min_spp", s.film.min_spp, 0, 1 << 20);
    s.film.time_s = f.number("time_s", s.film.time_s, 0.0f, 1e6f);
    f.finish();
  }
  if (top.has("integrator")) {
    Node in(top.get("integrator"), source, "integrator");
    s.integrator.max_depth = in.integer("max_depth", s.integrator.max_depth, 1, 1024);
    const std::string st = in.choice("strategy", {"mis", "bsdf", "light"}, false, "mis");
    s.integrator.strategy = st == "bsdf" ? Strategy::Bsdf : (st == "light" ? Strategy::Light : Strategy::Mis);
    const std::string sm = in.choice("sampler", {"sobol", "independent"}, false, "sobol");
    s.integrator.sampler = sm == "independent" ? SamplerKind::Independent : SamplerKind::Sobol;
    const std::string ls = in.choice("light_selection", {"auto", "power", "all"}, false, "auto");
    s.integrator.light_selection =
        ls == "all" ? LightSelection::All : (ls == "power" ? LightSelection::Power : LightSelection::Auto);
    s.integrator.clamp = in.number("clamp", s.integrator.clamp, 0.0f, 1e30f);
    s.integrator.filter_glossy = in.number("filter_glossy", s.integrator.filter_glossy, 0.0f, 100.0f);
    in.finish();
  }
  if (top.has("environment")) s.environment = read_environment(Node(top.get("environment"), source, "environment"), base_dir);
  if (top.has("lights")) {
    const json& ls = top.get("lights");
    if (!ls.is_array()) top.fail("lights", fmt::format("expected an array, got {}", json_type_name(ls)));
    for (size_t i = 0; i < ls.size(); ++i) s.lights.push_back(read_light(Node(ls[i], source, fmt::format("lights[{}]", i))));
  }
  const json& objs = top.get("objects");
  if (!objs.is_array()) top.fail("objects", fmt::format("expected an array, got {}", json_type_name(objs)));
  for (size_t i = 0; i < objs.size(); ++i)
    s.objects.push_back(read_object(Node(objs[i], source, fmt::format("objects[{}]", i)), base_dir));
  top.text("name");
  top.text("description");
  top.finish();
  return s;
}

Scene load_scene(const std::string& path) {
  return parse_scene(parse_json_text(read_text_file(path, "a scene file"), path), path, fs::path(path).parent_path().string());
}

}  // namespace aniso::render
