// models/measured.h: a MERL table as a material (docs/measured.md; kernel aniso/brdf/measured.h): the
// file is the material. Hand-written: the file is read by the checks (parse_material), the kernel
// points into its tables.
#pragma once

#include <vector>

#include "aniso/measured/measured.h"
#include "models/model.h"

namespace aniso::models {

struct Measured {
  // A tabulated BRDF has no parameters: the file is the material (docs/measured.md). A path ending
  // in .binary given as a material means {"model": "measured", "file": PATH}.
  static constexpr ParamSpec params[] = {
      {.name = "file",
       .kind = ParamKind::String,
       .doc = "MERL BRDF database .binary file (90 x 90 x 180 bins, Matusik et al. 2003), relative to the "
              "folder of the JSON or scene file naming it (else the working directory); no other parameters",
       .required = true},
  };
  static constexpr std::span<const ParamSpec> parts[] = {params};
  static constexpr ModelSpec spec{"measured", "Measured (MERL table)",
                                  "Matusik et al. 2003, A Data-Driven Reflectance Model (MERL BRDF database)", parts};
  // Keys the host resolves before the GPU sees them (no GLSL slot): the file is read into the
  // tables texture (glsl_tables).
  static constexpr std::string_view host_keys[] = {"file"};

  static void check(MaterialDesc& d, const std::string& base_dir) {
    const std::string& file = d.params.text("file");
    if (file.empty()) d.params.fail("file", "expected the path of a MERL .binary file, got an empty string");
    d.measured = load_measured(resolve_file(file, base_dir));  // InputError naming the file and the byte offset
  }

  template <typename T> static MeasuredT<T> build(const MaterialDesc& d) {
    if (!d.measured) throw InputError(fmt::format("{}: measured material without its table", d.params.where));
    return measured_kernel<T>(*d.measured);
  }

  // The bins and sampling tables come from the tables texture (measured.glsl, Measured_load;
  // glsl_tables() writes them at base 0).
  static std::string glsl(const ParamValues&, const SlotFn&) { return "  m = Measured_load(0);\n"; }

  // The tables texture's contents from base 0 (docs/glsl.md, "Measured materials"): measured.glsl's
  // header, the bins, the sampling tables and the cells' pdf.
  static std::vector<float> glsl_tables(const MaterialDesc& m) {
    if (!m.measured) throw InputError(fmt::format("{}: measured material without its table", m.params.where));
    const MeasuredData& d = *m.measured;
    const MeasuredT<float> k = measured_kernel<float>(d);
    constexpr int kH = MerlLayout::kThetaH;
    std::vector<float> out(16, 0.f);
    out[0] = 2.f;
    out[1] = float(d.theta_o_bins);
    out[2] = float(d.phi_h_bins);
    out[3] = k.uniform_fraction;
    auto put = [&](int slot, const std::vector<double>& v) {
      out[size_t(slot)] = float(out.size());
      for (double x : v) out.push_back(float(x));
    };
    put(4, d.brdf.table);
    put(5, d.marginal_cdf);
    put(6, d.conditional_cdf);
    put(7, d.v_edges);
    // P(cell) / solid angle(cell) in double, as MeasuredT::table_pdf computes it before its cast.
    out[8] = float(out.size());
    const int nj = d.phi_h_bins;
    for (int o = 0; o < d.theta_o_bins; ++o)
      for (int i = 0; i < kH; ++i) {
        const double* mcdf = d.marginal_cdf.data() + size_t(o) * (kH + 1);
        const double* ccdf = d.conditional_cdf.data() + (size_t(o) * kH + size_t(i)) * size_t(nj + 1);
        for (int j = 0; j < nj; ++j)
          out.push_back(float((mcdf[i + 1] - mcdf[i]) * (ccdf[j + 1] - ccdf[j]) / d.cell_solid_angle[size_t(i)]));
      }
    return out;
  }
};

}  // namespace aniso::models
