// aniso/io/input_error.h: the error every host reader raises (JSON materials, scenes, measured files,
// data tables); its message names the file, the key or line, and what was expected.
#pragma once

#include <stdexcept>

namespace aniso {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace aniso
