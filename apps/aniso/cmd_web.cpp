// apps/aniso/cmd_web.cpp: the browser explorer's two commands (docs/web.md).
//   aniso web-data -o FILE   the data the page is built from, generated from the sources of truth:
//                            the parameter tables (src/models/<member>.h) with their range texts and rules, the
//                            presets, the metals, the GLSL library (the files export-glsl
//                            assembles), the GLSL tone map (render::tonemap's twin) and, per material shape, the GLSL builder of
//                            gl::glsl_material() with uniforms, the measured tables' layout and
//                            readers' limits (web/measured.js); written as one JavaScript
//                            assignment so that the page also works opened from file://.
//   aniso serve [--port P]   a static server for the built page on 127.0.0.1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/data/metals.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "aniso/io/materials.h"
#include "aniso/io/presets.h"
#include "aniso/measured/measured.h"
#include "aniso/measured/merl.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/version.h"
#include "commands.h"
#include "io/enum_names.h"
#include "io/json_read.h"

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
  // The cross-key rules (ParamRule), applied by web/validate.js applyRule as by the C++ reader.
  t["rules"] = json::array();
  for (const ParamRule& r : spec.rules) {
    json keys = json::array();
    for (const std::string_view k : r.keys)
      if (!k.empty()) keys.push_back(k);
    t["rules"].push_back({{"kind", std::string(enum_name(r.kind))},
                          {"key", r.key},
                          {"keys", keys},
                          {"message", r.message},
                          {"exponent", r.exponent},
                          {"scale", r.scale},
                          {"limit", r.limit}});
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

// What the page's reader of measured files (web/measured.js) takes from the C++: the tables
// texture (gl::glsl_tables, docs/glsl.md "Measured materials"), MERL's layout and scales
// (measured/merl.h), the sampling tables' resolution (measured/measured.h), and the limits and
// texts of the readers' messages (rgl/rgl_material.h, measured/merl.h, io/json_read.h).
json measured_json() {
  json files = json::array();
  for (const ModelSpec* m : model_specs())
    if (m->find("file")) files.push_back(m->name);
  return {{"models", files},
          {"tables",
           {{"width", gl::kGlslTablesWidth}, {"max_floats", gl::kGlslTablesMaxFloats}, {"sampler", gl::kGlslTablesSampler}}},
          {"merl",
           {{"theta_h", MerlLayout::kThetaH},
            {"theta_d", MerlLayout::kThetaD},
            {"phi_d", MerlLayout::kPhiD},
            {"scale", MerlBrdf::kScale},
            {"file_bytes", MerlBrdf::kFileBytes},
            {"max_stored", MerlBrdf::kMaxStored},
            {"theta_o_bins", kMeasuredThetaOBins},
            {"phi_h_bins", kMeasuredPhiHBins},
            {"uniform_fraction", MeasuredT<float>{}.uniform_fraction}}},
          {"rgl",
           {{"max_file_bytes", kMaxTensorFileBytes},
            {"max_file_text", mib_text(kMaxTensorFileBytes)},
            {"rounding_noise_ulps", rgl::kRoundingNoiseUlps},
            {"max_table_value", rgl::kMaxTableValue},
            {"min_sigma", rgl::kMinSigma}}}};
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
        if (m->find("file")) {
          // A measured model: its material is a file, which the page reads itself (web/measured.js)
          // into the tables texture; its GLSL builder needs only the model (glsl_material does not
          // open the file, glsl_tables does).
          d.model = std::string(m->name);
          d.params.where = "shape";
          d.params.values["file"] = std::string();
        } else {
          try {
            d = parse_material(v, "shape");
          } catch (const InputError&) {
            continue;  // a variant the cross-key rules refuse (a metal without eta, k): the filled one serves
          }
        }
        gl::GlslMaterial g;
        try {
          g = gl::glsl_material(d, gl::GlslStorage::Uniform, "u_");
        } catch (const InputError&) {
          continue;  // a model without a GLSL twin (registry.h)
        }
        const gl::GlslMaterial c = gl::glsl_material(d, gl::GlslStorage::Const, "aniso_p_");
        json slots = json::array();
        for (const gl::GlslSlot& s : g.slots)
          slots.push_back({{"name", s.name}, {"key", s.table_key}, {"type", slot_type(s.type)}});
        shapes[shape_key(d)] = {
            {"slots", slots},
            {"needs_tables", g.needs_tables},
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
  data["measured"] = measured_json();
  return data;
}

// --- serve -------------------------------------------------------------------------------------
// A minimal HTTP/1.0 GET server on 127.0.0.1 for the static page. Hand-written on POSIX sockets:
// Debian has no maintained C++ HTTP server library packaged for this (cpp-httplib is not in
// Debian 12; libmicrohttpd would do but adds a dependency for ~100 lines of static file serving).
// It serves only the regular files directly in the page's folder (no subfolders, no "..").
//
// No request can stop or hold it (docs/web.md, "Bounds"): each connection is served on its own
// thread, at most kMaxConnections at once (one more is answered 503 at once); the request line
// must arrive whole within kRequestSeconds of the connection (408 otherwise) and within
// kMaxRequestLine bytes (431); a response is sent within kResponseSeconds or the connection is
// closed. A request line that is not `METHOD TARGET [HTTP/x.y]` is a 400; a name that is not a
// regular file in the folder is a 404.

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_stop(int) { g_stop = 1; }

constexpr int kMaxConnections = 32;
constexpr double kRequestSeconds = 5.0;
constexpr double kResponseSeconds = 30.0;
constexpr size_t kMaxRequestLine = 8192;

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

using Clock = std::chrono::steady_clock;

// Milliseconds left until `deadline` for poll(), at least 0.
int millis_left(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return int(std::clamp<long long>(left, 0, 60'000));
}

// Sends all of `s` before `deadline`; false when the client went away or was too slow.
bool send_all(int fd, std::string_view s, Clock::time_point deadline) {
  size_t off = 0;
  while (off < s.size()) {
    pollfd p{fd, POLLOUT, 0};
    const int ready = ::poll(&p, 1, millis_left(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    const ssize_t n = ::send(fd, s.data() + off, s.size() - off, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
    if (n <= 0) return false;
    off += size_t(n);
  }
  return true;
}

// The request line, without its line end (CR LF or a bare LF); nullopt with `status` set when it
// does not arrive whole in time or in kMaxRequestLine bytes, or the client closes first (status
// empty: nothing to answer).
std::optional<std::string> read_request_line(int fd, Clock::time_point deadline, std::string& status) {
  std::string req;
  char buf[2048];
  while (true) {
    if (const size_t eol = req.find('\n'); eol != std::string::npos) {
      std::string line = req.substr(0, eol);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      return line;
    }
    if (req.size() >= kMaxRequestLine) {
      status = "431 Request Header Fields Too Large";
      return std::nullopt;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, millis_left(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0 || (ready < 0 && Clock::now() >= deadline)) {
      status = "408 Request Timeout";
      return std::nullopt;
    }
    if (ready < 0) return std::nullopt;
    const ssize_t n = ::recv(fd, buf, std::min(sizeof buf, kMaxRequestLine - req.size()), MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
    if (n <= 0) return std::nullopt;
    req.append(buf, size_t(n));
  }
}

// Splits "METHOD TARGET [VERSION]" at single spaces (RFC 9112 Sec. 3); false for anything else:
// a control byte (NUL included), a missing or empty part, more than three parts, a target that is
// not an absolute path, a version that is not HTTP/x.y.
bool parse_request_line(std::string_view line, std::string& method, std::string& target) {
  for (const char ch : line)
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) return false;
  std::vector<std::string_view> parts;
  size_t start = 0;
  while (true) {
    const size_t sp = line.find(' ', start);
    parts.push_back(line.substr(start, sp == std::string_view::npos ? std::string_view::npos : sp - start));
    if (sp == std::string_view::npos) break;
    start = sp + 1;
  }
  if (parts.size() < 2 || parts.size() > 3) return false;
  for (const std::string_view part : parts)
    if (part.empty()) return false;
  if (parts[1][0] != '/') return false;
  if (parts.size() == 3 && (parts[2].size() != 8 || parts[2].substr(0, 5) != "HTTP/")) return false;
  method = parts[0];
  target = parts[1];
  return true;
}

void respond(int fd, const std::filesystem::path& root) {
  namespace fs = std::filesystem;
  const Clock::time_point accepted = Clock::now();
  const auto request_deadline =
      accepted + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRequestSeconds));
  const auto response_deadline =
      accepted + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRequestSeconds + kResponseSeconds));
  const auto status = [&](const std::string& code, const std::string& body) {
    send_all(fd,
             fmt::format("HTTP/1.0 {}\r\nContent-Type: text/plain\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}", code,
                         body.size(), body),
             response_deadline);
  };
  std::string why;
  const std::optional<std::string> line = read_request_line(fd, request_deadline, why);
  if (!line) {
    if (!why.empty()) status(why, why.substr(4) + "\n");
    return;
  }
  std::string method, target;
  if (!parse_request_line(*line, method, target)) return status("400 Bad Request", "bad request line\n");
  if (method != "GET" && method != "HEAD") return status("405 Method Not Allowed", "only GET\n");
  std::string name = target.substr(0, target.find_first_of("?#"));
  if (name == "/") name = "/index.html";
  name = name.substr(1);
  if (name.empty() || name.find('/') != std::string::npos || name.find("..") != std::string::npos || name[0] == '.')
    return status("404 Not Found", "not found\n");
  // Only a regular file (after links): a folder, a FIFO or a device in the root is not served (a
  // FIFO would block the open).
  std::error_code ec;
  const fs::path file = root / name;
  if (!fs::is_regular_file(file, ec)) return status("404 Not Found", "not found\n");
  const uintmax_t size = fs::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  if (ec || !in) return status("404 Not Found", "not found\n");
  if (!send_all(fd,
                fmt::format("HTTP/1.0 200 OK\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-cache\r\n"
                            "Connection: close\r\n\r\n",
                            content_type(name), size),
                response_deadline) ||
      method != "GET")
    return;
  std::vector<char> buf(size_t(1) << 16);
  for (uintmax_t left = size; left > 0;) {
    in.read(buf.data(), std::streamsize(std::min<uintmax_t>(left, buf.size())));
    const size_t n = size_t(in.gcount());
    if (n == 0 || !send_all(fd, std::string_view(buf.data(), n), response_deadline)) return;  // shortened, or gone
    left -= n;
  }
}

// Answers one connection and closes it. Unread request bytes (headers after the request line) are
// read away before the close, briefly, so that the kernel does not reset the connection under the
// response (RFC 9112 Sec. 9.6, "tear-down").
void serve_connection(int c, const std::filesystem::path& root) {
  try {
    respond(c, root);
  } catch (...) {  // out of memory or a stream failure: this connection only
  }
  ::shutdown(c, SHUT_WR);
  const Clock::time_point until = Clock::now() + std::chrono::milliseconds(500);
  char buf[4096];
  while (true) {
    pollfd p{c, POLLIN, 0};
    if (::poll(&p, 1, millis_left(until)) <= 0) break;
    if (::recv(c, buf, sizeof buf, MSG_DONTWAIT) <= 0) break;
  }
  ::close(c);
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
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);  // accept() after poll() never blocks
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
  ::listen(fd, 64);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  fmt::print("aniso serve: http://127.0.0.1:{}/ (serving {}; Ctrl-C stops)\n", ntohs(addr.sin_port), root.string());
  std::fflush(stdout);
  struct sigaction sa {};
  sa.sa_handler = on_stop;  // no SA_RESTART: poll() returns EINTR
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  // The connection threads block SIGINT and SIGTERM (they inherit the mask set around their
  // creation), so that the signal reaches this thread's poll().
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  // Shared with the detached connection threads, which may still hold it after serve() returns.
  struct Connections {
    std::mutex mutex;
    std::condition_variable idle;
    int active = 0;
  };
  const auto state = std::make_shared<Connections>();
  std::mutex& mutex = state->mutex;
  int& active = state->active;
  while (!g_stop) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 250) <= 0) continue;  // the timeout rechecks g_stop
    const int c = ::accept4(fd, nullptr, nullptr, SOCK_CLOEXEC);
    if (c < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // out of descriptors: let connections end
      continue;
    }
    {
      std::unique_lock lock(mutex);
      if (active >= kMaxConnections) {
        lock.unlock();
        const std::string busy =
            "HTTP/1.0 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: 5\r\n"
            "Connection: close\r\n\r\nbusy\n";
        ::send(c, busy.data(), busy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        ::close(c);
        continue;
      }
      ++active;
    }
    ::pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
    try {
      std::thread([c, root, state] {
        serve_connection(c, root);
        const std::lock_guard lock(state->mutex);
        if (--state->active == 0) state->idle.notify_all();
      }).detach();
    } catch (const std::system_error&) {  // no thread to be had: this connection is dropped
      ::close(c);
      const std::lock_guard lock(mutex);
      --active;
    }
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  }
  ::close(fd);
  // The connections under way end within their deadlines.
  std::unique_lock lock(mutex);
  state->idle.wait(lock, [&] { return active == 0; });
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
