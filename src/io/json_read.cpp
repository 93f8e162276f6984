// io/json_read.cpp: JSON documents with duplicate-key and depth checks, and file-kind messages.
#include "io/json_read.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <vector>

#include <sys/stat.h>

#include <fmt/format.h>

#include "aniso/io/params.h"

namespace aniso {

namespace {

// The parser callback sees every event with the current depth; a stack of frames tracks the JSON
// path and, per object, the keys seen so far.
struct Frame {
  bool is_object = false;
  std::set<std::string> keys;
  std::string key;  // the object's current key
  long index = -1;  // the array's current element
};

std::string path_of(const std::vector<Frame>& stack) {
  std::string p;
  for (const Frame& f : stack) {
    if (f.is_object) {
      if (!f.key.empty()) p += (p.empty() ? "" : ".") + text_escape(f.key);
    } else if (f.index >= 0) {
      p += fmt::format("[{}]", f.index);
    }
  }
  return p;
}

}  // namespace

std::string json_too_deep_message(const std::string& where, const std::string& path) {
  return fmt::format("{}: {}: nested deeper than {} levels (no material or scene needs more)", where,
                     path.empty() ? "top level" : path, kMaxJsonDepth);
}

nlohmann::json parse_json_text(std::string_view text, const std::string& where) {
  using json = nlohmann::json;
  std::vector<Frame> stack;
  // An element starts: in an array it is the next index.
  const auto element = [&] {
    if (!stack.empty() && !stack.back().is_object) ++stack.back().index;
  };
  const json::parser_callback_t cb = [&](int depth, json::parse_event_t event, json& parsed) -> bool {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        element();
        if (depth >= kMaxJsonDepth) throw InputError(json_too_deep_message(where, path_of(stack)));
        stack.push_back(Frame{event == json::parse_event_t::object_start, {}, {}, -1});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack.empty()) stack.pop_back();
        break;
      case json::parse_event_t::key: {
        Frame& f = stack.back();
        const std::string k = parsed.get<std::string>();
        f.key = k;
        if (!f.keys.insert(k).second)
          throw InputError(fmt::format("{}: {}: duplicate key \"{}\" (each key may appear once in an object)", where,
                                       path_of(stack), text_escape(k)));
        break;
      }
      case json::parse_event_t::value: element(); break;
    }
    return true;
  };
  try {
    return json::parse(text.begin(), text.end(), cb);
  } catch (const json::exception& e) {  // syntax errors, and numbers that overflow a double (1e999)
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 1, column 5: ...".
    std::string msg = e.what();
    if (const size_t p = msg.find("] "); p != std::string::npos) msg = msg.substr(p + 2);
    throw InputError(fmt::format("{}: invalid JSON: {}", where, text_escape(msg)));
  }
}

std::string mib_text(size_t bytes) { return fmt::format("{} MiB", bytes >> 20); }

std::string read_text_file(const std::string& path, std::string_view what, size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) throw InputError(fmt::format("{}: no such file (expected {})", path, what));
    throw InputError(fmt::format("{}: cannot access: {}", path, std::strerror(err)));
  }
  if (S_ISDIR(st.st_mode)) throw InputError(fmt::format("{}: is a directory, expected {}", path, what));
  const auto too_large = [&](const std::string& size) {
    return InputError(fmt::format("{}: {}larger than {}, the limit for {} (docs/cli.md, \"Size limits\")", path, size,
                                  mib_text(max_bytes), what));
  };
  if (S_ISREG(st.st_mode) && uintmax_t(st.st_size) > max_bytes) throw too_large(fmt::format("{} bytes: ", uintmax_t(st.st_size)));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open for reading: {}", path, std::strerror(errno)));
  // A FIFO or a device has no size: read up to one byte past the limit.
  std::string text;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, size_t(in.gcount()));
    if (text.size() > max_bytes) throw too_large("");
  }
  if (in.bad()) throw InputError(fmt::format("{}: read error: {}", path, std::strerror(errno)));
  return text;
}

nlohmann::json read_json_file(const std::string& path) { return parse_json_text(read_text_file(path, "a JSON file"), path); }

}  // namespace aniso
