// tests/test_docs.cpp: the documentation quotes what the code says. Each model page
// docs/models/<name>.md contains its parameter tables exactly as `aniso models --markdown` prints
// them (markdown_table() in src/io/params.cpp), and README.md gives the two commands up front.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "io/params.h"

namespace aniso {
namespace {

// The whole file, or "" when it cannot be read (the caller reports which).
std::string read_text(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::ostringstream s;
  if (ok) s << in.rdbuf();
  return s.str();
}

TEST(Docs, ModelPagesQuoteTheGeneratedParameterTables) {
  int pages = 0;
  for (const ModelSpec* spec : model_specs()) {
    const std::string name(spec->name);
    const std::string rel = "docs/models/" + name + ".md";
    bool ok = false;
    const std::string page = read_text(std::string(ANISO_SOURCE_DIR) + "/" + rel, ok);
    ASSERT_TRUE(ok) << rel << " is missing: every model in src/io/params.cpp has a page";
    ++pages;
    const std::string table = markdown_table(*spec);
    EXPECT_TRUE(page.find(table) != std::string::npos)
        << rel << " does not contain the current parameter table of `" << name << "` verbatim.\n"
        << "Regenerate it: replace the table(s) under \"## Parameters\" in " << rel << " with the output of\n"
        << "  build/release/bin/aniso models --markdown --model " << name << "\n"
        << "(from its first line \"Parameters of `" << name << "` ...\" through the last nested table; do not edit it "
        << "by hand: change src/io/params.cpp instead). Expected text:\n"
        << table;
  }
  EXPECT_GE(pages, 7);  // lambert phong ward ashikhmin-shirley lafortune ggx metal
}

TEST(Docs, ReadmeStartsWithTheTwoCommands) {
  bool ok = false;
  const std::string readme = read_text(std::string(ANISO_SOURCE_DIR) + "/README.md", ok);
  ASSERT_TRUE(ok) << "README.md is missing";
  std::istringstream in(readme);
  std::string head, line;
  for (int i = 0; i < 15 && std::getline(in, line); ++i) head += line + "\n";
  EXPECT_TRUE(head.find("make render") != std::string::npos)
      << "README.md's first 15 lines must give `make render` (the main job):\n" << head;
  EXPECT_TRUE(head.find("make test") != std::string::npos)
      << "README.md's first 15 lines must give `make test`:\n" << head;
}

}  // namespace
}  // namespace aniso
