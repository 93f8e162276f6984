// examples/cpp/errors.cpp: bad input is an aniso::InputError (CMake aniso::host).
//
// Every host reader (materials from JSON, presets and files, scenes, measured files, sample sets)
// checks its input once and throws aniso::InputError (include/aniso/io/input_error.h, a
// std::runtime_error) whose what() names where the input came from (the file, "inline material",
// "preset NAME", or the name the caller gave), the key or line, what was expected and what was
// found. The kernels themselves never throw. This program feeds a few bad materials to the readers,
// prints each message, and checks that it names the key or file it should. Exit status 1 when a
// case does not throw InputError or its message lacks what it should name.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <aniso/io/input_error.h>
#include <aniso/io/materials.h>

namespace {

struct Case {
  std::string spec;                   // what load_material gets
  std::vector<std::string> expected;  // what the message must contain
};

}  // namespace

int main() {
  // A material file with a wrong type in it: the message starts with the file's path.
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("aniso-errors-example-" + std::to_string(getpid()) + ".json");
  std::ofstream(file) << R"({"model": "ggx", "f0": "gold"})";

  const std::vector<Case> cases = {
      {R"({"model": "ward", "alpha_x": 2, "alpha_y": 0.1})", {"inline material", "\"alpha_x\"", "[0.001, 1]", "2"}},
      {R"({"model": "ward", "alpha_x": 0.2})", {"\"alpha_x\"", "\"alpha_y\""}},
      {R"({"model": "ward", "roughness": 0.2})", {"unknown key \"roughness\"", "allowed keys"}},
      {R"({"model": "wrd"})", {"\"model\"", "\"ward\""}},
      {R"({"model": "ward", "kd": 0.1)", {"invalid JSON", "line 1"}},
      {"brushed-gld", {"brushed-gld", "did you mean \"brushed-gold\""}},
      {file.string(), {file.string(), "\"f0\"", "the string \"gold\""}},
  };

  int failures = 0;
  for (const Case& c : cases) {
    try {
      const aniso::MaterialDesc desc = aniso::load_material(c.spec);
      (void)aniso::build_material<float>(desc);
      std::printf("%s\n  no error (expected an InputError)\n", c.spec.c_str());
      ++failures;
    } catch (const aniso::InputError& e) {
      const std::string message = e.what();
      std::printf("%s\n  -> %s\n", c.spec.c_str(), message.c_str());
      for (const std::string& part : c.expected)
        if (message.find(part) == std::string::npos) std::printf("  MISSING from the message: %s\n", part.c_str()), ++failures;
    }
  }

  // A material built in code goes through the same checks: parse_material(json, where) validates a
  // nlohmann::json object, and `where` opens its messages.
  try {
    aniso::parse_material(nlohmann::json{{"model", "lambert"}, {"kd", 1.5}}, "my material");
    ++failures;
  } catch (const aniso::InputError& e) {
    std::printf("parse_material(...)\n  -> %s\n", e.what());
    if (std::string(e.what()).rfind("my material: key \"kd\"", 0) != 0) ++failures;
  }

  std::filesystem::remove(file);
  if (failures) std::printf("FAILED: %d checks\n", failures);
  return failures ? 1 : 0;
}
