// examples/cpp/materials.cpp: materials from presets, JSON files, inline JSON and JSON built in
// code (CMake aniso::host).
//
// A material is read and validated once into a MaterialDesc (include/aniso/io/materials.h: the
// model's name, its validated parameters with defaults filled in, the JSON it came from), then
// built into the kernel value MaterialT<T> for float (a renderer) or double (statistics, the CLI).
//
//   materials [FILE.json]
//
// The program shows the four ways in (the third with FILE when given), and checks that a material's resolved JSON (every key,
// defaults filled in, what `aniso presets --show` prints) reads back as the same material. Exit
// status 1 when it does not.
#include <cstdio>
#include <string>

#include <aniso/io/materials.h>
#include <aniso/io/presets.h>
#include <aniso/kernels.h>

int main(int argc, char** argv) {
  // 1. A preset by name (`aniso presets` lists them; aniso::presets() here).
  std::printf("%zu presets, the first: %s (%s)\n", aniso::presets().size(), aniso::presets().front().name.c_str(),
              aniso::presets().front().source.c_str());
  const aniso::MaterialDesc brushed_gold = aniso::load_material("brushed-gold");

  // 2. Inline JSON: any spec that starts with '{'.
  const aniso::MaterialDesc satin =
      aniso::load_material(R"({"model": "ashikhmin-shirley", "rd": 0.3, "rs": 0.05, "n_u": 200, "n_v": 10})");

  // 3. A JSON file: any other existing path (relative paths inside it, such as a measured
  // material's "file", are relative to the file). A MERL .binary or RGL .bsdf file works the same.
  const aniso::MaterialDesc from_file = aniso::load_material(argc > 1 ? argv[1] : "matte-steel");

  // 4. JSON built in code: parse_material(object, where), `where` naming it in error messages.
  nlohmann::json object = {{"model", "ggx"}, {"f0", {0.95, 0.64, 0.54}}, {"alpha_x", 0.05}, {"alpha_y", 0.2}};
  object["rotation_deg"] = 45;
  const aniso::MaterialDesc copper_like = aniso::parse_material(object, "my copper");

  // The resolved JSON: every key of the model's table, defaults filled in, shorthands expanded.
  std::printf("brushed-gold resolves to %s\n", aniso::resolved_json(brushed_gold).dump().c_str());

  int failures = 0;
  const aniso::Vec3d wi = glm::normalize(aniso::Vec3d(0.3, 0.2, 0.9)), wo = glm::normalize(aniso::Vec3d(-0.4, 0.1, 0.9));
  for (const aniso::MaterialDesc* desc : {&brushed_gold, &satin, &from_file, &copper_like}) {
    // The kernel values: build once, then copy freely (a plain value: no heap, no virtual calls).
    const aniso::Material as_float = aniso::build_material<float>(*desc);
    const aniso::MaterialD as_double = aniso::build_material<double>(*desc);
    const aniso::MaterialD round_trip =
        aniso::build_material<double>(aniso::parse_material(aniso::resolved_json(*desc), "resolved"));
    const double f = as_double.f(wi, wo).y, f_round_trip = round_trip.f(wi, wo).y;
    const float f_float = as_float.f(aniso::Vec3(wi), aniso::Vec3(wo)).y;
    std::printf("%-17s f (green): double %.9g, float %.7g, resolved JSON read back %.9g\n", desc->model.c_str(), f, f_float,
                f_round_trip);
    if (f != f_round_trip) ++failures;
  }
  return failures ? 1 : 0;
}
