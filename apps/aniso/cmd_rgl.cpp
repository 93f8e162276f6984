// apps/aniso/cmd_rgl.cpp: `aniso export-rgl`, any material as an RGL tensor file (.bsdf) that
// pbrt-v4 and Mitsuba 3 render (docs/rgl.md).
#include <memory>

#include <fmt/format.h>

#include "aniso/data/metals.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/rgl_material.h"
#include "aniso/version.h"
#include "commands.h"
#include "io/text_input.h"

namespace aniso {

void add_rgl_command(CLI::App& app) {
  struct Args {
    std::string material, output, resolution, theta_i, phi_i, ndf, vndf;
    bool rgb = false, spectral = false, check = false, isotropic = false, anisotropic = false;
  };
  auto a = std::make_shared<Args>();
  // The notes of every RGL tensor file any command reads (rounding noise read as 0, sigma raised
  // to its floor: rgl/rgl_material.h), once per file, on stderr.
  rgl::set_note_sink([](const std::string& note) { fmt::print(stderr, "aniso: note: {}\n", note); });
  auto* cmd = app.add_subcommand("export-rgl",
                                 "write the material as an RGL tensor file (.bsdf) for pbrt-v4 "
                                 "(Material \"measured\") and Mitsuba 3 (<bsdf type=\"measured\">)");
  cmd->add_option("--material,-m", a->material, kMaterialHelp)->required();
  cmd->add_option("-o,--output", a->output, "output .bsdf file")->required();
  auto* spec = cmd->add_flag("--spectral", a->spectral, "spectra + wavelengths (default; pbrt-v4, spectral Mitsuba variants)");
  cmd->add_flag("--rgb", a->rgb, "an rgb table, no wavelengths (Mitsuba's RGB variants)")->excludes(spec);
  cmd->add_option("--resolution", a->resolution, "colour grid n x n on the VNDF-warped square (default 32, 4 to 256)");
  cmd->add_option("--theta-i", a->theta_i, "incident elevations (default 16, 2 to 128)");
  cmd->add_option("--phi-i", a->phi_i,
                  "incident azimuths over the full circle, anisotropic materials (default 33, 3 to 181; one more when the "
                  "material is turned)");
  cmd->add_option("--ndf", a->ndf, "ndf and sigma grid n x n (default 64, 8 to 512)");
  cmd->add_option(
      "--vndf", a->vndf,
      "vndf grid n x n, the warp of each incident direction (default 32 anisotropic, the ndf grid isotropic; 8 to 512)");
  auto* iso = cmd->add_flag("--isotropic", a->isotropic,
                            "write one phi_i slice (f as seen from azimuth 0), whatever the rotation test says");
  cmd->add_flag("--anisotropic", a->anisotropic, "write phi_i over the full circle, whatever the rotation test says")
      ->excludes(iso);
  cmd->add_flag("--check", a->check, "read the file back and print its accuracy against the material (docs/rgl.md)");
  cmd->callback([a] {
    run_command([&] {
      rgl::ExportOptions opt;
      opt.spectral = !a->rgb;
      if (!a->resolution.empty()) opt.colour = int(parse_integer(a->resolution, 4, 256, "--resolution"));
      if (!a->theta_i.empty()) opt.theta_i = int(parse_integer(a->theta_i, 2, 128, "--theta-i"));
      if (!a->phi_i.empty()) opt.phi_i = int(parse_integer(a->phi_i, 3, 181, "--phi-i"));
      if (!a->ndf.empty()) opt.ndf = int(parse_integer(a->ndf, 8, 512, "--ndf"));
      if (!a->vndf.empty()) opt.vndf = int(parse_integer(a->vndf, 8, 512, "--vndf"));
      if (a->isotropic) opt.isotropy = rgl::ExportOptions::Isotropy::Isotropic;
      if (a->anisotropic) opt.isotropy = rgl::ExportOptions::Isotropy::Anisotropic;
      // A grid asked for: a tensor source is resampled on it rather than written from its own tables.
      opt.resample = !(a->resolution.empty() && a->theta_i.empty() && a->phi_i.empty() && a->ndf.empty() && a->vndf.empty());
      const MaterialDesc desc = load_material(a->material);
      const MaterialD m = build_material<double>(desc);
      const MetalData* metal =
          desc.model == "metal" && desc.params.has("metal") ? find_metal(desc.params.text("metal")) : nullptr;
      rgl::BrdfSource src = rgl::brdf_source(m, metal);
      src.tensor = desc.rgl;
      // dump with replace: a file name in the material need not be UTF-8 (U+FFFD stands for its bad bytes).
      src.description =
          fmt::format("{} (written by aniso {} export-rgl)",
                      resolved_json(desc).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), ANISO_VERSION);
      rgl::ExportReport rep;
      const std::vector<rgl::TensorField> fields = rgl::export_rgl(src, opt, &rep);
      const std::vector<uint8_t> bytes = rgl::serialize_tensor(fields);
      write_atomically(a->output, std::string(bytes.begin(), bytes.end()));
      fmt::print(stderr, "{}\n", rep.isotropy);
      const std::string size = desc.rgl ? fmt::format(" ({:.2f} x the source's {} bytes)",
                                                      double(bytes.size()) / double(desc.rgl->file_size), desc.rgl->file_size)
                                        : "";
      fmt::print(stderr, "{}: {} bytes{}, {}, {}, {}: {}, {:.2f} s CPU\n", a->output, bytes.size(), size,
                 rep.isotropic ? "isotropic" : "anisotropic", opt.spectral ? "spectral" : "rgb", rep.transcoded ? "tables" : "D",
                 rep.d_method, rep.seconds);
      if (opt.spectral) fmt::print(stderr, "spectra: {}\n", rep.spectra);
      if (a->check) {
        const auto d = rgl::rgl_from_tensor(rgl::parse_tensor(bytes, a->output));
        const rgl::RoundTripStats s = rgl::compare_rgl(rgl::source_model(m), rgl::rgl_kernel<double>(*d));
        fmt::print("cosine-weighted relative L1: max {:.4f} (theta {} deg, phi {} deg), mean {:.4f}; albedo error max {:.4f}\n",
                   s.l1_max, s.worst_theta_deg, s.worst_phi_deg, s.l1_mean, s.albedo_max);
      }
    });
  });
}

}  // namespace aniso
