// fuzz/fuzz_material.cpp: the material JSON reader, end to end. The input is a JSON document (as
// given to `--material` inline or in a file): parse (duplicate keys, depth) -> validate against the
// parameter tables -> build in float and double -> evaluate f and pdf and sample over the pairs of
// fuzz_util.cpp. Every material the reader accepts must give finite, non-negative output in both
// precisions (issue 13), and its resolved form (`aniso presets --show`) must read back as valid
// input giving the same material.
#include "aniso/io/materials.h"
#include "fuzz_util.h"
#include "io/json_read.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  MaterialDesc desc;
  try {
    desc = parse_material(parse_json_text(fuzz::as_text(data, size), "fuzz input"), "fuzz input");
  } catch (const InputError& e) {
    fuzz::rejected(e);
    return 0;  // rejected with a message: the reader's job
  }
  fuzz::check_material(build_material<double>(desc));
  fuzz::check_material(build_material<float>(desc));
  // The resolved material is valid input, and resolving it again changes nothing.
  const nlohmann::json resolved = resolved_json(desc);
  const MaterialDesc again = parse_material(resolved, "resolved");
  FUZZ_CHECK(resolved_json(again) == resolved);
  return 0;
}
