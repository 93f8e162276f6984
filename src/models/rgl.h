// models/rgl.h: an RGL tensor file as a material (docs/rgl.md; kernel aniso/brdf/rgl.h): the file is
// the material, as a MERL table is. Hand-written: the file is read by the checks (parse_material),
// the kernel points into its tables.
#pragma once

#include <algorithm>
#include <vector>

#include "aniso/rgl/rgl_material.h"
#include "models/model.h"

namespace aniso::models {

struct Rgl {
  // An RGL tensor file (Dupuy & Jakob 2018; docs/rgl.md) is the material. A path ending in .bsdf
  // given as a material means {"model": "rgl", "file": PATH}.
  static constexpr ParamSpec params[] = {
      {.name = "file",
       .kind = ParamKind::String,
       .doc = "RGL tensor file (.bsdf: the RGL material database, `aniso export-rgl`), evaluated as pbrt-v4's "
              "MeasuredBxDF; relative to the folder of the JSON or scene file naming it (else the working "
              "directory); no other parameters",
       .required = true},
  };
  static constexpr std::span<const ParamSpec> parts[] = {params};
  static constexpr ModelSpec spec{"rgl", "Measured (RGL tensor file)",
                                  "Dupuy & Jakob 2018, An Adaptive Parameterization for Efficient Material Acquisition and "
                                  "Rendering (pbrt-v4 MeasuredBxDF)",
                                  parts};
  // Keys the host resolves before the GPU sees them (no GLSL slot): the file is read into the
  // tables texture (glsl_tables).
  static constexpr std::string_view host_keys[] = {"file"};
  // A tensor file is tabulated in its own frame: why it has no rotation_deg (parse_material).
  static constexpr std::string_view no_rotation =
      "a tensor file is tabulated in its own frame and has no rotation key; turn the surface's tangent instead (a "
      "scene's tangent.angle_deg)";

  static void check(MaterialDesc& d, const std::string& base_dir) {
    const std::string& file = d.params.text("file");
    if (file.empty()) d.params.fail("file", "expected the path of an RGL .bsdf tensor file, got an empty string");
    d.rgl = rgl::load_rgl(resolve_file(file, base_dir));  // InputError naming the file, the field and the problem
  }

  template <typename T> static RglT<T> build(const MaterialDesc& d) {
    if (!d.rgl) throw InputError(fmt::format("{}: rgl material without its tensor file", d.params.where));
    return rgl::rgl_kernel<T>(*d.rgl);
  }

  // The interpolants come from the tables texture (rgl.glsl, Rgl_load; glsl_tables() writes them at
  // base 0).
  static std::string glsl(const ParamValues&, const SlotFn&) { return "  m = Rgl_load(0);\n"; }

  // The tables texture's contents from base 0 (docs/glsl.md, "Measured materials"): rgl.glsl's
  // header, then each PL2D's header and tables.
  static std::vector<float> glsl_tables(const MaterialDesc& m) {
    if (!m.rgl) throw InputError(fmt::format("{}: rgl material without its tensor file", m.params.where));
    const rgl::RglData& d = *m.rgl;
    std::vector<float> out(96, 0.f);
    out[0] = 1.f;
    out[1] = d.tables.isotropic ? 1.f : 0.f;
    const rgl::PL2DTables* parts[5] = {&d.ndf, &d.sigma, &d.vndf, &d.luminance, &d.rgb};
    for (int k = 0; k < 5; ++k) append_pl2d(out, size_t(16 + 16 * k), *parts[k]);
    return out;
  }

 private:
  static size_t append(std::vector<float>& out, const float* v, size_t n) {
    const size_t at = out.size();
    out.insert(out.end(), v, v + n);
    return at;
  }

  // One PL2D header (rgl.glsl): sizes, strides, then the offsets of its tables, appended to `out`.
  static void append_pl2d(std::vector<float>& out, size_t header, const rgl::PL2DTables& t) {
    const PL2D& v = t.view;
    const float head[9] = {float(v.size_x),          float(v.size_y),          float(v.dim),
                           float(v.param_size[0]),   float(v.param_size[1]),   float(v.param_size[2]),
                           float(v.param_stride[0]), float(v.param_stride[1]), float(v.param_stride[2])};
    std::copy(head, head + 9, out.begin() + ptrdiff_t(header));
    for (int d = 0; d < 3; ++d) {
      const size_t at = append(out, t.param_values[d].data(), t.param_values[d].size());
      out[header + 9 + size_t(d)] = t.param_values[d].empty() ? 0.f : float(at);
    }
    const std::vector<float>* tables[3] = {&t.data, &t.marginal_cdf, &t.conditional_cdf};
    for (int k = 0; k < 3; ++k) {
      const size_t at = append(out, tables[k]->data(), tables[k]->size());
      out[header + 12 + size_t(k)] = tables[k]->empty() ? 0.f : float(at);
    }
  }
};

}  // namespace aniso::models
