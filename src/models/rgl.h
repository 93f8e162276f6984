// models/rgl.h: an RGL tensor file as a material (docs/rgl.md; kernel aniso/brdf/rgl.h): the file is
// the material, as a MERL table is. Hand-written: the file is read by the checks (parse_material),
// the kernel points into its tables.
#pragma once

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
};

}  // namespace aniso::models
