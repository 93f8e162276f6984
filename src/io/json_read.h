// io/json_read.h: the one way the project reads JSON documents (materials, scenes, fitted files).
//
// On top of nlohmann's parser it adds what a user needs to be told about:
//  - duplicate keys in an object are an error naming the key and its JSON path (nlohmann keeps the
//    last one silently; RFC 8259 Sec. 4 leaves the behaviour to the implementation);
//  - nesting deeper than kMaxJsonDepth is an error (nlohmann's copy and comparison of a value are
//    recursive: 200,000 levels overflow the stack; fuzz/corpus/material/issue13-deep-nesting.json);
//  - files are told apart: missing, a directory, unreadable, a read error, and invalid JSON, each
//    with its own message; pipes and FIFOs (`-m <(...)`) are read like files.
// Messages are `<where>: <what>`, with control characters in keys escaped (text_escape()).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace aniso {

// No material or scene nests more than 6 levels; 64 leaves room and keeps recursion shallow.
inline constexpr int kMaxJsonDepth = 64;

// The message for a value nested deeper than kMaxJsonDepth at JSON path `path` ("" for the top
// level); the Python bindings' dict conversion gives the same one.
std::string json_too_deep_message(const std::string& where, const std::string& path);

// Parses `text`; `where` names the source in messages ("gold.json", "inline material").
nlohmann::json parse_json_text(std::string_view text, const std::string& where);

// Reads and parses a file (a regular file, a FIFO or a /dev/fd pipe).
nlohmann::json read_json_file(const std::string& path);

// Reads a whole file into memory with the same file-kind messages (`what` says what was expected:
// "a JSON file", "a scene file"); throws InputError.
std::string read_text_file(const std::string& path, std::string_view what);

// Printable form of user text for messages: control characters, DEL and NUL as \n, \t, \u0000.
std::string text_escape(std::string_view s);

}  // namespace aniso
