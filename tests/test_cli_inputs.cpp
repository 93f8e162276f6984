// tests/test_cli_inputs.cpp: the size limits of the CLI's whole-file reads (docs/cli.md, "Size
// limits"; issue 40 item 5) and the OBJ face checks from the command line (item 12): each is exit 2
// naming the file and what was wrong, nothing on stdout. A regular file over a limit is a sparse
// file (no disk used; refused by its size, nothing read); /dev/zero is read up to the 64 MiB limit.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"

namespace aniso {
namespace {

class CliInputs : public Cli {
 protected:
  // A sparse file of `bytes` bytes named `name`; its path.
  std::string sparse(const std::string& name, uintmax_t bytes) {
    const std::string p = write(name, "");
    fs::resize_file(p, bytes);
    return p;
  }
  std::string scene_with(const nlohmann::json& object) {
    const nlohmann::json scene = {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}}},
                                  {"film", {{"width", 8}, {"height", 8}, {"spp", 1}}},
                                  {"objects", nlohmann::json::array({object})}};
    return write("s.json", scene.dump());
  }
};

// Before: `aniso eval -m /dev/zero` grew to 16.8 GB and ended "out of memory" (exit 1), and
// `-m /dev/urandom` never ended.
TEST_F(CliInputs, MaterialFromADeviceStopsAtTheLimit) {
  if (::access("/dev/zero", R_OK) != 0) GTEST_SKIP() << "no /dev/zero on this system";
  expect_input_error(run({"eval", "-m", "/dev/zero"}),
                     {"aniso: error: /dev/zero: larger than 64 MiB, the limit for a JSON file (docs/cli.md, \"Size limits\")"});
}

TEST_F(CliInputs, RegularFilesOverTheLimitAreRefusedBySize) {
  const std::string json = sparse("big.json", (uintmax_t(64) << 20) + 1);
  expect_input_error(run({"eval", "-m", json}), {json + ": 67108865 bytes: larger than 64 MiB, the limit for a JSON file"});
  const std::string csv = sparse("big.csv", (uintmax_t(256) << 20) + 1);
  expect_input_error(run({"fit", csv, "--model", "ward", "-o", (dir_ / "f.json").string()}),
                     {csv + ": ", "larger than 256 MiB, the limit for a CSV file of samples"});
  const std::string bsdf = sparse("big.bsdf", (uintmax_t(512) << 20) + 1);
  expect_input_error(run({"fit", bsdf, "--model", "ggx", "-o", (dir_ / "f.json").string()}),
                     {bsdf + ": ", "larger than 512 MiB, the limit for an RGL tensor file"});
  // A scene naming a material file over the limit (the scene's own reads share the reader).
  expect_input_error(run({"render", scene_with({{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", json}}),
                          "-o", (dir_ / "out.png").string()}),
                     {"larger than 64 MiB, the limit for a JSON file"});
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
}

// Before: exit 0 with the UVs dropped (tinyobjloader keeps the index and the mesh loses its UVs).
TEST_F(CliInputs, AnObjFaceNamingAMissingUvIsExitTwoNamingLineAndIndex) {
  write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/5 3/1\n");
  const std::string scene = scene_with({{"shape", "mesh"}, {"file", "m.obj"}, {"material", "clay"}});
  expect_input_error(run({"render", scene, "-o", (dir_ / "out.png").string()}),
                     {"m.obj: line 5: \"f 1/1 2/5 3/1\": vertex \"2/5\": vt index 5: the file has 1 \"vt\" line"});
}

}  // namespace
}  // namespace aniso
