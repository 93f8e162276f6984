// fuzz/fuzz_samples.cpp: the measured-sample readers (measured/samples.h; docs/fitting.md, "Data"):
// the CSV of samples and the Cornell gonioreflectometer files. The first byte chooses the reader
// (even: CSV, odd: Cornell); the rest is the file. An accepted file must give samples with unit
// directions above the horizon, finite non-negative values (a Cornell spectrum may reduce to a
// slightly negative sRGB channel outside the gamut, docs/fitting.md: finite is checked there) and
// finite positive weights.
#include <cmath>

#include "aniso/io/params.h"
#include "aniso/measured/samples.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace aniso;
  if (size == 0) return 0;
  const bool cornell = (data[0] & 1) != 0;
  const std::string path = fuzz::write_scratch_file(cornell ? "data.brdf" : "data.csv", data + 1, size - 1);
  SampleSet set;
  try {
    set = cornell ? read_cornell(path) : read_samples_csv(path);
  } catch (const aniso::InputError& e) {
    fuzz::rejected(e);
    return 0;
  }
  for (const MeasuredSample& s : set.samples) {
    for (const Vec3d& w : {s.wi, s.wo}) {
      FUZZ_CHECK(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z));
      FUZZ_CHECK(std::abs(glm::length(w) - 1.0) < 1e-9);
      FUZZ_CHECK(w.z > 0.0);  // theta strictly below 90 degrees
    }
    for (int c = 0; c < 3; ++c) {
      FUZZ_CHECK(std::isfinite(s.value[c]));
      if (!cornell) FUZZ_CHECK(s.value[c] >= 0.0);
    }
    FUZZ_CHECK(std::isfinite(s.weight) && s.weight > 0.0);
  }
  return 0;
}
