// tests/test_scene_input.cpp: what the scene reader must refuse or accept exactly (docs/scenes.md):
// OBJ numbers that tinyobjloader would read as 0 are errors naming the file and line; bounds are
// compared in double, so the documented limits themselves are accepted; lengths that are infinite
// in float are refused; `name` and `description` are strings; huge triangles are shaded.
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aniso/io/params.h"
#include "aniso/render/geometry.h"
#include "aniso/render/integrator.h"
#include "aniso/render/scene.h"
#include "input_error_text.h"

namespace aniso::render {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json base_scene() {
  return {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}}},
          {"objects", json::array({{{"shape", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"material", "clay"}}})}};
}

std::string scene_error(const json& j, const std::string& base_dir = "") {
  return error_of([&] { parse_scene(j, "s.json", base_dir); });
}

class ObjDir {
 public:
  ObjDir() {
    dir_ = fs::temp_directory_path() /
           ("aniso-obj-" + std::to_string(::getpid()) + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  ~ObjDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string dir() const { return dir_.string(); }
  // A scene with one mesh whose OBJ text is `obj`; returns the error (or "(no error)").
  std::string error_for(const std::string& obj) const {
    std::ofstream(dir_ / "m.obj", std::ios::binary) << obj;
    json j = base_scene();
    j["objects"] = json::array({{{"shape", "mesh"}, {"file", "m.obj"}, {"material", "clay"}}});
    return scene_error(j, dir());
  }

 private:
  fs::path dir_;
};

const char* kFace = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(SceneObj, NumbersThatAreNotFiniteDecimalsNameTheFileAndLine) {
  const ObjDir d;
  EXPECT_EQ(d.error_for(kFace), "(no error)");
  EXPECT_EQ(d.error_for(std::string(
                "# comment\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 # trailing\nvn 0 0 1\nvt 0.5\nvt 0 1 0\nf 1 2 3\n")),
            "(no error)");
  struct Case {
    std::string line, expect;
  };
  for (const Case& c : {Case{"v hello -1 0", "field 1: expected a finite decimal number, got \"hello\""},
                        Case{"v nan -1 0", "got \"nan\""}, Case{"v inf -1 0", "got \"inf\""}, Case{"v 0x1 0 0", "got \"0x1\""},
                        Case{"v -1", "expected the numbers of a \"v\" line (x y z [w], or x y z r g b), got 1"},
                        Case{"v 1 2 3 4 5", "got 5"}, Case{"v 1 2 3 4 5 6 7", "got 7"}, Case{"vn nan 0 1", "got \"nan\""},
                        Case{"vn 0 1", "expected the numbers of a \"vn\" line (x y z), got 2"},
                        Case{"vt", "expected the numbers of a \"vt\" line (u [v [w]]), got 0"},
                        Case{"v", "expected the numbers of a \"v\" line (x y z [w], or x y z r g b), got 0"}}) {
    const std::string err = d.error_for("v 0 0 0\n" + c.line + "\nv 1 0 0\nv 0 1 0\nf 1 3 4\n");
    EXPECT_TRUE(contains(err, "s.json: objects[0].file: " + d.dir() + "/m.obj: line 2: \"" + c.line + "\": ")) << err;
    EXPECT_TRUE(contains(err, c.expect)) << err << "\n  expected: " << c.expect;
  }
}

// Issue 40 item 12: tinyobjloader reads face indices with atoi, so "1.5" was 1, 4294967297 and
// 9223372036854775808 wrapped, and a vt / vn index past the end dropped the mesh's UVs or normals
// without a word. Each is an error naming the file, the line and the index.
TEST(SceneObj, FaceIndicesOutOfRangeOrNotWholeNameTheFileLineAndIndex) {
  const ObjDir d;
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  EXPECT_EQ(d.error_for(head + "f 1/1/1 2/1/1 3/1/1\n"), "(no error)");
  EXPECT_EQ(d.error_for(head + "f 1//1 2//1 3//1\n"), "(no error)");
  EXPECT_EQ(d.error_for(head + "f -3/-1 -2/-1 -1/-1\n"), "(no error)");
  EXPECT_EQ(d.error_for("f 1 2 3\n" + head), "(no error)");  // a face may name later vertices
  struct Case {
    std::string line, expect;
  };
  for (const Case& c :
       {Case{"f 1/1 2/5 3/1", "line 6: \"f 1/1 2/5 3/1\": vertex \"2/5\": vt index 5: the file has 1 \"vt\" line"},
        Case{"f 1//7 2//1 3//1", "line 6: \"f 1//7 2//1 3//1\": vertex \"1//7\": vn index 7: the file has 1 \"vn\" line"},
        Case{"f 1 2 99", "vertex \"99\": v index 99: the file has 3 \"v\" lines"},
        Case{"f 1 2 4294967297", "vertex 3 \"4294967297\": v index \"4294967297\": above 2147483647"},
        Case{"f 1 2 9223372036854775808", "v index \"9223372036854775808\": above 2147483647"},
        Case{"f 1.5 2 3", "vertex 1 \"1.5\": v index \"1.5\": expected a whole decimal number"},
        Case{"f 1e0 2 3", "v index \"1e0\": expected a whole decimal number"},
        Case{"f x 2 3", "v index \"x\": expected a whole decimal number"},
        Case{"f 0 2 3", "v index \"0\": expected a number from 1, or negative"},
        Case{"f -4 2 3", "v index \"-4\": counts back past the first element: 3 \"v\" lines before this face"},
        Case{"f 1/-2 2 3", "vt index \"-2\": counts back past the first element: 1 \"vt\" line before this face"},
        Case{"f 1/ 2 3", "vertex 1 \"1/\": expected an index after \"/\""},
        Case{"f 1/1/1/1 2 3", "expected v, v/vt, v//vn or v/vt/vn"}, Case{"f 1 2", "a face needs at least 3 vertices, got 2"}}) {
    const std::string err = d.error_for(head + c.line + "\n");
    EXPECT_TRUE(contains(err, "s.json: objects[0].file: " + d.dir() + "/m.obj: line 6: \"" + c.line + "\": ")) << err;
    EXPECT_TRUE(contains(err, c.expect)) << err << "\n  expected: " << c.expect;
  }
}

TEST(SceneBounds, DocumentedLimitsThemselvesAreAccepted) {
  json j = base_scene();
  j["objects"][0]["radius"] = 1e15;
  EXPECT_EQ(scene_error(j), "(no error)");
  j["objects"][0]["radius"] = 1.0000001e15;
  EXPECT_TRUE(contains(scene_error(j), "objects[0].radius")) << scene_error(j);
  j = base_scene();
  j["objects"] = json::array({{{"shape", "torus"}, {"center", {0, 0, 0}}, {"major_radius", 1e15}, {"material", "clay"}}});
  EXPECT_EQ(scene_error(j), "(no error)");
  j = base_scene();
  j["environment"] = {{"type", "sky"}, {"sun_radius_deg", 0.05}, {"resolution", 16}};
  EXPECT_EQ(scene_error(j), "(no error)");
  j["environment"]["sun_radius_deg"] = 0.0499999;
  EXPECT_TRUE(contains(scene_error(j), "sun_radius_deg")) << scene_error(j);
  j = base_scene();
  j["lights"] = json::array({{{"type", "sphere"}, {"center", {0, 5, 0}}, {"radius", 1e15}, {"radiance", 1}}});
  EXPECT_EQ(scene_error(j), "(no error)");
}

TEST(SceneBounds, EnvironmentMapScaleOf1e12IsAccepted) {
  const ObjDir d;
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
  for (int b : {128, 64, 0, 129, 128, 128, 128, 130}) hdr.push_back(char(b));
  std::ofstream(fs::path(d.dir()) / "env.hdr", std::ios::binary) << hdr;
  json j = base_scene();
  j["environment"] = {{"type", "map"}, {"file", "env.hdr"}, {"scale", 1e12}};
  EXPECT_EQ(scene_error(j, d.dir()), "(no error)");
  j["environment"]["scale"] = 1.0001e12;
  EXPECT_TRUE(contains(scene_error(j, d.dir()), "environment.scale")) << scene_error(j, d.dir());
}

TEST(SceneBounds, RectangleSizeInfiniteInFloatIsRefused) {
  json j = base_scene();
  j["objects"] = json::array({{{"shape", "rectangle"},
                               {"center", {0, 0, 0}},
                               {"normal", {0, 0, 1}},
                               {"u", {1, 0, 0}},
                               {"size", {1e39, 1}},
                               {"material", "clay"}}});
  EXPECT_TRUE(contains(scene_error(j), "objects[0].size: expected [width, height], two numbers in (0, 1e15]")) << scene_error(j);
  j["objects"][0]["size"] = {1e15, 2};
  EXPECT_EQ(scene_error(j), "(no error)");
}

TEST(SceneText, NameAndDescriptionMustBeStrings) {
  json j = base_scene();
  j["name"] = "a scene";
  j["description"] = "";
  j["objects"][0]["name"] = "ball";
  EXPECT_EQ(scene_error(j), "(no error)");
  j["name"] = 5;
  EXPECT_TRUE(contains(scene_error(j), "name: expected a string (free text), got")) << scene_error(j);
  j["name"] = "ok";
  j["description"] = json::array({1});
  EXPECT_TRUE(contains(scene_error(j), "description: expected a string")) << scene_error(j);
  j["description"] = "ok";
  j["objects"][0]["name"] = json::object();
  EXPECT_TRUE(contains(scene_error(j), "objects[0].name: expected a string")) << scene_error(j);
}

// A triangle's normal is finite and unit for any finite edges: |e1 x e2| overflows float for edges
// above about 4e9, where a normal taken from the unscaled cross product would be 0 (a triangle of
// size 1e11 would render black).
TEST(SceneMesh, TriangleNormalOfHugeEdgesIsUnit) {
  for (float s : {1.0f, 1e10f, 1e19f, 1e38f}) {
    const Vec3 n = SceneGeometry::triangle_normal(Vec3(s, 0, 0), Vec3(0, s, 0));
    EXPECT_EQ(n, Vec3(0, 0, 1)) << s;
  }
  EXPECT_EQ(SceneGeometry::triangle_normal(Vec3(1, 0, 0), Vec3(2, 0, 0)), Vec3(0, 1, 0));  // degenerate
}

TEST(SceneMesh, HugeTriangleRendersAsASmallerOne) {
  const ObjDir d;
  std::ofstream(fs::path(d.dir()) / "tri.obj") << "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
  const auto mean_for = [&](double scale) {
    json j = {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}}},
              {"film", {{"width", 8}, {"height", 8}, {"spp", 1}}},
              {"environment", {{"type", "uniform"}, {"radiance", 1}}},
              {"objects", json::array({{{"shape", "mesh"}, {"file", "tri.obj"}, {"scale", scale}, {"material", "clay"}}})}};
    const Image img = render(parse_scene(j, "s.json", d.dir()), RenderOptions{});
    double sum = 0;
    for (float v : img.rgb) sum += v;
    return sum / double(img.rgb.size());
  };
  const double small = mean_for(1e5);  // covers the whole view already
  EXPECT_GT(small, 0.1);
  EXPECT_NEAR(mean_for(1e11), small, 1e-3 * small);
}

}  // namespace
}  // namespace aniso::render
