// apps/aniso/cmd_web.cpp: the browser explorer's two commands (docs/web.md).
//   aniso web-data -o FILE   the data the page is built from, generated from the sources of truth:
//                            the parameter tables (src/io/params.cpp) with their range texts, the
//                            presets, the metals, the GLSL library (the files export-glsl
//                            assembles), the GLSL tone map (render::tonemap's twin) and, per material shape, the GLSL builder of
//                            gl::glsl_material() with uniforms; written as one JavaScript
//                            assignment so that the page also works opened from file://.
//   aniso serve [--port P]   a static server for the built page on 127.0.0.1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "aniso/data/metals.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "aniso/version.h"
#include "commands.h"
#include "io/enum_names.h"

namespace aniso {
namespace {

using nlohmann::json;

// A number for JSON: NaN ("no default") is null.
json number(double x) { return std::isnan(x) ? json(nullptr) : json(x); }

json table_json(const ModelSpec& spec) {
  json t = {{"name", spec.name}, {"title", spec.title}, {"citation", spec.citation}, {"params", json::array()}};
  for (const ParamSpec* p : spec.params()) {
    json j = {{"name", p->name},
              {"kind", std::string(enum_name(p->kind))},
              {"doc", p->doc},
              {"min", p->min},
              {"max", p->max},
              {"min_exclusive", p->min_exclusive},
              {"default", number(p->default_value)},
              {"required", p->required},
              {"range", describe_range(*p)},  // the text of the reader's "expected ..." messages
              {"default_text", default_text(*p)}};
    json choices = json::array();
    for (auto c : p->choices) choices.push_back(c);
    j["choices"] = choices;
    if (p->kind == ParamKind::List) j["max_items"] = p->max_items;
    if (!p->partner.empty()) j["partner"] = p->partner;
    if (!p->sets[0].empty()) j["sets"] = {p->sets[0], p->sets[1]};
    if (p->kind == ParamKind::Object || p->kind == ParamKind::List) j["sub"] = table_json(*p->sub);
    if (p->kind == ParamKind::TaggedObject) {
      j["subs"] = json::object();
      for (const ModelSpec* s : nested_specs(*p)) j["subs"][std::string(s->name)] = table_json(*s);
    }
    t["params"].push_back(j);
  }
  return t;
}

// A value inside a key's range, for the example materials of the shapes below.
double inside(const ParamSpec& p) {
  if (!std::isnan(p.default_value)) return p.default_value;
  const double x = std::clamp(1.0, p.min, p.max);
  return p.min_exclusive && x <= p.min ? 0.5 * (p.min + p.max) : x;
}

// Every structural variant of a table: each tagged object's models, each optional object absent
// and present, each list from 1 to max_items items (with default keys). `fill` also gives the
// optional keys that have no default a value (a metal's eta and k).
std::vector<json> variants(const ModelSpec& spec, bool fill) {
  std::vector<json> out = {json::object()};
  for (const ParamSpec* p : spec.params()) {
    if (!p->sets[0].empty()) continue;  // shorthands: their halves are set
    std::vector<json> options;          // the values this key takes; null: absent
    switch (p->kind) {
      case ParamKind::Scalar:
        if (p->required || (fill && std::isnan(p->default_value))) options.push_back(inside(*p));
        break;
      case ParamKind::Color:
        if (p->required || (fill && std::isnan(p->default_value))) options.push_back(inside(*p));
        break;
      case ParamKind::Object:
        options.push_back(nullptr);
        for (const json& v : variants(*p->sub, fill)) options.push_back(v);
        break;
      case ParamKind::TaggedObject:
        for (const ModelSpec* s : nested_specs(*p))
          for (json v : variants(*s, fill)) {
            v["model"] = s->name;
            options.push_back(v);
          }
        break;
      case ParamKind::List: {
        const std::vector<json> items = variants(*p->sub, fill);
        for (int n = 1; n <= p->max_items; ++n) options.push_back(json::array_t(size_t(n), items.front()));
        break;
      }
      default: break;
    }
    if (options.empty()) continue;
    std::vector<json> next;
    for (const json& base : out)
      for (const json& o : options) {
        json v = base;
        if (!o.is_null()) v[std::string(p->name)] = o;
        next.push_back(v);
      }
    out = std::move(next);
  }
  return out;
}

// The shape of a material: which tagged models, which optional objects and how many list items;
// the page computes the same key from its material (web/explorer.js, shapeKey) to pick the GLSL.
void shape_parts(const ModelSpec& spec, const ParamValues& pv, const std::string& path, std::vector<std::string>& parts) {
  for (const ParamSpec* p : spec.params()) {
    const std::string key = path + std::string(p->name);
    if (p->kind == ParamKind::Object) {
      parts.push_back(fmt::format("{}={}", key, pv.has(p->name) ? 1 : 0));
      if (pv.has(p->name)) shape_parts(*p->sub, pv.object(p->name), key + ".", parts);
    } else if (p->kind == ParamKind::TaggedObject && pv.has(p->name)) {
      const ParamValues& o = pv.object(p->name);
      parts.push_back(fmt::format("{}={}", key, o.text("model")));
      shape_parts(metal_lobe_spec(o.text("model")), o, key + ".", parts);
    } else if (p->kind == ParamKind::List && pv.has(p->name)) {
      const auto& items = pv.list(p->name);
      parts.push_back(fmt::format("{}={}", key, items.size()));
    }
  }
}

std::string shape_key(const MaterialDesc& d) {
  std::vector<std::string> parts;
  shape_parts(*find_model_spec(d.model), d.params, "", parts);
  std::string k = d.model;
  for (const std::string& p : parts) k += "|" + p;
  return k;
}

const char* slot_type(gl::GlslSlot::Type t) {
  switch (t) {
    case gl::GlslSlot::Type::Float: return "float";
    case gl::GlslSlot::Type::Vec3: return "vec3";
    case gl::GlslSlot::Type::Bool: return "bool";
    case gl::GlslSlot::Type::Int: return "int";
  }
  return "float";
}

json web_data() {
  json data = {{"generator", "aniso " ANISO_VERSION " web-data (apps/aniso/cmd_web.cpp)"}, {"version", ANISO_VERSION}};
  data["models"] = json::array();
  for (const ModelSpec* m : model_specs()) data["models"].push_back(table_json(*m));
  data["metals"] = json::array();
  for (const MetalData& md : metal_table())
    data["metals"].push_back({{"name", md.name}, {"eta", {md.eta.x, md.eta.y, md.eta.z}}, {"k", {md.k.x, md.k.y, md.k.z}}});
  data["metal_names"] = metal_names();
  data["presets"] = json::array();
  for (const PresetInfo& p : presets()) data["presets"].push_back({{"name", p.name}, {"source", p.source}, {"material", p.json}});
  const std::string lib = gl::glsl_library_source();
  // The tone map (the twin of render::tonemap) beside the library, for the page's display pass.
  data["glsl"] = {{"library", lib},
                  {"library_prefixed", gl::glsl_prefix_names(lib, "aniso_")},
                  {"tonemap", std::string(gl::glsl_tonemap_source())}};
  // One GLSL builder per shape, with uniforms named u_<slot> (the page sets them from its material).
  json shapes = json::object();
  std::vector<std::string> no_glsl;
  for (const ModelSpec* m : model_specs()) {
    bool any = false;
    for (bool fill : {false, true}) {
      for (json v : variants(*m, fill)) {
        v["model"] = m->name;
        MaterialDesc d;
        try {
          d = parse_material(v, "shape");
        } catch (const InputError&) {
          continue;  // a variant the cross-key rules refuse (a metal without eta, k): the filled one serves
        }
        gl::GlslMaterial g;
        try {
          g = gl::glsl_material(d, gl::GlslStorage::Uniform, "u_");
        } catch (const InputError&) {
          continue;  // measured: no GLSL form
        }
        const gl::GlslMaterial c = gl::glsl_material(d, gl::GlslStorage::Const, "aniso_p_");
        json slots = json::array();
        for (const gl::GlslSlot& s : g.slots)
          slots.push_back({{"name", s.name}, {"key", s.table_key}, {"type", slot_type(s.type)}});
        shapes[shape_key(d)] = {
            {"slots", slots},
            {"declarations", g.declarations},
            {"code", g.code},
            {"code_prefixed", gl::glsl_prefix_names(c.code, "aniso_")},
            {"brdf_code", gl::glsl_prefix_names(gl::glsl_material(d, gl::GlslStorage::BrdfExplorer, "").code, "aniso_")}};
        any = true;
      }
    }
    if (!any) no_glsl.emplace_back(m->name);
  }
  data["shapes"] = shapes;
  data["no_glsl"] = no_glsl;
  return data;
}

// --- serve -------------------------------------------------------------------------------------
// A minimal HTTP/1.0 GET server on 127.0.0.1 for the static page. Hand-written on POSIX sockets:
// Debian has no maintained C++ HTTP server library packaged for this (cpp-httplib is not in
// Debian 12; libmicrohttpd would do but adds a dependency for ~100 lines of static file serving).
// It serves only the files directly in the page's folder (no subfolders, no "..").

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_stop(int) { g_stop = 1; }

std::string content_type(const std::string& name) {
  const auto ends = [&](std::string_view s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".json")) return "application/json";
  if (ends(".png")) return "image/png";
  return "application/octet-stream";
}

void send_all(int fd, const std::string& s) {
  size_t off = 0;
  while (off < s.size()) {
    const ssize_t n = ::send(fd, s.data() + off, s.size() - off, MSG_NOSIGNAL);
    if (n <= 0) return;  // the client went away: nothing to do
    off += size_t(n);
  }
}

void respond(int fd, const std::filesystem::path& root) {
  std::string req;
  char buf[2048];
  while (req.find("\r\n") == std::string::npos && req.size() < 8192) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) return;
    req.append(buf, size_t(n));
  }
  std::istringstream line(req.substr(0, req.find("\r\n")));
  std::string method, target;
  line >> method >> target;
  const auto status = [&](const char* code, const std::string& body) {
    send_all(fd, fmt::format("HTTP/1.0 {}\r\nContent-Type: text/plain\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}", code,
                             body.size(), body));
  };
  if (method != "GET" && method != "HEAD") return status("405 Method Not Allowed", "only GET\n");
  std::string name = target.substr(0, target.find_first_of("?#"));
  if (name == "/") name = "/index.html";
  name = name.substr(1);
  if (name.empty() || name.find('/') != std::string::npos || name.find("..") != std::string::npos || name[0] == '.')
    return status("404 Not Found", "not found\n");
  std::ifstream in(root / name, std::ios::binary);
  if (!in) return status("404 Not Found", "not found\n");
  const std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  send_all(fd, fmt::format("HTTP/1.0 200 OK\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-cache\r\n"
                           "Connection: close\r\n\r\n",
                           content_type(name), body.size()));
  if (method == "GET") send_all(fd, body);
}

void serve(const std::string& root_arg, int port) {
  namespace fs = std::filesystem;
  fs::path root = root_arg;
  if (root.empty()) {
    // The page built beside the binary: build/<preset>/bin/aniso serves build/<preset>/web; an
    // installed one (cmake/install.cmake) serves <prefix>/share/aniso/web.
    const fs::path prefix = fs::read_symlink("/proc/self/exe").parent_path().parent_path();
    root = fs::is_regular_file(prefix / "web" / "index.html") ? prefix / "web" : prefix / "share" / "aniso" / "web";
  }
  if (!fs::is_regular_file(root / "index.html"))
    throw InputError(
        fmt::format("--root {}: no index.html (build the page: cmake --build ... --target aniso_web)", root.string()));
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error(fmt::format("socket: {}", std::strerror(errno)));
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // 127.0.0.1 only: nothing outside this machine
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    throw InputError(fmt::format("--port {}: cannot listen on 127.0.0.1:{}: {}", port, port, std::strerror(err)));
  }
  ::listen(fd, 16);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  fmt::print("aniso serve: http://127.0.0.1:{}/ (serving {}; Ctrl-C stops)\n", ntohs(addr.sin_port), root.string());
  std::fflush(stdout);
  struct sigaction sa {};
  sa.sa_handler = on_stop;  // no SA_RESTART: accept() returns EINTR
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  while (!g_stop) {
    const int c = ::accept(fd, nullptr, nullptr);
    if (c < 0) continue;
    timeval tv{5, 0};  // a client that sends nothing does not hold the server
    ::setsockopt(c, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    respond(c, root);
    ::close(c);
  }
  ::close(fd);
}

}  // namespace

void add_web_commands(CLI::App& app) {
  auto* data =
      app.add_subcommand("web-data", "write the browser explorer's generated data (tables, presets, GLSL) as JavaScript");
  static std::string out;
  data->add_option("-o,--output", out, "output file (default stdout)");
  data->callback([] {
    run_command([] {
      write_atomically(out, "// Generated by `aniso web-data`; do not edit.\nwindow.ANISO_DATA = " + web_data().dump() + ";\n");
    });
  });
  auto* srv = app.add_subcommand("serve", "serve the browser explorer (docs/web.md) on 127.0.0.1");
  static int port = 8047;
  static std::string root;
  srv->add_option("--port", port, "TCP port (0: any free port; default 8047)")->check(CLI::Range(0, 65535));
  srv->add_option("--root", root, "the built page's folder (default: <build>/web beside the binary)");
  srv->callback([] { run_command([] { serve(root, port); }); });
}

}  // namespace aniso
