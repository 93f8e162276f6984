// fuzz/fuzz_merl.cpp: the MERL .binary reader (measured/merl.h; docs/measured.md). A valid file is
// 35 MB (three int32 dimensions, then 3 x 90 x 90 x 180 doubles), far above a fuzz input, so this
// target exercises what comes before the table: the header, the dimensions, the size check and
// their messages, on arbitrary bytes. Every input must be rejected with an InputError (no crash, no
// allocation from an unchecked size, no hang); the table's value checks are the unit tests'
// (tests/test_merl.cpp, tests/test_measured.cpp).
#include "aniso/io/params.h"
#include "aniso/measured/merl.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  const std::string path = fuzz::write_scratch_file("brdf.binary", data, size);
  try {
    const MerlBrdf merl = read_merl(path);
    // Only a full-size file can be accepted; then every stored value is finite.
    for (const double v : merl.table) FUZZ_CHECK(std::isfinite(v));
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
  }
  return 0;
}
