// fuzz/fuzz_eval_line.cpp: the stdin line parser of `aniso eval` (io/text_input.h). The input is
// the text of stdin; the first byte chooses vector lines (even) or `--angles` lines (odd). Each
// line goes through is_blank_or_comment and parse_direction_line as the CLI reads it; a parsed pair
// must be two unit vectors, and three presets (a Lafortune fit, a balanced Ward metal with a
// directional-diffuse lobe, a GGX conductor) must give finite, non-negative f and pdf for it in
// double and float. The tokens are also fed to the number rule's parse_decimal / parse_integer.
#include <array>

#include "aniso/io/materials.h"
#include "fuzz_util.h"
#include "io/text_input.h"

namespace {
using namespace aniso;

struct Materials {
  std::array<MaterialT<double>, 3> d;
  std::array<MaterialT<float>, 3> f;
};
const Materials& materials() {
  static const Materials m = [] {
    Materials r;
    const char* names[3] = {"matte-steel", "brushed-gold", "gold"};
    for (int i = 0; i < 3; ++i) {
      const MaterialDesc desc = load_material(names[i]);
      r.d[size_t(i)] = build_material<double>(desc);
      r.f[size_t(i)] = build_material<float>(desc);
    }
    return r;
  }();
  return m;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool angles = (data[0] & 1) != 0;
  const std::string_view text = fuzz::as_text(data + 1, size - 1);
  size_t line_no = 0, start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    // Tokens through the integer rule as well (--count, --seed, --spp read them).
    try {
      (void)parse_integer(line, -5, 1000, "--x");
    } catch (const InputError&) {}
    try {
      (void)parse_unsigned(line, UINT64_MAX, "--seed");
    } catch (const InputError&) {}
    if (is_blank_or_comment(line)) continue;
    DirectionPair d;
    try {
      d = parse_direction_line(line, line_no, angles);
    } catch (const InputError& e) {
      fuzz::rejected(e);
      continue;  // the CLI stops here with exit 2; the fuzzer looks at the next line
    }
    FUZZ_CHECK(std::abs(glm::length(d.wi) - 1.0) < 1e-12 && std::abs(glm::length(d.wo) - 1.0) < 1e-12);
    const Materials& m = materials();
    for (size_t i = 0; i < m.d.size(); ++i) {
      const RGBT<double> f = m.d[i].f(d.wi, d.wo);
      const double pdf = m.d[i].pdf(d.wi, d.wo);
      for (int c = 0; c < 3; ++c) FUZZ_CHECK(std::isfinite(f[c]) && f[c] >= 0.0);
      FUZZ_CHECK(std::isfinite(pdf) && pdf >= 0.0);
      const Vec3 wi(d.wi), wo(d.wo);
      const RGB ff = m.f[i].f(wi, wo);
      const float pf = m.f[i].pdf(wi, wo);
      for (int c = 0; c < 3; ++c) FUZZ_CHECK(std::isfinite(ff[c]) && ff[c] >= 0.0f);
      FUZZ_CHECK(std::isfinite(pf) && pf >= 0.0f);
    }
    if (end == text.size()) break;
  }
  return 0;
}
