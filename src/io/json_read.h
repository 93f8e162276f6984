// io/json_read.h: the one way the project reads JSON documents (materials, scenes, fitted files).
//
// On top of nlohmann's parser it adds what a user needs to be told about:
//  - duplicate keys in an object are an error naming the key and its JSON path (nlohmann keeps the
//    last one silently; RFC 8259 Sec. 4 leaves the behaviour to the implementation);
//  - nesting deeper than kMaxJsonDepth is an error (nlohmann's copy and comparison of a value are
//    recursive: 200,000 levels overflow the stack; fuzz/corpus/material/issue13-deep-nesting.json);
//  - files are told apart: missing, a directory, unreadable, a read error, too large, and invalid
//    JSON, each with its own message; pipes and FIFOs (`-m <(...)`) are read like files, up to the
//    same size limit (so `-m /dev/zero` or `-m /dev/urandom` ends with an error, not out of memory).
// Messages are `<where>: <what>`, with control characters in keys escaped (text_escape()).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "io/text_escape.h"

namespace aniso {

// No material or scene nests more than 6 levels; 64 leaves room and keeps recursion shallow.
inline constexpr int kMaxJsonDepth = 64;

// Size limits of whole-file reads (docs/cli.md, "Size limits"): far above every real file, low
// enough that a wrong file (`/dev/zero`, a disk image) is refused before it fills the memory. A
// regular file's size is checked before reading; a FIFO or device is read up to the limit.
// JSON documents (materials, scenes, fitted files): the largest real ones are a few KB.
inline constexpr size_t kMaxJsonFileBytes = size_t(64) << 20;
// Tables of measured samples (CSV, Cornell .brdf): the Cornell files are 0.46 MB; a MERL table
// written out as CSV (1.46 million rows of about 80 bytes) is 117 MB.
inline constexpr size_t kMaxSampleFileBytes = size_t(256) << 20;
// RGL tensor files (.bsdf): the RGL database's are 0.66 MB; export-rgl writes up to about 50 MB
// (33 phi_i slices of an anisotropic material).
inline constexpr size_t kMaxTensorFileBytes = size_t(512) << 20;
// Wavefront OBJ meshes (render/scene.cpp): a ten-million-triangle mesh is about 0.5 GB of text.
inline constexpr size_t kMaxObjFileBytes = size_t(1) << 30;

// "64 MiB" for a limit in bytes (whole MiB).
std::string mib_text(size_t bytes);

// The message for a value nested deeper than kMaxJsonDepth at JSON path `path` ("" for the top
// level); the Python bindings' dict conversion gives the same one.
std::string json_too_deep_message(const std::string& where, const std::string& path);

// Parses `text`; `where` names the source in messages ("gold.json", "inline material").
nlohmann::json parse_json_text(std::string_view text, const std::string& where);

// Reads and parses a file (a regular file, a FIFO or a /dev/fd pipe).
nlohmann::json read_json_file(const std::string& path);

// Reads a whole file into memory with the same file-kind messages (`what` says what was expected:
// "a JSON file", "a scene file"); more than `max_bytes` is an InputError naming the file and the
// limit. Throws InputError.
std::string read_text_file(const std::string& path, std::string_view what, size_t max_bytes = kMaxJsonFileBytes);

}  // namespace aniso
