// tests/input_error_text.h: the text of the InputError a call raises, and substring matching, for
// the tests of error messages (each names the file, the key path or line, and what was expected).
#pragma once

#include <functional>
#include <string>

#include "aniso/io/input_error.h"

namespace aniso {

// The message of the InputError that `fn` raises ("(no error)" if it raises none).
inline std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

inline bool contains(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

}  // namespace aniso
